//! The README and `docs/` are the user's manual: every command has its
//! line in the README and its section in `docs/commands.md`; every flag of
//! every command, every scene key that a resolved scene can hold (each in
//! the table of its own section of `docs/scene-reference.md`, `## [render.camera]`, ...),
//! every file a run writes and every column of `stats.csv`, `sweep.csv` and
//! `study.csv` is documented; the README stays short (at most
//! [`README_MAX_LINES`] lines) and its scene example is a valid scene.

use crate::cli_common as common;
use common::*;

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

const README: &str = include_str!("../../README.md");
const COMMANDS: &str = include_str!("../../docs/commands.md");
const SCENE_REFERENCE: &str = include_str!("../../docs/scene-reference.md");
const REFERENCE: &str = include_str!("../../docs/reference.md");
/// Every other page of `docs/`, so that a file moved or dropped fails to build.
const OTHER_DOCS: [&str; 5] = [
    include_str!("../../docs/gallery.md"),
    include_str!("../../docs/physics.md"),
    include_str!("../../docs/benchmarks.md"),
    include_str!("../../docs/hard-cases.md"),
    include_str!("../../docs/architecture.md"),
];

/// The README says what elasto is and links into `docs/`; it grows no longer than this.
const README_MAX_LINES: usize = 250;

/// The README and every page of `docs/`, one text.
fn manual() -> String {
    [README, COMMANDS, SCENE_REFERENCE, REFERENCE]
        .into_iter()
        .chain(OTHER_DOCS)
        .collect::<Vec<_>>()
        .join("\n")
}

/// The keys listed in each scene-file section of `docs/scene-reference.md`:
/// `""` for the top level, `"render.camera"` for `## [render.camera] ...`.
fn documented_keys() -> BTreeMap<String, BTreeSet<String>> {
    let mut sections: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut current: Option<String> = None;
    let mut fence = false;
    for line in SCENE_REFERENCE.lines() {
        if line.starts_with("```") {
            fence = !fence;
        }
        if fence {
            continue;
        }
        if let Some(title) = line.strip_prefix("## ") {
            current = if title.starts_with("Top level") {
                Some(String::new())
            } else {
                title
                    .strip_prefix("`[[")
                    .and_then(|t| t.split_once("]]`"))
                    .or_else(|| title.strip_prefix("`[").and_then(|t| t.split_once("]`")))
                    .map(|(table, _)| table.to_owned())
                    .or_else(|| {
                        title
                            .strip_prefix("`[")
                            .and_then(|t| t.split_once("]`"))
                            .map(|(table, _)| table.to_owned())
                    })
            };
        } else if line.starts_with("# ") {
            current = None;
        } else if let (Some(section), Some(row)) = (&current, line.strip_prefix("| `"))
            && let Some((key, _)) = row.split_once('`')
        {
            sections
                .entry(section.clone())
                .or_default()
                .insert(key.to_owned());
        }
    }
    sections
}

/// Every `(table, key)` of a TOML document whose value is not a table.
fn scene_keys(table: &toml::Table, path: &str, keys: &mut BTreeSet<(String, String)>) {
    for (key, value) in table {
        match value {
            toml::Value::Table(inner) => {
                let inner_path = if path.is_empty() {
                    key.clone()
                } else {
                    format!("{path}.{key}")
                };
                scene_keys(inner, &inner_path, keys);
            }
            // `[[effects.pinned]]`: each region's keys, under `effects.pinned`.
            toml::Value::Array(items) if path == "effects" && key == "pinned" => {
                for item in items.iter().filter_map(toml::Value::as_table) {
                    scene_keys(item, "effects.pinned", keys);
                }
            }
            _ => {
                keys.insert((path.to_owned(), key.clone()));
            }
        }
    }
}

#[test]
fn the_readme_is_short() {
    let lines = README.lines().count();
    assert!(
        lines <= README_MAX_LINES,
        "README.md has {lines} lines, more than {README_MAX_LINES}: move the detail into docs/"
    );
}

/// The README's scene example is a scene elasto accepts.
#[test]
fn the_readmes_scene_example_is_valid() {
    let tmp = tempfile::tempdir().unwrap();
    let start = README
        .find("```toml\n")
        .expect("the README has a scene example")
        + "```toml\n".len();
    let end = start + README[start..].find("```").unwrap();
    let name = README[start..end]
        .lines()
        .find_map(|l| l.strip_prefix("name = \""))
        .and_then(|l| l.split('"').next())
        .expect("the example has a name");
    let file = format!("{name}.toml");
    std::fs::write(tmp.path().join(&file), &README[start..end]).unwrap();
    let o = elasto(tmp.path(), &["check", &file]);
    assert_code(&o, 0);
    assert!(
        README.contains(&format!("elasto run {file}")),
        "the README runs its example"
    );
}

#[test]
fn every_flag_of_every_command_is_in_the_manual() {
    let tmp = tempfile::tempdir().unwrap();
    let mut flags = BTreeSet::new();
    // Every subcommand `elasto --help` lists.
    let help = stdout(&elasto(tmp.path(), &["--help"]));
    let commands: Vec<String> = help
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next().map(str::to_owned))
        .filter(|c| c != "help")
        .collect();
    assert!(commands.len() >= 5, "{commands:?} from:\n{help}");
    for command in &commands {
        assert!(
            README.contains(&format!("- `elasto {command}")),
            "no README line for `elasto {command}`"
        );
        assert!(
            COMMANDS.contains(&format!("\n## `elasto {command}")),
            "no docs/commands.md section for `elasto {command}`"
        );
        let o = elasto(tmp.path(), &[command.as_str(), "--help"]);
        assert_code(&o, 0);
        for line in stdout(&o).lines() {
            let line = line.trim_start();
            if !line.starts_with('-') {
                continue;
            }
            for word in line.split([' ', ',', '=', '<', '[']) {
                if let Some(name) = word.strip_prefix("--")
                    && !name.is_empty()
                    && name != "help"
                    && name != "version"
                {
                    flags.insert(format!("{command} --{name}"));
                }
            }
        }
    }
    assert!(
        flags.len() >= 10,
        "the help texts list too few flags: {flags:?}"
    );
    let missing: Vec<_> = flags
        .iter()
        .filter(|f| {
            let flag = f.split_once(' ').unwrap().1;
            !COMMANDS.contains(&format!("`{flag}"))
        })
        .collect();
    assert!(
        missing.is_empty(),
        "flags missing from docs/commands.md: {missing:?}"
    );
}

#[test]
fn every_key_of_a_resolved_scene_and_every_stats_column_is_documented() {
    let tmp = tempfile::tempdir().unwrap();
    // The built-in scenes, plus the optional keys they leave out.
    let twist = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/hard/twist-3d.toml");
    let squash = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/hard/squash-2d.toml");
    let runs: [(&str, &[&str]); 9] = [
        (twist, &[]),
        (squash, &[]),
        ("bunny-drop", &[]),
        ("two-bodies", &[]),
        ("report-drop-2d", &["--set", "render.range=[0.0, 1.0]"]),
        (
            "report-drop-2d",
            &[
                "--set",
                "render.camera.center=[0.0, 5.0]",
                "--set",
                "render.camera.height=12.0",
                "--set",
                "effects.ground.kappa=1000.0",
            ],
        ),
        ("drop-3d", &[]),
        (
            "hanging-bar-3d",
            &[
                "--set",
                "render.camera.eye=[3.0, 1.0, 6.0]",
                "--set",
                "render.camera.target=[0.0, -2.0, 0.0]",
            ],
        ),
        (
            "hanging-bar-2d",
            &["--set", "solver.method=gradient-descent"],
        ),
    ];
    let mut keys = BTreeSet::new();
    let mut columns = BTreeSet::new();
    for (i, (scene, extra)) in runs.iter().enumerate() {
        let out = format!("resolved-{i}");
        let mut args = vec![
            "run",
            scene,
            "--no-render",
            "-q",
            "--frames",
            "1",
            "--out",
            &out,
        ];
        args.extend(extra.iter());
        let o = elasto(tmp.path(), &args);
        assert_code(&o, 0);
        let resolved = std::fs::read_to_string(tmp.path().join(&out).join("scene.toml")).unwrap();
        let table: toml::Table = resolved.parse().unwrap();
        scene_keys(&table, "", &mut keys);
        let (header, _) = read_csv(&tmp.path().join(&out).join("stats.csv"));
        columns.extend(header);
    }
    for expected in [
        "gravity",
        "barrier",
        "contact",
        "boundary_error",
        "min_distance",
    ] {
        assert!(
            columns.contains(expected),
            "no run has {expected}: {columns:?}"
        );
    }
    let undocumented: Vec<_> = columns
        .iter()
        .filter(|c| !REFERENCE.contains(&format!("`{c}`")))
        .collect();
    assert!(
        undocumented.is_empty(),
        "stats.csv columns missing from docs/reference.md: {undocumented:?}"
    );
    for expected in [
        ("render", "range"),
        ("render.camera", "center"),
        ("render.camera", "eye"),
    ] {
        assert!(
            keys.contains(&(expected.0.to_owned(), expected.1.to_owned())),
            "the resolved scenes lack {expected:?}: {keys:?}"
        );
    }
    let documented = documented_keys();
    let missing: Vec<_> = keys
        .iter()
        .filter(|(table, key)| !documented.get(table).is_some_and(|keys| keys.contains(key)))
        .collect();
    assert!(
        missing.is_empty(),
        "scene keys missing from their docs/scene-reference.md section (table, key): {missing:?}\n\
         documented: {documented:?}"
    );
}

/// Every file a run writes, in every form, is in the outputs table of
/// `docs/reference.md` (numbered files by their first name, `frame_0000.png`).
#[test]
fn every_output_file_is_documented() {
    let tmp = tempfile::tempdir().unwrap();
    for (out, extra) in [
        (
            "a",
            &["--video", "auto", "--save-meshes", "--save-surface", "obj"][..],
        ),
        ("b", &["--video", "gif", "--save-surface", "ply"][..]),
    ] {
        let mut args = vec![
            "run",
            "--frames",
            "2",
            "--resolution",
            "64x48",
            "-q",
            "--out",
            out,
        ];
        args.extend(extra);
        assert_code(&elasto(tmp.path(), &args), 0);
    }
    let mut files = BTreeSet::new();
    for out in ["a", "b"] {
        collect_files(&tmp.path().join(out), "", &mut files);
    }
    for expected in [
        "stats.csv",
        "frames/frame_0000.png",
        "video.mp4",
        "video.gif",
        "surfaces/surface_0000.ply",
    ] {
        assert!(
            files.contains(expected),
            "no run wrote {expected}: {files:?}"
        );
    }
    let missing: Vec<_> = files
        .iter()
        .filter(|f| !REFERENCE.contains(&format!("`{f}")))
        .collect();
    assert!(
        missing.is_empty(),
        "output files missing from docs/reference.md: {missing:?}"
    );
}

/// The files under `dir`, relative, with their frame numbers as `0000`.
fn collect_files(dir: &Path, prefix: &str, files: &mut BTreeSet<String>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let entry = entry.unwrap();
        let name = entry.file_name().to_string_lossy().into_owned();
        let path = format!("{prefix}{name}");
        if entry.file_type().unwrap().is_dir() {
            collect_files(&entry.path(), &format!("{path}/"), files);
        } else {
            // A frame number is a run of four or more digits (`video.mp4` has one).
            let mut numbered = String::new();
            let mut digits = String::new();
            for c in path.chars().chain(std::iter::once('\0')) {
                if c.is_ascii_digit() {
                    digits.push(c);
                    continue;
                }
                if digits.len() >= 4 {
                    numbered.push_str(&"0".repeat(digits.len()));
                } else {
                    numbered.push_str(&digits);
                }
                digits.clear();
                if c != '\0' {
                    numbered.push(c);
                }
            }
            files.insert(numbered);
        }
    }
}

/// The columns of `sweep.csv` and `study.csv` are in `docs/commands.md`.
#[test]
fn every_sweep_and_study_column_is_documented() {
    let sweep = ["index", "folder", "status", "exit_code", "wall_seconds"]
        .into_iter()
        .chain(elasto::sweep::SUMMARY_COLUMNS);
    let study = std::iter::once("run").chain(elasto::study::STUDY_COLUMNS);
    let missing: Vec<_> = sweep
        .chain(study)
        .filter(|c| !COMMANDS.contains(&format!("`{c}`")))
        .collect();
    assert!(
        missing.is_empty(),
        "sweep.csv / study.csv columns missing from docs/commands.md: {missing:?}"
    );
    // The whole manual, README included, is what a reader searches.
    assert!(manual().contains("sweep.csv") && manual().contains("study.csv"));
}
