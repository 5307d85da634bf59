//! elasto: elastic solids with linear finite elements in 2D and 3D, stepped by
//! an implicit integrator (backward Euler, BDF2 or Newmark) posed as an
//! incremental-potential minimisation and solved with Newton's method (the
//! Hessian projected to PSD on demand), and
//! rendered headless with wgpu to PNG frames and video.
//!
//! Data flows one way: scene → mesh + effects → time stepper → positions →
//! renderer → files. The simulation core ([`math`], [`input_file`], [`mesh`],
//! [`material`], [`assembly`], [`contact`], [`mesh_io`], [`energy`],
//! [`finite_volume`], [`solver`], [`integrator`], [`sim`]) knows nothing about
//! rendering; the renderer ([`render`]) knows nothing about materials, and
//! the encoders ([`encode`]) only see its whole images. Contact
//! geometry ([`contact`]: collision mesh, broad phase, distances, CCD) sits
//! beside [`assembly`], below the energy terms. `docs/architecture.md` follows
//! the data's path through these modules.
//!
//! The modules form layers, lowest first; a module refers only to modules of
//! its own layer and of the layers below:
//!
//! <!-- layers: begin -->
//! 1. [`math`], [`input_file`]
//! 2. [`mesh`], [`material`]
//! 3. [`assembly`], [`contact`], [`mesh_io`]
//! 4. [`energy`], [`finite_volume`]
//! 5. [`solver`]
//! 6. [`integrator`]
//! 7. [`sim`]
//! 8. [`output`], [`render`], [`encode`], [`compare`], [`study`]
//! 9. [`scene`]
//! 10. [`sweep`]
//! 11. [`app`]
//! <!-- layers: end -->
//!
//! `tests/integration/layering.rs` holds the order, enforces it on every
//! `crate::` path in `src/`, and checks that this list and the one in
//! `docs/architecture.md` are the same.
#![warn(missing_docs)]
// `!(x > 0.0)` is used on purpose throughout: unlike `x <= 0.0` it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

// Simulation core (layers 1 to 7 in the crate doc above).
pub mod assembly;
pub mod contact;
pub mod energy;
pub mod finite_volume;
pub mod input_file;
pub mod integrator;
pub mod material;
pub mod math;
pub mod mesh;
pub mod mesh_io;
pub mod sim;
pub mod solver;

// Outputs: data files, rendering, image and video files, image comparison
// and studies (layer 8).
pub mod compare;
pub mod encode;
pub mod output;
pub mod render;
pub mod study;

// Scene files, sweeps and the commands (layers 9 to 11).
pub mod app;
pub mod scene;
pub mod sweep;
