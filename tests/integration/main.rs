//! elasto's integration tests, in one test binary.
//!
//! Each test binary links the whole of elasto with wgpu, faer and the rest:
//! one binary per file meant 41 links of about 50 MB each (360 MB each with
//! full debug information, 15 GB in all, which filled a CI machine's disk)
//! and about ten minutes of CI. Here each file is a module, so
//! `cargo test --test integration golden_scenes` runs one file's tests.
//!
//! One test stays a binary of its own, because it changes the whole
//! process: `tests/allocations.rs` installs a counting global allocator.

// Helpers shared by the modules below (`support` also brings the
// `both_dimensions!` macro).
#[macro_use]
mod support;
mod cli_common;
// The independent intersection check of saved surfaces (its own tests
// allocate, so it stays out of `support`, which tests/allocations.rs shares).
#[path = "support/intersection/mod.rs"]
mod intersection;
mod mp4_file;
mod render_support;

mod analytic;
mod cli_errors;
mod cli_mesh_files;
mod cli_render;
mod cli_run;
mod cli_scenes;
mod cli_study;
mod cli_sweep;
mod compare;
mod compare_flip;
mod contact;
mod contact_hard_cases;
mod derivatives;
mod determinism;
mod element_fields;
mod friction;
mod golden_scenes;
mod hard_cases;
mod input_refused_early;
mod integrators;
mod layering;
mod mesh;
mod mesh_file_guards;
mod mesh_import;
mod moving_boundaries;
mod moving_boundaries_input;
mod obstacles;
mod output_folder;
mod output_whole_files;
mod readme_manual;
mod render_colour_and_text;
mod render_errors;
mod render_export;
mod render_image;
mod render_mesh_view;
mod render_obstacles;
mod render_pipeline;
mod render_profile;
mod render_streaming;
mod report_example;
mod robustness;
mod scene_properties;
mod scene_validation;
mod set_overrides;
mod solver_options;
mod stability;
mod surface_export;
mod sweep_guards;
mod sweep_processes;
mod tutorial_replica;
