//! Issue 30's acceptance figures through the binary: the default scene over 3000 frames (100 s) with every material settles at rest, with no step stalled, no body frozen, momentum conserved, and StVK kept uninverted by its volume barrier. (The old absolute J floor froze the StVK box at frame 347 for the remaining 88 s.)

use crate::cli_common as common;
use common::*;

/// One column of a run's `stats.csv`, as numbers.
fn column(dir: &std::path::Path, name: &str) -> Vec<f64> {
    let (header, rows) = read_csv(&dir.join("stats.csv"));
    let c = header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name}"));
    rows.iter().map(|r| r[c].parse().unwrap()).collect()
}

#[test]
fn the_default_scene_settles_over_100_seconds_with_every_material() {
    let tmp = tempfile::tempdir().unwrap();
    let mut resting_heights = Vec::new();
    for model in [
        "neo-hookean",
        "stvk",
        "stable-neo-hookean",
        "fixed-corotated",
    ] {
        let setting = format!("material.model=\"{model}\"");
        let o = elasto(
            tmp.path(),
            &[
                "run",
                "--no-render",
                "--frames",
                "3000",
                "--strict",
                "-q",
                "--set",
                &setting,
                "-o",
                model,
            ],
        );
        assert_code(&o, 0);
        let dir = tmp.path().join(model);
        for name in ["stalled_steps", "unconverged_steps"] {
            let steps = column(&dir, name);
            assert!(
                steps.iter().all(|&s| s == 0.0),
                "{model}: {name} in some frame"
            );
        }
        let com_x = column(&dir, "com_x");
        let drift = com_x
            .iter()
            .map(|x| (x - com_x[0]).abs())
            .fold(0.0, f64::max);
        assert!(drift < 1e-9, "{model}: com_x drifted by {drift}");
        let kinetic = column(&dir, "kinetic");
        let heights = column(&dir, "com_y");
        // No frozen body: kinetic energy exactly 0 only once at rest.
        let moving = heights.windows(2).position(|w| (w[1] - w[0]).abs() > 1e-6);
        for (frame, k) in kinetic.iter().enumerate().skip(1) {
            if *k == 0.0 {
                assert!(
                    moving.is_none_or(|m| frame > m + 1000),
                    "{model}: kinetic energy exactly 0 at frame {frame} while moving"
                );
            }
        }
        let elastic = column(&dir, "elastic");
        assert!(
            *elastic.last().unwrap() < 1e-2,
            "{model}: elastic energy at the end {}",
            elastic.last().unwrap()
        );
        if model != "stable-neo-hookean" && model != "fixed-corotated" {
            let j = column(&dir, "min_volume_ratio");
            assert!(j.iter().all(|&j| j > 0.0), "{model}: an element inverted");
        }
        resting_heights.push((model, *heights.last().unwrap()));
    }
    let neo_hookean = resting_heights[0].1;
    assert!(
        (neo_hookean - 0.5955).abs() < 1e-3,
        "Neo-Hookean rests at {neo_hookean}"
    );
    for (model, height) in &resting_heights[1..] {
        assert!(
            (height - neo_hookean).abs() < 5e-3,
            "{model} rests at com_y {height}, Neo-Hookean at {neo_hookean}"
        );
    }
}
