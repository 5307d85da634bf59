//! Issue 12, item 4: the hard-case suite. Every scene in `scenes/hard/`
//! runs with each of the four materials through the real binary, and each
//! run must stay numerically sound and deterministic.
//!
//! Per run, from its `stats.csv` (one row per frame):
//! - every value is finite (no NaN or inf anywhere);
//! - `min_height` (the lowest vertex's gap to the ground, a measured
//!   number, never the barrier's value) stays > 0;
//! - `min_volume_ratio` (the smallest `J = det F`) stays > 0;
//! - without a moving boundary, `total_energy` never exceeds frame 0's by
//!   more than `ENERGY_TOLERANCE * max(|E_0|, 1)` (backward Euler only
//!   dissipates); with one, the same holds from the first frame after every
//!   region has stopped (`until`);
//! - at least 99.5% of the steps converge within the iteration cap
//!   ([`CONVERGED_SHARE`]) and none stalls in the line search (issue 30,
//!   item 4), except for the runs in [`KNOWN_LIMITS`], which must instead
//!   fall short and say so (health summary), or fail with the stated
//!   message: a known limit that starts passing fails this test, so the
//!   list only shrinks;
//! - a second run gives bitwise the same `stats.csv` (timing columns aside)
//!   over its first `DETERMINISM_FRAMES` frames.
//!
//! Every case runs with all four materials, the longest (`twist-3d`,
//! `report-box-3000`) included: with projection on demand the StVK twist
//! takes seconds, not a quarter of an hour.
//!
//! One `#[test]` per case (`cargo test --test integration hard_cases::twist_3d`
//! runs one). `ELASTO_HARD_CASES=twist-3d,squash-2d` limits the table command
//! to the cases named. The `#[ignore]`d `hard_case_table` runs the same cases and rewrites the
//! table of `docs/hard-cases.md` (`cargo test --test integration hard_cases -- --ignored`).

use crate::cli_common as common;
use common::*;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Allowed energy rise over the reference frame, relative to `max(|E_0|, 1)`.
const ENERGY_TOLERANCE: f64 = 1e-6;
/// Frames compared between the two runs of a case.
const DETERMINISM_FRAMES: usize = 20;
/// The share of a run's steps that must converge (issue 30, item 4).
const CONVERGED_SHARE: f64 = 0.995;

const MATERIALS: [&str; 4] = [
    "stvk",
    "neo-hookean",
    "stable-neo-hookean",
    "fixed-corotated",
];

/// How a known limit shows. No run needs one since issue 30; kept for a
/// case that would (an equilibrium a material cannot hold, for one).
#[derive(Debug, Clone, Copy, PartialEq)]
#[allow(dead_code)]
enum Limit {
    /// Fewer than [`CONVERGED_SHARE`] of the steps converge, or one stalls
    /// (reported in the health summary).
    Unconverged,
    /// The run stops (exit 1) with this message.
    Fails(&'static str),
}

/// Runs that do not meet the bar today, and why: none.
///
/// Issue 30 emptied this list (33 entries before it): StVK has a volume
/// barrier below `J = 0.2`, stable Neo-Hookean and fixed corotated pass
/// through inversion and recover (no cap on `J`), Neo-Hookean's cap is
/// IPC's relative filter, steps that do not converge are retried as half
/// steps, and moving regions reach their path within the solve. With the
/// Hessian projected on demand (item 4) every run converges every step
/// (release binary, 5 December): the twist taken to three full turns, the
/// longest case, took StVK 7,265 Newton iterations for its 1,532 steps (8 of
/// them divided), where projecting always took 308,514 and left one step at
/// the cap even as 16 shorter steps.
const KNOWN_LIMITS: &[(&str, &str, Limit)] = &[];

/// What one run of a case measured.
struct CaseRun {
    case: String,
    material: &'static str,
    dimension: usize,
    header: Vec<String>,
    rows: Vec<Vec<String>>,
    stderr: String,
    exit: Option<i32>,
    steps_per_frame: usize,
    /// Time after which no pinned region moves (0 without moving regions).
    motion_ends: Option<f64>,
    wall: Duration,
}

impl CaseRun {
    fn column(&self, c: &str) -> usize {
        self.header.iter().position(|h| h == c).unwrap()
    }
    /// A column's values; an empty cell (`min_height` without a ground) reads
    /// as `+inf`.
    fn values(&self, c: &str) -> Vec<f64> {
        let i = self.column(c);
        self.rows
            .iter()
            .map(|r| match r[i].as_str() {
                "" => f64::INFINITY,
                v => v.parse().unwrap(),
            })
            .collect()
    }
    /// Whether the scene has a ground (its `min_height` cells are filled).
    fn has_ground(&self) -> bool {
        let i = self.column("min_height");
        self.rows.iter().all(|r| !r[i].is_empty())
    }
    fn steps(&self) -> usize {
        (self.rows.len().saturating_sub(1)) * self.steps_per_frame
    }
    fn bad_steps(&self) -> f64 {
        self.values("unconverged_steps")
            .iter()
            .zip(self.values("stalled_steps"))
            .map(|(a, b)| a + b)
            .sum()
    }
    fn converged_fraction(&self) -> f64 {
        let steps = self.steps() as f64;
        (steps - self.bad_steps()) / steps
    }
    /// The frame energy is checked from, and the largest rise after it,
    /// relative to `max(|E_ref|, 1)`.
    /// The total energy's change from frame 0 to the last frame, relative
    /// to `max(|E_0|, 1)` (negative: dissipated).
    fn energy_change(&self) -> f64 {
        let energy = self.values("total_energy");
        (energy[energy.len() - 1] - energy[0]) / energy[0].abs().max(1.0)
    }
    fn energy_rise(&self) -> (usize, f64) {
        let time = self.values("time");
        let energy = self.values("total_energy");
        let from = match self.motion_ends {
            None => 0,
            Some(end) => time.iter().position(|t| *t >= end).unwrap_or(time.len()),
        };
        if from >= energy.len() {
            return (from, 0.0);
        }
        let reference = energy[from];
        let highest = energy[from..].iter().copied().fold(f64::MIN, f64::max);
        (from, (highest - reference) / reference.abs().max(1.0))
    }
}

/// A key's value in a scene file (first `key = value` line).
fn scene_value(text: &str, key: &str) -> Option<String> {
    text.lines().find_map(|l| {
        let (k, v) = l.split_once('=')?;
        (k.trim() == key).then(|| v.split('#').next().unwrap().trim().to_owned())
    })
}

fn scenes() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/hard");
    let only = std::env::var("ELASTO_HARD_CASES").ok();
    let mut scenes: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        // The contact cases have several bodies, each with its material:
        // `contact_hard_cases.rs` runs them.
        .filter(|p| {
            !p.file_stem()
                .is_some_and(|s| s.to_string_lossy().starts_with("contact-"))
        })
        .filter(|p| {
            only.as_ref()
                .is_none_or(|o| o.split(',').any(|c| p.file_stem().is_some_and(|s| s == c)))
        })
        .collect();
    scenes.sort();
    scenes
}

/// Runs `scene` with `material` (all frames, or the first `frames`).
fn run(dir: &Path, scene: &Path, material: &'static str, frames: Option<usize>) -> CaseRun {
    let case = scene.file_stem().unwrap().to_str().unwrap().to_owned();
    let out = format!("{case}-{material}-{}", frames.map_or(0, |f| f));
    let text = std::fs::read_to_string(scene).unwrap();
    let frames_arg = frames.map(|f| f.to_string());
    let mut args = vec![
        "run",
        scene.to_str().unwrap(),
        "--no-render",
        "-q",
        "--force",
        "--set",
    ];
    let model = format!("material.model={material}");
    args.push(&model);
    args.extend(["-o", &out]);
    if let Some(f) = &frames_arg {
        args.extend(["--frames", f]);
    }
    let start = Instant::now();
    let o = elasto(dir, &args);
    let wall = start.elapsed();
    let stats = dir.join(&out).join("stats.csv");
    let (header, rows) = if stats.exists() {
        read_csv(&stats)
    } else {
        (Vec::new(), Vec::new())
    };
    let moving = text.contains("velocity = [") && text.contains("[[effects.pinned]]");
    let motion_ends = moving.then(|| {
        text.lines()
            .filter_map(|l| {
                let (k, v) = l.split_once('=')?;
                (k.trim() == "until").then(|| v.trim().parse::<f64>().unwrap())
            })
            .fold(0.0, f64::max)
    });
    CaseRun {
        case,
        material,
        dimension: scene_value(&text, "dimension").unwrap().parse().unwrap(),
        header,
        rows,
        stderr: stderr(&o),
        exit: o.status.code(),
        steps_per_frame: scene_value(&text, "substeps")
            .expect("the scene states time.substeps")
            .parse()
            .unwrap(),
        motion_ends,
        wall,
    }
}

/// Every assertion of the suite on one run (and its repeat); problems are
/// pushed to `failures`.
fn check(first: &CaseRun, again: &CaseRun, failures: &mut Vec<String>) {
    let name = format!("{}/{}", first.case, first.material);
    let limit = KNOWN_LIMITS
        .iter()
        .find(|(c, m, _)| *c == first.case && *m == first.material)
        .map(|(_, _, l)| *l);
    match (limit, first.exit) {
        (Some(Limit::Fails(message)), Some(1)) if first.stderr.contains(message) => return,
        (Some(Limit::Fails(message)), code) => {
            failures.push(format!(
                "{name}: listed in KNOWN_LIMITS as failing with {message:?}, got exit {code:?}: {} \
                 (remove it if it now passes)",
                first.stderr
            ));
            return;
        }
        (_, Some(0)) => {}
        (_, code) => {
            failures.push(format!("{name}: exit {code:?}: {}", first.stderr));
            return;
        }
    }
    for (f, row) in first.rows.iter().enumerate() {
        for (h, v) in first.header.iter().zip(row) {
            if h == "min_height" && v.is_empty() && !first.has_ground() {
                continue;
            }
            // Empty while no pair of surface primitives is within d_hat
            // (and always without [effects.contact]).
            if matches!(
                h.as_str(),
                "min_distance" | "boundary_error" | "friction_dissipated"
            ) && v.is_empty()
            {
                continue;
            }
            match v.parse::<f64>() {
                Ok(x) if x.is_finite() => {}
                _ => failures.push(format!("{name}: frame {f}: {h} = {v}")),
            }
        }
    }
    let gaps = if first.has_ground() {
        first.values("min_height")
    } else {
        Vec::new()
    };
    for (f, gap) in gaps.iter().enumerate() {
        if gap.is_nan() || *gap <= 0.0 {
            failures.push(format!("{name}: frame {f}: ground gap {gap}"));
        }
    }
    // Neo-Hookean and StVK (its volume barrier) forbid inversion: J > 0 in
    // every frame. Stable Neo-Hookean and fixed corotated may pass through
    // J <= 0 and recover (issue 30): a finite J in every frame.
    let may_invert = matches!(first.material, "stable-neo-hookean" | "fixed-corotated");
    for (f, j) in first.values("min_volume_ratio").iter().enumerate() {
        if j.is_nan() || (*j <= 0.0 && !may_invert) {
            failures.push(format!("{name}: frame {f}: J = {j}"));
        }
    }
    let (from, rise) = first.energy_rise();
    if rise > ENERGY_TOLERANCE {
        failures.push(format!(
            "{name}: total energy rose by {rise:e} (relative) after frame {from}"
        ));
    }
    let converged = first.converged_fraction();
    let stalled: f64 = first.values("stalled_steps").iter().sum();
    let meets_the_bar = converged >= CONVERGED_SHARE && stalled == 0.0;
    match limit {
        Some(_) if meets_the_bar => failures.push(format!(
            "{name}: listed in KNOWN_LIMITS but {:.1}% of steps converge, none stalled: \
             remove it",
            100.0 * converged
        )),
        Some(_) if !first.stderr.contains("health:") => failures.push(format!(
            "{name}: {} bad steps but no health summary: {}",
            first.bad_steps(),
            first.stderr
        )),
        None if !meets_the_bar => failures.push(format!(
            "{name}: {:.1}% of {} steps converged, {stalled} stalled ({})",
            100.0 * converged,
            first.steps(),
            first.stderr
        )),
        _ => {}
    }
    let timing = |h: &String| h.ends_with("_ms");
    if again.rows.len() != DETERMINISM_FRAMES.min(first.rows.len()) {
        failures.push(format!(
            "{name}: the repeat wrote {} rows",
            again.rows.len()
        ));
    }
    for (r, (a, b)) in first.rows.iter().zip(&again.rows).enumerate() {
        for ((h, x), y) in first.header.iter().zip(a).zip(b) {
            if !timing(h) && x != y {
                failures.push(format!("{name}: frame {r}: {h} {x} then {y}"));
            }
        }
    }
}

/// Runs `case` (a scene of `scenes/hard/`) with each of its suite
/// materials, twice (the second for determinism), and checks every run.
fn check_case(case: &str) {
    let tmp = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/hard")
        .join(format!("{case}.toml"));
    let mut failures = Vec::new();
    for material in MATERIALS {
        let first = run(tmp.path(), &scene, material, None);
        let frames = first.rows.len().clamp(1, DETERMINISM_FRAMES);
        let again = run(tmp.path(), &scene, material, Some(frames));
        check(&first, &again, &mut failures);
    }
    assert!(
        failures.is_empty(),
        "{} problems:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// One `#[test]` per hard case, so the harness spreads them over the cores
/// and a failure names its case; `every_hard_case_has_a_test` keeps the list
/// equal to `scenes/hard/`.
macro_rules! hard_case_tests {
    ($($test:ident => $case:literal,)*) => {
        $(
            #[test]
            fn $test() {
                check_case($case);
            }
        )*
        const CASES_WITH_A_TEST: &[&str] = &[$($case),*];
    };
}

hard_case_tests! {
    big_step_2d => "big-step-2d",
    big_step_3d => "big-step-3d",
    friction_drag_2d => "friction-drag-2d",
    heavy_gravity_2d => "heavy-gravity-2d",
    heavy_gravity_3d => "heavy-gravity-3d",
    impact_50_2d => "impact-50-2d",
    impact_50_3d => "impact-50-3d",
    impact_500_2d => "impact-500-2d",
    impact_500_3d => "impact-500-3d",
    long_run_2d => "long-run-2d",
    poisson_0_49_2d => "poisson-0.49-2d",
    poisson_0_499_2d => "poisson-0.499-2d",
    poisson_0_4999_2d => "poisson-0.4999-2d",
    poisson_0_4999_3d => "poisson-0.4999-3d",
    report_box_3000 => "report-box-3000",
    sliver_2d => "sliver-2d",
    sliver_3d => "sliver-3d",
    soft_2d => "soft-2d",
    soft_3d => "soft-3d",
    squash_2d => "squash-2d",
    squash_3d => "squash-3d",
    stiff_2d => "stiff-2d",
    stiff_3d => "stiff-3d",
    twist_3d => "twist-3d",
}

#[test]
fn every_hard_case_has_a_test() {
    let found: Vec<String> = scenes()
        .iter()
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    if std::env::var("ELASTO_HARD_CASES").is_err() {
        assert_eq!(
            found, CASES_WITH_A_TEST,
            "scenes/hard/ and the tests differ"
        );
    }
    for (case, _, _) in KNOWN_LIMITS {
        assert!(CASES_WITH_A_TEST.contains(case), "{case}");
    }
}

/// Regenerates the table of `docs/hard-cases.md` (between its markers) from a
/// run of every case: `cargo test --test integration hard_cases -- --ignored`.
#[test]
#[ignore = "rewrites docs/hard-cases.md; run by hand to refresh the table"]
fn hard_case_table() {
    let tmp = tempfile::tempdir().unwrap();
    let mut table = String::from(
        "| case | material | dim | steps | Newton it./step | worst gap | worst J | energy drift: max rise / end | wall time |\n\
         |---|---|---|---|---|---|---|---|---|\n",
    );
    for scene in &scenes() {
        for material in MATERIALS {
            let r = run(tmp.path(), scene, material, None);
            let wall = format!("{:.1} s", r.wall.as_secs_f64());
            if r.exit != Some(0) {
                let reason = r
                    .stderr
                    .split("failed at ")
                    .nth(1)
                    .and_then(|s| s.split(':').next())
                    .unwrap_or("failed");
                table.push_str(&format!(
                    "| {} | {material} | {}D | stops at {reason} | | | | | {wall} |\n",
                    r.case, r.dimension
                ));
                continue;
            }
            let iterations: f64 = r.values("newton_iters").iter().sum();
            let gap = r
                .values("min_height")
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min);
            let j = r
                .values("min_volume_ratio")
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min);
            let (_, rise) = r.energy_rise();
            let converged = r.converged_fraction();
            let steps = if converged < CONVERGED_SHARE {
                format!("{} ({:.1}% conv.)", r.steps(), 100.0 * converged)
            } else {
                r.steps().to_string()
            };
            let drift = match r.motion_ends {
                Some(_) => format!("{rise:.1e} (after stop) / {:+.2e}", r.energy_change()),
                None => format!("{rise:.1e} / {:+.2e}", r.energy_change()),
            };
            table.push_str(&format!(
                "| {} | {material} | {}D | {steps} | {:.2} | {} | {:.3e} | {drift} | {wall} |\n",
                r.case,
                r.dimension,
                iterations / r.steps() as f64,
                if gap.is_finite() {
                    format!("{gap:.3e}")
                } else {
                    "no ground".to_owned()
                },
                j,
            ));
        }
    }
    let page = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/hard-cases.md");
    let text = std::fs::read_to_string(&page).unwrap();
    let (begin, end) = (
        "<!-- hard-case table: begin -->\n",
        "<!-- hard-case table: end -->",
    );
    let start = text
        .find(begin)
        .expect("docs/hard-cases.md has the table's begin marker")
        + begin.len();
    let stop = text
        .find(end)
        .expect("docs/hard-cases.md has the table's end marker");
    let updated = format!("{}{table}{}", &text[..start], &text[stop..]);
    std::fs::write(&page, updated).unwrap();
    println!("{table}");
}
