//! `elasto run --profile`: where the time of a run went, phase by phase.
//!
//! Every output frame contributes one duration per phase: the solver's
//! phases summed over the frame's substeps (frame 0, the initial state, is
//! not simulated and does not count for them), and the rendering phases of
//! its image (which `stats.csv` does not carry: its rows do not wait for
//! the images). The table gives, per phase, the median over the frames in
//! milliseconds and the total over the run in seconds, and the run's wall
//! time. Rendering phases run on other threads than the simulation (drawing
//! on the main thread, PNG and video encoding on workers), so the totals can
//! add up to more than the wall time: that is the work that overlapped.
//!
//! The run's wall time, and that of the rendering after the simulation when
//! the frames wait for the whole run (automatic camera or colour range) and
//! of its part from the first frame sent to be drawn to the last written
//! (after the camera is framed and the backdrop and base are drawn), come
//! with the cores busy on average over each: the process's CPU time over
//! the wall time (see `process_clock`), out of the machine's cores.

use super::process_clock::Span;
use crate::encode::FrameCost;
use crate::solver::PhaseTimes;
use std::fmt::Write as _;
use std::time::Duration;

/// The phases of the table, in order.
const PHASES: [&str; 10] = [
    "assembly",
    "factorisation",
    "solve",
    "line search",
    "other simulation",
    "draw",
    "readback",
    "paste + legend",
    "PNG encode + write",
    "video encode + write",
];
const SIMULATION_PHASES: usize = 5;
/// The rows of a contact scene's own work, within the solver's phases.
const CONTACT_ROWS: [&str; 4] = [
    "  contact broad phase",
    "  contact CCD",
    "  contact assembly",
    "  pattern growth",
];

/// Per-frame durations of every phase.
#[derive(Debug, Default)]
pub struct RunProfile {
    simulated: Vec<[Duration; SIMULATION_PHASES]>,
    /// Per simulated frame of a contact scene: the broad phase (part of
    /// assembly and line search), CCD (part of the line search), the
    /// stencils' derivatives and assembly, and the pattern's growth (parts
    /// of assembly).
    contact: Vec<[Duration; CONTACT_ROWS.len()]>,
    rendered: Vec<[Duration; PHASES.len() - SIMULATION_PHASES]>,
}

/// The stretches of a run the table ends with.
#[derive(Debug, Clone, Copy)]
pub struct RunSpans {
    /// The whole run.
    pub run: Span,
    /// The rendering after the simulation, when the frames waited for it.
    pub rendering: Option<Span>,
    /// Its part from the first frame sent to be drawn to the last written.
    pub frames: Option<Span>,
}

impl RunProfile {
    /// Records a simulated frame: its solver phases and its whole wall
    /// time, and for a contact scene its contact work ([`CONTACT_ROWS`]).
    pub fn simulated(
        &mut self,
        times: &PhaseTimes,
        wall: Duration,
        contact: Option<[Duration; CONTACT_ROWS.len()]>,
    ) {
        self.contact.extend(contact);
        let solver = times.assembly + times.factorisation + times.solve + times.line_search;
        self.simulated.push([
            times.assembly,
            times.factorisation,
            times.solve,
            times.line_search,
            wall.saturating_sub(solver),
        ]);
    }

    /// Records a rendered and written frame.
    pub fn rendered(&mut self, cost: &FrameCost) {
        self.rendered.push([
            cost.timings.draw,
            cost.timings.readback,
            cost.timings.overlay,
            cost.png,
            cost.video,
        ]);
    }

    /// The table, ending with the run's wall time and, when the frames were
    /// rendered after the simulation, that rendering's and its frames'; each
    /// with the cores busy over it out of `cores`.
    pub fn table(&self, spans: &RunSpans, cores: usize) -> String {
        let mut text = String::new();
        let _ = writeln!(
            text,
            "{:<22} {:>8} {:>14} {:>9}",
            "phase", "frames", "median ms", "total s"
        );
        let columns = |phase: usize| -> Vec<Duration> {
            if phase < SIMULATION_PHASES {
                self.simulated.iter().map(|row| row[phase]).collect()
            } else {
                let phase = phase - SIMULATION_PHASES;
                self.rendered.iter().map(|row| row[phase]).collect()
            }
        };
        for (phase, name) in PHASES.iter().enumerate() {
            let values = columns(phase);
            if values.is_empty() {
                continue;
            }
            let total: Duration = values.iter().sum();
            let _ = writeln!(
                text,
                "{name:<22} {:>8} {:>14.3} {:>9.3}",
                values.len(),
                median(&values).as_secs_f64() * 1e3,
                total.as_secs_f64()
            );
        }
        for (k, name) in CONTACT_ROWS.iter().enumerate() {
            let values: Vec<Duration> = self.contact.iter().map(|row| row[k]).collect();
            if values.is_empty() {
                continue;
            }
            let total: Duration = values.iter().sum();
            let _ = writeln!(
                text,
                "{name:<22} {:>8} {:>14.3} {:>9.3}   (within assembly and line search)",
                values.len(),
                median(&values).as_secs_f64() * 1e3,
                total.as_secs_f64()
            );
        }
        let rows = [
            ("wall time of the run", Some(spans.run)),
            ("rendering after the simulation", spans.rendering),
            ("frames drawn, encoded and written", spans.frames),
        ];
        for (name, span) in rows {
            let Some(span) = span else { continue };
            let _ = write!(text, "{name:<46} {:>9.3}", span.wall.as_secs_f64());
            if let Some(busy) = span.cores_busy() {
                let _ = write!(text, "   {busy:.2} of {cores} cores busy");
            }
            text.push('\n');
        }
        text
    }
}

/// The median (the upper one of an even count).
fn median(values: &[Duration]) -> Duration {
    let mut sorted = values.to_vec();
    sorted.sort();
    sorted[sorted.len() / 2]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::FrameTimings;

    fn ms(v: u64) -> Duration {
        Duration::from_millis(v)
    }

    /// A span of `wall` ms, with `cpu` ms of CPU time when known.
    fn span(wall: u64, cpu: Option<u64>) -> Span {
        Span {
            wall: ms(wall),
            cpu: cpu.map(ms),
        }
    }

    fn spans(run: Span, rendering: Option<Span>, frames: Option<Span>) -> RunSpans {
        RunSpans {
            run,
            rendering,
            frames,
        }
    }

    /// The cells of the row of `phase`.
    fn row(table: &str, phase: &str) -> Vec<String> {
        let line = table
            .lines()
            .find(|l| l.starts_with(phase))
            .unwrap_or_else(|| panic!("no row {phase} in\n{table}"));
        line[phase.len()..]
            .split_whitespace()
            .map(str::to_owned)
            .collect()
    }

    #[test]
    fn the_table_gives_medians_and_totals_per_phase() {
        let mut profile = RunProfile::default();
        for (assembly, wall) in [(1, 10), (3, 12), (2, 20)] {
            let times = PhaseTimes {
                assembly: ms(assembly),
                factorisation: ms(3),
                solve: ms(1),
                line_search: ms(1),
                pattern_growth: Duration::ZERO,
            };
            profile.simulated(&times, ms(wall), None);
        }
        for draw in [30, 10, 20, 40] {
            profile.rendered(&FrameCost {
                timings: FrameTimings {
                    draw: ms(draw),
                    readback: ms(1),
                    overlay: Duration::ZERO,
                },
                png: ms(3),
                video: ms(5),
            });
        }
        let table = profile.table(&spans(span(1500, None), None, None), 2);
        assert_eq!(row(&table, "assembly"), ["3", "2.000", "0.006"]);
        assert_eq!(row(&table, "factorisation"), ["3", "3.000", "0.009"]);
        assert_eq!(row(&table, "solve"), ["3", "1.000", "0.003"]);
        // wall - (assembly + factorisation + solve + line search) = 10 - 6, 12 - 8, 20 - 7 ms.
        assert_eq!(row(&table, "other simulation"), ["3", "4.000", "0.021"]);
        // Median of 10, 20, 30, 40: the upper middle value.
        assert_eq!(row(&table, "draw"), ["4", "30.000", "0.100"]);
        assert_eq!(row(&table, "video encode + write"), ["4", "5.000", "0.020"]);
        assert_eq!(row(&table, "wall time of the run"), ["1.500"]);
        // No contact: no contact rows.
        assert!(!table.contains("contact"));
        profile.simulated(
            &PhaseTimes::default(),
            ms(5),
            Some([ms(2), ms(1), ms(4), ms(3)]),
        );
        let table = profile.table(&spans(span(1500, None), None, None), 2);
        assert_eq!(
            row(&table, "  contact broad phase")[..3],
            ["1", "2.000", "0.002"]
        );
        assert_eq!(row(&table, "  contact CCD")[..3], ["1", "1.000", "0.001"]);
        assert_eq!(
            row(&table, "  contact assembly")[..3],
            ["1", "4.000", "0.004"]
        );
        assert_eq!(
            row(&table, "  pattern growth")[..3],
            ["1", "3.000", "0.003"]
        );
    }

    #[test]
    fn a_run_without_rendering_has_no_rendering_rows() {
        let mut profile = RunProfile::default();
        profile.simulated(&PhaseTimes::default(), ms(2), None);
        let table = profile.table(&spans(span(2, None), None, None), 2);
        assert_eq!(row(&table, "other simulation"), ["1", "2.000", "0.002"]);
        assert!(!table.contains("draw"), "{table}");
    }

    #[test]
    fn spans_show_the_cores_busy_over_them() {
        let mut profile = RunProfile::default();
        profile.simulated(&PhaseTimes::default(), ms(2), None);
        let rendering = span(200, Some(370));
        let frames = span(180, Some(354));
        let table = profile.table(
            &spans(span(400, Some(620)), Some(rendering), Some(frames)),
            2,
        );
        assert_eq!(
            row(&table, "wall time of the run"),
            ["0.400", "1.55", "of", "2", "cores", "busy"]
        );
        assert_eq!(
            row(&table, "rendering after the simulation"),
            ["0.200", "1.85", "of", "2", "cores", "busy"]
        );
        assert_eq!(
            row(&table, "frames drawn, encoded and written"),
            ["0.180", "1.97", "of", "2", "cores", "busy"]
        );
        // Without a CPU clock, the wall time alone.
        let table = profile.table(&spans(span(400, None), None, None), 2);
        assert_eq!(row(&table, "wall time of the run"), ["0.400"]);
        assert!(!table.contains("rendering after"), "{table}");
    }
}
