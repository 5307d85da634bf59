//! No heap per element or per iteration: a counting global allocator shows
//! that, after a warm-up, the Newton iteration's assembly (gradient and
//! projected Hessian of the elasticity, the gather) allocates nothing on a
//! small mesh and the same handful of times on a mesh 36x larger, for every
//! material in 2D and 3D (fixed corotated's SVD once allocated 468 times per
//! pass of a 3 x 3 square), and that a whole time step allocates a fixed
//! number of times whatever the mesh size.
//!
//! Everything runs in one test function: the process-wide counter is global,
//! and tests of one binary run on parallel threads. The sequential passes
//! are counted on the calling thread only: rayon's workers, still winding
//! down from an earlier parallel pass, may allocate in the window (seen once:
//! 4 allocations counted during a sequential pass under a concurrent build).

#[path = "integration/support/mod.rs"]
mod support;

use elasto::assembly::SparseHessian;
use elasto::contact::CollisionMesh;
use elasto::energy::{BodyElasticity, ContactBarrier, ContactSettings, Elasticity, EnergyTerm};
use elasto::material::Material;
use elasto::math::{Matrix, Vector};
use elasto::mesh::Mesh;
use elasto::sim::{Effects, Ground, Simulation, SimulationSettings};
use elasto::solver::{Projection, SolverSettings};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use support::*;

struct CountingAllocator;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

thread_local! {
    /// Allocations made by this thread (a `const` cell: reading it never allocates).
    static THREAD_ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn count_allocation() {
    ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
    // `try_with`: a thread being torn down no longer has its cell.
    let _ = THREAD_ALLOCATIONS.try_with(|count| count.set(count.get() + 1));
}

unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count_allocation();
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count_allocation();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

/// Allocations made by every thread while `work` runs.
fn allocations_of(work: impl FnOnce()) -> usize {
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    work();
    ALLOCATIONS.load(Ordering::SeqCst) - before
}

/// Allocations made by this thread while `work` runs: for work that runs
/// on the calling thread only.
fn allocations_on_this_thread(work: impl FnOnce()) -> usize {
    let before = THREAD_ALLOCATIONS.with(Cell::get);
    work();
    THREAD_ALLOCATIONS.with(Cell::get) - before
}

fn square(cells: usize) -> Mesh<2> {
    Mesh::axis_aligned_box(
        Vector::<2>::zeros(),
        Vector::<2>::from_element(1.0),
        [cells; 2],
    )
    .unwrap()
}

/// Allocations of one gradient-and-Hessian pass of the elasticity of an
/// `n x n` square (after a warm-up pass), single body and two bodies,
/// counted by `count` ([`allocations_of`] or [`allocations_on_this_thread`]).
fn assembly_allocations(cells: usize, count: fn(&mut dyn FnMut()) -> usize) -> (usize, usize) {
    let mesh = Arc::new(square(cells));
    let mut rng = Rng::new(7);
    let x = perturbed(mesh.rest_positions(), 0.02, &mut rng);
    let free = (0..mesh.vertex_count()).map(Some).collect();
    let mut hessian = SparseHessian::new(&mesh, free).unwrap();
    let mut gradient = vec![Vector::<2>::zeros(); mesh.vertex_count()];
    let elasticity = Elasticity::new(mesh.clone(), neo_hookean());
    let mut pass = || {
        hessian.clear();
        elasticity.add_gradient_and_hessian(&x, 1e-4, &mut gradient, &mut hessian);
    };
    pass();
    let single = count(&mut pass);

    // Two bodies, each the square: their slots fill the scene Hessian directly.
    let both = Mesh::new(
        mesh.rest_positions()
            .iter()
            .chain(mesh.rest_positions())
            .copied()
            .collect(),
        mesh.simplices()
            .chain(mesh.simplices())
            .enumerate()
            .map(|(e, s)| {
                let shift = if e < mesh.element_count() {
                    0
                } else {
                    mesh.vertex_count()
                };
                s.iter().map(|v| v + shift).collect()
            })
            .collect(),
    )
    .unwrap();
    let bodies =
        BodyElasticity::bodies(vec![(mesh.clone(), neo_hookean()), (mesh.clone(), stvk())])
            .unwrap();
    let x2: Vec<_> = x.iter().chain(&x).copied().collect();
    let free = (0..both.vertex_count()).map(Some).collect();
    let mut hessian = SparseHessian::new(&both, free).unwrap();
    let mut gradient = vec![Vector::<2>::zeros(); both.vertex_count()];
    let mut pass = || {
        hessian.clear();
        bodies.add_gradient_and_hessian(&x2, 1e-4, &mut gradient, &mut hessian);
    };
    pass();
    (single, count(&mut pass))
}

/// Allocations of one sequential gradient-and-Hessian pass (after a warm-up
/// pass) of a small `D`-dimensional box of `material`, some elements
/// stretched and some compressed (so both the positive definite path and the
/// projection in the SVD frame run): projected, unprojected (Newton with
/// projection on demand), and the answer of a Cholesky factorisation to an
/// indefinite matrix (the unprojected Hessian's usual failure, met each time
/// projection on demand falls back).
fn material_pass_allocations<const D: usize>(material: Material) -> [usize; 3] {
    let mesh = Arc::new(
        Mesh::axis_aligned_box(Vector::<D>::zeros(), Vector::<D>::from_element(1.0), [3; D])
            .unwrap(),
    );
    let mut rng = Rng::new(11);
    let x: Vec<Vector<D>> = perturbed(mesh.rest_positions(), 0.05, &mut rng)
        .iter()
        .map(|p| p * 0.8)
        .collect();
    let free = (0..mesh.vertex_count()).map(Some).collect();
    let mut hessian = SparseHessian::new(&mesh, free).unwrap();
    let mut gradient = vec![Vector::<D>::zeros(); mesh.vertex_count()];
    let elasticity = Elasticity::new(mesh.clone(), material);
    let mut pass = |project: bool| {
        hessian.clear();
        if project {
            elasticity.add_gradient_and_hessian(&x, 1e-4, &mut gradient, &mut hessian);
        } else {
            elasticity.add_gradient_and_unprojected_hessian(&x, 1e-4, &mut gradient, &mut hessian);
        }
    };
    pass(true);
    pass(false);
    let projected = allocations_on_this_thread(|| pass(true));
    let unprojected = allocations_on_this_thread(|| pass(false));
    // Minus the identity on every diagonal block: not positive definite.
    let minus_identity = -Matrix::<D>::identity();
    for v in 0..mesh.vertex_count() {
        hessian.add_vertex_block(v, &(minus_identity * 1e3));
    }
    let mut definite = true;
    let refused =
        allocations_on_this_thread(|| definite = hessian.factorise_if_positive_definite());
    assert!(!definite, "the matrix is indefinite");
    [projected, unprojected, refused]
}

/// Allocations of the 4th time step of the square dropping on the ground,
/// with the Hessian projected as `projection` says.
fn step_allocations(cells: usize, projection: Projection) -> (usize, usize) {
    let mesh = square(cells);
    let effects = Effects {
        gravity: Some(Vector::<2>::new(0.0, -9.81)),
        ground: Some(Ground {
            height: -0.02,
            activation_distance: 0.05,
            stiffness: None,
            friction: 0.0,
        }),
        contact: None,
        pinned: Vec::new(),
        obstacles: Vec::new(),
    };
    let settings = SimulationSettings {
        dt: 0.01,
        solver: SolverSettings {
            projection,
            ..Default::default()
        },
        ..Default::default()
    };
    let velocity = Vector::<2>::new(0.0, -1.0);
    let mut sim =
        Simulation::new(mesh, neo_hookean(), 1000.0, effects, settings, velocity).unwrap();
    for _ in 0..3 {
        sim.step().unwrap();
    }
    let mut iterations = 0;
    let count = allocations_of(|| iterations = sim.step().unwrap().solver.iterations);
    (count, iterations)
}

/// Allocations of one Newton iteration's contact work once the pattern
/// holds every pair: the active set at `x`, the pattern check, the
/// gradient and stencil Hessians, and the line search's swept candidates
/// with CCD. Two squares of 4 x 4 cells, one 0.002 above the other
/// (`d_hat` 0.005): 2D point-edge stencils.
fn contact_iteration_allocations() -> (usize, usize) {
    let lower = square(4);
    let n = lower.vertex_count();
    let positions: Vec<Vector<2>> = lower
        .rest_positions()
        .iter()
        .copied()
        .chain(
            lower
                .rest_positions()
                .iter()
                .map(|p| p + Vector::<2>::new(0.3, 1.002)),
        )
        .collect();
    let simplices = lower
        .simplices()
        .map(<[usize]>::to_vec)
        .chain(lower.simplices().map(|s| s.iter().map(|v| v + n).collect()))
        .collect();
    let mesh = Mesh::new(positions.clone(), simplices).unwrap();
    let owner: Vec<usize> = (0..2 * n).map(|v| v / n).collect();
    let settings = ContactSettings {
        activation_distance: 0.005,
        stiffness: Some(1e3),
        self_contact: true,
    };
    let masses = vec![1.0; 2 * n];
    let mut term = ContactBarrier::new(
        CollisionMesh::new(&mesh, &owner),
        settings,
        &masses,
        2.0,
        &positions,
    );
    let free = (0..2 * n).map(Some).collect();
    let mut hessian = SparseHessian::new(&mesh, free).unwrap();
    let mut gradient = vec![Vector::<2>::zeros(); 2 * n];
    let mut pairs = Vec::new();
    let dx: Vec<Vector<2>> = (0..2 * n)
        .map(|v| Vector::<2>::new(0.0, if v < n { 0.0 } else { -0.01 }))
        .collect();
    let mut iteration = || {
        term.begin_iteration(&positions);
        pairs.clear();
        term.coupled_pairs(&mut pairs);
        hessian.include_pairs(pairs.iter().copied()).unwrap();
        hessian.clear();
        term.add_gradient_and_hessian(&positions, 1e-4, &mut gradient, &mut hessian);
        let step = term.max_step(&positions, &dx);
        assert!(
            step > 0.0 && step < 1.0,
            "the step is capped by CCD: {step}"
        );
    };
    iteration();
    let count = allocations_of(iteration);
    (count, pairs.len())
}

#[test]
fn assembly_and_steps_allocate_independently_of_the_mesh_size() {
    // Contact: once the pattern holds its pairs, an iteration allocates nothing.
    let (contact, pairs) = contact_iteration_allocations();
    assert!(
        pairs > 0,
        "the squares are within d_hat: stencils are active"
    );
    assert_eq!(
        contact, 0,
        "a contact iteration with a stable pattern allocated"
    );

    // 200 triangles (below the parallel threshold) and 7200 (split across threads).
    let (small_single, small_bodies) =
        assembly_allocations(10, |pass| allocations_on_this_thread(pass));
    let (large_single, large_bodies) = assembly_allocations(60, |pass| allocations_of(pass));
    assert_eq!(
        (small_single, small_bodies),
        (0, 0),
        "a sequential assembly pass allocates nothing"
    );
    // Every material, in 2D and 3D: no heap in the element kernel (the SVD
    // and the projection are fixed-size).
    // The same for the unprojected pass and the refused factorisation of
    // projection on demand.
    for (name, material) in materials() {
        assert_eq!(
            material_pass_allocations::<2>(material),
            [0; 3],
            "{name} 2D"
        );
        assert_eq!(
            material_pass_allocations::<3>(material),
            [0; 3],
            "{name} 3D"
        );
    }
    // A parallel pass may let rayon allocate a few job records, never per element.
    assert!(
        large_single <= 16 && large_bodies <= 32,
        "a parallel assembly pass of 7200 triangles allocated {large_single} times \
         (two bodies: {large_bodies})"
    );

    // A whole step: solver vectors, statistics, the per-step copies. The
    // count grows with the Newton iterations (a few per iteration), not
    // with the elements.
    for projection in [Projection::Always, Projection::OnDemand] {
        let (small_step, small_iterations) = step_allocations(10, projection);
        let (large_step, large_iterations) = step_allocations(40, projection);
        let per_iteration =
            |count: usize, iterations: usize| count as f64 / iterations.max(1) as f64;
        println!(
            "step allocations ({projection:?}): 10x10 {small_step} ({small_iterations} \
             iterations), 40x40 {large_step} ({large_iterations} iterations)"
        );
        assert!(
            small_step < 100 && large_step < 100 + 16 * large_iterations,
            "a step allocated {small_step} (10 x 10) and {large_step} (40 x 40) times \
             ({projection:?})"
        );
        assert!(
            per_iteration(large_step, large_iterations)
                <= per_iteration(small_step, small_iterations) + 16.0,
            "allocations per iteration grow with the mesh: {small_step}/{small_iterations} \
             against {large_step}/{large_iterations} ({projection:?})"
        );
    }
}
