//! Progress of a long phase: a bar on a terminal, periodic plain lines otherwise, or nothing.

use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::time::Instant;

/// How progress is shown.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProgressMode {
    /// An animated bar (stderr is a terminal).
    Bar,
    /// A plain line on stderr at every 10% (logs, CI).
    Lines,
    /// Nothing (`--quiet`).
    Quiet,
}

impl ProgressMode {
    /// Bar on a terminal, lines otherwise, nothing when quiet.
    pub fn detect(quiet: bool) -> Self {
        if quiet {
            ProgressMode::Quiet
        } else if std::io::stderr().is_terminal() {
            ProgressMode::Bar
        } else {
            ProgressMode::Lines
        }
    }
}

/// Reports `done` out of `total` items of one phase.
pub struct Progress {
    mode: ProgressMode,
    label: &'static str,
    total: usize,
    bar: Option<ProgressBar>,
    next_tenth: usize,
    start: Instant,
}

impl Progress {
    /// Starts a phase of `total` items.
    pub fn start(mode: ProgressMode, label: &'static str, total: usize) -> Self {
        let bar = (mode == ProgressMode::Bar).then(|| {
            let bar = ProgressBar::new(total as u64);
            let style = ProgressStyle::with_template(
                "{prefix:>10} [{bar:32}] {pos}/{len} frames  {elapsed_precise} ETA {eta_precise}  {msg}",
            )
            .expect("the progress template is valid")
            .progress_chars("=> ");
            bar.set_style(style);
            bar.set_prefix(label);
            bar
        });
        Self {
            mode,
            label,
            total,
            bar,
            next_tenth: 1,
            start: Instant::now(),
        }
    }

    /// `done` items are finished; `detail` describes the latest one.
    pub fn update(&mut self, done: usize, detail: impl FnOnce() -> String) {
        match self.mode {
            ProgressMode::Quiet => {}
            ProgressMode::Bar => {
                if let Some(bar) = &self.bar {
                    bar.set_position(done as u64);
                    bar.set_message(detail());
                }
            }
            ProgressMode::Lines => {
                // Print when crossing each 10% mark (and once at the end).
                let tenths = done * 10 / self.total.max(1);
                if tenths >= self.next_tenth || done == self.total {
                    self.next_tenth = tenths + 1;
                    eprintln!(
                        "{}: {done}/{} frames ({}%), {:.1} s elapsed, {}",
                        self.label,
                        self.total,
                        done * 100 / self.total.max(1),
                        self.start.elapsed().as_secs_f64(),
                        detail()
                    );
                }
            }
        }
    }

    /// Ends the phase, clearing the bar.
    pub fn finish(self) {
        if let Some(bar) = self.bar {
            bar.finish_and_clear();
        }
    }
}
