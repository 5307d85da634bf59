use super::*;
use crate::contact::friction::normal_force;
use crate::contact::{ContactStencil, StencilKind};
use crate::math::Vector2;
use crate::mesh::Mesh;

const SETTINGS: FrictionSettings = FrictionSettings {
    contact: 0.4,
    ground: 0.7,
    velocity_threshold: 0.05,
};

/// Two triangles, vertex 3 of the upper one 0.03 above edge 1-2 of the
/// lower one, and vertex 0 0.02 above the ground at 0.
fn pair() -> (Mesh<2>, Vec<Vector2>) {
    let x = vec![
        Vector2::new(0.0, 0.02),
        Vector2::new(1.0, 0.5),
        Vector2::new(-0.2, 0.5),
        Vector2::new(0.3, 0.53),
        Vector2::new(1.1, 1.2),
        Vector2::new(-0.1, 1.3),
    ];
    let mesh = Mesh::new(x.clone(), vec![vec![0, 1, 2], vec![3, 4, 5]]).unwrap();
    (mesh, x)
}

/// The term lagged at `start`: the point-edge stencil (3; 1, 2) with its
/// barrier's normal force and the ground vertex 0 with a given one.
fn lagged(start: &[Vector2], dt: f64) -> Friction<2> {
    let contact = ContactStencil {
        kind: StencilKind::PointEdge,
        vertices: [3, 1, 2, 0],
        mollifier_threshold: 0.0,
    };
    let lambda = normal_force(&contact, start, 0.1 * 0.1, 10.0);
    assert!(lambda > 0.0, "the pair is within d_hat");
    let stencils = vec![
        FrictionStencil::of_contact(&contact, start, start, SETTINGS.contact * lambda).unwrap(),
        FrictionStencil::vertex_on_plane(0, start, Vector2::new(0.0, 1.0), SETTINGS.ground * 2.5),
    ];
    let mut friction = Friction::new(SETTINGS);
    friction.lag(stencils, dt);
    friction
}

/// Moves every vertex of `x` by `scale` times a fixed pattern of slips.
fn slid(x: &[Vector2], scale: f64) -> Vec<Vector2> {
    x.iter()
        .enumerate()
        .map(|(i, p)| p + Vector2::new(0.013 * (i as f64 - 2.5), 0.004 * i as f64) * scale)
        .collect()
}

#[test]
fn the_term_has_the_gradient_and_hessian_of_its_value() {
    let (mesh, start) = pair();
    let friction = lagged(&start, 0.5);
    let mut hessian = SparseHessian::new(&mesh, (0..6).map(Some).collect()).unwrap();
    let mut pairs = Vec::new();
    friction.coupled_pairs(&mut pairs);
    assert_eq!(pairs.len(), 3, "one point-edge stencil: three pairs");
    hessian.include_pairs(pairs).unwrap();
    // Within the slip threshold (static, smoothed) and beyond it (sliding).
    for scale in [0.3, 4.0] {
        let x = slid(&start, scale);
        let mut gradient = vec![Vector2::zeros(); 6];
        hessian.clear();
        friction.add_gradient_and_hessian(&x, 1.0, &mut gradient, &mut hessian);
        let h = 1e-6;
        let dense = hessian.to_dense();
        for v in 0..6 {
            for k in 0..2 {
                let shifted = |delta: f64| {
                    let mut y = x.clone();
                    y[v][k] += delta;
                    y
                };
                let fd = (friction.value(&shifted(h)) - friction.value(&shifted(-h))) / (2.0 * h);
                assert!(
                    (fd - gradient[v][k]).abs() <= 1e-6 * (1.0 + fd.abs()),
                    "scale {scale}: dD/dx[{v}][{k}] = {} against {fd}",
                    gradient[v][k]
                );
                let mut plus = vec![Vector2::zeros(); 6];
                let mut minus = vec![Vector2::zeros(); 6];
                friction.add_gradient(&shifted(h), 1.0, &mut plus);
                friction.add_gradient(&shifted(-h), 1.0, &mut minus);
                for w in 0..6 {
                    for j in 0..2 {
                        let fd = (plus[w][j] - minus[w][j]) / (2.0 * h);
                        let exact = dense[(w * 2 + j, v * 2 + k)];
                        assert!(
                            (fd - exact).abs() <= 1e-5 * (1.0 + fd.abs()),
                            "scale {scale}: H[{w}{j}][{v}{k}] = {exact} against {fd}"
                        );
                    }
                }
            }
        }
        // The force is the negative gradient; friction took work out.
        let forces = friction.forces(&x);
        for (f, g) in forces.iter().zip(&gradient) {
            assert_eq!(*f, -*g);
        }
        assert!(friction.dissipated(&x) > 0.0);
    }
    // At the start nothing slipped (up to the round-off of `sum w_a x_a`):
    // no force, no work.
    assert!(friction.dissipated(&start) < 1e-30);
    assert!(friction.forces(&start).iter().all(|f| f.norm() < 1e-12));
}

#[test]
fn a_step_twice_as_long_doubles_the_slip_threshold() {
    let (_, start) = pair();
    let x = slid(&start, 1.0);
    let (short, long) = (lagged(&start, 0.5), lagged(&start, 1.0));
    // Ground vertex 0 slides by 0.0325: beyond the short step's threshold
    // (eps = 0.05 x 0.5) and within the long one's (0.05 x 1).
    let slip = (x[0] - start[0]).x.abs();
    assert!(0.025 < slip && slip < 0.05, "slip {slip}");
    let ground = |f: &Friction<2>| f.stencils()[1].potential(&x, f.slip_threshold);
    assert!((ground(&short) - SETTINGS.ground * 2.5 * slip).abs() < 1e-15);
    assert!(ground(&long) > SETTINGS.ground * 2.5 * slip);
}
