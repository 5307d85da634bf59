//! Progress of a sweep: one bar (runs done, failed, ETA, the current runs' frames) on a terminal, a plain line per finished run otherwise.

use indicatif::{ProgressBar, ProgressStyle};
use std::time::Instant;

/// How progress is shown.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProgressStyleChoice {
    /// An animated bar (stderr is a terminal).
    Bar,
    /// A plain line on stderr per finished run (logs, CI).
    Lines,
    /// Nothing.
    Quiet,
}

/// Reports the runs of a sweep as they start and end.
pub struct SweepProgress {
    style: ProgressStyleChoice,
    bar: Option<ProgressBar>,
    total: usize,
    done: usize,
    failed: usize,
    start: Instant,
}

/// A run going on: its folder name and frames done / total.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CurrentRun {
    /// The run's index.
    pub index: usize,
    /// Frames written so far.
    pub frames_done: usize,
    /// Frames of the run.
    pub frames: usize,
}

impl SweepProgress {
    /// Starts reporting `total` runs.
    pub fn start(style: ProgressStyleChoice, total: usize) -> Self {
        let bar = (style == ProgressStyleChoice::Bar).then(|| {
            let bar = ProgressBar::new(total as u64);
            bar.set_style(
                ProgressStyle::with_template(
                    "     sweep [{bar:32}] {pos}/{len} runs  {elapsed_precise} ETA {eta_precise}  {msg}",
                )
                .expect("the progress template is valid")
                .progress_chars("=> "),
            );
            bar
        });
        Self {
            style,
            bar,
            total,
            done: 0,
            failed: 0,
            start: Instant::now(),
        }
    }

    /// Shows the runs going on now.
    pub fn current(&mut self, runs: &[CurrentRun]) {
        if let Some(bar) = &self.bar {
            let now: Vec<String> = runs
                .iter()
                .map(|r| format!("#{} {}/{}", r.index, r.frames_done, r.frames))
                .collect();
            bar.set_message(format!(
                "{} failed | running: {}",
                self.failed,
                now.join(", ")
            ));
        }
    }

    /// A run ended (`failure`: why it failed).
    pub fn finished(&mut self, folder: &str, failure: Option<&str>, wall_seconds: f64) {
        self.done += 1;
        if failure.is_some() {
            self.failed += 1;
        }
        match self.style {
            ProgressStyleChoice::Quiet => {}
            ProgressStyleChoice::Bar => {
                if let Some(bar) = &self.bar {
                    if let Some(reason) = failure {
                        bar.println(format!("failed: {folder}: {reason}"));
                    }
                    bar.set_position(self.done as u64);
                }
            }
            ProgressStyleChoice::Lines => {
                let elapsed = self.start.elapsed().as_secs_f64();
                let left = self.total - self.done;
                let eta = elapsed / self.done as f64 * left as f64;
                let outcome = match failure {
                    None => "ok".to_owned(),
                    Some(reason) => format!("failed: {reason}"),
                };
                eprintln!(
                    "sweep: {}/{} runs done, {} failed, ETA {eta:.0} s: {folder} {outcome} in {wall_seconds:.1} s",
                    self.done, self.total, self.failed
                );
            }
        }
    }

    /// Clears the bar.
    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}
