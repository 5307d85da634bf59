//! The same scene gives bitwise the same positions whatever the thread count.

use crate::support::*;
use elasto::math::Vector;
use elasto::mesh::Mesh;
use elasto::sim::{Effects, Ground, Simulation, SimulationSettings};

fn run<const D: usize>(threads: usize, cells: [usize; D]) -> Vec<Vector<D>> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| simulate(cells))
}

/// Eight steps of a box falling onto the ground, on the calling thread's pool.
fn simulate<const D: usize>(cells: [usize; D]) -> Vec<Vector<D>> {
    let min = Vector::<D>::from_fn(|k, _| if k == 1 { 0.05 } else { 0.0 });
    let mesh = Mesh::axis_aligned_box(min, min + Vector::<D>::from_element(1.0), cells).unwrap();
    let effects = Effects {
        gravity: Some(Vector::<D>::from_fn(
            |k, _| if k == 1 { -9.81 } else { 0.0 },
        )),
        ground: Some(Ground {
            height: 0.0,
            activation_distance: 0.1,
            stiffness: None,
            friction: 0.0,
        }),
        contact: None,
        pinned: Vec::new(),
        obstacles: Vec::new(),
    };
    let velocity = Vector::<D>::from_fn(|k, _| if k == 0 { 1.0 } else { -2.0 });
    let mut sim = Simulation::new(
        mesh,
        neo_hookean(),
        1.0,
        effects,
        SimulationSettings {
            dt: 0.01,
            ..Default::default()
        },
        velocity,
    )
    .unwrap();
    for _ in 0..8 {
        sim.step().unwrap();
    }
    sim.positions().to_vec()
}

#[test]
fn one_and_two_threads_give_identical_positions_2d() {
    // 2 * 24 * 24 = 1152 triangles: enough for the work to be split across threads.
    let one = run::<2>(1, [24, 24]);
    let two = run::<2>(2, [24, 24]);
    assert!(one.iter().zip(&two).all(|(a, b)| {
        a.iter()
            .zip(b.iter())
            .all(|(x, y)| x.to_bits() == y.to_bits())
    }));
}

#[test]
fn one_and_two_threads_give_identical_positions_3d() {
    // 6 * 6^3 = 1296 tetrahedra.
    let one = run::<3>(1, [6, 6, 6]);
    let two = run::<3>(2, [6, 6, 6]);
    assert!(one.iter().zip(&two).all(|(a, b)| {
        a.iter()
            .zip(b.iter())
            .all(|(x, y)| x.to_bits() == y.to_bits())
    }));
}

#[test]
fn one_and_two_threads_give_identical_positions_on_a_large_mesh() {
    // 2 * 64 * 64 = 8192 triangles, about 45 000 stored matrix entries: the
    // element pass, the gradient scatter and the matrix gather all run in
    // parallel (above their sequential thresholds) with two threads.
    let one = run::<2>(1, [64, 64]);
    let two = run::<2>(2, [64, 64]);
    assert!(one.iter().zip(&two).all(|(a, b)| {
        a.iter()
            .zip(b.iter())
            .all(|(x, y)| x.to_bits() == y.to_bits())
    }));
}

#[test]
fn a_step_called_from_outside_the_pool_gives_the_same_positions() {
    // The test thread is not one of rayon's: a step of a large mesh moves to
    // the global pool's threads (and back); a step inside a one-thread pool
    // stays where it is. Both give the same bits.
    let outside = simulate::<2>([24, 24]);
    let one = run::<2>(1, [24, 24]);
    assert!(outside.iter().zip(&one).all(|(a, b)| {
        a.iter()
            .zip(b.iter())
            .all(|(x, y)| x.to_bits() == y.to_bits())
    }));
}

/// Steps of a box dropped onto a wider one (3D, contact on) until many
/// stencils are active (above the contact term's parallel threshold),
/// on a pool of `threads`.
fn contact_run(threads: usize) -> (Vec<Vector<3>>, usize) {
    use elasto::sim::{Body, Contact};
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let block = |low: Vector<3>, size: Vector<3>, cells: [usize; 3]| {
            Mesh::axis_aligned_box(low, low + size, cells).unwrap()
        };
        let lower = block(
            Vector::<3>::new(0.0, 0.05, 0.0),
            Vector::<3>::new(1.0, 0.3, 1.0),
            [8, 2, 8],
        );
        let upper = block(
            Vector::<3>::new(0.1, 0.37, 0.1),
            Vector::<3>::new(0.8, 0.3, 0.8),
            [6, 2, 6],
        );
        let body = |mesh: Mesh<3>, velocity: Vector<3>| Body {
            mesh,
            material: neo_hookean(),
            density: 1.0,
            velocity,
            pinned: None,
        };
        let effects = Effects {
            gravity: Some(Vector::<3>::new(0.0, -9.81, 0.0)),
            ground: Some(Ground {
                height: 0.0,
                activation_distance: 0.02,
                stiffness: None,
                friction: 0.0,
            }),
            contact: Some(Contact {
                distance: Some(0.005),
                stiffness: None,
                self_contact: true,
                friction: 0.0,
            }),
            pinned: Vec::new(),
            obstacles: Vec::new(),
        };
        let mut sim = Simulation::with_bodies(
            vec![
                body(lower, Vector::<3>::zeros()),
                body(upper, Vector::<3>::new(0.0, -1.0, 0.0)),
            ],
            effects,
            SimulationSettings {
                dt: 0.01,
                ..Default::default()
            },
        )
        .unwrap();
        let mut most_pairs = 0;
        for _ in 0..6 {
            let frame = sim.advance_frame(1).unwrap();
            most_pairs = most_pairs.max(frame.contact.unwrap().active_pairs);
        }
        (sim.positions().to_vec(), most_pairs)
    })
}

#[test]
fn one_and_two_threads_give_identical_positions_with_contact() {
    let (one, pairs) = contact_run(1);
    let (two, _) = contact_run(2);
    // The contact term computes its stencils' derivatives in parallel from 64 on.
    assert!(pairs >= 64, "only {pairs} stencils were active");
    assert!(one.iter().zip(&two).all(|(a, b)| {
        a.iter()
            .zip(b.iter())
            .all(|(x, y)| x.to_bits() == y.to_bits())
    }));
}
