//! One run's outcome in a few numbers, read back from its `stats.csv`.
//!
//! Over the rows of `stats.csv` (one per output frame):
//! `newton_iterations` = Σ `newton_iters`, `unconverged_steps` =
//! Σ `unconverged_steps`, `stalled_steps` = Σ `stalled_steps`,
//! `min_ground_gap` = min `min_height` (the lowest vertex height above the
//! ground; empty without a ground), `min_volume_ratio` = min
//! `min_volume_ratio`, `energy_start` / `energy_end` = `total_energy` of the
//! first / last row, and `com_x`, `com_y`, `com_z` of the last row.

use serde::Serialize;
use std::path::Path;

/// The summary of one run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunSummary {
    /// Output frames written (rows of `stats.csv`).
    pub frames: usize,
    /// Newton (or gradient-descent) iterations over the whole run.
    pub newton_iterations: u64,
    /// Steps that hit the iteration cap.
    pub unconverged_steps: u64,
    /// Steps whose line search stalled.
    pub stalled_steps: u64,
    /// The lowest vertex height above the ground over all frames (`None` without a ground).
    pub min_ground_gap: Option<f64>,
    /// The smallest volume ratio J over all frames and elements.
    pub min_volume_ratio: f64,
    /// Total energy of the first frame.
    pub energy_start: f64,
    /// Total energy of the last frame.
    pub energy_end: f64,
    /// Centre of mass of the last frame.
    pub final_com: [f64; 3],
}

impl RunSummary {
    /// Reads `stats.csv`; `None` when it is missing, has no rows or lacks a
    /// column (a run that failed before its first frame).
    pub fn read(stats_csv: &Path) -> Option<Self> {
        Self::parse(&std::fs::read_to_string(stats_csv).ok()?)
    }

    /// Summarises the text of a `stats.csv`.
    pub fn parse(text: &str) -> Option<Self> {
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next()?.split(',').collect();
        let column = |name: &str| header.iter().position(|h| *h == name);
        let [
            iters,
            unconverged,
            stalled,
            height,
            volume,
            energy,
            cx,
            cy,
            cz,
        ] = [
            "newton_iters",
            "unconverged_steps",
            "stalled_steps",
            "min_height",
            "min_volume_ratio",
            "total_energy",
            "com_x",
            "com_y",
            "com_z",
        ]
        .map(column);
        let (iters, unconverged, stalled, height) = (iters?, unconverged?, stalled?, height?);
        let (volume, energy, cx, cy, cz) = (volume?, energy?, cx?, cy?, cz?);
        let mut summary: Option<RunSummary> = None;
        for line in lines.filter(|l| !l.trim().is_empty()) {
            let cells: Vec<&str> = line.split(',').collect();
            if cells.len() != header.len() {
                // A row cut short by a killed run: stop at the last whole one.
                break;
            }
            let float = |i: usize| cells[i].trim().parse::<f64>().unwrap_or(f64::NAN);
            let count = |i: usize| cells[i].trim().parse::<u64>().unwrap_or(0);
            let gap = cells[height].trim().parse::<f64>().ok();
            let s = summary.get_or_insert(RunSummary {
                frames: 0,
                newton_iterations: 0,
                unconverged_steps: 0,
                stalled_steps: 0,
                min_ground_gap: gap,
                min_volume_ratio: float(volume),
                energy_start: float(energy),
                energy_end: float(energy),
                final_com: [0.0; 3],
            });
            s.frames += 1;
            s.newton_iterations += count(iters);
            s.unconverged_steps += count(unconverged);
            s.stalled_steps += count(stalled);
            s.min_ground_gap = match (s.min_ground_gap, gap) {
                (Some(a), Some(b)) => Some(nan_min(a, b)),
                (a, b) => a.or(b),
            };
            s.min_volume_ratio = nan_min(s.min_volume_ratio, float(volume));
            s.energy_end = float(energy);
            s.final_com = [float(cx), float(cy), float(cz)];
        }
        summary
    }
}

/// The smaller of two numbers, NaN if either is (a NaN must show, not hide).
fn nan_min(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.min(b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const STATS: &str = "\
frame,time,newton_iters,linear_solves,backtracks,kinetic,elastic,gravity,barrier,total_energy,com_x,com_y,com_z,min_height,min_volume_ratio,sim_ms,unconverged_steps,stalled_steps,assembly_ms,factorisation_ms,line_search_ms
0,0,0,0,0,0,0,10.5,0,10.5,0.5,10.5,0,10,1,0.000,0,0,0.000,0.000,0.000
1,0.033,7,7,0,0.1,0.01,10.39,0,10.5,0.5,10.49,0,9.99,0.98,1.2,1,0,0.1,0.1,0.1
2,0.067,9,9,1,0.2,0.02,10.2,0.01,10.43,0.5,10.4,0,9.9,0.99,1.2,0,2,0.1,0.1,0.1
3,0.1,4,4
";

    #[test]
    fn sums_minima_and_ends_come_from_the_rows() {
        let s = RunSummary::parse(STATS).unwrap();
        assert_eq!(s.frames, 3, "the cut row is not counted");
        assert_eq!(s.newton_iterations, 16);
        assert_eq!(s.unconverged_steps, 1);
        assert_eq!(s.stalled_steps, 2);
        assert_eq!(s.min_ground_gap, Some(9.9));
        assert_eq!(s.min_volume_ratio, 0.98);
        assert_eq!(s.energy_start, 10.5);
        assert_eq!(s.energy_end, 10.43);
        assert_eq!(s.final_com, [0.5, 10.4, 0.0]);
    }

    #[test]
    fn no_ground_no_gap_and_no_rows_no_summary() {
        let text = STATS
            .replace(",10,1,0.000", ",,1,0.000")
            .replace(",9.99,", ",,")
            .replace(",9.9,", ",,");
        assert_eq!(RunSummary::parse(&text).unwrap().min_ground_gap, None);
        assert_eq!(RunSummary::parse(STATS.lines().next().unwrap()), None);
        assert_eq!(RunSummary::parse(""), None);
        let nan = STATS.replace(",0.99,", ",NaN,");
        assert!(RunSummary::parse(&nan).unwrap().min_volume_ratio.is_nan());
    }
}
