//! Bad scene values refused before any work starts: exit 2 naming the file
//! (or flag), the key and the reason, with nothing written; values that
//! would fail at step 0 or push the body from the first step.
//!
//! Each `mod regression_*` here guards one fixed bug and is named after it
//! (`cargo test --test integration regression_` selects them all).

/// Issue 9, items 3-7, 13 and 14: bad input that was found only after work had
/// started (files written, then exit 1, 101 or 134), messages that showed
/// internal names or 300-digit numbers, and negative flag values clap
/// refused as unknown arguments. Each is now exit 2 before any file is
/// written, naming the file (or flag), the key and the reason.
mod regression_bad_input_caught_late {
    use crate::cli_common as common;
    use common::*;
    use std::path::Path;

    /// Runs `args` in a fresh folder (with `scene.toml` = `scene` when given),
    /// checks exit code 2, one line on stderr, no panic and no output folder,
    /// and returns stderr.
    fn refused(scene: Option<&str>, args: &[&str]) -> String {
        let tmp = tempfile::tempdir().unwrap();
        if let Some(text) = scene {
            std::fs::write(tmp.path().join("scene.toml"), text).unwrap();
        }
        let o = elasto(tmp.path(), args);
        assert_code(&o, 2);
        let err = stderr(&o);
        assert!(!err.contains("panicked"), "{err}");
        assert_eq!(err.lines().count(), 1, "one line: {err}");
        let left: Vec<_> = std::fs::read_dir(tmp.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n != "scene.toml")
            .collect();
        assert!(left.is_empty(), "{args:?} wrote {left:?}");
        err
    }

    /// `refused` for `elasto check` and `elasto run` (rendering, and without).
    fn refused_by_check_and_run(scene: Option<&str>, target: &str, sets: &[&str]) -> Vec<String> {
        let mut errors = Vec::new();
        for command in [
            &["check", target][..],
            &["run", target],
            &["run", target, "--no-render"],
        ] {
            let mut args = command.to_vec();
            for set in sets {
                args.extend(["--set", set]);
            }
            errors.push(refused(scene, &args));
        }
        errors
    }

    fn assert_says(err: &str, words: &[&str]) {
        for w in words {
            assert!(err.contains(w), "expected `{w}` in: {err}");
        }
        // Numbers are short: no run of more than 20 digits.
        let longest = err
            .split(|c: char| !c.is_ascii_digit())
            .map(str::len)
            .max()
            .unwrap_or(0);
        assert!(longest <= 20, "a {longest}-digit number in: {err}");
    }

    #[test]
    fn frame_counts_and_durations_are_bounded_before_anything_is_allocated() {
        // Aborted with "memory allocation of 48000000000 bytes failed".
        let err = refused(None, &["run", "--frames", "1000000000"]);
        assert_says(
            &err,
            &["--frames 1000000000", "`time.frames`", "at most 1000000"],
        );
        // Panicked with "capacity overflow"; check called it valid with 18446744073709551615 frames.
        let scene = SMALL_SCENE.replace("frames = 4", "duration = 1e300");
        for err in refused_by_check_and_run(Some(&scene), "scene.toml", &[]) {
            assert_says(
                &err,
                &[
                    "scene.toml:14:",
                    "`time.duration`",
                    "3e301 frames",
                    "1000000",
                ],
            );
        }
        let err = refused(
            None,
            &["check", "report-drop-2d", "--set", "time.dt=1e-300"],
        );
        assert_says(&err, &["`time.dt`", "steps per frame", "1000000"]);
        let err = refused(
            None,
            &[
                "check",
                "report-drop-2d",
                "--set",
                "time.substeps=2000",
                "--set",
                "time.frames=1000000",
            ],
        );
        assert_says(&err, &["`time.frames`", "time steps", "1000000000"]);
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn memory_for_the_run_is_checked_against_the_machine() {
        // The automatic camera keeps every frame: 1e6 frames of a 1000 x 1000 mesh are 20 TB.
        let err = refused(
            None,
            &[
                "run",
                "--frames",
                "1000000",
                "--set",
                "mesh.cells=[1000, 1000]",
            ],
        );
        assert_says(
            &err,
            &[
                "--frames 1000000",
                "`time.frames`",
                "20.0 TB",
                "render.camera",
                "--no-render",
            ],
        );
        // The simulation itself: 50 million cells of tetrahedra need about 600 GB.
        let err = refused(
            None,
            &[
                "run",
                "drop-3d",
                "--no-render",
                "--set",
                "mesh.cells=[368, 368, 368]",
            ],
        );
        assert_says(&err, &["`mesh.cells`", "299016192 elements", "GB"]);
    }

    #[test]
    fn image_sizes_beyond_the_read_back_buffer_are_refused_before_simulating() {
        // Simulated, then failed in the GPU with a multi-line wgpu message.
        let err = refused(None, &["run", "--resolution", "8193x8192"]);
        assert_says(
            &err,
            &["--resolution 8193x8192", "`render.resolution`", "256 MiB"],
        );
        let err = refused(
            None,
            &[
                "check",
                "report-drop-2d",
                "--set",
                "render.resolution=[8193, 8192]",
            ],
        );
        assert_says(&err, &["`render.resolution`", "258.0 MiB"]);
        let err = refused(
            None,
            &[
                "check",
                "report-drop-2d",
                "--set",
                "render.resolution=[16385, 10]",
            ],
        );
        assert_says(&err, &["`render.resolution`", "16384"]);
    }

    #[test]
    fn values_beyond_32_bit_floats_are_caught_at_validation() {
        let camera = [
            "render.camera.center=[0.5, 5.0]",
            "render.camera.height=12.0",
        ];
        let cases: &[(&str, &[&str], &str, &str)] = &[
            (
                "report-drop-2d",
                &["render.camera.center=[0.5, 1e39]", camera[1]],
                "render.camera.center",
                "1e39",
            ),
            (
                "report-drop-2d",
                &["render.range=[0, 1e39]"],
                "render.range",
                "1e39",
            ),
            (
                "report-drop-2d",
                &["render.range=[0, 1e-50]"],
                "render.range",
                "32-bit",
            ),
            (
                "report-drop-2d",
                &[camera[0], "render.camera.height=1e-46"],
                "render.camera.height",
                "1e-46",
            ),
            (
                "drop-3d",
                &[
                    "render.camera.eye=[1e39, 1.0, 1.0]",
                    "render.camera.target=[0, 0, 0]",
                ],
                "render.camera.eye",
                "1e39",
            ),
            (
                "drop-3d",
                &[
                    "render.camera.eye=[3e38, 3e38, 3e38]",
                    "render.camera.target=[-3e38, -3e38, -3e38]",
                ],
                "render.camera.target",
                "from `eye`",
            ),
            (
                "report-drop-2d",
                &["effects.ground.height=-1e39", "mesh.offset=[0, 1]"],
                "effects.ground.height",
                "1e39",
            ),
        ];
        for (scene, sets, key, words) in cases {
            for err in refused_by_check_and_run(None, scene, sets) {
                assert_says(&err, &[&format!("`{key}`"), words, "32-bit floats"]);
            }
        }
    }

    #[test]
    fn an_infinite_starting_energy_is_refused_before_writing() {
        // Wrote a row of inf/NaN to stats.csv, then exited 1.
        let errors = refused_by_check_and_run(
            None,
            "report-drop-2d",
            &["effects.gravity.acceleration=[0, -1e308]"],
        );
        for err in errors {
            assert_says(
                &err,
                &[
                    "--set effects.gravity.acceleration=[0, -1e308]",
                    "`effects.gravity.acceleration`",
                    "gravitational energy is inf",
                ],
            );
        }
        for err in refused_by_check_and_run(None, "report-drop-2d", &["time.fps=1e-300"]) {
            assert_says(&err, &["`time.fps`", "dt = 1 / (fps × substeps) = 1e299 s"]);
        }
        let err = refused(
            None,
            &["run", "--no-render", "--set", "mesh.velocity=[1e200, 0]"],
        );
        assert_says(&err, &["`mesh.velocity`", "kinetic energy is inf"]);
    }

    #[test]
    fn the_barrier_stiffness_is_bounded_by_the_automatic_one() {
        // Froze the body in mid-air at height a, every step at the iteration cap, exit 0.
        for kappa in ["1e308", "1e9", "1e-300", "0.0002"] {
            let set = format!("effects.ground.kappa={kappa}");
            for err in refused_by_check_and_run(None, "report-drop-2d", &[&set]) {
                assert_says(
                    &err,
                    &[
                        "`effects.ground.kappa`",
                        "[0.0004653, 4.653e8]",
                        "465.3",
                        &format!("got {kappa}"),
                    ],
                );
            }
        }
        let tmp = tempfile::tempdir().unwrap();
        for kappa in ["0.001", "465", "400000000"] {
            let o = elasto(
                tmp.path(),
                &[
                    "check",
                    "report-drop-2d",
                    "--set",
                    &format!("effects.ground.kappa={kappa}"),
                ],
            );
            assert_code(&o, 0);
            assert!(
                stdout(&o).contains(&format!("kappa = {kappa}")),
                "{}",
                stdout(&o)
            );
        }
    }

    #[test]
    fn messages_name_file_key_and_reason_in_the_scene_files_words() {
        let cases: &[(&str, &[&str])] = &[
            ("mesh=3", &["`mesh`", "expected a table"]),
            ("render.camera=3", &["`render.camera`", "expected a table"]),
            ("solver=[1]", &["`solver`", "expected a table"]),
            (
                "material.model=3",
                &[
                    "`material.model`",
                    "`stvk`, `neo-hookean`, `stable-neo-hookean` or `fixed-corotated`",
                ],
            ),
            (
                "time.frames=1.5",
                &["`time.frames`", "expected a whole number"],
            ),
            ("time.frames=1e300", &["`time.frames`", "number `1e300`"]),
            (
                "effects.ground.kappa=[]",
                &["`effects.ground.kappa`", "expected a number"],
            ),
            ("mesh.cells=5", &["`mesh.cells`", "expected an array"]),
            (
                "mesh.cells=[-1, 2]",
                &["`mesh.cells`", "at least 1, got -1"],
            ),
            // Was "invalid box: axis 1: max 10 must exceed min 10" without file or key.
            (
                "mesh.size=[1e-300, 1e-300]",
                &["`mesh.size`", "2e-301", "too small"],
            ),
            ("mesh.size=[1e300, 1e300]", &["`mesh.size`", "1e300"]),
            (
                "material.density=-1e300",
                &["`material.density`", "got -1e300"],
            ),
            // Were "the starting barrier energy is NaN" (0 × inf in the automatic stiffness).
            (
                "effects.ground.a=1e300",
                &["`effects.ground.a`", "[1e-150, 1e150]"],
            ),
            (
                "effects.ground.a=1e-300",
                &["`effects.ground.a`", "got 1e-300"],
            ),
            (
                "effects.pinned={min=[-1, -1], max=[2, 20]}",
                &["`effects.pinned`", "every mesh vertex"],
            ),
            // Two regions that each leave vertices free but hold all of
            // them together (the validator's second stage, on the mesh).
            (
                "effects.pinned=[{min=[-1, -1], max=[0.6, 20]}, {min=[0.4, -1], max=[2, 20]}]",
                &["`effects.pinned`", "together hold every mesh vertex"],
            ),
            // Was refused only by the simulation ("vertex 0 starts at height -0.5").
            (
                "mesh.offset=[0, -0.5]",
                &["`mesh.offset`", "on or below the ground at 0"],
            ),
        ];
        for (set, words) in cases {
            let args = ["check", "report-drop-2d", "--set", set];
            let err = refused(None, &args);
            assert_says(&err, words);
            assert!(
                err.contains(&format!("--set {set} (in built-in scene `report-drop-2d`)")),
                "{err}"
            );
            for internal in ["Raw", "u64", "i64", "f64", "sequence", "wanted string"] {
                assert!(!err.contains(internal), "`{internal}` in: {err}");
            }
        }
        // Was a 300-digit number.
        let err = refused(
            None,
            &[
                "check",
                "report-drop-2d",
                "--set",
                "mesh.size=[1e-300, 1e-300]",
                "--set",
                "mesh.offset=[0, 1e-200]",
            ],
        );
        assert_says(&err, &["`mesh.size`", "too small", "1e-200"]);
        // A duplicate key names itself.
        let scene = SMALL_SCENE.replace("poisson = 0.3", "poisson = 0.3\npoisson = 0.2");
        let err = refused(Some(&scene), &["check", "scene.toml"]);
        assert_says(
            &err,
            &["scene.toml:12:", "`material.poisson`", "more than once"],
        );
        let scene = format!("{SMALL_SCENE}[material]\ndensity = 2.0\n");
        let err = refused(Some(&scene), &["check", "scene.toml"]);
        assert_says(&err, &["`material`", "more than once"]);
        // compare's own flag names, not its internal field names.
        let err = refused(
            None,
            &[
                "compare",
                "--golden",
                "g",
                "--frames",
                "f",
                "--threshold-percentile",
                "2",
            ],
        );
        assert_says(&err, &["--threshold-percentile 2", "[0, 1]"]);
        assert!(!err.contains("percentile_value"), "{err}");
    }

    #[test]
    fn negative_flag_values_reach_the_range_check() {
        // Were "unexpected argument '-5' found".
        let err = refused(None, &["run", "--frames", "-5"]);
        assert_says(
            &err,
            &["--frames -5", "`time.frames`", "must be at least 1, got -5"],
        );
        let err = refused(
            None,
            &[
                "compare",
                "--golden",
                "g",
                "--frames",
                "f",
                "--threshold-mean",
                "-1",
            ],
        );
        assert_says(
            &err,
            &["--threshold-mean -1", "must lie in [0, 1]", "got -1"],
        );
        let err = refused(
            None,
            &[
                "compare",
                "--golden",
                "g",
                "--frames",
                "f",
                "--percentile",
                "-0.5",
            ],
        );
        assert_says(&err, &["--percentile -0.5", "strictly between 0 and 1"]);
        let tmp = tempfile::tempdir().unwrap();
        let o = elasto(tmp.path(), &["run", "--resolution", "-5x3"]);
        assert_code(&o, 2);
        assert!(stderr(&o).contains("each side must be"), "{}", stderr(&o));
        assert!(!Path::new(&tmp.path().join("out")).exists());
    }
}

/// Issue 33, item 5: valid-looking extreme parameters passed `check` and
/// then failed at step 0 (`--set material.density=1e-20`,
/// `--set effects.ground.a=1e50`) or ran every step into the iteration cap
/// (`--set material.young=1e20` with Neo-Hookean, stable Neo-Hookean and
/// fixed corotated). Now `check` and `run` refuse them with exit 2 before
/// any work, naming the key and the limit: the masses lost beside dt² times
/// the stiffness (more than 1e12 between them at a vertex), a ground barrier
/// wider than 100 times the scene's size.
mod regression_extreme_parameters_failed_at_step_0 {
    use crate::cli_common as common;
    use common::*;

    /// `check` and `run` both refuse `sets` on the default scene with exit 2,
    /// naming `key` and saying `expected`; the run writes nothing.
    fn refused(sets: &[&str], key: &str, expected: &[&str]) {
        let tmp = tempfile::tempdir().unwrap();
        let mut with_sets: Vec<&str> = Vec::new();
        for set in sets {
            with_sets.extend(["--set", set]);
        }
        for command in [
            &["check", "report-drop-2d"][..],
            &["run", "--no-render", "-q", "-o", "o"],
        ] {
            let o = elasto(tmp.path(), &[command, &with_sets[..]].concat());
            assert_code(&o, 2);
            let err = stderr(&o);
            assert!(
                err.contains(&format!("`{key}`: ")) && !err.contains("{ "),
                "{sets:?}: {err}"
            );
            for part in expected {
                assert!(err.contains(part), "{sets:?}: {part:?} not in {err}");
            }
        }
        assert!(!tmp.path().join("o").exists());
    }

    #[test]
    fn masses_lost_beside_the_stiffness_are_refused_naming_the_key_and_limit() {
        refused(
            &["material.density=1e-20"],
            "material.density",
            &[
                "the masses are lost beside the stiffness: dt² (λ + 2μ) / mass reaches 6.731e19",
                "more than the 1e12 up to which",
                "by a factor of at least 6.731e7",
            ],
        );
        for model in [
            "stvk",
            "neo-hookean",
            "stable-neo-hookean",
            "fixed-corotated",
        ] {
            refused(
                &[&format!("material.model={model}"), "material.young=1e20"],
                "material.young",
                &["reaches 2.244e17", "more than the 1e12"],
            );
        }
        // The key the user changed last is the one named.
        refused(
            &["material.young=1e16", "time.substeps=1"],
            "time.substeps",
            &["more than the 1e12"],
        );
    }

    #[test]
    fn a_ground_barrier_far_wider_than_the_scene_is_refused() {
        refused(
            &["effects.ground.a=1e50"],
            "effects.ground.a",
            &[
                "1e50 is more than 100 times the scene's size 11.41",
                "at most 1141 here",
            ],
        );
    }

    #[test]
    fn stiff_but_representable_parameters_still_run() {
        let tmp = tempfile::tempdir().unwrap();
        // young = 1e14: dt² (λ + 2μ) / mass = 2.2e11, below the limit: the box
        // falls as backward Euler drops it, g dt² n (n + 1) / 2 after n steps
        // (frame 9: n = 90 steps of 1/300 s, 0.0455).
        let o = elasto(
            tmp.path(),
            &[
                "run",
                "--no-render",
                "-q",
                "--strict",
                "--frames",
                "10",
                "-o",
                "o",
                "--set",
                "material.young=1e14",
            ],
        );
        assert_code(&o, 0);
        let (header, rows) = read_csv(&tmp.path().join("o/stats.csv"));
        let com_y = header.iter().position(|c| c == "com_y").unwrap();
        let fall = 10.5 - rows[9][com_y].parse::<f64>().unwrap();
        let expected = 90.0 * 91.0 / 2.0 / 300.0_f64.powi(2);
        assert!(
            (fall - expected).abs() < 1e-6,
            "fell {fall}, not {expected}"
        );
        // A barrier wider than the gap but within 100 times the scene: a warning.
        let o = elasto(
            tmp.path(),
            &["check", "report-drop-2d", "--set", "effects.ground.a=1000"],
        );
        assert_code(&o, 0);
        assert!(stdout(&o).contains("warning"), "{}", stdout(&o));
    }
}

/// Issue 33, item 6: a ground barrier wider than the gap the body starts at
/// (`--set effects.ground.a=100` with the box 1 above the ground) pushed the
/// body from the first step with only a generic health line at the end (and
/// `a = 11` pushed it upward silently). Now `check` and `run` say so before
/// the run, naming the key and both lengths; a barrier narrower than the
/// gap says nothing.
mod regression_barrier_wider_than_the_gap_was_silent {
    use crate::cli_common as common;
    use common::*;

    #[test]
    fn a_barrier_wider_than_the_starting_gap_is_warned_before_the_run() {
        let tmp = tempfile::tempdir().unwrap();
        std::fs::write(tmp.path().join("s.toml"), SMALL_SCENE).unwrap();
        let expected = "effects.ground.a = 100 is more than the gap of 1 the bodies start at above \
                    the ground: the barrier pushes them up from the first step";
        let o = elasto(
            tmp.path(),
            &["check", "s.toml", "--set", "effects.ground.a=100"],
        );
        assert_code(&o, 0);
        assert!(
            stdout(&o).contains(&format!("warning         {expected}")),
            "{}",
            stdout(&o)
        );
        let o = elasto(
            tmp.path(),
            &[
                "run",
                "s.toml",
                "--set",
                "effects.ground.a=100",
                "--frames",
                "2",
                "--no-render",
                "-q",
                "-o",
                "wide",
            ],
        );
        let err = stderr(&o);
        let warned = err
            .find(&format!("elasto: warning: {expected}"))
            .unwrap_or_else(|| panic!("{err}"));
        // Said before anything else the run prints (the health line comes last).
        assert!(err[..warned].trim().is_empty(), "{err}");
        // The scene as it is (a = 0.1 below a gap of 1): no warning.
        let o = elasto(tmp.path(), &["check", "s.toml"]);
        assert_code(&o, 0);
        assert!(!stdout(&o).contains("warning"), "{}", stdout(&o));
    }
}
