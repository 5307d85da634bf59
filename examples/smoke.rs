use elasto::material::*;
use elasto::math::Vector;
use elasto::mesh::Mesh;
use elasto::sim::*;
fn main() {
    let young: f64 = std::env::args().nth(1).map(|s| s.parse().unwrap()).unwrap_or(300.0);
    let nh = std::env::args().nth(2).is_some();
    let mesh = Mesh::<2>::axis_aligned_box(Vector::<2>::new(0.0, 10.0), Vector::<2>::new(1.0, 11.0), [5, 5]).unwrap();
    let lame: LameParameters = YoungPoisson { young, poisson: 0.3 }.into();
    let material = if nh { Material::NeoHookean(NeoHookean { lame }) } else { Material::StVenantKirchhoff(StVenantKirchhoff { lame }) };
    let effects = Effects { gravity: Some(Vector::<2>::new(0.0, -1.0)), ground: Some(Ground { height: 0.0, activation_distance: 0.1, stiffness: None }), pinned: None };
    let mut sim = Simulation::new(mesh, material, 1.0, effects, SimulationSettings::default(), Vector::<2>::zeros()).unwrap();
    println!("kappa {:?}", sim.barrier_stiffness());
    for f in 0..300 {
        let s = sim.advance_frame(10).unwrap();
        if f % 5 == 0 {
            println!("{f:3} t={:.2} it={} bt={} unconv={} com_y={:.3} minh={:.4} J={:.3} E={:.4} ms={:.1}", s.time, s.iterations, s.backtracks, s.unconverged_steps, s.centre_of_mass[1], s.min_height.unwrap(), s.min_volume_ratio, s.energy.total(), s.wall_time.as_secs_f64()*1e3);
        }
    }
}
