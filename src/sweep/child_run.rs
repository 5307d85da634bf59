//! One run of a sweep as a child process: `elasto run` of the same binary, its stderr kept in `run.log`.
//!
//! A child process isolates runs from each other (a run that fails, or even
//! panics, does not take the sweep down) and makes each run's outputs those
//! of `elasto run` itself. Each child gets `RAYON_NUM_THREADS` so that the
//! runs going at once share the machine's cores; results do not depend on
//! the thread count. On Linux a child is sent SIGTERM if the sweep dies, so a
//! killed sweep leaves no run going (the child then removes its partial
//! files, like an interrupted `elasto run`).

use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::Instant;

/// The file in a run folder that holds the stderr of its `elasto run`.
pub const RUN_LOG_FILE: &str = "run.log";

/// How to start one run.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ChildRun {
    /// The `elasto` binary.
    pub program: PathBuf,
    /// The arguments after the program (`run SCENE --out DIR ...`).
    pub args: Vec<String>,
    /// The run folder (already created), where `run.log` goes.
    pub dir: PathBuf,
    /// Threads for the run's assembly (`RAYON_NUM_THREADS`).
    pub threads: usize,
}

/// How a run ended.
#[derive(Debug, Clone, PartialEq)]
pub struct ChildOutcome {
    /// The exit code (`None` when a signal ended it).
    pub exit_code: Option<i32>,
    /// Why it failed (`None` when it succeeded): the last `error:` line of
    /// its log, else the exit code or the signal.
    pub failure: Option<String>,
    /// Wall time in seconds.
    pub wall_seconds: f64,
}

impl ChildRun {
    /// Starts the run.
    pub fn spawn(&self) -> std::io::Result<Child> {
        let log = std::fs::File::create(self.dir.join(RUN_LOG_FILE))?;
        let mut command = Command::new(&self.program);
        command
            .args(&self.args)
            .env("RAYON_NUM_THREADS", self.threads.max(1).to_string())
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::from(log));
        #[cfg(target_os = "linux")]
        {
            use std::os::unix::process::CommandExt;
            // SAFETY: prctl is async-signal-safe and touches no memory of the parent.
            unsafe {
                command.pre_exec(|| {
                    if libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGTERM) != 0 {
                        return Err(std::io::Error::last_os_error());
                    }
                    Ok(())
                });
            }
        }
        command.spawn()
    }

    /// Runs to the end (the calling thread waits; on Linux it must live
    /// until then, since the parent-death signal follows the thread).
    pub fn run(&self) -> ChildOutcome {
        let start = Instant::now();
        let status = self.spawn().and_then(|mut child| child.wait());
        let wall_seconds = start.elapsed().as_secs_f64();
        match status {
            Ok(status) => ChildOutcome {
                exit_code: status.code(),
                failure: (!status.success()).then(|| failure_reason(&self.dir, status)),
                wall_seconds,
            },
            Err(error) => ChildOutcome {
                exit_code: None,
                failure: Some(format!("cannot start {}: {error}", self.program.display())),
                wall_seconds,
            },
        }
    }
}

/// The last `error:` line of the run's log, else what the status says.
fn failure_reason(dir: &Path, status: ExitStatus) -> String {
    let log = std::fs::read_to_string(dir.join(RUN_LOG_FILE)).unwrap_or_default();
    if let Some(line) = log.lines().rev().find(|l| l.starts_with("error: ")) {
        return line.trim_start_matches("error: ").trim().to_owned();
    }
    #[cfg(unix)]
    {
        use std::os::unix::process::ExitStatusExt;
        if let Some(signal) = status.signal() {
            return format!("killed by signal {signal}");
        }
    }
    match status.code() {
        Some(code) => format!("exit code {code}"),
        None => "ended without an exit code".into(),
    }
}
