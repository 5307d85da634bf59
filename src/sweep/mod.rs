//! Parameter sweeps: many runs of one scene with some keys varied (`elasto sweep`).
//!
//! A sweep is a list of varied keys, each with a list of values
//! (`--vary KEY=V1,V2,…`, ranges, or a sweep file's `[vary]` table, see
//! [`parse_vary`] and [`SweepFile`]), expanded by [`expand`] into
//! [`RunSpec`]s: the cartesian product, or the values paired position by
//! position with `zip`. Each run is the scene with the sweep's `--set`
//! overrides and then the run's own overrides ([`RunSpec::overrides`]), and
//! goes to its own folder ([`RunSpec::folder_name`]), where it runs as a
//! child `elasto run` ([`ChildRun`]) and leaves its record and completion
//! marker ([`RunRecord`]). From the folders, the sweep's table
//! ([`write_csv`], [`write_json`], each run summarised by [`RunSummary`])
//! and its side-by-side images ([`TileGrid`]) are made — by the sweep
//! itself or, after sharded runs, by `--collect`.

mod child_run;
mod collect;
mod contact_sheet;
mod label_text;
mod run_record;
mod run_summary;
mod sweep_error;
mod sweep_file;
mod sweep_progress;
mod sweep_table;
mod vary;

pub use child_run::{ChildOutcome, ChildRun, RUN_LOG_FILE};
pub use collect::{Collected, SheetOptions, collect};
pub use contact_sheet::{MAX_COMPARISON_SIZE, MAX_SHEET_SIZE, TileGrid, read_frame, run_frames};
pub use run_record::{
    RUN_RECORD_FILE, RecordError, RunIdentity, RunRecord, RunStatus, write_atomically,
};
pub use run_summary::RunSummary;
pub use sweep_error::SweepError;
pub use sweep_file::{SweepFile, is_sweep_file};
pub use sweep_progress::{CurrentRun, ProgressStyleChoice, SweepProgress};
pub use sweep_table::{
    RowStatus, SUMMARY_COLUMNS, SweepDescription, SweepRow, TableError, write_csv, write_json,
};
pub use vary::{
    AxisOrigin, MAX_FOLDER_NAME_BYTES, MAX_RUNS, RunSpec, VaryAxis, VaryValue, axis_from_toml,
    expand, parse_vary,
};
