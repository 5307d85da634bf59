//! Bad input exits with code 2 and a message naming the file, the key and the line.
//!
//! Each `mod regression_*` here guards one fixed bug and is named after it
//! (`cargo test --test integration regression_` selects them all).

use crate::cli_common as common;
use common::*;

/// Writes `text` as a scene file, runs `run` on it and returns stderr after checking exit code 2.
fn run_bad(text: &str, extra: &[&str]) -> String {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("bad.toml"), text).unwrap();
    let mut args = vec!["run", "bad.toml", "--no-render", "--out", "result"];
    args.extend_from_slice(extra);
    let o = elasto(tmp.path(), &args);
    assert_code(&o, 2);
    // Nothing was written.
    assert!(!tmp.path().join("result").exists());
    let err = stderr(&o);
    assert!(!err.contains("panicked"), "{err}");
    err
}

fn replace(old: &str, new: &str) -> String {
    assert!(SMALL_SCENE.contains(old));
    SMALL_SCENE.replacen(old, new, 1)
}

#[test]
fn bad_scene_files_name_file_key_and_line() {
    let cases: &[(String, &str, &str)] = &[
        (
            replace("young = 300.0", "young = 300.0\nyoungs = 1"),
            "bad.toml:11:",
            "material.youngs",
        ),
        (
            replace("young = 300.0", "young = -300.0"),
            "bad.toml:10:",
            "material.young",
        ),
        (
            replace("poisson = 0.3", "poisson = 0.5"),
            "bad.toml:11:",
            "material.poisson",
        ),
        (
            replace("offset = [0.0, 1.0]", "offset = [0.0, -0.5]"),
            "bad.toml:6:",
            "mesh.offset",
        ),
        (
            replace("young = 300.0", "young = 300.0.0"),
            "bad.toml:10:",
            "invalid TOML",
        ),
        (
            replace("young = 300.0", "young = \"hard\""),
            "bad.toml:10:",
            "material.young",
        ),
        (
            replace("frames = 4", "frames = 0"),
            "bad.toml:14:",
            "time.frames",
        ),
        (
            replace("frames = 4", "frames = 4\ndt = 0.0"),
            "bad.toml:15:",
            "time.dt",
        ),
        (
            replace("frames = 4", "frames = 4\ndt = -1e-3"),
            "bad.toml:15:",
            "time.dt",
        ),
    ];
    for (text, position, key) in cases {
        let err = run_bad(text, &[]);
        assert!(err.contains(position), "expected {position} in: {err}");
        assert!(err.contains(key), "expected {key} in: {err}");
        assert_eq!(err.lines().count(), 1, "one clear line: {err}");
    }
}

#[test]
fn bad_overrides_name_the_flag() {
    let err = run_bad(SMALL_SCENE, &["--set", "material.stiffness=3"]);
    assert!(
        err.contains("--set material.stiffness=3") && err.contains("unknown field"),
        "{err}"
    );
    let err = run_bad(SMALL_SCENE, &["--set", "physics.gravity=3"]);
    assert!(err.contains("--set physics.gravity=3"), "{err}");
    let err = run_bad(SMALL_SCENE, &["--set", "material.young"]);
    assert!(
        err.contains("--set material.young") && err.contains("key.path=value"),
        "{err}"
    );
    let err = run_bad(SMALL_SCENE, &["--set", "time.frames=-2"]);
    assert!(err.contains("time.frames"), "{err}");
    let err = run_bad(SMALL_SCENE, &["--frames", "0"]);
    assert!(
        err.contains("--frames 0") && err.contains("time.frames"),
        "{err}"
    );
}

#[test]
fn bad_flags_and_missing_scenes_exit_2() {
    let tmp = tempfile::tempdir().unwrap();
    for args in [
        &["run", "missing.toml"][..],
        &["run", "no-such-builtin"],
        &["run", "--resolution", "wide"],
        &["run", "--video", "avi"],
        &["run", "--frames", "many"],
        &["check"],
        &["frobnicate"],
    ] {
        let o = elasto(tmp.path(), args);
        assert_code(&o, 2);
        assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
    }
    let o = elasto(tmp.path(), &["run", "missing.toml"]);
    assert!(stderr(&o).contains("missing.toml"), "{}", stderr(&o));
    let o = elasto(tmp.path(), &["--help"]);
    assert_code(&o, 0);
    for command in ["run", "scenes", "check", "compare"] {
        assert!(stdout(&o).contains(command));
    }
}

/// Issue 33, item 4: a failed write to standard output (`> /dev/full`)
/// panicked with exit 101 and a backtrace (`print!` panics on ENOSPC). Now
/// every command that prints says "cannot write to standard output: ..." and
/// exits 1, and the files it wrote stay complete.
#[cfg(target_os = "linux")]
mod regression_stdout_write_panicked {
    use crate::cli_common as common;
    use common::*;
    use std::path::Path;
    use std::process::{Output, Stdio};

    /// Runs the real binary in `cwd` with its standard output on `/dev/full`.
    fn elasto_to_full_disk(cwd: &Path, args: &[&str]) -> Output {
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .expect("/dev/full opens");
        crate::cli_common::elasto_command()
            .args(args)
            .current_dir(cwd)
            .env_remove("RUST_BACKTRACE")
            .stdout(Stdio::from(full))
            .stderr(Stdio::piped())
            .output()
            .expect("the elasto binary runs")
    }

    /// Exit 1 with the message, and no panic.
    fn assert_says_it_cannot_write(o: &Output, args: &[&str]) {
        let err = stderr(o);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(
            err.contains("error: cannot write to standard output: No space left on device"),
            "{args:?}: {err}"
        );
    }

    #[test]
    fn the_commands_that_print_say_they_cannot_write_and_exit_1() {
        let tmp = tempfile::tempdir().unwrap();
        for args in [
            &["scenes"][..],
            &["scenes", "show", "drop-3d"],
            &["check", "drop-3d"],
            &[
                "sweep",
                "drop-3d",
                "--vary",
                "material.young=100,200",
                "--list",
            ],
            &["--help"],
            &["--version"],
        ] {
            let o = elasto_to_full_disk(tmp.path(), args);
            assert_says_it_cannot_write(&o, args);
        }
    }

    #[test]
    fn a_run_with_profile_keeps_its_files_when_the_table_cannot_be_written() {
        let tmp = tempfile::tempdir().unwrap();
        std::fs::write(tmp.path().join("s.toml"), SMALL_SCENE).unwrap();
        let args = ["run", "s.toml", "--no-render", "--profile", "-o", "out"];
        let o = elasto_to_full_disk(tmp.path(), &args);
        assert_says_it_cannot_write(&o, &args);
        let (_, rows) = read_csv(&tmp.path().join("out/stats.csv"));
        assert_eq!(rows.len(), 4, "frames 0 to 3: {rows:?}");
    }

    #[test]
    fn a_study_keeps_its_files_when_the_report_cannot_be_written() {
        let tmp = tempfile::tempdir().unwrap();
        std::fs::write(tmp.path().join("s.toml"), SMALL_SCENE).unwrap();
        let args = [
            "study",
            "s.toml",
            "--vary",
            "time.substeps=1,2",
            "-o",
            "st",
            "--quiet",
        ];
        let o = elasto_to_full_disk(tmp.path(), &args);
        assert_says_it_cannot_write(&o, &args);
        for file in ["study.csv", "study.md", "study.png"] {
            let size = std::fs::metadata(tmp.path().join("st").join(file))
                .map(|m| m.len())
                .unwrap_or(0);
            assert!(size > 0, "{file} is missing or empty");
        }
    }
}

/// Issue 33, item 3: `RAYON_NUM_THREADS=100000` started 100 000 threads (a
/// 3-frame run took over a minute) and `RAYON_NUM_THREADS=abc` was silently
/// ignored. Now a value that is not a whole number is exit 2 naming the
/// variable, before any work, and one above the cap (4 threads per core, at
/// least 64) is lowered to it with a warning.
mod regression_rayon_threads_unchecked {
    use crate::cli_common as common;
    use common::*;
    use std::path::Path;
    use std::process::Output;

    /// Runs the real binary in `cwd` with `RAYON_NUM_THREADS` = `threads`.
    fn elasto_with_threads(cwd: &Path, threads: &str, args: &[&str]) -> Output {
        crate::cli_common::elasto_command()
            .args(args)
            .current_dir(cwd)
            .env_remove("RUST_BACKTRACE")
            .env("RAYON_NUM_THREADS", threads)
            .output()
            .expect("the elasto binary runs")
    }

    #[test]
    fn a_thread_count_that_is_not_a_whole_number_is_refused_before_any_work() {
        let tmp = tempfile::tempdir().unwrap();
        std::fs::write(tmp.path().join("s.toml"), SMALL_SCENE).unwrap();
        for value in ["abc", "-4", "2.5", ""] {
            for args in [
                &["check", "s.toml"][..],
                &["run", "s.toml", "--no-render", "-o", "out"],
            ] {
                let o = elasto_with_threads(tmp.path(), value, args);
                assert_code(&o, 2);
                let err = stderr(&o);
                assert!(
                    err.contains(&format!("`RAYON_NUM_THREADS={value}`"))
                        && err.contains("must be a whole number of threads"),
                    "{value:?} {args:?}: {err}"
                );
                assert!(!tmp.path().join("out").exists(), "{args:?} wrote a folder");
            }
        }
    }

    #[test]
    fn a_thread_count_above_the_cap_is_lowered_with_a_warning() {
        let tmp = tempfile::tempdir().unwrap();
        std::fs::write(tmp.path().join("s.toml"), SMALL_SCENE).unwrap();
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        let cap = (4 * cores).max(64);
        let o = elasto_with_threads(
            tmp.path(),
            "100000",
            &["run", "s.toml", "--no-render", "--quiet", "-o", "out"],
        );
        assert_code(&o, 0);
        let err = stderr(&o);
        assert!(
            err.contains(&format!(
                "warning: RAYON_NUM_THREADS=100000 is more than the {cap} threads elasto starts"
            )) && err.contains(&format!("using {cap}")),
            "{err}"
        );
        let (_, rows) = read_csv(&tmp.path().join("out/stats.csv"));
        assert_eq!(rows.len(), 4, "the run completed");
        // Within the cap, the value is kept without a word.
        let o = elasto_with_threads(tmp.path(), "2", &["check", "s.toml"]);
        assert_code(&o, 0);
        assert!(stderr(&o).is_empty(), "{}", stderr(&o));
    }
}

/// Issue 33, item 27: `WGPU_BACKEND=nonsense` was found only after the whole
/// simulation, as "no graphics adapter found (backends tried: none)" (wgpu
/// skips a name it does not know). Now a value that names anything but
/// wgpu's backends is exit 2 naming the variable and the unknown name,
/// before any work, for every command; known names pass in any case.
mod regression_unknown_graphics_backend_found_late {
    use crate::cli_common as common;
    use common::*;
    use std::path::Path;
    use std::process::Output;

    fn elasto_with_backend(cwd: &Path, backend: &str, args: &[&str]) -> Output {
        crate::cli_common::elasto_command()
            .args(args)
            .current_dir(cwd)
            .env_remove("RUST_BACKTRACE")
            .env("WGPU_BACKEND", backend)
            .output()
            .expect("the elasto binary runs")
    }

    #[test]
    fn an_unknown_graphics_backend_is_refused_before_any_work() {
        let tmp = tempfile::tempdir().unwrap();
        std::fs::write(tmp.path().join("s.toml"), SMALL_SCENE).unwrap();
        for (value, unknown) in [
            ("nonsense", "`nonsense`"),
            ("gl,nonsense", "`nonsense`"),
            ("", "``"),
            ("noop", "`noop`"),
        ] {
            for args in [&["check", "s.toml"][..], &["run", "s.toml", "-o", "out"]] {
                let o = elasto_with_backend(tmp.path(), value, args);
                assert_code(&o, 2);
                let err = stderr(&o);
                assert!(
                    err.contains(&format!("`WGPU_BACKEND={value}`"))
                        && err.contains("names no graphics backend wgpu knows")
                        && err.contains(unknown),
                    "{value:?} {args:?}: {err}"
                );
                assert!(!tmp.path().join("out").exists(), "{args:?} wrote a folder");
            }
        }
        // wgpu's names, in any case and with spaces, pass.
        for value in ["gl", "GL", "vulkan, gl", "Vk,GLES"] {
            let o = elasto_with_backend(tmp.path(), value, &["check", "s.toml"]);
            assert_code(&o, 0);
        }
    }
}

/// Issue 33, items 1 and 24: a mesh, scene or sweep file that was a named
/// pipe blocked `check` and `run` forever (a link to `/dev/zero` read
/// without end), and "cannot read mesh file PATH" dropped the OS's reason.
/// Now anything but a regular file (after following links) is refused at
/// once with exit 2 and what it is, and every read error keeps its cause.
#[cfg(unix)]
mod regression_input_file_blocked_or_hid_its_cause {
    use crate::cli_common as common;
    use common::*;
    use std::path::Path;
    use std::time::Duration;

    /// Long enough for a refusal on a loaded machine, far shorter than a hang.
    const LIMIT: Duration = Duration::from_secs(60);

    /// A one-body 3D scene reading its mesh from `path`.
    fn mesh_scene(path: &str) -> String {
        format!(
            "dimension = 3\n[mesh]\ngenerator = \"file\"\npath = \"{path}\"\n\
         [material]\nmodel = \"neo-hookean\"\nyoung = 300.0\npoisson = 0.3\n\
         [time]\nframes = 2\n"
        )
    }

    fn make_fifo(path: &Path) {
        let name = std::ffi::CString::new(path.to_str().unwrap()).unwrap();
        // SAFETY: `name` is a valid NUL-terminated path.
        assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o644) }, 0, "mkfifo");
    }

    /// Runs `args` in `dir`, expecting a prompt exit 2 whose one-line message
    /// holds every one of `words`, and no output folder.
    fn refused_at_once(dir: &Path, args: &[&str], words: &[&str]) {
        let o = elasto_within(dir, args, LIMIT);
        assert_code(&o, 2);
        let err = stderr(&o);
        assert!(!err.contains("panicked"), "{err}");
        for word in words {
            assert!(err.contains(word), "{args:?}: no `{word}` in: {err}");
        }
        assert!(!dir.join("out").exists(), "{args:?} made an output folder");
    }

    #[test]
    fn a_named_pipe_as_mesh_file_is_refused_by_check_and_run() {
        let tmp = tempfile::tempdir().unwrap();
        make_fifo(&tmp.path().join("m.msh"));
        std::fs::write(tmp.path().join("s.toml"), mesh_scene("m.msh")).unwrap();
        let words = ["m.msh", "a named pipe (FIFO), not a regular file"];
        refused_at_once(tmp.path(), &["check", "s.toml"], &words);
        refused_at_once(
            tmp.path(),
            &["run", "s.toml", "--no-render", "-o", "out"],
            &words,
        );
    }

    #[test]
    fn a_named_pipe_as_scene_or_sweep_file_is_refused() {
        let tmp = tempfile::tempdir().unwrap();
        make_fifo(&tmp.path().join("s.toml"));
        let words = ["cannot read scene file s.toml", "a named pipe (FIFO)"];
        refused_at_once(tmp.path(), &["check", "s.toml"], &words);
        refused_at_once(
            tmp.path(),
            &["run", "s.toml", "--no-render", "-o", "out"],
            &words,
        );
        refused_at_once(
            tmp.path(),
            &[
                "sweep",
                "s.toml",
                "--vary",
                "material.young=100,200",
                "-o",
                "out",
            ],
            &words,
        );
    }

    #[test]
    fn a_link_to_an_endless_device_is_refused_before_reading() {
        let tmp = tempfile::tempdir().unwrap();
        std::os::unix::fs::symlink("/dev/zero", tmp.path().join("m.msh")).unwrap();
        std::os::unix::fs::symlink("/dev/zero", tmp.path().join("z.toml")).unwrap();
        std::fs::write(tmp.path().join("s.toml"), mesh_scene("m.msh")).unwrap();
        refused_at_once(
            tmp.path(),
            &["check", "s.toml"],
            &["m.msh", "a character device, not a regular file"],
        );
        refused_at_once(
            tmp.path(),
            &["check", "z.toml"],
            &["z.toml", "a character device, not a regular file"],
        );
    }

    #[test]
    fn an_unreadable_mesh_file_is_named_with_the_os_cause() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        std::fs::create_dir(dir.join("folder.msh")).unwrap();
        std::os::unix::fs::symlink("loop.msh", dir.join("loop.msh")).unwrap();
        std::os::unix::fs::symlink("nowhere.msh", dir.join("dangling.msh")).unwrap();
        std::fs::copy(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/meshes/cube.node"),
            dir.join("alone.node"),
        )
        .unwrap();
        for (mesh, cause) in [
            (
                "folder.msh",
                "folder.msh: it is a folder, not a regular file",
            ),
            ("loop.msh", "loop.msh: Too many levels of symbolic links"),
            ("dangling.msh", "dangling.msh: No such file or directory"),
            ("missing.msh", "missing.msh: No such file or directory"),
            ("alone.node", "alone.ele: No such file or directory"),
        ] {
            std::fs::write(dir.join("s.toml"), mesh_scene(mesh)).unwrap();
            refused_at_once(dir, &["check", "s.toml"], &["cannot read mesh file", cause]);
        }
    }
}

/// Issue 33, item 5 (in part): valid-looking extreme parameters that fail
/// at step 0 printed a Rust debug string (`sparse Cholesky factorisation
/// failed: NonPositivePivot { index: 70 }`). The failure now says in words
/// what went wrong and what may help; no Debug-formatted internals. (The
/// command line refuses these parameters before the run now, see
/// `input_refused_early::regression_extreme_parameters_failed_at_step_0`; the library, which has
/// no such check, still reports the failure in words.)
mod regression_solver_failure_spoke_debug {
    use elasto::material::{LameParameters, Material, StVenantKirchhoff, YoungPoisson};
    use elasto::math::Vector;
    use elasto::mesh::Mesh;
    use elasto::sim::{Effects, Ground, Simulation, SimulationSettings};

    #[test]
    fn a_factorisation_that_fails_says_why_in_words() {
        let mesh = Mesh::axis_aligned_box(
            Vector::<2>::new(0.0, 10.0),
            Vector::<2>::new(1.0, 11.0),
            [5, 5],
        )
        .unwrap();
        let lame: LameParameters = YoungPoisson {
            young: 300.0,
            poisson: 0.3,
        }
        .into();
        let effects = Effects {
            gravity: Some(Vector::<2>::new(0.0, -1.0)),
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
        let settings = SimulationSettings {
            dt: 1.0 / 300.0,
            integrator: Default::default(),
            solver: Default::default(),
        };
        // The report's box with its masses lost beside dt² K (density 1e-20).
        let mut sim = Simulation::new(
            mesh,
            Material::StVenantKirchhoff(StVenantKirchhoff { lame }),
            1e-20,
            effects,
            settings,
            Vector::<2>::zeros(),
        )
        .unwrap();
        let err = sim.advance_frame(10).unwrap_err().to_string();
        assert!(
            err.contains("the system matrix is not positive definite in floating point")
                && err.contains("material.density")
                && !err.contains("NonPositivePivot")
                && !err.contains("{ index"),
            "{err}"
        );
    }
}
