//! Issue 33, items 1 and 24: a mesh, scene or sweep file that was a named
//! pipe blocked `check` and `run` forever (a link to `/dev/zero` read
//! without end), and "cannot read mesh file PATH" dropped the OS's reason.
//! Now anything but a regular file (after following links) is refused at
//! once with exit 2 and what it is, and every read error keeps its cause.
#![cfg(unix)]

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
