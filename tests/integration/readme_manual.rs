//! The README is the user's manual: every flag of every command and every
//! scene key that a resolved scene can hold is documented there, each key
//! in the table of its own section (`### [render.camera]`, ...).

use crate::cli_common as common;
use common::*;

use std::collections::{BTreeMap, BTreeSet};

const README: &str = include_str!("../../README.md");

/// The keys listed in each scene-file section of the README: `"" ` for the
/// top level, `"render.camera"` for `### [render.camera] ...`.
fn documented_keys() -> BTreeMap<String, BTreeSet<String>> {
    let mut sections: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut current: Option<String> = None;
    for line in README.lines() {
        if let Some(title) = line.strip_prefix("### ") {
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
        } else if line.starts_with("## ") {
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
fn every_flag_of_every_command_is_in_the_readme() {
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
            README.contains(&format!("### `elasto {command}")),
            "no README section for `elasto {command}`"
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
            !README.contains(&format!("`{flag}"))
        })
        .collect();
    assert!(
        missing.is_empty(),
        "flags missing from README.md: {missing:?}"
    );
}

#[test]
fn every_key_of_a_resolved_scene_is_in_its_readme_section() {
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
    }
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
        "scene keys missing from their README section (table, key): {missing:?}\n\
         documented: {documented:?}"
    );
}
