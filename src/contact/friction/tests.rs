//! Friction on a stencil: the mollifier and the whole potential against the
//! IPC toolkit (ipctk 1.6.1, numbers stored below), finite differences of
//! the gradient and Hessian for every stencil kind on both sides of the
//! slip threshold, the Hessian's definiteness, Coulomb's law in full slip,
//! and the scaling with the time step.

use super::*;
use crate::contact::distance::StencilDerivatives;
use crate::contact::distance::test_support::{Rng, check_finite_differences};
use nalgebra::{SMatrix, SVector};

/// The reference cases' barrier: `d_hat`, `kappa`, and the friction's `mu`, `eps_v`.
const DHAT: f64 = 0.1;
const KAPPA: f64 = 10.0;
const MU: f64 = 0.4;
const EPS_V: f64 = 0.05;

#[test]
fn the_mollifier_matches_the_ipc_toolkit() {
    // ipctk.smooth_friction_f0 / f1 / f1_over_x (y, eps_v = 0.05).
    let reference = [
        (0.0, 0.016666666666666666, 0.0, f64::NAN),
        (0.01, 0.018533333333333332, 0.36, 36.0),
        (0.03, 0.031066666666666666, 0.84, 27.999999999999996),
        (0.05, 0.05, 1.0, 20.0),
        (0.2, 0.2, 1.0, 5.0),
    ];
    for (y, f0, f1, f1_over_y) in reference {
        assert!((friction_f0(y, EPS_V) - f0).abs() < 1e-15, "f0({y})");
        assert!((friction_f1(y, EPS_V) - f1).abs() < 1e-15, "f1({y})");
        if y > 0.0 {
            assert!((friction_f1_over_y(y, EPS_V) - f1_over_y).abs() < 1e-12);
        }
    }
    // f1 = f0' and f2 y = (f1' y - f1) / y^2, by central differences, on
    // both sides of eps.
    let h = 1e-7;
    for y in [0.004, 0.021, 0.049, 0.051, 0.3] {
        let df0 = (friction_f0(y + h, EPS_V) - friction_f0(y - h, EPS_V)) / (2.0 * h);
        assert!((df0 - friction_f1(y, EPS_V)).abs() < 1e-7, "f0' at {y}");
        let df1 = (friction_f1(y + h, EPS_V) - friction_f1(y - h, EPS_V)) / (2.0 * h);
        let f2_y = (df1 * y - friction_f1(y, EPS_V)) / (y * y);
        assert!(
            (f2_y - friction_f2_times_y(y, EPS_V)).abs() < 1e-5 * f2_y.abs(),
            "f2 at {y}"
        );
    }
}

/// A contact stencil over vertices `0..count` of `kind`.
fn stencil(kind: StencilKind) -> ContactStencil {
    ContactStencil {
        kind,
        vertices: [0, 1, 2, 3],
        mollifier_threshold: 0.0,
    }
}

/// The friction stencil of `kind` with its start `start` and force from
/// the reference barrier (`mu lambda`).
fn frozen<const D: usize>(kind: StencilKind, start: &[Vector<D>]) -> FrictionStencil<D> {
    let contact = stencil(kind);
    let lambda = normal_force(&contact, start, DHAT * DHAT, KAPPA);
    FrictionStencil::of_contact(&contact, start, start, MU * lambda).expect("the pair is apart")
}

/// `x = start + u` for the velocities `u` (dt = 1).
fn moved<const D: usize>(start: &[Vector<D>], u: &[Vector<D>]) -> Vec<Vector<D>> {
    start.iter().zip(u).map(|(x, u)| x + u).collect()
}

fn assert_close(actual: f64, expected: f64, what: &str) {
    assert!(
        (actual - expected).abs() <= 1e-10 * expected.abs().max(1e-12),
        "{what}: {actual:e} vs the IPC toolkit's {expected:e}"
    );
}

/// Checks the stencil's potential and gradient at `start + u` against the
/// toolkit's (its potential of velocities `u`, with dt = 1 the same function).
fn check_reference<const D: usize>(
    kind: StencilKind,
    start: &[Vector<D>],
    u: &[Vector<D>],
    lambda: f64,
    value: f64,
    gradient: &[f64],
) {
    let contact = stencil(kind);
    assert_close(
        normal_force(&contact, start, DHAT * DHAT, KAPPA),
        lambda,
        "lambda",
    );
    let friction = frozen(kind, start);
    let x = moved(start, u);
    let d = friction.derivatives(&x, EPS_V);
    assert_close(friction.potential(&x, EPS_V), value, "potential");
    assert_close(d.value, value, "derivatives' value");
    for (a, w) in friction.weights[..friction.count].iter().enumerate() {
        for k in 0..D {
            assert_close(w * d.gradient[k], gradient[a * D + k], "gradient");
        }
    }
}

#[test]
fn point_edge_friction_matches_the_ipc_toolkit() {
    // ipctk: CollisionMesh(V, E = [[1, 2]]), NormalCollisions.build(dhat =
    // 0.1), TangentialCollisions.build(mesh, V, collisions,
    // BarrierPotential(0.1, 10), mu = 0.4), FrictionPotential(0.05) and its
    // gradient at the velocities U.
    let start = [
        Vector2::new(0.3, 0.04),
        Vector2::new(-0.5, 0.0),
        Vector2::new(0.6, 0.01),
    ];
    let lambda = 0.07483621635586557;
    // Full slip (|u| > eps_v).
    let u = [
        Vector2::new(0.03, -0.01),
        Vector2::new(-0.01, 0.0),
        Vector2::new(0.005, 0.002),
    ];
    let gradient = [
        0.02464372593343457,
        0.00022403387212213243,
        -0.006714351243908255,
        -6.103955676280231e-05,
        -0.017929374689526316,
        -0.0001629943153593301,
    ];
    check_reference(
        StencilKind::PointEdge,
        &start,
        &u,
        lambda,
        0.0009046076342107098,
        &gradient,
    );
    // Static friction (|u| < eps_v).
    let u = [
        Vector2::new(0.01, -0.01),
        Vector2::new(-0.002, 0.0),
        Vector2::new(0.001, 0.002),
    ];
    let gradient = [
        0.010499914576029057,
        9.545376887299142e-05,
        -0.0028607733540341965,
        -2.6007030491219962e-05,
        -0.007639141221994861,
        -6.944673838177146e-05,
    ];
    check_reference(
        StencilKind::PointEdge,
        &start,
        &u,
        lambda,
        0.0005517307668280477,
        &gradient,
    );
}

#[test]
fn point_triangle_friction_matches_the_ipc_toolkit() {
    // As above with F = [[1, 2, 3]] (a face-vertex collision).
    let start = [
        Vector3::new(0.2, 0.05, 0.25),
        Vector3::new(0.0, 0.0, 0.0),
        Vector3::new(1.0, 0.02, 0.0),
        Vector3::new(0.0, 0.01, 1.0),
    ];
    let u = [
        Vector3::new(0.06, -0.01, 0.03),
        Vector3::new(0.0, 0.0, -0.01),
        Vector3::new(0.01, 0.0, 0.0),
        Vector3::new(0.0, 0.002, 0.0),
    ];
    let gradient = [
        0.018323041942279388,
        0.00047867139908102963,
        0.01122105602354418,
        -0.010053773448328952,
        -0.00026264491549576495,
        -0.006156944652918589,
        -0.0036805414684056865,
        -9.615051581540683e-05,
        -0.0022539686447293093,
        -0.004588727025544752,
        -0.00011987596776985785,
        -0.002810142725896282,
    ];
    check_reference(
        StencilKind::PointTriangle,
        &start,
        &u,
        0.05372819852102483,
        0.0014557517631618674,
        &gradient,
    );
}

#[test]
fn edge_edge_friction_matches_the_ipc_toolkit() {
    // As above with E = [[0, 1], [2, 3]] and no faces (an edge-edge
    // collision; the toolkit lists it as edges (2, 3), (0, 1), the gradient
    // is over the vertices in order).
    let start = [
        Vector3::new(-0.5, 0.05, 0.1),
        Vector3::new(0.5, 0.06, -0.1),
        Vector3::new(0.1, 0.0, -0.5),
        Vector3::new(-0.1, 0.01, 0.5),
    ];
    let u = [
        Vector3::new(0.02, -0.01, 0.03),
        Vector3::new(0.01, 0.0, 0.0),
        Vector3::new(-0.01, 0.0, 0.0),
        Vector3::new(0.0, 0.002, -0.01),
    ];
    let gradient = [
        0.0049628179615904345,
        0.00012416774452981988,
        0.004970601600795159,
        0.004947338180050853,
        0.00012378044651194776,
        0.00495509754090497,
        -0.004947338180050853,
        -0.00012378044651194776,
        -0.0049550975409049704,
        -0.0049628179615904345,
        -0.00012416774452981988,
        -0.004970601600795159,
    ];
    check_reference(
        StencilKind::EdgeEdge,
        &start,
        &u,
        0.04330622100642059,
        0.0005123629802396973,
        &gradient,
    );
}

/// The stencil's potential and derivatives over its stacked coordinates
/// (`N = count D`), with the blocks `w_a g` and `w_a w_b H`.
fn stacked<const D: usize, const N: usize>(
    friction: &FrictionStencil<D>,
    y: &SVector<f64, N>,
    eps: f64,
) -> StencilDerivatives<N> {
    let x: Vec<Vector<D>> = (0..N / D)
        .map(|a| y.fixed_rows::<D>(a * D).into_owned())
        .collect();
    let d = friction.derivatives(&x, eps);
    let mut out = StencilDerivatives::<N>::constant(d.value);
    for a in 0..N / D {
        let wa = friction.weights[a];
        out.gradient
            .fixed_rows_mut::<D>(a * D)
            .copy_from(&(d.gradient * wa));
        for b in 0..N / D {
            let wb = friction.weights[b];
            out.hessian
                .fixed_view_mut::<D, D>(a * D, b * D)
                .copy_from(&(d.hessian * (wa * wb)));
        }
    }
    out
}

fn check_kind<const D: usize, const N: usize>(
    kind: StencilKind,
    start: &[Vector<D>],
    rng: &mut Rng,
) {
    // A unit force, so that the checks' error (relative to the largest
    // entry or 1) is not met by smallness alone.
    let friction = FrictionStencil {
        force: 1.0,
        ..frozen(kind, start)
    };
    let stack = |x: &[Vector<D>]| SVector::<f64, N>::from_fn(|i, _| x[i / D][i % D]);
    // Slips well below, near and above eps (the mollifier's two pieces).
    for scale in [0.003, 0.03, 0.2] {
        let u: Vec<Vector<D>> = (0..N / D)
            .map(|_| Vector::<D>::from_fn(|_, _| rng.uniform(-scale, scale)))
            .collect();
        let y = stack(&moved(start, &u));
        let value = |y: &SVector<f64, N>| stacked(&friction, y, EPS_V).value;
        let d = check_finite_differences(&y, value, |y| stacked(&friction, y, EPS_V), 1e-7, 1e-5);
        let dense = nalgebra::DMatrix::from_fn(N, N, |i, j| d.hessian[(i, j)]);
        let smallest = dense.symmetric_eigen().eigenvalues.min();
        assert!(
            smallest > -1e-12 * friction.force * 2.0 / EPS_V,
            "{kind:?}: the Hessian has eigenvalue {smallest:e} (largest entry {:e})",
            d.hessian.amax()
        );
    }
}

#[test]
fn derivatives_match_finite_differences_and_the_hessian_is_psd() {
    let mut rng = Rng::new(11);
    for _ in 0..20 {
        let p = Vector2::new(rng.uniform(-0.4, 0.4), rng.uniform(0.01, 0.09));
        let start = [
            p,
            Vector2::new(-0.5, 0.0),
            Vector2::new(0.5, rng.uniform(-0.02, 0.02)),
        ];
        check_kind::<2, 6>(StencilKind::PointEdge, &start, &mut rng);
        let p = Vector3::new(
            rng.uniform(0.1, 0.4),
            rng.uniform(0.01, 0.09),
            rng.uniform(0.1, 0.4),
        );
        let triangle = [
            Vector3::zeros(),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.0, 0.0, 1.0),
        ];
        let start = [p, triangle[0], triangle[1], triangle[2]];
        check_kind::<3, 12>(StencilKind::PointTriangle, &start, &mut rng);
        let lift = rng.uniform(0.01, 0.09);
        let start = [
            Vector3::new(-0.5, lift, rng.uniform(-0.2, 0.2)),
            Vector3::new(0.5, lift, rng.uniform(-0.2, 0.2)),
            Vector3::new(rng.uniform(-0.2, 0.2), 0.0, -0.5),
            Vector3::new(rng.uniform(-0.2, 0.2), 0.0, 0.5),
        ];
        check_kind::<3, 12>(StencilKind::EdgeEdge, &start, &mut rng);
    }
}

#[test]
fn full_slip_is_coulombs_law_and_rest_costs_nothing() {
    let start = [Vector2::new(0.2, 0.05)];
    let ground = FrictionStencil::vertex_on_plane(0, &start, Vector2::new(0.0, 1.0), 3.0);
    // At rest: no force, the Hessian's stiffness 2 mu lambda / eps across
    // the normal, none along it.
    let d = ground.derivatives(&start, EPS_V);
    assert_eq!(d.gradient, Vector2::zeros());
    assert!(
        (d.hessian - SMatrix::<f64, 2, 2>::new(2.0 * 3.0 / EPS_V, 0.0, 0.0, 0.0)).amax() < 1e-12
    );
    assert_eq!(ground.dissipated(&start, EPS_V), 0.0);
    // Sliding by 0.5 along the plane (and 0.01 off it): force mu lambda
    // against the slip, work mu lambda 0.5; the normal motion does not count.
    let x = [start[0] + Vector2::new(-0.5, 0.01)];
    let d = ground.derivatives(&x, EPS_V);
    assert!(
        (d.gradient - Vector2::new(-3.0, 0.0)).amax() < 1e-12,
        "{:?}",
        d.gradient
    );
    assert!((ground.dissipated(&x, EPS_V) - 1.5).abs() < 1e-12);
    assert!((ground.potential(&x, EPS_V) - 1.5).abs() < 1e-12);
}

#[test]
fn the_potential_is_the_velocity_potential_times_dt() {
    // Over a step dt with the slip threshold eps_v dt, the potential of the
    // displacement dt v is dt times that of the velocity v (threshold eps_v):
    // the toolkit's velocity potential is this one per unit time.
    let start = [
        Vector3::new(0.2, 0.05, 0.25),
        Vector3::new(0.0, 0.0, 0.0),
        Vector3::new(1.0, 0.02, 0.0),
        Vector3::new(0.0, 0.01, 1.0),
    ];
    let friction = frozen(StencilKind::PointTriangle, &start);
    let v = [
        Vector3::new(0.03, -0.01, 0.01),
        Vector3::zeros(),
        Vector3::new(0.01, 0.0, 0.0),
        Vector3::zeros(),
    ];
    for dt in [1e-3, 0.01, 0.5] {
        let step: Vec<Vector3> = v.iter().map(|v| v * dt).collect();
        let per_step = friction.potential(&moved(&start, &step), EPS_V * dt);
        let per_time = friction.potential(&moved(&start, &v), EPS_V);
        assert!((per_step - dt * per_time).abs() < 1e-14, "dt = {dt}");
    }
}
