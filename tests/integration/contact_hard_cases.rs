//! Issue 29, item 11: the hard cases with contact. Each `scenes/hard/contact-*.toml`
//! runs through the real binary with each of the four materials (its
//! `model = "..."` lines rewritten in a copy: `--set material.model` does not
//! reach `[[bodies]]`), one `#[test]` per scene, saving every frame's surface.
//!
//! Per run:
//! - exit 0, and every saved frame is intersection-free by the independent
//!   check of `support/intersection/` (crossings and containment), the
//!   frame's obstacles (`obstacles_NNNN.obj`, or frame 0's when they hold
//!   still) appended to its bodies: body–obstacle pairs count, obstacle–
//!   obstacle pairs do not;
//! - the bodies met: the sparse pattern grew for contact pairs (`reanalyses`)
//!   or, as pairs with an obstacle add nothing to the pattern, some frame
//!   ends with pairs within d̂ (`contact_pairs`);
//! - every `stats.csv` value is finite (`min_distance` may be empty: no pair
//!   within d̂ at that frame's end), and `min_distance` > 0 where given;
//! - `min_volume_ratio` (J) > 0 and `min_height` > 0 on every frame;
//! - at least 99.5% of the steps converge (`unconverged_steps` +
//!   `stalled_steps` over `(frames − 1) × substeps`) and none stalls
//!   (issue 30, item 4), except for the runs in
//!   [`KNOWN_LIMITS`], which must still fall short and say so in the health
//!   summary: a known limit that starts passing fails its test, so the list
//!   only shrinks. The checks above hold for the known limits too.
//!
//! The squeezes (`contact-squeeze-2d`, `-3d`: a plate obstacle pressing a box
//! onto the ground) also end with the body at most 20% of its starting
//! height, measured on the saved surfaces.
//!
//! `contact-sheet-fold-3d` also has a negative control: with
//! `effects.contact.self = false` (Neo-Hookean) the sheet passes through
//! itself, so the case does test self-contact.

use crate::cli_common::{assert_code, elasto, read_csv, stderr};
use crate::intersection::{SavedSurface, find_intersections};
use std::path::{Path, PathBuf};

const MATERIALS: [&str; 4] = [
    "stvk",
    "neo-hookean",
    "stable-neo-hookean",
    "fixed-corotated",
];

/// Runs that converge in fewer than 99.5% of their steps today, and why
/// (measured with the scenes as they are; each stays intersection-free, with
/// positive distances, and J > 0 for the materials that forbid inversion).
/// Empty: a run that falls short is a failure.
///
/// Issue 30 (StVK's volume barrier, no J cap for stable Neo-Hookean and
/// fixed corotated, IPC's relative inversion filter for Neo-Hookean, step
/// subdivision) took every case but StVK at -500 units/s off this list
/// (2D and 3D: 89 of 90 steps, one failing even as sixteenths). Its volume
/// barrier was 25 times softer than its moduli (`k = lambda + mu` against
/// `(J - J^)^2 <= 0.04`): Newton's iterates crushed elements to
/// `J = 6e-10`, where the exact Hessian is indefinite and the projected one
/// crept. With `k = (lambda + mu) / J^^2` (5 December) both converge every
/// step (`src/material/st_venant_kirchhoff.rs`).
const KNOWN_LIMITS: &[(&str, &str)] = &[];

fn scene_path(case: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenes/hard/{case}.toml"))
}

/// A key's value in a scene's text (first `key = value` line).
fn scene_value(text: &str, key: &str) -> Option<String> {
    text.lines().find_map(|l| {
        let (k, v) = l.split_once('=')?;
        (k.trim() == key).then(|| v.split('#').next().unwrap().trim().to_owned())
    })
}

/// Whether `material` allows inversion (its energy is finite at `J <= 0`).
fn allows_inversion(material: &str) -> bool {
    matches!(material, "stable-neo-hookean" | "fixed-corotated")
}

/// The scene's text with every body's material model set to `material`, and
/// its mesh files (`"../meshes/..."`, beside `scenes/hard/`) named by their
/// full path, as the copy runs from a temporary folder.
fn with_material(text: &str, material: &str) -> String {
    let meshes = format!("\"{}/scenes/meshes/", env!("CARGO_MANIFEST_DIR"));
    let mut out: String = text
        .lines()
        .map(|l| {
            if l.trim_start().starts_with("model = ") {
                format!("model = \"{material}\"")
            } else {
                l.replace("\"../meshes/", &meshes)
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    out.push('\n');
    out
}

/// What one run measured.
struct Run {
    name: String,
    header: Vec<String>,
    rows: Vec<Vec<String>>,
    stderr: String,
    folder: PathBuf,
    substeps: usize,
    /// Whether the scene has `[[obstacles]]` (then their files must be saved).
    obstacles: bool,
}

impl Run {
    fn cells(&self, column: &str) -> Vec<&str> {
        let i = self
            .header
            .iter()
            .position(|h| h == column)
            .unwrap_or_else(|| panic!("{}: no column {column}", self.name));
        self.rows.iter().map(|r| r[i].as_str()).collect()
    }
    fn numbers(&self, column: &str) -> Vec<f64> {
        self.cells(column)
            .iter()
            .filter(|c| !c.is_empty())
            .map(|c| c.parse().unwrap())
            .collect()
    }
    fn total(&self, column: &str) -> f64 {
        self.numbers(column).iter().sum()
    }
    fn steps(&self) -> usize {
        self.rows.len().saturating_sub(1) * self.substeps
    }
    fn converged_fraction(&self) -> f64 {
        let steps = self.steps() as f64;
        (steps - self.total("unconverged_steps") - self.total("stalled_steps")) / steps
    }
    /// The saved `surfaces/` files whose name starts with `prefix`, sorted.
    fn saved_files(&self, prefix: &str) -> Vec<PathBuf> {
        let mut files: Vec<_> = std::fs::read_dir(self.folder.join("surfaces"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "obj"))
            .filter(|p| p.file_name().unwrap().to_string_lossy().starts_with(prefix))
            .collect();
        files.sort();
        files
    }
    /// Each frame's saved surface: the bodies' `surface_NNNN.obj` with the
    /// obstacles' `obstacles_NNNN.obj` appended (frame 0's when the
    /// obstacles hold still and only it is written), so that the check sees
    /// bodies against obstacles.
    fn frames(&self) -> Vec<(PathBuf, SavedSurface)> {
        let files = self.saved_files("surface_");
        assert_eq!(
            files.len(),
            self.rows.len(),
            "{}: one surface per frame",
            self.name
        );
        let obstacles = self.saved_files("obstacles_");
        assert_eq!(
            !obstacles.is_empty(),
            self.obstacles,
            "{}: obstacle files saved for a scene with obstacles only",
            self.name
        );
        assert!(
            obstacles.len() <= 1 || obstacles.len() == files.len(),
            "{}: {} obstacle files for {} frames",
            self.name,
            obstacles.len(),
            files.len()
        );
        files
            .into_iter()
            .enumerate()
            .map(|(k, f)| {
                let bodies = SavedSurface::read_obj(&f).unwrap();
                let surface = match obstacles.get(k).or(obstacles.first()) {
                    Some(o) => {
                        let name = |p: &Path| p.file_name().unwrap().to_string_lossy().into_owned();
                        assert!(
                            obstacles.len() == 1
                                || name(o) == name(&f).replacen("surface_", "obstacles_", 1),
                            "{}: {} beside {}",
                            self.name,
                            name(o),
                            name(&f)
                        );
                        bodies.with_obstacles(&SavedSurface::read_obj(o).unwrap())
                    }
                    None => bodies,
                };
                (f, surface)
            })
            .collect()
    }
    /// Saved frames the independent check finds intersecting, with the first
    /// problem of each.
    fn intersecting_frames(&self) -> Vec<String> {
        self.frames()
            .iter()
            .filter_map(|(f, surface)| {
                let found = find_intersections(surface);
                found.first().map(|first| {
                    format!(
                        "{} ({} problems, first {first:?})",
                        f.file_name().unwrap().to_string_lossy(),
                        found.len()
                    )
                })
            })
            .collect()
    }
}

/// Runs `case` with `material` (and `extra` flags) in `dir`, saving surfaces.
fn run(dir: &Path, case: &str, material: &str, extra: &[&str]) -> Run {
    let text = std::fs::read_to_string(scene_path(case)).unwrap();
    let name = format!("{case}/{material} {}", extra.join(" "))
        .trim_end()
        .to_owned();
    let out = format!(
        "{case}-{material}{}",
        if extra.is_empty() { "" } else { "-x" }
    );
    let scene = dir.join(format!("{out}.toml"));
    std::fs::write(&scene, with_material(&text, material)).unwrap();
    let mut args = vec![
        "run",
        scene.to_str().unwrap(),
        "--no-render",
        "--save-surface",
        "obj",
        "-q",
        "--force",
        "--out",
        &out,
    ];
    args.extend_from_slice(extra);
    let o = elasto(dir, &args);
    assert_code(&o, 0);
    let (header, rows) = read_csv(&dir.join(&out).join("stats.csv"));
    Run {
        name,
        header,
        rows,
        stderr: stderr(&o),
        folder: dir.join(&out),
        substeps: scene_value(&text, "substeps")
            .expect("the scene states time.substeps")
            .parse()
            .unwrap(),
        obstacles: text.contains("[[obstacles]]"),
    }
}

/// Every check of the module on one run; problems are pushed to `failures`.
fn check(case: &str, material: &str, r: &Run, failures: &mut Vec<String>) {
    let name = &r.name;
    let crossing = r.intersecting_frames();
    if !crossing.is_empty() {
        failures.push(format!("{name}: intersecting frames {crossing:?}"));
    }
    // Pairs with a body and an obstacle do not grow the pattern (the
    // obstacles' points are not unknowns): there, pairs within d̂ at a
    // frame's end show the meeting.
    let pairs = r.numbers("contact_pairs").into_iter().fold(0.0, f64::max);
    if r.total("reanalyses") == 0.0 && pairs == 0.0 {
        failures.push(format!(
            "{name}: the bodies never met (no reanalyses, no contact pairs)"
        ));
    }
    for (f, row) in r.rows.iter().enumerate() {
        for (h, v) in r.header.iter().zip(row) {
            if matches!(
                h.as_str(),
                "min_distance" | "boundary_error" | "friction_dissipated"
            ) && v.is_empty()
            {
                continue;
            }
            if !v.parse::<f64>().is_ok_and(f64::is_finite) {
                failures.push(format!("{name}: frame {f}: {h} = {v:?}"));
            }
        }
    }
    for column in ["min_distance", "min_volume_ratio", "min_height"] {
        let worst = r.numbers(column).into_iter().fold(f64::INFINITY, f64::min);
        // Stable Neo-Hookean and fixed corotated may pass through J <= 0
        // and recover (issue 30): only a finite J is required of them.
        let may_invert = column == "min_volume_ratio" && allows_inversion(material);
        if worst.is_nan() || (worst <= 0.0 && !may_invert) {
            failures.push(format!("{name}: {column} reaches {worst}"));
        }
    }
    let converged = r.converged_fraction();
    let stalled = r.total("stalled_steps");
    let meets_the_bar = converged >= 0.995 && stalled == 0.0;
    let known = KNOWN_LIMITS.contains(&(case, material));
    if known && meets_the_bar {
        failures.push(format!(
            "{name}: listed in KNOWN_LIMITS but {:.1}% of {} steps converge, none stalled: \
             remove it",
            100.0 * converged,
            r.steps()
        ));
    } else if known && !r.stderr.contains("health:") {
        failures.push(format!(
            "{name}: falls short ({:.1}%) but no health summary: {}",
            100.0 * converged,
            r.stderr
        ));
    } else if !known && !meets_the_bar {
        failures.push(format!(
            "{name}: {:.1}% of {} steps converged, {stalled} stalled: {}",
            100.0 * converged,
            r.steps(),
            r.stderr
        ));
    }
}

fn check_case(case: &str) {
    check_case_and(case, |_, _| {});
}

/// Runs `case` with every material and checks each run, with the checks of
/// [`check`] and `more`.
fn check_case_and(case: &str, more: impl Fn(&Run, &mut Vec<String>)) {
    let dir = tempfile::tempdir().unwrap();
    let mut failures = Vec::new();
    for material in MATERIALS {
        let start = std::time::Instant::now();
        let r = run(dir.path(), case, material, &[]);
        eprintln!("{}: ran in {:.1} s", r.name, start.elapsed().as_secs_f64());
        check(case, material, &r, &mut failures);
        more(&r, &mut failures);
    }
    assert!(
        failures.is_empty(),
        "{} problems:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// The bodies' height (extent along y) in a saved surface, obstacles left out.
fn body_height(surface: &SavedSurface) -> f64 {
    let end = surface.obstacles_from.unwrap_or(surface.vertices.len());
    let ys = surface.vertices[..end].iter().map(|p| p[1]);
    ys.clone().fold(f64::NEG_INFINITY, f64::max) - ys.fold(f64::INFINITY, f64::min)
}

/// A squeeze: the run ends with the body at most 20% of its starting height
/// (from the saved surfaces, the plate held at 20% since `until`).
fn squeezed_to_a_fifth(r: &Run, failures: &mut Vec<String>) {
    let frames = r.frames();
    let first = body_height(&frames[0].1);
    let last = body_height(&frames.last().unwrap().1);
    eprintln!(
        "{}: height {first} -> {last} ({:.2}%)",
        r.name,
        100.0 * last / first
    );
    // NaN fails too.
    if last.is_nan() || last > 0.2 * first {
        failures.push(format!(
            "{}: squeezed to a height of {last} from {first} only",
            r.name
        ));
    }
}

#[test]
fn contact_impact_50_2d() {
    check_case("contact-impact-50-2d");
}

#[test]
fn contact_impact_50_3d() {
    check_case("contact-impact-50-3d");
}

#[test]
fn contact_impact_500_2d() {
    check_case("contact-impact-500-2d");
}

#[test]
fn contact_impact_500_3d() {
    check_case("contact-impact-500-3d");
}

#[test]
fn contact_bowl_impact_50_3d() {
    check_case("contact-bowl-impact-50-3d");
}

#[test]
fn contact_squeeze_2d() {
    check_case_and("contact-squeeze-2d", squeezed_to_a_fifth);
}

#[test]
fn contact_squeeze_3d() {
    check_case_and("contact-squeeze-3d", squeezed_to_a_fifth);
}

#[test]
fn contact_pile_3d() {
    check_case("contact-pile-3d");
}

#[test]
fn contact_sheet_fold_3d() {
    check_case("contact-sheet-fold-3d");
    // Without self-contact the sheet folds through itself: the case tests it.
    let dir = tempfile::tempdir().unwrap();
    let r = run(
        dir.path(),
        "contact-sheet-fold-3d",
        "neo-hookean",
        &["--set", "effects.contact.self=false"],
    );
    assert!(
        !r.intersecting_frames().is_empty(),
        "the sheet never met itself: the case does not test self-contact"
    );
}

#[test]
fn every_contact_hard_case_has_a_test() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/hard");
    let mut found: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .filter_map(|p| p.file_stem()?.to_str().map(str::to_owned))
        .filter(|s| s.starts_with("contact-"))
        .collect();
    found.sort();
    assert_eq!(
        found,
        [
            "contact-bowl-impact-50-3d",
            "contact-impact-50-2d",
            "contact-impact-50-3d",
            "contact-impact-500-2d",
            "contact-impact-500-3d",
            "contact-pile-3d",
            "contact-sheet-fold-3d",
            "contact-squeeze-2d",
            "contact-squeeze-3d",
        ]
    );
    for (case, _) in KNOWN_LIMITS {
        assert!(found.iter().any(|f| f == case), "{case}");
    }
}
