//! Shared helpers of the tests that run the real binary with a fake `ffmpeg`
//! first on `PATH`: the fake itself, a bounded wait for the binary, and
//! checks on the files and processes left behind.
#![allow(dead_code)]

use std::io::Read;
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// A folder holding an executable `ffmpeg` script that lists libx264 when
/// asked for its encoders (and counts the times it was asked, in
/// `listings`) and otherwise writes its process id to `pid` in
/// that folder, creates its output file (the last argument), and runs
/// `body` with the output file in `$last`.
pub struct FakeFfmpeg {
    dir: tempfile::TempDir,
}

impl FakeFfmpeg {
    pub fn new(body: &str) -> Self {
        let dir = tempfile::tempdir().unwrap();
        let script = format!(
            "#!/bin/sh\n\
             if [ \"$2\" = \"-encoders\" ]; then\n\
             \x20   echo listed >> '{listings}'\n\
             \x20   echo ' V..... libx264              libx264 H.264 (fake)'\n\
             \x20   exit 0\n\
             fi\n\
             for last in \"$@\"; do :; done\n\
             : > \"$last\"\n\
             echo $$ > '{}'\n\
             {body}\n",
            dir.path().join("pid").display(),
            listings = dir.path().join("listings").display(),
        );
        let path = dir.path().join("ffmpeg");
        std::fs::write(&path, script).unwrap();
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
        Self { dir }
    }

    /// `PATH` with the fake first.
    pub fn path_variable(&self) -> String {
        let system = std::env::var("PATH").unwrap_or_default();
        format!("{}:{system}", self.dir.path().display())
    }

    /// The `elasto` binary with the fake first on `PATH`.
    pub fn elasto(&self, args: &[&str]) -> Command {
        let mut command = Command::new(env!("CARGO_BIN_EXE_elasto"));
        command
            .args(args)
            .env("PATH", self.path_variable())
            .env_remove("RUST_BACKTRACE")
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        command
    }

    /// How many times the fake was asked to list its encoders.
    pub fn encoder_listings(&self) -> usize {
        std::fs::read_to_string(self.dir.path().join("listings"))
            .map(|text| text.lines().count())
            .unwrap_or(0)
    }

    /// The process id the fake wrote once it ran as the encoder.
    pub fn encoder_pid(&self) -> Option<i32> {
        std::fs::read_to_string(self.dir.path().join("pid"))
            .ok()
            .and_then(|text| text.trim().parse().ok())
    }
}

/// Waits for `child`, killing it and failing the test after `limit`;
/// returns its status and its stderr.
pub fn wait_at_most(child: &mut Child, limit: Duration) -> (ExitStatus, String) {
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("elasto still ran after {limit:?}: it hangs");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut stderr = String::new();
    if let Some(mut pipe) = child.stderr.take() {
        pipe.read_to_string(&mut stderr).unwrap();
    }
    (status, stderr)
}

/// Waits until `path` exists, for at most `limit`.
pub fn wait_for_file(path: &Path, limit: Duration) -> bool {
    let start = Instant::now();
    while start.elapsed() < limit {
        if path.exists() {
            return true;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    false
}

/// Every file under `dir`, recursively, relative to it.
pub fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(folder) = pending.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                pending.push(path);
            } else {
                files.push(path.strip_prefix(dir).unwrap().to_path_buf());
            }
        }
    }
    files.sort();
    files
}

/// True when process `pid` no longer runs (gone, or a zombie nobody reaps).
pub fn process_ended(pid: i32) -> bool {
    match std::fs::read_to_string(format!("/proc/{pid}/stat")) {
        // The state follows the command name in parentheses.
        Ok(stat) => stat
            .rsplit_once(')')
            .is_some_and(|(_, rest)| rest.trim_start().starts_with(['Z', 'X'])),
        Err(_) => true,
    }
}
