//! Issue 33, item 15: a full disk while writing `--save-meshes` left a cut
//! `meshes/frame_NNNN.vtu` under its final name (PNGs and surfaces used
//! temporary names; the VTU writer, `scene.toml` and `study.md` did not).
//! Now every whole file is written under a hidden temporary name and renamed
//! when complete: a failed write leaves no file under the final name, and the
//! message names the file and the cause. A full disk is stood in for by a
//! file-size limit (`RLIMIT_FSIZE`): writing past it fails with EFBIG.
#![cfg(target_os = "linux")]

use crate::cli_common as common;
use common::*;
use std::os::unix::process::CommandExt;
use std::path::Path;
use std::process::{Command, Output};

/// Runs the real binary in `cwd`, where no file may grow past `max_bytes`.
fn elasto_with_file_size_limit(cwd: &Path, max_bytes: u64, args: &[&str]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_elasto"));
    command
        .args(args)
        .current_dir(cwd)
        .env_remove("RUST_BACKTRACE");
    // SAFETY: only async-signal-safe calls (signal, setrlimit) run between
    // fork and exec.
    unsafe {
        command.pre_exec(move || {
            // Ignored, SIGXFSZ turns a write past the limit into EFBIG
            // instead of killing the process; the disposition survives exec.
            libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
            let limit = libc::rlimit {
                rlim_cur: max_bytes,
                rlim_max: max_bytes,
            };
            if libc::setrlimit(libc::RLIMIT_FSIZE, &limit) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    command.output().expect("the elasto binary runs")
}

/// Every file under `dir`, recursively, as paths relative to it.
fn files_under(dir: &Path) -> Vec<String> {
    let mut files = Vec::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(folder) = pending.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                pending.push(path);
            } else {
                let relative = path.strip_prefix(dir).unwrap();
                files.push(relative.to_string_lossy().into_owned());
            }
        }
    }
    files.sort();
    files
}

#[test]
fn a_mesh_that_cannot_be_written_whole_leaves_no_file_under_its_name() {
    let tmp = tempfile::tempdir().unwrap();
    // A finer grid than the small scene's, so that a frame's VTU is far
    // larger than scene.toml and the limit falls between them.
    let scene = SMALL_SCENE.replace("cells = [2, 2]", "cells = [12, 12]");
    std::fs::write(tmp.path().join("s.toml"), scene).unwrap();
    let args = [
        "run",
        "s.toml",
        "--no-render",
        "--save-meshes",
        "--quiet",
        "-o",
        "out",
    ];
    let o = elasto_with_file_size_limit(tmp.path(), 8 << 10, &args);
    assert_code(&o, 1);
    let err = stderr(&o);
    assert!(
        err.contains("cannot write") && err.contains("frame_0000.vtu: File too large"),
        "{err}"
    );
    let files = files_under(&tmp.path().join("out"));
    assert!(
        !files
            .iter()
            .any(|f| f.ends_with(".vtu") || f.ends_with(".partial")),
        "a cut mesh or a temporary is left: {files:?}"
    );
    assert!(files.contains(&"scene.toml".to_owned()), "{files:?}");
}

#[test]
fn a_scene_file_that_cannot_be_written_whole_is_not_left_cut() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("s.toml"), SMALL_SCENE).unwrap();
    let args = ["run", "s.toml", "--no-render", "--quiet", "-o", "out"];
    let o = elasto_with_file_size_limit(tmp.path(), 256, &args);
    assert_code(&o, 1);
    let err = stderr(&o);
    assert!(err.contains("scene.toml: File too large"), "{err}");
    let files = files_under(&tmp.path().join("out"));
    assert!(!files.iter().any(|f| f.contains("scene.toml")), "{files:?}");
}

/// Issue 33, item 16: a full disk while rendering said only "cannot render:
/// an earlier frame failed; the run cannot continue" (the encoder's error,
/// kept between frames, was checked after the generic refusal). Now the run
/// stops with the first error: the frame file and the OS cause.
#[test]
fn a_full_disk_while_rendering_names_the_frame_and_the_cause() {
    let tmp = tempfile::tempdir().unwrap();
    let o = elasto_with_file_size_limit(
        tmp.path(),
        8192,
        &[
            "run",
            "--frames",
            "12",
            "--resolution",
            "640x480",
            "-q",
            "-o",
            "o",
        ],
    );
    assert_code(&o, 1);
    let err = stderr(&o);
    assert!(
        err.contains("cannot write o/frames/frame_0")
            && err.contains("File too large")
            && !err.contains("an earlier frame failed"),
        "{err}"
    );
}
