//! Contact between and within bodies, the IPC way (Li et al. 2020, "Incremental Potential Contact"): the geometry.
//!
//! Contact is a pipeline of small parts, each tested on its own (the shape
//! of the IPC toolkit):
//!
//! 1. [`CollisionMesh`]: the surface of all bodies (2D boundary edges; 3D
//!    boundary triangles and their edges), with each primitive's body.
//! 2. [`broad_phase`]: candidate pairs of primitives whose (swept) boxes come
//!    within `d_hat`, in a fixed order; [`CandidateFinder`] turns them into
//!    [`ContactStencil`]s (2D point-edge; 3D point-triangle and edge-edge),
//!    leaving out pairs that share a vertex.
//! 3. [`distance`]: squared distances of each stencil kind with their
//!    closest-feature classification, gradients and Hessians, and the
//!    edge-edge mollifier.
//! 4. [`barrier`](mod@barrier): the clamped log barrier; [`ContactStencil::energy_derivatives`]
//!    puts it on a stencil with a PSD-projected Hessian.
//! 5. [`ccd`] and [`collision_free_step`]: additive continuous collision
//!    detection, which caps the line search so that no pair ever touches.
//! 6. [`friction`]: lagged smoothed Coulomb friction on a stencil frozen
//!    at a step's start (its slip, potential, gradient and Hessian).
//! 7. [`first_surface_crossing`] and [`first_contained_body`]: surfaces
//!    that cross and bodies wholly inside others, for the check that a
//!    scene does not start intersecting.
//!
//! The energy term that sums the barrier over the active stencils, with its
//! stiffness rule, is `energy::ContactBarrier`; this module knows nothing of
//! energies, solvers or scenes. It is elasto's own code: contact is the
//! subject of the project, and no Rust crate offers IPC's distances, barrier
//! derivatives or additive CCD (the IPC toolkit is C++; its numbers are stored
//! in the tests as references).

pub mod barrier;
pub mod broad_phase;
mod candidates;
pub mod ccd;
mod collision_free_step;
mod collision_mesh;
mod containment;
pub mod distance;
pub mod friction;
mod stencil;
mod surface_crossing;

pub use barrier::{barrier, barrier_derivative, barrier_second_derivative};
pub use candidates::CandidateFinder;
pub use collision_free_step::{CollisionFreeStep, collision_free_step};
pub use collision_mesh::{CollisionMesh, ObstacleSurface};
pub use containment::{Containment, first_contained_body};
pub use stencil::{ContactStencil, MAX_STENCIL_COORDINATES, StencilEnergy, StencilKind};
pub use surface_crossing::{SurfaceCrossing, first_surface_crossing};
