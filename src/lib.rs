//! elasto: elastic solids with linear finite elements in 2D and 3D, stepped by
//! backward Euler as an incremental-potential minimisation with projected
//! Newton, and rendered headless with wgpu to PNG frames and video.
//!
//! Data flows one way: scene → mesh + effects → time stepper → positions →
//! renderer → files. The simulation core ([`math`], [`mesh`], [`material`],
//! [`assembly`], [`energy`], [`solver`], [`integrator`], [`sim`]) knows
//! nothing about rendering; the renderer ([`render`]) knows nothing about
//! materials. Contact geometry ([`contact`]: collision mesh, broad phase,
//! distances, CCD) sits beside [`assembly`], below the energy terms.
//!
//! The modules form layers, lowest first: `math`, `input_file` → `mesh`, `material` →
//! `assembly`, `contact`, `mesh_io` → `energy`, `finite_volume` → `solver` → `integrator` → `sim` → `output`,
//! `render`, `compare`, `study` → `scene` → `sweep` → `app`. No module refers to a layer above
//! its own; `tests/integration/layering.rs` holds the order and enforces it.
#![warn(missing_docs)]
// `!(x > 0.0)` is used on purpose throughout: unlike `x <= 0.0` it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

// Simulation core (its layer order is in the crate doc above).
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

// Outputs: data files, rendering and image comparison.
pub mod compare;
pub mod output;
pub mod render;
pub mod study;

// Scene files and the application layer.
pub mod app;
pub mod scene;
pub mod sweep;
