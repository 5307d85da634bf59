//! Issue 33, item 27: `WGPU_BACKEND=nonsense` was found only after the whole
//! simulation, as "no graphics adapter found (backends tried: none)" (wgpu
//! skips a name it does not know). Now a value that names anything but
//! wgpu's backends is exit 2 naming the variable and the unknown name,
//! before any work, for every command; known names pass in any case.

use crate::cli_common as common;
use common::*;
use std::path::Path;
use std::process::{Command, Output};

fn elasto_with_backend(cwd: &Path, backend: &str, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_elasto"))
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
