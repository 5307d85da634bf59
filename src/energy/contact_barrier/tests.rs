//! Tests of `contact_barrier`.

use super::*;

#[test]
fn adaptive_stiffness_matches_ipctk() {
    // ipctk 1.6.1 reference script (/work/scratch/kappa/kappa_reference.py):
    // # Reference values of ipctk's adaptive barrier stiffness for elasto's
    // # contact_barrier.rs tests. Run: /work/scratch/venv/bin/python kappa_reference.py
    // # ipctk 1.6.1 Python signatures (help()):
    // #   initial_barrier_stiffness(bbox_diagonal, barrier, dhat, average_mass,
    // #       grad_energy, grad_barrier, min_barrier_stiffness_scale=1e11, dmin=0)
    // #       -> (kappa, max_barrier_stiffness)
    // #   update_barrier_stiffness(prev_min_distance, min_distance,
    // #       max_barrier_stiffness, barrier_stiffness, bbox_diagonal,
    // #       dhat_epsilon_scale=1e-9, dmin=0) -> kappa
    // # Distances in update_barrier_stiffness are squared (IPC convention).
    // import numpy as np
    // import ipctk
    //
    // print("ipctk", ipctk.__version__)
    // barrier = ipctk.ClampedLogBarrier()
    // base = np.array([0.3, -1.2, 0.7, 0.05, -0.4, 2.1, -0.9, 0.6, 1.5, -0.25, 0.8, -1.1])
    //
    // cases = {
    //     # name: (bbox_diagonal, dhat, average_mass, grad_energy, grad_barrier)
    //     "zero_barrier_gradient": (1.0, 1e-3, 1.0,
    //         np.array([1.0, -2.0, 3.0, -4.0, 5.0, -6.0, 7.0, -8.0, 9.0, -10.0, 11.0, -12.0]),
    //         np.zeros(12)),
    //     "below_min": (2.5, 2e-3, 0.37,
    //         np.array([-0.31, 1.17, -0.72, -0.04, 0.43, -2.08, 0.88, -0.61, -1.52, 0.27, -0.79, 1.13]),
    //         base * 1e-3),
    //     "inside": (10.0, 0.05, 4.2,
    //         np.array([-900.0, 3650.5, -2080.0, -160.0, 1210.0, -6300.0, 2705.0, -1790.0, -4500.0, 760.0, -2395.0, 3300.0]),
    //         base.copy()),
    //     "above_max": (0.3, 1e-4, 1e-3,
    //         np.array([-3.1e3, 1.19e4, -7.0e3, -4.0e2, 4.1e3, -2.1e4, 9.2e3, -5.9e3, -1.5e4, 2.4e3, -8.1e3, 1.12e4]),
    //         base * 1e-6),
    // }
    // for name, (L, dhat, m, ge, gb) in cases.items():
    //     kappa, kmax = ipctk.initial_barrier_stiffness(L, barrier, dhat, m, ge, gb)
    //     nb = gb.dot(gb)
    //     ratio = float(-gb.dot(ge) / nb) if nb > 0 else float("nan")
    //     print(f"initial {name}: L={L!r} dhat={dhat!r} m={m!r}")
    //     print(f"  kappa={kappa!r} kappa_max={kmax!r} balance={ratio!r}")
    //     print(f"  grad_energy={[float(v) for v in ge]!r}")
    //     print(f"  grad_barrier={[float(v) for v in gb]!r}")
    //
    // # update_barrier_stiffness: L = 1e6 (threshold distance 1e-9 L = 1e-3),
    // # dhat = 0.1, average mass 1; kappa, kappa_max from initial_barrier_stiffness.
    // L, dhat = 1e6, 0.1
    // kmin, kmax = ipctk.initial_barrier_stiffness(L, barrier, dhat, 1.0, np.zeros(12), np.zeros(12))
    // print(f"update setup: L={L!r} dhat={dhat!r} kappa_min={kmin!r} kappa_max={kmax!r}")
    // updates = {
    //     "doubles": ((6e-4) ** 2, (4e-4) ** 2, kmin),
    //     "capped": ((6e-4) ** 2, (4e-4) ** 2, 0.75 * kmax),
    //     "unchanged": ((4e-4) ** 2, (6e-4) ** 2, kmin),
    // }
    // for name, (prev, cur, kappa) in updates.items():
    //     new = ipctk.update_barrier_stiffness(prev, cur, kmax, kappa, L)
    //     print(f"update {name}: prev_min_distance={prev!r} min_distance={cur!r} kappa={kappa!r} -> {new!r}")

    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs();

    // initial_barrier_stiffness: (bbox_diagonal, dhat, average_mass,
    // grad_energy, grad_barrier, ipctk kappa, ipctk kappa_max).
    let cases = [
        (
            "zero_barrier_gradient",
            1.0,
            0.001,
            1.0,
            [
                1.0, -2.0, 3.0, -4.0, 5.0, -6.0, 7.0, -8.0, 9.0, -10.0, 11.0, -12.0,
            ],
            [0.0; 12],
            2499999.999500001,
            249999999.95000008,
        ),
        (
            "below_min",
            2.5,
            0.002,
            0.37,
            [
                -0.31, 1.17, -0.72, -0.04, 0.43, -2.08, 0.88, -0.61, -1.52, 0.27, -0.79, 1.13,
            ],
            [
                0.0003,
                -0.0012,
                0.0007,
                5e-05,
                -0.0004,
                0.0021000000000000003,
                -0.0009000000000000001,
                0.0006,
                0.0015,
                -0.00025,
                0.0008,
                -0.0011,
            ],
            361328.12488708494,
            36132812.488708496,
        ),
        (
            "inside",
            10.0,
            0.05,
            4.2,
            [
                -900.0, 3650.5, -2080.0, -160.0, 1210.0, -6300.0, 2705.0, -1790.0, -4500.0, 760.0,
                -2395.0, 3300.0,
            ],
            [
                0.3, -1.2, 0.7, 0.05, -0.4, 2.1, -0.9, 0.6, 1.5, -0.25, 0.8, -1.1,
            ],
            3004.033542976939,
            16799.99999986559,
        ),
        (
            "above_max",
            0.3,
            0.0001,
            0.001,
            [
                -3100.0, 11900.0, -7000.0, -400.0, 4100.0, -21000.0, 9200.0, -5900.0, -15000.0,
                2400.0, -8100.0, 11200.0,
            ],
            [
                3e-07, -1.2e-06, 7e-07, 5e-08, -4e-07, 2.1e-06, -9e-07, 6e-07, 1.5e-06, -2.5e-07,
                8e-07, -1.1e-06,
            ],
            224999999.595,
            224999999.595,
        ),
    ];
    let square =
        crate::mesh::Mesh::axis_aligned_box(Vector::<2>::zeros(), Vector::<2>::repeat(1.0), [1, 1])
            .unwrap();
    for (name, diagonal, dhat, mass, grad_energy, grad_barrier, kappa_ref, max_ref) in cases {
        let settings = ContactSettings {
            activation_distance: dhat,
            stiffness: None,
            self_contact: true,
        };
        let term = ContactBarrier::<2>::new(
            CollisionMesh::new(&square, &[0; 4]),
            settings,
            &[mass; 4],
            diagonal,
            square.rest_positions(),
        );
        let (min, max) = term.stiffness_bounds(1.0);
        assert!(
            close(max, max_ref),
            "{name}: kappa_max {max:e} vs ipctk {max_ref:e}"
        );
        // `balance_stiffness` with weight 1.
        let dot: f64 = grad_barrier
            .iter()
            .zip(&grad_energy)
            .map(|(b, e)| b * e)
            .sum();
        let norm_squared: f64 = grad_barrier.iter().map(|b| b * b).sum();
        let balanced = if norm_squared > 0.0 {
            -dot / norm_squared
        } else {
            1.0
        };
        let kappa = if balanced.is_finite() {
            balanced.clamp(min, max)
        } else {
            min
        };
        assert!(
            close(kappa, kappa_ref),
            "{name}: kappa {kappa:e} vs ipctk {kappa_ref:e}"
        );
        // In these two cases ipctk returns kappa_min itself.
        if name == "zero_barrier_gradient" || name == "below_min" {
            assert!(
                close(min, kappa_ref),
                "{name}: kappa_min {min:e} vs ipctk {kappa_ref:e}"
            );
            assert!(close(term.stiffness(), kappa_ref), "{name}: initial kappa");
        }
    }

    // update_barrier_stiffness through `begin_step` + `begin_iteration`:
    // L = 1e6 (threshold distance 1e-9 L = 1e-3), d_hat = 0.1, masses 1, a
    // vertex of body 1 above an edge of body 0 at height h (distance^2 h^2).
    let at = |h: f64| {
        vec![
            Vector::<2>::new(0.0, 0.0),
            Vector::<2>::new(0.5, -1.0),
            Vector::<2>::new(1.0, 0.0),
            Vector::<2>::new(0.5, h),
            Vector::<2>::new(1.0, 1.0),
            Vector::<2>::new(0.0, 1.0),
        ]
    };
    let (far, near) = (at(6e-4), at(4e-4));
    let pair = crate::mesh::Mesh::new(far.clone(), vec![vec![0, 1, 2], vec![3, 4, 5]]).unwrap();
    let settings = ContactSettings {
        activation_distance: 0.1,
        stiffness: None,
        self_contact: true,
    };
    let make = || {
        ContactBarrier::<2>::new(
            CollisionMesh::new(&pair, &[0, 0, 0, 1, 1, 1]),
            settings,
            &[1.0; 6],
            1e6,
            &far,
        )
    };
    let (min_ref, max_ref) = (24494890038.77304, 2449489003877.304);
    // (name, from, to, kappa before: None = kappa_min, Some(f) = f kappa_max, ipctk's result)
    let updates = [
        (
            "doubles",
            far.as_slice(),
            near.as_slice(),
            None,
            48989780077.54608,
        ),
        (
            "capped",
            far.as_slice(),
            near.as_slice(),
            Some(0.75),
            2449489003877.304,
        ),
        (
            "unchanged",
            near.as_slice(),
            far.as_slice(),
            None,
            24494890038.77304,
        ),
    ];
    for (name, from, to, start, expected) in updates {
        let mut term = make();
        assert!(
            close(term.stiffness(), min_ref),
            "{name}: kappa_min {:e}",
            term.stiffness()
        );
        assert!(
            close(term.max_stiffness, max_ref),
            "{name}: kappa_max {:e}",
            term.max_stiffness
        );
        if let Some(fraction) = start {
            term.stiffness = fraction * term.max_stiffness;
        }
        let before = term.stiffness();
        term.begin_step(from, from);
        let changed = term.begin_iteration(to);
        let distance = term.min_distance(to).expect("the pair is active");
        assert!(
            (distance - to[3].y).abs() < 1e-12,
            "{name}: distance {distance:e}"
        );
        assert!(
            close(term.stiffness(), expected),
            "{name}: kappa {:e} vs ipctk {expected:e}",
            term.stiffness()
        );
        assert_eq!(changed, term.stiffness() != before, "{name}: changed");
    }
}
