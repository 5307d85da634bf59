//! `stats.csv`: one row per output frame, written and flushed as each frame
//! is simulated, whatever the rendering does (its times are in `elasto run
//! --profile`'s table).

use super::OutputError;
use super::number_text::format_number as num;
use crate::sim::FrameStats;
use std::fmt::Write as _;
use std::fs::File;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::time::Duration;

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

/// The columns of `stats.csv` before the energies.
const LEADING_COLUMNS: &[&str] = &[
    "frame",
    "time",
    "newton_iters",
    "linear_solves",
    "backtracks",
];

/// The columns of `stats.csv` after the energies.
const TRAILING_COLUMNS: &[&str] = &[
    "total_energy",
    "com_x",
    "com_y",
    "com_z",
    "min_height",
    "min_volume_ratio",
    "sim_ms",
    "unconverged_steps",
    "stalled_steps",
    "assembly_ms",
    "factorisation_ms",
    "solve_ms",
    "line_search_ms",
    "min_distance",
    "contact_pairs",
    "broad_phase_ms",
    "ccd_ms",
    "ccd_budget_exhausted",
    "reanalyses",
    "subdivided_steps",
    "damped_steps",
    "boundary_error",
    "friction_dissipated",
    "projected_iterations",
];

/// The columns of `stats.csv`, in order, for a simulation whose energy
/// breakdown has the entries `energy_names` (`kinetic`, then one per energy
/// term of the scene: [`crate::sim::Simulation::energy_names`]).
///
/// `frame`: output frame index (frame 0 is the initial state); `time`: its
/// simulated time, s; `newton_iters`, `linear_solves`, `backtracks`: summed
/// over the frame's steps (0 for frame 0); then one column per energy entry
/// (`kinetic`, `elastic`, and `gravity`, `barrier`, ... for the effects the
/// scene has) and `total_energy`, at the frame's end; `com_x`, `com_y`,
/// `com_z`: centre of mass (`com_z` is 0 in 2D); `min_height`: lowest vertex
/// height above the ground (empty without a ground); `min_volume_ratio`:
/// smallest `J = det F` over the elements; `sim_ms`: wall time spent
/// simulating the frame; `unconverged_steps`: steps that hit the iteration
/// cap; `stalled_steps`: steps whose line search stalled before the
/// tolerance; `assembly_ms`, `factorisation_ms`, `solve_ms` (the triangular
/// solves), `line_search_ms`: the wall time of each solver phase;
/// `min_distance`: the smallest distance between two surface primitives
/// closer than the contact distance `d_hat`, or of a vertex closer to the
/// ground than its barrier width `a`, at the frame's end (empty when
/// nothing is that close, or without `[effects.contact]`); `contact_pairs`:
/// the contact stencils within `d_hat` at the last Newton iterate;
/// `broad_phase_ms`, `ccd_ms`: wall time finding candidate pairs and in
/// continuous collision detection; `ccd_budget_exhausted`: CCD queries that
/// ran out of their iteration budget and used the safe step reached (all 0
/// without contact); `reanalyses`: times the sparse Hessian's pattern grew
/// with new contact pairs and its symbolic factorisation was redone;
/// `subdivided_steps`: steps that did not converge whole and were retried
/// as shorter steps (`solver.max_subdivisions`); `damped_steps`: Newmark
/// steps that would have gained energy and were taken again as
/// backward-Euler steps (0 for the other schemes); `boundary_error`: the
/// largest distance of a prescribed (moving pinned) vertex from its path at
/// the end of a step of the frame (0 when every step could put the regions
/// on their path before its solve; empty in scenes without moving regions);
/// `friction_dissipated`: the work friction has taken out of the bodies
/// since frame 0 (energy units; empty in scenes without friction);
/// `projected_iterations`: Newton iterations whose direction came from the
/// projected Hessian (all of them with `solver.projection = "always"`).
pub fn stats_columns(energy_names: &[&str]) -> Vec<String> {
    LEADING_COLUMNS
        .iter()
        .chain(energy_names)
        .chain(TRAILING_COLUMNS)
        .map(|c| (*c).to_owned())
        .collect()
}

/// Streams frame statistics to a CSV file.
#[derive(Debug)]
pub struct StatsWriter {
    file: File,
    path: PathBuf,
    energy_names: Vec<String>,
}

impl StatsWriter {
    /// Creates the file and writes the header, with one energy column per
    /// entry of `energy_names` (see [`stats_columns`]).
    pub fn create(path: &Path, energy_names: &[&str]) -> Result<Self, OutputError> {
        let file = File::create(path).map_err(OutputError::io("create", path))?;
        let mut writer = Self {
            file,
            path: path.to_owned(),
            energy_names: energy_names.iter().map(|n| (*n).to_owned()).collect(),
        };
        writer.write_line(&(stats_columns(energy_names).join(",") + "\n"))?;
        Ok(writer)
    }

    /// Appends the row of output frame `frame` and flushes it to disk.
    pub fn write_frame<const D: usize>(
        &mut self,
        frame: usize,
        stats: &FrameStats<D>,
    ) -> Result<(), OutputError> {
        let mut row = self.row(frame, stats);
        row.push('\n');
        self.write_line(&row)
    }

    /// The row of output frame `frame`, without its line end.
    fn row<const D: usize>(&self, frame: usize, stats: &FrameStats<D>) -> String {
        let com = |axis: usize| {
            if axis < D {
                stats.centre_of_mass[axis]
            } else {
                0.0
            }
        };
        let mut row = format!(
            "{frame},{},{},{},{}",
            num(stats.time),
            stats.iterations,
            stats.linear_solves,
            stats.backtracks
        );
        for name in &self.energy_names {
            // An entry the frame lacks would be a programming error; an empty
            // cell keeps the columns aligned.
            match stats.energy.get(name) {
                Some(e) => write!(row, ",{}", num(e)),
                None => write!(row, ","),
            }
            .expect("formatting into a String cannot fail");
        }
        let min_height = stats.min_height.map(num).unwrap_or_default();
        write!(
            row,
            ",{},{},{},{},{min_height},{},{:.3},{},{},{:.3},{:.3},{:.3},{:.3}",
            num(stats.energy.total()),
            num(com(0)),
            num(com(1)),
            num(com(2)),
            num(stats.min_volume_ratio),
            ms(stats.wall_time),
            stats.unconverged_steps,
            stats.stalled_steps,
            ms(stats.times.assembly),
            ms(stats.times.factorisation),
            ms(stats.times.solve),
            ms(stats.times.line_search),
        )
        .expect("formatting into a String cannot fail");
        let contact = stats.contact.unwrap_or_default();
        let min_distance = contact.min_distance.map(num).unwrap_or_default();
        write!(
            row,
            ",{min_distance},{},{:.3},{:.3},{},{},{},{},{},{},{}",
            contact.active_pairs,
            ms(contact.broad_phase),
            ms(contact.ccd),
            contact.ccd_budget_exhausted,
            stats.reanalyses,
            stats.subdivided_steps,
            stats.damped_steps,
            stats.boundary_error.map(num).unwrap_or_default(),
            stats.friction_dissipated.map(num).unwrap_or_default(),
            stats.projected_iterations,
        )
        .expect("formatting into a String cannot fail");
        row
    }

    fn write_line(&mut self, line: &str) -> Result<(), OutputError> {
        self.file
            .write_all(line.as_bytes())
            .map_err(OutputError::io("write", &self.path))?;
        self.file
            .flush()
            .map_err(OutputError::io("write", &self.path))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vector;
    use crate::sim::EnergyBreakdown;
    use crate::solver::PhaseTimes;
    use std::time::Duration;

    fn stats<const D: usize>(min_height: Option<f64>) -> FrameStats<D> {
        FrameStats {
            time: 0.5,
            iterations: 7,
            linear_solves: 7,
            backtracks: 1,
            projected_iterations: 0,
            unconverged_steps: 0,
            stalled_steps: 2,
            reanalyses: 0,
            subdivided_steps: 0,
            damped_steps: 0,
            blocked_by: None,
            boundary_error: None,
            contact: None,
            friction_dissipated: None,
            energy: EnergyBreakdown {
                kinetic: 1.0,
                potentials: vec![("elastic", 0.25), ("gravity", -2.0), ("barrier", 0.125)],
            },
            centre_of_mass: Vector::<D>::from_fn(|i, _| i as f64 + 0.5),
            min_height,
            min_volume_ratio: 0.875,
            times: PhaseTimes::default(),
            wall_time: Duration::from_micros(1500),
        }
    }

    #[test]
    fn rows_have_every_column_and_are_on_disk_at_once() {
        let tmp = tempfile::tempdir().unwrap();
        let path = tmp.path().join("stats.csv");
        let names = ["kinetic", "elastic", "gravity", "barrier"];
        let columns = stats_columns(&names);
        let mut writer = StatsWriter::create(&path, &names).unwrap();
        writer.write_frame(3, &stats::<2>(None)).unwrap();
        // Read while the writer is still open: the row must already be there.
        let text = std::fs::read_to_string(&path).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], columns.join(","));
        let cells: Vec<&str> = lines[1].split(',').collect();
        assert_eq!(cells.len(), columns.len());
        let column = |name: &str| cells[columns.iter().position(|c| c == name).unwrap()];
        assert_eq!(column("frame"), "3");
        assert_eq!(column("total_energy"), "-0.625");
        assert_eq!(column("com_y"), "1.5");
        assert_eq!(column("com_z"), "0");
        assert_eq!(column("min_height"), "");
        assert_eq!(column("sim_ms"), "1.500");
        assert_eq!(column("elastic"), "0.25");
        assert_eq!(column("barrier"), "0.125");
        assert_eq!(column("stalled_steps"), "2");
        writer.write_frame(4, &stats::<3>(Some(0.25))).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let row: Vec<&str> = text.lines().nth(2).unwrap().split(',').collect();
        assert_eq!(row[12], "2.5");
        assert_eq!(row[13], "0.25");
        assert_eq!(columns.last().unwrap(), "projected_iterations");
    }
}
