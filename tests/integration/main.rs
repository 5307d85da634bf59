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
#[path = "support/intersection.rs"]
mod intersection;
mod mp4_file;
mod render_support;

mod analytic;
mod compare;
mod cli_errors;
mod cli_mesh_files;
mod cli_render;
mod cli_run;
mod cli_scenes;
mod cli_study;
mod cli_sweep;
mod compare_flip;
mod contact;
mod contact_hard_cases;
mod derivatives;
mod determinism;
mod element_fields;
mod friction;
mod golden_scenes;
mod hard_cases;
mod integrators;
mod layering;
mod mesh;
mod mesh_import;
mod moving_boundaries;
mod obstacles;
mod readme_manual;
mod regression_array_items_could_not_be_set;
mod regression_bad_input_caught_late;
mod regression_barrier_wider_than_the_gap_was_silent;
mod regression_changed_mesh_file_went_unnoticed;
mod regression_compressed_vtu_bomb;
mod regression_duplicate_elements_doubled_the_mass;
mod regression_extreme_parameters_failed_at_step_0;
mod regression_force_removed_frames_it_never_wrote;
mod regression_force_rerun_destroyed_the_earlier_run;
mod regression_full_disk_left_cut_files;
mod regression_gradient_descent_never_moved;
mod regression_input_file_blocked_or_hid_its_cause;
mod regression_interrupt_left_partial_video;
mod regression_loose_tolerance_froze_the_body;
mod regression_mesh_header_counts_trusted;
mod regression_overflowing_coordinates_called_degenerate;
mod regression_projection_kept_newton_linear;
mod regression_rayon_threads_unchecked;
mod regression_silent_bad_results;
mod regression_solver_failure_spoke_debug;
mod regression_stdout_write_panicked;
mod regression_stvk_folded_inside_out;
mod regression_sweep_collect_wrote_runs_that_never_ran;
mod regression_sweep_flag_replaced_a_varied_key;
mod regression_sweep_overwrote_a_foreign_folder;
mod regression_tolerance_ignored_the_scene_size;
mod regression_two_writers_mixed_one_folder;
mod regression_unknown_graphics_backend_found_late;
mod regression_writes_outside_output_folder;
mod render_errors;
mod render_export;
mod render_image;
mod render_obstacles;
mod render_pipeline;
mod render_profile;
mod render_streaming;
mod report_example;
mod robustness;
mod scene_properties;
mod scene_validation;
mod solver_options;
mod stability;
mod surface_export;
