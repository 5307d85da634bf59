//! Parameter sweeps: many runs of one scene with some keys varied (`elasto sweep`).
//!
//! A sweep is a list of varied keys, each with a list of values
//! (`--vary KEY=V1,V2,…`, ranges, or a sweep file's `[vary]` table, see
//! [`parse_vary`]), expanded by [`expand`] into [`RunSpec`]s: the cartesian
//! product, or the values paired position by position with `zip`. Each run is
//! the scene with the sweep's `--set` overrides and then the run's own
//! overrides ([`RunSpec::overrides`]), and goes to its own folder
//! ([`RunSpec::folder_name`]).

mod sweep_error;
mod vary;

pub use sweep_error::SweepError;
pub use vary::{
    AxisOrigin, MAX_FOLDER_NAME_BYTES, MAX_RUNS, RunSpec, VaryAxis, VaryValue, axis_from_toml,
    expand, parse_vary,
};
