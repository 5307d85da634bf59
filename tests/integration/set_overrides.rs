//! `--set` and `--vary` addressing one item of an array of tables
//! (`effects.pinned[0].release`, `bodies[1].material.young`).
//!
//! Each `mod regression_*` here guards one fixed bug and is named after it
//! (`cargo test --test integration regression_` selects them all).

/// Issue 33, item 23: `--set` and `--vary` could not address one item of an
/// array of tables: `--set effects.pinned.release=0.5` said "`effects.pinned`
/// is a array, not a table", `--set 'effects.pinned[0].release=0.5'` "not a
/// plain key", and `sweep two-bodies --vary 'bodies.material.young=…'` failed
/// the same way, so one body's material could not be swept. Now
/// `bodies[1].material.young` and `effects.pinned[0].release` work in `--set`,
/// `--vary`, sweep files and study series, an index out of range is named,
/// and a key through an array without an index says how to index it.
mod regression_array_items_could_not_be_set {
    use crate::cli_common as common;
    use crate::cli_sweep::folders;
    use common::*;
    use std::path::Path;

    /// Two boxes side by side, each held by a pinned region of its own.
    const TWO_BOXES: &str = r#"dimension = 2

[[bodies]]
[bodies.mesh]
size = [1.0, 1.0]
cells = [2, 2]
offset = [0.0, 1.0]
[bodies.material]
model = "stvk"
young = 300.0
poisson = 0.3

[[bodies]]
[bodies.mesh]
size = [1.0, 1.0]
cells = [2, 2]
offset = [3.0, 1.0]
[bodies.material]
model = "stvk"
young = 300.0
poisson = 0.3

[time]
frames = 3

[effects.gravity]
acceleration = [0.0, -1.0]

[effects.ground]
height = 0.0

[[effects.pinned]]
min = [-0.1, 1.9]
max = [1.1, 2.1]

[[effects.pinned]]
min = [2.9, 1.9]
max = [4.1, 2.1]
"#;

    /// The resolved scene a run wrote.
    fn resolved(folder: &Path) -> toml::Table {
        std::fs::read_to_string(folder.join("scene.toml"))
            .unwrap()
            .parse()
            .unwrap()
    }

    /// `bodies[i].material.young` of a resolved scene.
    fn young(scene: &toml::Table, body: usize) -> f64 {
        scene["bodies"][body]["material"]["young"]
            .as_float()
            .unwrap()
    }

    /// `effects.pinned[i].release` of a resolved scene, if set.
    fn release(scene: &toml::Table, region: usize) -> Option<f64> {
        scene["effects"]["pinned"][region]
            .get("release")
            .and_then(toml::Value::as_float)
    }

    #[test]
    fn set_changes_one_item_of_an_array_of_tables() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        std::fs::write(dir.join("s.toml"), TWO_BOXES).unwrap();
        let o = elasto(
            dir,
            &[
                "run",
                "s.toml",
                "--no-render",
                "-q",
                "-o",
                "o",
                "--set",
                "bodies[1].material.young=500",
                "--set",
                "effects.pinned[0].release=0.05",
            ],
        );
        assert_code(&o, 0);
        let scene = resolved(&dir.join("o"));
        assert_eq!((young(&scene, 0), young(&scene, 1)), (300.0, 500.0));
        assert_eq!((release(&scene, 0), release(&scene, 1)), (Some(0.05), None));
        // One value of an array of values, too.
        let o = elasto(
            dir,
            &["check", "s.toml", "--set", "bodies[0].mesh.cells[0]=4"],
        );
        assert_code(&o, 0);
        // 5 x 3 vertices in the first box (4 x 2 cells), 3 x 3 in the second.
        assert!(
            stdout(&o).contains("mesh            24 vertices"),
            "{}",
            stdout(&o)
        );
    }

    #[test]
    fn bad_indices_and_missing_ones_are_named() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        std::fs::write(dir.join("s.toml"), TWO_BOXES).unwrap();
        let cases: &[(&str, &str)] = &[
            (
                "bodies[2].material.young=5",
                "index 2 of `bodies[2]` is out of range: `bodies` has 2 items, `[0]` to `[1]`",
            ),
            (
                "effects.pinned[7].release=0.5",
                "index 7 of `effects.pinned[7]` is out of range: `pinned` has 2 items",
            ),
            (
                "bodies.material.young=5",
                "`bodies` is an array of 2 tables: address one by its index, `bodies[0]` to \
             `bodies[1]`, e.g. `bodies[0].material.young`",
            ),
            (
                "effects.pinned.release=0.5",
                "`effects.pinned` is an array of 2 tables: address one by its index, \
             `effects.pinned[0]` to `effects.pinned[1]`, e.g. `effects.pinned[0].release`",
            ),
            (
                "time[0].frames=3",
                "`time` is a table, not an array: drop the index `[0]`",
            ),
            (
                "mesh[0].cells=[2,2]",
                "the scene has no `mesh`, so `mesh[0]` names no item",
            ),
            (
                "bodies[x].material.young=5",
                "the index in `bodies[x]` must be a whole number from 0",
            ),
        ];
        for (set, expected) in cases {
            let o = elasto(dir, &["check", "s.toml", "--set", set]);
            assert_code(&o, 2);
            let err = stderr(&o);
            assert!(err.contains(&format!("--set {set}")), "{set}: {err}");
            assert!(err.contains(expected), "{set}: {err}");
        }
    }

    #[test]
    fn one_bodys_material_is_swept_by_flag_and_by_sweep_file() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        std::fs::write(dir.join("s.toml"), TWO_BOXES).unwrap();
        let o = elasto(
            dir,
            &[
                "sweep",
                "s.toml",
                "--vary",
                "bodies[1].material.young=100,2000",
                "--no-render",
                "--quiet",
                "-o",
                "sw",
            ],
        );
        assert_code(&o, 0);
        let runs: Vec<_> = folders(&dir.join("sw"))
            .iter()
            .map(|name| dir.join("sw").join(name))
            .collect();
        assert_eq!(runs.len(), 2, "{runs:?}");
        let youngs: Vec<(f64, f64)> = runs
            .iter()
            .map(|run| {
                let scene = resolved(run);
                (young(&scene, 0), young(&scene, 1))
            })
            .collect();
        assert_eq!(youngs, [(300.0, 100.0), (300.0, 2000.0)]);
        let table = std::fs::read_to_string(dir.join("sw/sweep.csv")).unwrap();
        assert!(
            table.starts_with("index,folder,bodies[1].material.young,"),
            "{table}"
        );

        std::fs::write(
            dir.join("release.toml"),
            "scene = \"s.toml\"\nset = { \"bodies[0].material.young\" = 900 }\n\
         [vary]\n\"effects.pinned[1].release\" = [0.05, 0.5]\n",
        )
        .unwrap();
        let o = elasto(
            dir,
            &[
                "sweep",
                "release.toml",
                "--no-render",
                "--quiet",
                "-o",
                "sf",
            ],
        );
        assert_code(&o, 0);
        let runs: Vec<_> = folders(&dir.join("sf"))
            .iter()
            .map(|name| dir.join("sf").join(name))
            .collect();
        let releases: Vec<(f64, Option<f64>, Option<f64>)> = runs
            .iter()
            .map(|run| {
                let scene = resolved(run);
                (young(&scene, 0), release(&scene, 0), release(&scene, 1))
            })
            .collect();
        assert_eq!(
            releases,
            [(900.0, None, Some(0.05)), (900.0, None, Some(0.5))]
        );
    }

    #[test]
    fn a_study_series_addresses_one_body() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        std::fs::write(dir.join("s.toml"), TWO_BOXES).unwrap();
        let o = elasto(
            dir,
            &[
                "study",
                "s.toml",
                "--vary",
                "time.substeps=1,2",
                "--series",
                "bodies[1].material.young=600",
                "-o",
                "st",
                "--quiet",
            ],
        );
        assert_code(&o, 0);
        let (header, rows) = read_csv(&dir.join("st/study.csv"));
        let column = header
            .iter()
            .position(|c| c == "bodies[1].material.young")
            .unwrap_or_else(|| panic!("{header:?}"));
        // The reference and two runs, each with the series' value.
        assert_eq!(rows.len(), 3, "{rows:?}");
        for row in rows.iter().skip(1) {
            assert_eq!(row[column].parse::<f64>().unwrap(), 600.0, "{row:?}");
        }
        // An index out of range in a series is named like in --set.
        let o = elasto(
            dir,
            &[
                "study",
                "s.toml",
                "--vary",
                "time.substeps=1,2",
                "--series",
                "bodies[5].material.young=600",
                "-o",
                "st2",
                "--quiet",
            ],
        );
        assert_code(&o, 2);
        assert!(
            stderr(&o).contains("index 5 of `bodies[5]` is out of range"),
            "{}",
            stderr(&o)
        );
    }
}
