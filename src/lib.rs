//! elasto: elastic solids with linear finite elements in 2D and 3D, stepped by
//! backward Euler as an incremental-potential minimisation with projected
//! Newton, and rendered headless with wgpu to PNG frames and video.
//!
//! Data flows one way: scene → mesh + effects → time stepper → positions →
//! renderer → files. The simulation core ([`mesh`], [`material`], [`energy`],
//! [`solver`], [`sim`]) knows nothing about rendering; the renderer
//! ([`render`]) knows nothing about materials.
#![warn(missing_docs)]
// `!(x > 0.0)` is used on purpose throughout: unlike `x <= 0.0` it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

// Simulation core.
pub mod energy;
pub mod finite_volume;
pub mod material;
pub mod math;
pub mod mesh;
pub mod mesh_io;
pub mod sim;
pub mod solver;

// Scene files and the application layer.
pub mod app;
pub mod output;
pub mod scene;

// Rendering and image comparison.
pub mod compare;
pub mod render;
