//! The default scene end to end, as a user runs it (issue 13, item 5): the
//! `elasto` binary renders report-drop-2d (300 frames at 1280x720) with the
//! APNG as its only video, against the same run with `--no-render`.
//!
//! Run with `cargo bench --bench default_run`. The two runs alternate, so
//! that a slower spell of a shared machine hits both; each row is the median
//! wall time over the runs (`ELASTO_BENCH_RUNS`, default 7), and the ratio
//! is that of the medians. The default videos (APNG and MP4) and the PNG
//! frames alone are timed too. Each variant re-runs
//! into a folder of its own with `--force`, as a user re-renders a scene
//! (its frames reuse the files of its previous run). The rendering runs
//! also print `--profile`'s cores busy over the rendering after the
//! simulation, and over its frames alone (from the first frame sent to be
//! drawn to the last written, after the camera, backdrop and base are
//! made): the process's CPU time over the wall time of that stretch, the
//! median over the runs.
//!
//! One more variant runs the APNG with
//! Mesa's shader cache off (`MESA_SHADER_CACHE_DISABLE=true`): what the
//! first run on a new machine costs, when llvmpipe compiles every shader
//! (it keeps them in `~/.cache/mesa_shader_cache` for the runs after).

use std::process::Command;
use std::time::{Duration, Instant};

/// A run of the bench: its name, its flags, and the environment it runs in.
type Variant = (
    &'static str,
    &'static [&'static str],
    &'static [(&'static str, &'static str)],
);

fn main() {
    let runs: usize = std::env::var("ELASTO_BENCH_RUNS")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(7)
        .max(1);
    let out = tempfile::tempdir().expect("a temporary folder");
    let variants: [Variant; 5] = [
        ("--no-render", &["--no-render"], &[]),
        ("--video apng", &["--video", "apng"], &[]),
        ("--video none (PNG frames only)", &["--video", "none"], &[]),
        ("default videos", &[], &[]),
        (
            "--video apng, no shader cache",
            &["--video", "apng"],
            &[("MESA_SHADER_CACHE_DISABLE", "true")],
        ),
    ];
    let rows = [
        "rendering after the simulation",
        "frames drawn, encoded and written",
    ];
    let mut times: Vec<Vec<Duration>> = vec![Vec::new(); variants.len()];
    let mut busy: Vec<[Vec<f64>; 2]> = vec![Default::default(); variants.len()];
    for _ in 0..runs {
        for (index, (_, flags, environment)) in variants.iter().enumerate() {
            let mut command = Command::new(env!("CARGO_BIN_EXE_elasto"));
            command
                .args(["run", "--quiet", "--force", "--profile", "--out"])
                .arg(out.path().join(format!("variant-{index}")))
                .args(*flags)
                .envs(environment.iter().copied());
            let start = Instant::now();
            let output = command.output().expect("elasto runs");
            times[index].push(start.elapsed());
            assert!(output.status.success(), "elasto run {flags:?} failed");
            let profile = String::from_utf8_lossy(&output.stdout);
            for (row, busy) in rows.iter().zip(&mut busy[index]) {
                if let Some(cores) = cores_busy(&profile, row) {
                    busy.push(cores);
                }
            }
        }
    }
    let medians: Vec<f64> = times.iter_mut().map(|t| median(t)).collect();
    println!("report-drop-2d, 300 frames at 1280x720, median of {runs} runs");
    println!(
        "{:<32} {:>8} {:>14} {:>21} {:>12}",
        "run", "wall s", "/ --no-render", "cores busy rendering", "its frames"
    );
    for (((name, _, _), seconds), busy) in variants.iter().zip(&medians).zip(&mut busy) {
        let [rendering, frames] = busy.each_mut().map(|busy| {
            if busy.is_empty() {
                "-".to_owned()
            } else {
                busy.sort_by(f64::total_cmp);
                format!("{:.2}", busy[busy.len() / 2])
            }
        });
        println!(
            "{name:<32} {seconds:>8.3} {:>14.2} {rendering:>21} {frames:>12}",
            seconds / medians[0]
        );
    }
}

/// The cores busy on `--profile`'s span row `name`, e.g.
/// `rendering after the simulation  0.212   1.86 of 2 cores busy`.
fn cores_busy(profile: &str, name: &str) -> Option<f64> {
    let row = profile.lines().find(|line| line.starts_with(name))?;
    let words: Vec<&str> = row.split_whitespace().collect();
    let of = words.iter().position(|&w| w == "of")?;
    words.get(of.checked_sub(1)?)?.parse().ok()
}

/// The median in seconds.
fn median(times: &mut [Duration]) -> f64 {
    times.sort();
    times[times.len() / 2].as_secs_f64()
}
