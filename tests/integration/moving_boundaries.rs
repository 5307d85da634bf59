//! Issue 12, item 3: moving pinned regions (`[[effects.pinned]]` with
//! `velocity`, `angular_velocity`, `axis`, `center`, `until`).
//!
//! Pinned vertices are eliminated unknowns that follow the rigid path
//! `x(t) = c + R(w tau)(X - c) + v tau`, `tau = min(t, until)`: the tests
//! check that they are on it to round-off (translation, rotation, stop),
//! that their velocities are the path's under every integrator, that a bar
//! pulled at one end carries the analytic static force, that a body dragged
//! by a region ends up moving with it, that a move that would invert an
//! element or enter the ground is refused with a message, and that the scene
//! keys are validated with messages naming `effects.pinned[i].key`.

use elasto::integrator::IntegratorKind;
use elasto::material::{LameParameters, Material, MaterialModel, YoungPoisson};
use elasto::math::{Vector, Vector3};
use elasto::mesh::Mesh;
use elasto::scene::{Scene, SceneError, SceneSource};
use elasto::sim::{Effects, Ground, PinMotion, PinRegion, Simulation, SimulationSettings, rotate};

fn material(model: MaterialModel, young: f64, poisson: f64) -> Material {
    let lame: LameParameters = YoungPoisson { young, poisson }.into();
    model.with_lame(lame)
}

/// A bar `[0, length] x [0, 1]^(D-1)` of `cells` cells along x and 2 across.
fn bar<const D: usize>(length: f64, cells: usize) -> Mesh<D> {
    let max = Vector::<D>::from_fn(|k, _| if k == 0 { length } else { 1.0 });
    let mut counts = [2; D];
    counts[0] = cells;
    Mesh::axis_aligned_box(Vector::<D>::zeros(), max, counts).unwrap()
}

/// The slab `x <= eps` (left end) or `x >= length - eps` (right end).
fn end<const D: usize>(x0: f64, x1: f64) -> PinRegion<D> {
    PinRegion::new(
        Vector::<D>::from_fn(|k, _| if k == 0 { x0 } else { -1.0 }),
        Vector::<D>::from_fn(|k, _| if k == 0 { x1 } else { 2.0 }),
    )
}

fn simulation<const D: usize>(
    mesh: Mesh<D>,
    material: Material,
    pinned: Vec<PinRegion<D>>,
    dt: f64,
    integrator: IntegratorKind,
) -> Simulation<D> {
    let effects = Effects {
        gravity: None,
        ground: None,
        contact: None,
        pinned,
        obstacles: Vec::new(),
    };
    let mut settings = SimulationSettings {
        dt,
        integrator,
        ..Default::default()
    };
    settings.solver.tolerance = 1e-9;
    Simulation::new(mesh, material, 1.0, effects, settings, Vector::<D>::zeros()).unwrap()
}

/// The pinned vertices: `(vertex, rest position)`.
fn pinned_vertices<const D: usize>(sim: &Simulation<D>) -> Vec<(usize, Vector<D>)> {
    sim.free_index()
        .iter()
        .enumerate()
        .filter(|(_, f)| f.is_none())
        .map(|(v, _)| (v, sim.mesh().rest_positions()[v]))
        .collect()
}

/// Round-off bound for a position of magnitude about `scale`.
fn round_off(scale: f64) -> f64 {
    16.0 * f64::EPSILON * scale.max(1.0)
}

both_dimensions! {
    translating_region_holds_its_vertices_on_the_path => translating_region_2d, translating_region_3d;
    rotating_region_has_turned_by_w_t => rotating_region_2d, rotating_region_3d;
    until_stops_the_region_where_the_path_left_it => until_stops_2d, until_stops_3d;
    pulled_bar_carries_the_analytic_static_force => pulled_bar_2d, pulled_bar_3d;
    dragged_body_ends_up_moving_with_the_region => dragged_body_2d, dragged_body_3d;
    a_released_region_lets_its_vertices_go => released_region_2d, released_region_3d;
}

/// A left end moving at constant `v`: every pinned vertex at `X + v t`
/// after every step, and its velocity exactly `v`, with every integrator.
fn translating_region_holds_its_vertices_on_the_path<const D: usize>() {
    let v = Vector::<D>::from_fn(|k, _| [0.7, -0.2, 0.3][k]);
    for integrator in IntegratorKind::ALL {
        let region = end::<D>(-1.0, 1e-9).moving(PinMotion {
            velocity: v,
            ..PinMotion::default()
        });
        let mut sim = simulation(
            bar::<D>(2.0, 4),
            material(MaterialModel::NeoHookean, 100.0, 0.3),
            vec![region],
            0.01,
            integrator,
        );
        let pinned = pinned_vertices(&sim);
        assert_eq!(pinned.len(), 3usize.pow(D as u32 - 1), "{integrator:?}");
        for p in &pinned {
            assert_eq!(
                sim.velocities()[p.0],
                v,
                "initial velocity of a pinned vertex"
            );
        }
        for _ in 0..40 {
            let stats = sim.step().unwrap();
            assert!(stats.solver.converged, "{integrator:?}");
            let t = sim.time();
            for &(vertex, rest) in &pinned {
                let expected = rest + v * t;
                let error = (sim.positions()[vertex] - expected).amax();
                assert!(
                    error <= round_off(expected.amax()),
                    "{integrator:?}: vertex {vertex} at t = {t} is {error} off its path"
                );
                assert_eq!(sim.velocities()[vertex], v, "{integrator:?}");
            }
        }
        // The free end has followed (the body is dragged, not left behind).
        let far = sim.positions()[sim.mesh().vertex_count() - 1];
        let far_rest = sim.mesh().rest_positions()[sim.mesh().vertex_count() - 1];
        assert!(
            (far - far_rest).dot(&v) > 0.5 * v.norm_squared() * sim.time(),
            "{integrator:?}: the free end moved {:?}",
            far - far_rest
        );
    }
}

/// The signed angle from `a` to `b` about `axis` (3D) or in the plane (2D),
/// and the change of the component along the axis.
fn turned<const D: usize>(a: &Vector<D>, b: &Vector<D>, axis: &Vector3) -> (f64, f64) {
    let lift = |v: &Vector<D>| Vector3::from_fn(|k, _| if k < D { v[k] } else { 0.0 });
    let (a, b) = (lift(a), lift(b));
    let (a_perp, b_perp) = (a - axis * axis.dot(&a), b - axis * axis.dot(&b));
    let angle = axis.dot(&a_perp.cross(&b_perp)).atan2(a_perp.dot(&b_perp));
    (angle, axis.dot(&b) - axis.dot(&a))
}

/// A right end rotating at `w` about the bar's axis (3D) or in the plane
/// (2D) about its centre: after each step every pinned vertex has turned by
/// exactly `w t` about the centre, at unchanged distance and axial position.
fn rotating_region_has_turned_by_w_t<const D: usize>() {
    let w = 0.4 * std::f64::consts::PI;
    let axis = if D == 3 { Vector3::x() } else { Vector3::z() };
    let center = Vector::<D>::from_fn(|k, _| if k == 0 { 4.0 } else { 0.5 });
    let right = end::<D>(4.0 - 1e-9, 5.0).moving(PinMotion {
        angular_velocity: w,
        axis,
        center,
        ..PinMotion::default()
    });
    let mut sim = simulation(
        bar::<D>(4.0, 8),
        material(MaterialModel::StableNeoHookean, 1000.0, 0.3),
        vec![end::<D>(-1.0, 1e-9), right],
        0.02,
        IntegratorKind::BackwardEuler,
    );
    let moving: Vec<_> = pinned_vertices(&sim)
        .into_iter()
        .filter(|(_, x)| x[0] > 2.0 && (x - center).norm() > 0.1)
        .collect();
    assert!(!moving.is_empty());
    for _ in 0..50 {
        sim.step().unwrap();
        let t = sim.time();
        for &(vertex, rest) in &moving {
            let x = sim.positions()[vertex];
            let (angle, axial) = turned(&(rest - center), &(x - center), &axis);
            let expected = (w * t + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI)
                - std::f64::consts::PI;
            assert!(
                (angle - expected).abs() < 1e-12,
                "vertex {vertex} at t = {t}: turned {angle}, expected {expected}"
            );
            assert!(axial.abs() < 1e-12, "moved {axial} along the axis");
            assert!(((x - center).norm() - (rest - center).norm()).abs() < 1e-12);
            // Its velocity is w k x r: tangent, of size w |r_perp|.
            let velocity = sim.velocities()[vertex];
            assert!((velocity.norm() - w * (rest - center).norm()).abs() < 1e-12);
            assert!(velocity.dot(&(x - center)).abs() < 1e-12);
        }
    }
    // The body between the ends is twisted but sound.
    assert!(sim.frame_stats().min_volume_ratio > 0.0);
    // The same rotation by `rotate` (the public helper) gives the positions bit for bit.
    let (vertex, rest) = moving[0];
    let by_hand = center + rotate(&axis, w * sim.time(), &(rest - center));
    assert_eq!(sim.positions()[vertex], by_hand);
}

/// `until = 0.1`: the region moves until then and stands still after, where
/// the path left it, with zero velocity.
fn until_stops_the_region_where_the_path_left_it<const D: usize>() {
    let v = Vector::<D>::from_fn(|k, _| if k == 0 { -0.5 } else { 0.25 });
    let region = end::<D>(-1.0, 1e-9).moving(PinMotion {
        velocity: v,
        until: Some(0.1),
        ..PinMotion::default()
    });
    let mut sim = simulation(
        bar::<D>(2.0, 4),
        material(MaterialModel::FixedCorotated, 100.0, 0.3),
        vec![region],
        0.01,
        IntegratorKind::Bdf2,
    );
    let pinned = pinned_vertices(&sim);
    for step in 1..=30 {
        sim.step().unwrap();
        let t = sim.time();
        for &(vertex, rest) in &pinned {
            let expected = rest + v * t.min(0.1);
            let error = (sim.positions()[vertex] - expected).amax();
            assert!(error <= round_off(2.0), "step {step}: {error}");
            let speed = sim.velocities()[vertex];
            if t < 0.1 - 1e-12 {
                assert_eq!(speed, v, "step {step}");
            } else if step > 10 {
                assert_eq!(speed, Vector::<D>::zeros(), "step {step}");
            }
        }
    }
}

/// The reaction on the pinned right end of a St. Venant-Kirchhoff bar with
/// `nu = 0` (so `lambda = 0` and no lateral stress), pulled by `delta`:
/// the homogeneous stretch `F = diag(1 + e, 1, 1)` is the exact equilibrium,
/// with first Piola stress `P_11 = (1 + e) 2 mu (e + e^2 / 2)`, so the force
/// is `A P_11` (`A` = cross-section, 1) and every vertex sits at
/// `X_1 (1 + e)`.
fn pulled_bar_carries_the_analytic_static_force<const D: usize>() {
    let (length, young, delta, until) = (4.0, 1000.0, 0.02, 0.5);
    let pull = end::<D>(length - 1e-9, length + 1.0).moving(PinMotion {
        velocity: Vector::<D>::from_fn(|k, _| if k == 0 { delta / until } else { 0.0 }),
        until: Some(until),
        ..PinMotion::default()
    });
    let mut sim = simulation(
        bar::<D>(length, 8),
        material(MaterialModel::StVenantKirchhoff, young, 0.0),
        vec![end::<D>(-1.0, 1e-9), pull],
        0.05,
        IntegratorKind::BackwardEuler,
    );
    // Slow pull, then let backward Euler damp the motion out.
    for _ in 0..400 {
        assert!(sim.step().unwrap().solver.converged);
    }
    let strain = delta / length;
    let mu = young / 2.0;
    let p11 = (1.0 + strain) * 2.0 * mu * (strain + 0.5 * strain * strain);
    let potentials = sim.potentials();
    let elastic = potentials[0];
    let mut gradient = vec![Vector::<D>::zeros(); sim.positions().len()];
    elastic.add_gradient(sim.positions(), 1.0, &mut gradient);
    let rest = sim.mesh().rest_positions();
    let reaction: f64 = (0..rest.len())
        .filter(|&v| rest[v][0] > length - 1e-6)
        .map(|v| gradient[v][0])
        .sum();
    assert!(
        (reaction - p11).abs() < 1e-6 * p11,
        "reaction {reaction}, analytic A P_11 = {p11}"
    );
    for (x, rest) in sim.positions().iter().zip(rest) {
        let expected = Vector::<D>::from_fn(|k, _| {
            if k == 0 {
                rest[0] * (1.0 + strain)
            } else {
                rest[k]
            }
        });
        assert!((x - expected).amax() < 1e-8, "{x:?} against {expected:?}");
    }
    // The linear-elastic value E e is within O(e) of it.
    assert!((reaction - young * strain).abs() < 2.0 * strain * young * strain);
}

/// A body dragged at constant `v` by its left end (no gravity, backward
/// Euler damps the oscillation): it ends up moving rigidly with `v`, its
/// kinetic energy `1/2 M |v|^2` and its strain energy zero.
fn dragged_body_ends_up_moving_with_the_region<const D: usize>() {
    let v = Vector::<D>::from_fn(|k, _| [0.6, 0.3, -0.3][k]);
    let region = end::<D>(-1.0, 1e-9).moving(PinMotion {
        velocity: v,
        ..PinMotion::default()
    });
    let mut sim = simulation(
        bar::<D>(2.0, 4),
        material(MaterialModel::NeoHookean, 500.0, 0.3),
        vec![region],
        0.1,
        IntegratorKind::BackwardEuler,
    );
    for _ in 0..300 {
        sim.step().unwrap();
    }
    let mass: f64 = sim.masses().iter().sum();
    let energy = sim.energies();
    let kinetic = 0.5 * mass * v.norm_squared();
    assert!(
        (energy.kinetic - kinetic).abs() < 1e-6 * kinetic,
        "kinetic {} against 1/2 M v^2 = {kinetic}",
        energy.kinetic
    );
    assert!(energy.get("elastic").unwrap() < 1e-9 * kinetic);
    for u in sim.velocities() {
        assert!((u - v).amax() < 1e-5 * v.amax(), "{u:?}");
    }
}

/// A region that jumps across an element in one step would invert it if it
/// were put on its path before the solve (this stopped the run with "inverts
/// an element before the solve"): it is moved as far as is feasible and
/// pulled the rest of the way within the solve (augmented Lagrangian), the
/// free vertices following. Every step converges, the region ends on its
/// path, no Neo-Hookean element inverts.
#[test]
fn a_move_too_far_for_one_step_arrives_through_the_solve() {
    let velocity = Vector::<2>::new(200.0, 0.0);
    let region = end::<2>(-1.0, 1e-9).moving(PinMotion {
        velocity,
        ..PinMotion::default()
    });
    let mut sim = simulation(
        bar::<2>(2.0, 4),
        material(MaterialModel::NeoHookean, 100.0, 0.3),
        vec![region],
        0.01,
        IntegratorKind::BackwardEuler,
    );
    let pinned: Vec<usize> = (0..sim.positions().len())
        .filter(|&v| sim.free_index()[v].is_none())
        .collect();
    let rest = sim.positions().to_vec();
    let mut pulled = 0;
    for step in 1..=5 {
        let stats = sim.step().unwrap();
        assert!(stats.solver.converged, "step {step}: {:?}", stats.solver);
        assert!(
            stats.min_volume_ratio > 0.0,
            "step {step}: J = {}",
            stats.min_volume_ratio
        );
        if let Some(error) = stats.solver.constraint_error {
            pulled += 1;
            assert!(error <= 1e-3 * 2.0, "step {step}: boundary error {error}");
        }
        for &v in &pinned {
            let target = rest[v] + velocity * sim.time();
            assert!(
                (sim.positions()[v] - target).norm() <= 1e-3 * velocity.norm() * 0.01,
                "step {step}: vertex {v} at {:?}, its path at {target:?}",
                sim.positions()[v]
            );
        }
    }
    assert!(
        pulled > 0,
        "no step needed the augmented Lagrangian: the case is too easy"
    );
}

/// A region driven into the ground is refused before the solve.
#[test]
fn a_move_into_the_ground_is_refused() {
    let mesh = Mesh::axis_aligned_box(
        Vector::<2>::new(0.0, 0.5),
        Vector::<2>::new(1.0, 1.5),
        [2, 2],
    )
    .unwrap();
    let plate =
        PinRegion::new(Vector::<2>::new(-1.0, 0.4), Vector::<2>::new(2.0, 0.6)).moving(PinMotion {
            velocity: Vector::<2>::new(0.0, -1.0),
            ..PinMotion::default()
        });
    let effects = Effects {
        gravity: None,
        ground: Some(Ground {
            height: 0.0,
            activation_distance: 0.1,
            stiffness: None,
            friction: 0.0,
        }),
        contact: None,
        pinned: vec![plate],
        obstacles: Vec::new(),
    };
    let settings = SimulationSettings {
        dt: 0.1,
        ..Default::default()
    };
    let mut sim = Simulation::new(
        mesh,
        material(MaterialModel::NeoHookean, 100.0, 0.3),
        1.0,
        effects,
        settings,
        Vector::<2>::zeros(),
    )
    .unwrap();
    let mut outcome = Ok(());
    for _ in 0..10 {
        if let Err(e) = sim.step() {
            outcome = Err(e);
            break;
        }
        assert!(sim.frame_stats().min_height.unwrap() > 0.0);
    }
    let text = outcome.unwrap_err().to_string();
    assert!(text.contains("on or below the ground"), "{text}");
    // Steps 0..4 reach heights 0.4 .. 0.1; the 5th would reach 0.
    assert_eq!(sim.step_count(), 4);
}

fn load(text: &str) -> Result<Scene, SceneError> {
    let source = SceneSource {
        label: "test.toml".into(),
        default_name: "test".into(),
        path: None,
        text: text.into(),
    };
    Scene::load(&source, &[])
}

const BAR_2D: &str = "dimension = 2\n\n[mesh]\nsize = [4.0, 1.0]\ncells = [4, 1]\n\n\
                      [material]\nmodel = \"neo-hookean\"\nyoung = 100.0\npoisson = 0.3\n";
const BAR_3D: &str = "dimension = 3\n\n[mesh]\nsize = [4.0, 1.0, 1.0]\ncells = [4, 1, 1]\n\n\
                      [material]\nmodel = \"neo-hookean\"\nyoung = 100.0\npoisson = 0.3\n";

/// `[[effects.pinned]]` regions read into the effects, with their motion
/// and the centre of the box as the default centre of rotation; the old
/// single `[effects.pinned]` table still reads as one region.
#[test]
fn pinned_regions_are_read_from_the_scene() {
    let text = format!(
        "{BAR_3D}\n[[effects.pinned]]\nmin = [-1, -1, -1]\nmax = [0, 2, 2]\n\
         angular_velocity = -1.2566\naxis = [2, 0, 0]\nuntil = 5.0\n\n\
         [[effects.pinned]]\nmin = [4, -1, -1]\nmax = [5, 2, 2]\nvelocity = [0.1, 0, 0]\n"
    );
    let Scene::Three(c) = load(&text).unwrap() else {
        panic!("3D")
    };
    assert_eq!(c.effects.pinned.len(), 2);
    let twist = c.effects.pinned[0].motion;
    assert_eq!(twist.angular_velocity, -1.2566);
    assert_eq!(twist.axis, Vector3::x());
    assert_eq!(twist.center, Vector3::new(-0.5, 0.5, 0.5));
    assert_eq!(twist.until, Some(5.0));
    assert_eq!(
        c.effects.pinned[1].motion.velocity,
        Vector3::new(0.1, 0.0, 0.0)
    );
    assert_eq!(c.effects.pinned[1].motion.until, None);
    let old = format!("{BAR_2D}\n[effects.pinned]\nmin = [-1, -1]\nmax = [0, 2]\n");
    let Scene::Two(c) = load(&old).unwrap() else {
        panic!("2D")
    };
    assert_eq!(c.effects.pinned.len(), 1);
    assert!(!c.effects.pinned[0].motion.is_moving());
}

/// Every bad region key is named with its index.
#[test]
fn bad_region_keys_are_named_with_their_index() {
    let region0 = "[[effects.pinned]]\nmin = [-1, -1]\nmax = [0, 2]\n";
    let cases: &[(&str, &str, &str, &str)] = &[
        (
            BAR_2D,
            "axis = [0, 0, 1]\nangular_velocity = 1.0\n",
            "effects.pinned[1].axis",
            "3D key",
        ),
        (
            BAR_2D,
            "velocity = [1, 2, 3]\n",
            "effects.pinned[1].velocity",
            "2 components",
        ),
        (
            BAR_2D,
            "velocity = [nan, 0]\n",
            "effects.pinned[1].velocity",
            "finite",
        ),
        (
            BAR_2D,
            "angular_velocity = inf\n",
            "effects.pinned[1].angular_velocity",
            "finite",
        ),
        (
            BAR_2D,
            "center = [1, 1]\n",
            "effects.pinned[1].center",
            "without",
        ),
        (
            BAR_2D,
            "until = 1.0\n",
            "effects.pinned[1].until",
            "does not move",
        ),
        (
            BAR_2D,
            "velocity = [1, 0]\nuntil = -1.0\n",
            "effects.pinned[1].until",
            ">= 0",
        ),
        (
            BAR_2D,
            "speed = 1.0\n",
            "effects.pinned[1].speed",
            "unknown field",
        ),
        (
            BAR_3D,
            "angular_velocity = 1.0\n",
            "effects.pinned[1].axis",
            "required",
        ),
        (
            BAR_3D,
            "angular_velocity = 1.0\naxis = [0, 0, 0]\n",
            "effects.pinned[1].axis",
            "non-zero",
        ),
    ];
    for (scene, extra, key, words) in cases {
        let (min, max) = if scene.contains("dimension = 2") {
            ("[4, -1]", "[5, 2]")
        } else {
            ("[4, -1, -1]", "[5, 2, 2]")
        };
        let first = if scene.contains("dimension = 2") {
            region0.to_owned()
        } else {
            "[[effects.pinned]]\nmin = [-1, -1, -1]\nmax = [0, 2, 2]\n".to_owned()
        };
        let text =
            format!("{scene}\n{first}\n[[effects.pinned]]\nmin = {min}\nmax = {max}\n{extra}");
        let Err(SceneError::Invalid(d)) = load(&text) else {
            panic!("{extra}: expected an error")
        };
        assert_eq!(d.key.as_deref(), Some(*key), "{extra}: {d}");
        assert!(d.reason.contains(words), "{extra}: {d}");
        assert!(d.to_string().starts_with("test.toml:"), "{d}");
    }
    // A region that catches nothing is named by its index too.
    let text = format!("{BAR_2D}\n{region0}\n[[effects.pinned]]\nmin = [9, 9]\nmax = [10, 10]\n");
    let Err(SceneError::Invalid(d)) = load(&text) else {
        panic!("expected an error")
    };
    assert_eq!(d.key.as_deref(), Some("effects.pinned[1]"), "{d}");
}

/// A body's own pinned region (`[[bodies]]`' `pinned`) takes the same
/// motion: the second body's left end follows its path while the first
/// body, pinned still by the effects' region, keeps its pinned vertices at rest.
#[test]
fn a_body_region_moves_like_an_effects_region() {
    use elasto::sim::Body;
    let v = Vector::<2>::new(0.0, 0.4);
    let still = Body {
        mesh: bar::<2>(2.0, 2),
        material: material(MaterialModel::NeoHookean, 100.0, 0.3),
        density: 1.0,
        velocity: Vector::<2>::zeros(),
        pinned: None,
    };
    let moved = Mesh::axis_aligned_box(
        Vector::<2>::new(0.0, 3.0),
        Vector::<2>::new(2.0, 4.0),
        [2, 2],
    )
    .unwrap();
    let dragged = Body {
        mesh: moved,
        material: material(MaterialModel::NeoHookean, 100.0, 0.3),
        density: 1.0,
        velocity: Vector::<2>::zeros(),
        pinned: Some(
            PinRegion::new(Vector::<2>::new(-1.0, 2.5), Vector::<2>::new(1e-9, 5.0)).moving(
                PinMotion {
                    velocity: v,
                    ..PinMotion::default()
                },
            ),
        ),
    };
    let effects = Effects {
        gravity: None,
        ground: None,
        contact: None,
        pinned: vec![PinRegion::new(
            Vector::<2>::new(-1.0, -1.0),
            Vector::<2>::new(1e-9, 1.5),
        )],
        obstacles: Vec::new(),
    };
    let mut sim = Simulation::with_bodies(
        vec![still, dragged],
        effects,
        SimulationSettings {
            dt: 0.01,
            ..Default::default()
        },
    )
    .unwrap();
    let pinned = pinned_vertices(&sim);
    assert_eq!(pinned.len(), 6);
    for _ in 0..20 {
        sim.step().unwrap();
    }
    let t = sim.time();
    for (vertex, rest) in pinned {
        let expected = if rest[1] > 2.0 { rest + v * t } else { rest };
        assert!((sim.positions()[vertex] - expected).amax() <= round_off(4.0));
    }
}

/// A left end dragging a bar at `v`, released at t = 0.2 s while it moves:
/// on its path to round-off until then, then its vertices are unknowns like
/// the others, and with no external force the body's momentum stays what it
/// was at the release (backward Euler conserves linear momentum).
fn a_released_region_lets_its_vertices_go<const D: usize>() {
    let v = Vector::<D>::from_fn(|k, _| [0.5, -0.25, 0.25][k]);
    let region = end::<D>(-1.0, 1e-9).moving(PinMotion {
        velocity: v,
        release: Some(0.2),
        ..PinMotion::default()
    });
    let mut sim = simulation(
        bar::<D>(2.0, 4),
        material(MaterialModel::NeoHookean, 50.0, 0.3),
        vec![region],
        0.01,
        IntegratorKind::BackwardEuler,
    );
    let pinned = pinned_vertices(&sim);
    assert!(!pinned.is_empty());
    let momentum = |sim: &Simulation<D>| -> Vector<D> {
        sim.velocities()
            .iter()
            .zip(sim.masses())
            .fold(Vector::<D>::zeros(), |p, (v, m)| p + v * *m)
    };
    for step in 1..=20 {
        sim.step().unwrap();
        for &(vertex, rest) in &pinned {
            let expected = rest + v * sim.time();
            assert!(
                (sim.positions()[vertex] - expected).amax() <= round_off(2.0),
                "step {step}"
            );
        }
    }
    assert!(
        sim.free_index().iter().any(Option::is_none),
        "held until t = 0.2"
    );
    sim.step().unwrap();
    assert!(
        sim.free_index().iter().all(Option::is_some),
        "released at t = 0.2"
    );
    let at_release = momentum(&sim);
    // The end was pulled: the body is not yet moving rigidly with v.
    let released_end = sim.positions()[pinned[0].0] - pinned[0].1;
    assert!(released_end.amax() > 0.0);
    for _ in 0..50 {
        assert!(sim.step().unwrap().solver.converged);
        let drift = (momentum(&sim) - at_release).amax();
        assert!(drift < 1e-8 * at_release.amax(), "momentum drift {drift}");
    }
    // The released vertices moved off the path they would have followed.
    let (vertex, rest) = pinned[0];
    let on_path = rest + v * sim.time();
    assert!((sim.positions()[vertex] - on_path).amax() > 1e-6);
}
