//! The rows of a study and their two written forms: `study.csv` (one row
//! per run plus the reference) and `study.md` (a table to paste).

use super::RunErrors;
use crate::output::format_number;
use std::fmt::Write;

/// How a run ended.
#[derive(Debug, Clone, PartialEq)]
pub enum RunStatus {
    /// Every frame was simulated.
    Ok,
    /// The run stopped with this error.
    Failed(String),
}

/// One run of a study, measured.
#[derive(Debug, Clone, PartialEq)]
pub struct StudyRow {
    /// `reference`, or the run's index.
    pub run: String,
    /// The run's value of each varied key, as TOML text (in the study's key order).
    pub values: Vec<String>,
    /// The series: solver method and time integrator, e.g. `newton / bdf2`.
    pub series: String,
    /// The time step, in seconds.
    pub dt: f64,
    /// How the run ended.
    pub status: RunStatus,
    /// Median wall time over the repeats, in milliseconds (setup and
    /// simulation; no files are written).
    pub wall_ms: f64,
    /// Median CPU time of the process over the repeats (all threads), in
    /// milliseconds: steadier than the wall time on a shared machine (NaN
    /// where the platform does not tell).
    pub cpu_ms: f64,
    /// How many times the run was timed.
    pub repeats: usize,
    /// Solver iterations over the whole run.
    pub iterations: usize,
    /// Time steps taken.
    pub steps: usize,
    /// Steps that hit the iteration cap.
    pub unconverged_steps: usize,
    /// Steps whose line search stalled.
    pub stalled_steps: usize,
    /// Errors against the reference (`None` for a failed run).
    pub errors: Option<RunErrors>,
}

impl StudyRow {
    /// Solver iterations per time step.
    pub fn iterations_per_step(&self) -> f64 {
        self.iterations as f64 / self.steps.max(1) as f64
    }

    fn status_text(&self) -> String {
        match &self.status {
            RunStatus::Ok => "ok".to_owned(),
            RunStatus::Failed(reason) => format!("failed: {reason}"),
        }
    }
}

/// The rows of a study, with the varied keys that label them.
#[derive(Debug, Clone, PartialEq)]
pub struct StudyTable {
    /// The varied keys, one column each.
    pub keys: Vec<String>,
    /// The reference first, then the runs in order.
    pub rows: Vec<StudyRow>,
}

/// The columns of `study.csv` after the varied keys.
pub const STUDY_COLUMNS: [&str; 14] = [
    "series",
    "dt",
    "status",
    "wall_ms",
    "cpu_ms",
    "repeats",
    "iterations",
    "iterations_per_step",
    "unconverged_steps",
    "stalled_steps",
    "error_kind",
    "trajectory_error",
    "energy_error",
    "steps",
];

impl StudyTable {
    /// `study.csv`: a header `run,<varied keys>,series,dt,...` and one line per row.
    pub fn csv(&self) -> String {
        let mut text = String::new();
        let header: Vec<String> = std::iter::once("run".to_owned())
            .chain(self.keys.iter().cloned())
            .chain(STUDY_COLUMNS.iter().map(|c| (*c).to_owned()))
            .collect();
        text.push_str(&csv_line(&header));
        for row in &self.rows {
            let (kind, trajectory, energy) = match &row.errors {
                Some(e) => (e.kind.name(), num(e.trajectory), num(e.energy)),
                None => ("", String::new(), String::new()),
            };
            let fields: Vec<String> = std::iter::once(row.run.clone())
                .chain(row.values.iter().cloned())
                .chain([
                    row.series.clone(),
                    num(row.dt),
                    row.status_text(),
                    format!("{:.3}", row.wall_ms),
                    format!("{:.3}", row.cpu_ms),
                    row.repeats.to_string(),
                    row.iterations.to_string(),
                    format!("{:.3}", row.iterations_per_step()),
                    row.unconverged_steps.to_string(),
                    row.stalled_steps.to_string(),
                    kind.to_owned(),
                    trajectory,
                    energy,
                    row.steps.to_string(),
                ])
                .collect();
            text.push_str(&csv_line(&fields));
        }
        text
    }

    /// `study.md`: a Markdown table, one line per row.
    pub fn markdown(&self) -> String {
        let mut text = String::from("| run | series |");
        for key in &self.keys {
            let _ = write!(text, " {key} |");
        }
        text.push_str(
            " dt (s) | wall ms | CPU ms | its/step | unconverged steps | trajectory error | energy error | status |\n",
        );
        text.push_str("|---|---|");
        text.push_str(&"---|".repeat(self.keys.len()));
        text.push_str("--:|--:|--:|--:|--:|--:|--:|---|\n");
        for row in &self.rows {
            let _ = write!(text, "| {} | {} |", row.run, row.series);
            for value in &row.values {
                let _ = write!(text, " {} |", value.replace('|', "\\|"));
            }
            let (trajectory, energy) = match &row.errors {
                Some(e) => (short(e.trajectory), short(e.energy)),
                None => ("—".to_owned(), "—".to_owned()),
            };
            let _ = writeln!(
                text,
                " {} | {:.0} | {:.0} | {:.1} | {} | {} | {} | {} |",
                short(row.dt),
                row.wall_ms,
                row.cpu_ms,
                row.iterations_per_step(),
                row.unconverged_steps,
                trajectory,
                energy,
                row.status_text().replace('|', "\\|"),
            );
        }
        text
    }
}

/// A number in full (round-trip) precision, in the data files' one form.
fn num(x: f64) -> String {
    format_number(x)
}

/// A number with three significant digits.
fn short(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        format!("{x}")
    } else {
        format!("{x:.2e}")
    }
}

/// One CSV line; a field with a comma, quote or line break is quoted (RFC 4180).
fn csv_line(fields: &[String]) -> String {
    let quoted: Vec<String> = fields
        .iter()
        .map(|f| {
            if f.contains([',', '"', '\n', '\r']) {
                format!("\"{}\"", f.replace('"', "\"\""))
            } else {
                f.clone()
            }
        })
        .collect();
    quoted.join(",") + "\n"
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::ErrorKind;

    fn row(run: &str, value: &str, errors: Option<RunErrors>) -> StudyRow {
        StudyRow {
            run: run.into(),
            values: vec![value.into()],
            series: "newton / bdf2".into(),
            dt: 0.01,
            status: if errors.is_some() {
                RunStatus::Ok
            } else {
                RunStatus::Failed("step 3, frame 1: NaN".into())
            },
            wall_ms: 12.4,
            cpu_ms: 20.0,
            repeats: 3,
            iterations: 30,
            steps: 10,
            unconverged_steps: 0,
            stalled_steps: 0,
            errors,
        }
    }

    #[test]
    fn csv_has_a_header_and_a_line_per_row_with_quoted_vectors() {
        let errors = RunErrors {
            kind: ErrorKind::Vertices,
            trajectory: 0.125,
            energy: 0.5,
        };
        let table = StudyTable {
            keys: vec!["mesh.velocity".into()],
            rows: vec![
                row("reference", "[0, -1]", Some(errors)),
                row("0", "[0, -5]", None),
            ],
        };
        let csv = table.csv();
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines.len(), 3);
        assert!(lines[0].starts_with("run,mesh.velocity,series,dt,status,wall_ms"));
        assert!(
            lines[1].starts_with(
                "reference,\"[0, -1]\",newton / bdf2,0.01,ok,12.400,20.000,3,30,3.000"
            )
        );
        assert!(lines[1].ends_with(",vertices,0.125,0.5,10"));
        assert!(
            lines[2].contains(",failed: step 3, frame 1: NaN,")
                || lines[2].contains("\"failed: step 3, frame 1: NaN\"")
        );
        let md = table.markdown();
        assert_eq!(md.lines().count(), 4);
        assert!(md.contains("| reference | newton / bdf2 | [0, -1] | 1.00e-2 | 12 | 20 | 3.0 | 0 | 1.25e-1 | 5.00e-1 | ok |"), "{md}");
    }
}
