//! `sweep.csv` (one row per run) and `sweep.json` (the whole sweep, machine-readable).

use super::run_record::write_atomically;
use super::{RunSpec, RunSummary, VaryAxis};
use crate::output::format_number;
use std::path::{Path, PathBuf};

/// What became of one run.
#[derive(Debug, Clone, PartialEq)]
pub enum RowStatus {
    /// Finished with every output complete.
    Ok,
    /// Finished with a non-zero exit code, or killed; the reason.
    Failed(String),
    /// Not run (yet): another shard's run not collected, or the sweep stopped first.
    Skipped,
}

impl RowStatus {
    /// `ok`, `failed: REASON` or `skipped`.
    pub fn text(&self) -> String {
        match self {
            RowStatus::Ok => "ok".into(),
            RowStatus::Failed(reason) => format!("failed: {reason}"),
            RowStatus::Skipped => "skipped".into(),
        }
    }
}

/// One row of the sweep table.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepRow {
    /// The run.
    pub spec: RunSpec,
    /// What became of it.
    pub status: RowStatus,
    /// The exit code of `elasto run` (none when skipped or killed by a signal).
    pub exit_code: Option<i32>,
    /// Wall time in seconds (none when skipped).
    pub wall_seconds: Option<f64>,
    /// The summary of its `stats.csv` (none without rows).
    pub summary: Option<RunSummary>,
}

/// The sweep as a whole, for `sweep.json`.
#[derive(Debug, Clone, Copy)]
pub struct SweepDescription<'a> {
    /// The sweep's name.
    pub name: &'a str,
    /// The scene argument (file or built-in name).
    pub scene: &'a str,
    /// Whether the lists were zipped.
    pub zip: bool,
    /// The overrides of every run (`key=value`).
    pub set: &'a [String],
    /// The varied keys.
    pub axes: &'a [VaryAxis],
}

/// The summary columns of `sweep.csv`, after `index`, `folder`, the varied
/// keys, `status`, `exit_code` and `wall_seconds`.
pub const SUMMARY_COLUMNS: [&str; 11] = [
    "frames",
    "newton_iterations",
    "unconverged_steps",
    "stalled_steps",
    "min_ground_gap",
    "min_volume_ratio",
    "energy_start",
    "energy_end",
    "com_x",
    "com_y",
    "com_z",
];

/// A file of the sweep that could not be written.
#[derive(Debug, thiserror::Error)]
#[error("cannot write {}: {source}", path.display())]
pub struct TableError {
    /// The file.
    pub path: PathBuf,
    /// The I/O error.
    pub source: std::io::Error,
}

/// Writes `sweep.csv`: `index`, `folder`, one column per varied key (its
/// TOML value), `status`, `exit_code`, `wall_seconds`, then
/// [`SUMMARY_COLUMNS`] (empty when the run left no rows).
pub fn write_csv(path: &Path, axes: &[VaryAxis], rows: &[SweepRow]) -> Result<(), TableError> {
    let mut writer = csv::Writer::from_writer(Vec::new());
    let mut header: Vec<String> = vec!["index".into(), "folder".into()];
    header.extend(axes.iter().map(|a| a.key.clone()));
    header.extend(["status", "exit_code", "wall_seconds"].map(String::from));
    header.extend(SUMMARY_COLUMNS.map(String::from));
    let io = |e: csv::Error| TableError {
        path: path.to_owned(),
        source: e.into(),
    };
    writer.write_record(&header).map_err(io)?;
    for row in rows {
        let mut record: Vec<String> = vec![row.spec.index.to_string(), row.spec.folder_name()];
        record.extend(row.spec.values.iter().map(|(_, v)| v.toml.clone()));
        record.push(row.status.text());
        record.push(row.exit_code.map(|c| c.to_string()).unwrap_or_default());
        record.push(
            row.wall_seconds
                .map(|s| format!("{s:.3}"))
                .unwrap_or_default(),
        );
        match &row.summary {
            Some(s) => record.extend([
                s.frames.to_string(),
                s.newton_iterations.to_string(),
                s.unconverged_steps.to_string(),
                s.stalled_steps.to_string(),
                s.min_ground_gap.map(format_number).unwrap_or_default(),
                format_number(s.min_volume_ratio),
                format_number(s.energy_start),
                format_number(s.energy_end),
                format_number(s.final_com[0]),
                format_number(s.final_com[1]),
                format_number(s.final_com[2]),
            ]),
            None => record.extend(SUMMARY_COLUMNS.map(|_| String::new())),
        }
        writer.write_record(&record).map_err(io)?;
    }
    let bytes = writer.into_inner().map_err(|e| TableError {
        path: path.to_owned(),
        source: e.into_error(),
    })?;
    write_atomically(path, &bytes).map_err(|(path, source)| TableError { path, source })
}

/// Writes `sweep.json`: the sweep's description and every run with its
/// values, status, exit code, wall time and summary.
pub fn write_json(
    path: &Path,
    sweep: SweepDescription<'_>,
    rows: &[SweepRow],
) -> Result<(), TableError> {
    use serde_json::json;
    let axes: Vec<_> = sweep
        .axes
        .iter()
        .map(|a| json!({ "key": a.key, "values": a.values.iter().map(|v| &v.toml).collect::<Vec<_>>() }))
        .collect();
    let runs: Vec<_> = rows
        .iter()
        .map(|row| {
            let values: serde_json::Map<String, serde_json::Value> = row
                .spec
                .values
                .iter()
                .map(|(k, v)| (k.clone(), json!(v.toml)))
                .collect();
            let (status, reason) = match &row.status {
                RowStatus::Ok => ("ok", None),
                RowStatus::Failed(reason) => ("failed", Some(reason)),
                RowStatus::Skipped => ("skipped", None),
            };
            json!({
                "index": row.spec.index,
                "folder": row.spec.folder_name(),
                "label": row.spec.label(),
                "values": values,
                "status": status,
                "reason": reason,
                "exit_code": row.exit_code,
                "wall_seconds": row.wall_seconds,
                "summary": row.summary,
            })
        })
        .collect();
    let manifest = json!({
        "name": sweep.name,
        "scene": sweep.scene,
        "zip": sweep.zip,
        "set": sweep.set,
        "vary": axes,
        "runs": runs,
    });
    let text = serde_json::to_string_pretty(&manifest).expect("the manifest serialises");
    write_atomically(path, text.as_bytes()).map_err(|(path, source)| TableError { path, source })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep::{expand, parse_vary};

    #[test]
    fn csv_quotes_vector_values_and_leaves_missing_summaries_empty() {
        let axes = [parse_vary("mesh.velocity=[0,-1],[0,-5]").unwrap()];
        let runs = expand(&axes, false).unwrap();
        let summary = RunSummary::parse(
            "newton_iters,unconverged_steps,stalled_steps,min_height,min_volume_ratio,total_energy,com_x,com_y,com_z\n\
             3,0,0,0.5,0.9,2,1,2,0\n",
        );
        let rows = [
            SweepRow {
                spec: runs[0].clone(),
                status: RowStatus::Ok,
                exit_code: Some(0),
                wall_seconds: Some(1.5),
                summary,
            },
            SweepRow {
                spec: runs[1].clone(),
                status: RowStatus::Failed("simulation failed, frame 3".into()),
                exit_code: Some(1),
                wall_seconds: Some(0.25),
                summary: None,
            },
        ];
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sweep.csv");
        write_csv(&path, &axes, &rows).unwrap();
        let mut reader = csv::Reader::from_path(&path).unwrap();
        let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
        assert_eq!(
            header[..6],
            [
                "index",
                "folder",
                "mesh.velocity",
                "status",
                "exit_code",
                "wall_seconds"
            ]
        );
        assert_eq!(header.len(), 6 + SUMMARY_COLUMNS.len());
        let records: Vec<csv::StringRecord> = reader.records().map(Result::unwrap).collect();
        assert_eq!(&records[0][2], "[0,-1]");
        assert_eq!(&records[0][3], "ok");
        assert_eq!(&records[0][6], "1");
        assert_eq!(&records[0][7], "3");
        assert_eq!(&records[1][3], "failed: simulation failed, frame 3");
        assert!(records[1].iter().skip(6).all(str::is_empty));

        let json_path = dir.path().join("sweep.json");
        let description = SweepDescription {
            name: "s",
            scene: "report-drop-2d",
            zip: false,
            set: &[],
            axes: &axes,
        };
        write_json(&json_path, description, &rows).unwrap();
        let value: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&json_path).unwrap()).unwrap();
        assert_eq!(value["runs"][1]["status"], "failed");
        assert_eq!(value["runs"][0]["summary"]["newton_iterations"], 3);
        assert_eq!(value["runs"][1]["values"]["mesh.velocity"], "[0,-5]");
    }
}
