//! The default scene end to end, as a user runs it (issue 13, item 5): the
//! `elasto` binary renders report-drop-2d (300 frames at 1280x720) with the
//! APNG as its only video, against the same run with `--no-render`.
//!
//! Run with `cargo bench --bench default_run`. The two runs alternate, so
//! that a slower spell of a shared machine hits both; each row is the median
//! wall time over the runs (`ELASTO_BENCH_RUNS`, default 7), and the ratio
//! is that of the medians. The default videos (APNG and MP4, when ffmpeg is
//! on `PATH`) and the PNG frames alone are timed too. Each variant re-runs
//! into a folder of its own with `--force`, as a user re-renders a scene
//! (its frames reuse the files of its previous run).

use std::process::Command;
use std::time::{Duration, Instant};

fn main() {
    let runs: usize = std::env::var("ELASTO_BENCH_RUNS")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(7)
        .max(1);
    let out = tempfile::tempdir().expect("a temporary folder");
    let variants: [(&str, &[&str]); 4] = [
        ("--no-render", &["--no-render"]),
        ("--video apng", &["--video", "apng"]),
        ("--video none (PNG frames only)", &["--video", "none"]),
        ("default videos", &[]),
    ];
    let mut times: Vec<Vec<Duration>> = vec![Vec::new(); variants.len()];
    for _ in 0..runs {
        for (index, ((_, flags), times)) in variants.iter().zip(&mut times).enumerate() {
            let start = Instant::now();
            let status = Command::new(env!("CARGO_BIN_EXE_elasto"))
                .args(["run", "--quiet", "--force", "--out"])
                .arg(out.path().join(format!("variant-{index}")))
                .args(*flags)
                .status()
                .expect("elasto runs");
            assert!(status.success(), "elasto run {flags:?} failed");
            times.push(start.elapsed());
        }
    }
    let medians: Vec<f64> = times.iter_mut().map(|t| median(t)).collect();
    println!("report-drop-2d, 300 frames at 1280x720, median of {runs} runs");
    println!("{:<32} {:>8} {:>14}", "run", "wall s", "/ --no-render");
    for ((name, _), seconds) in variants.iter().zip(&medians) {
        println!("{name:<32} {seconds:>8.3} {:>14.2}", seconds / medians[0]);
    }
}

/// The median in seconds.
fn median(times: &mut [Duration]) -> f64 {
    times.sort();
    times[times.len() / 2].as_secs_f64()
}
