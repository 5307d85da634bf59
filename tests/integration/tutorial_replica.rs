//! `scenes/contact/self-friction-2d.toml` against the solid-sim tutorial's
//! own `8_self_friction`, whose trajectory is stored here as numbers: the
//! two squares' centres (the mean of their 9 vertices, the tutorial's y
//! shifted by +1 to elasto's ground at 0) after 50 … 300 steps of 0.01 s, from
//! `benches/tutorial/tutorial_run.py` on the tutorial at commit f463ddc.
//! The scenes differ in their barrier functions and mass lumping
//! (benches/tutorial/README.md), so the trajectories agree to a few
//! hundredths while the squares fall, meet and are squeezed, and the squeezed
//! heights to a thousandth. Friction decides where the upper square is
//! pushed out to: with μ = 0.3 instead of 0.4 the lower square ends 0.3
//! further right, with μ ≈ 0 the squares slide 0.9 and 2.7 away, so the
//! bounds below fail for a friction that acts differently.

use crate::cli_common::*;
use std::path::Path;

/// (step, top square's centre x, y, bottom square's centre x, y), the tutorial's.
const TUTORIAL: [(usize, f64, f64, f64, f64); 7] = [
    (50, -0.041705456, 0.764746027, 0.027942961, 0.239687144),
    (100, -0.159675484, 0.570034534, 0.001057567, 0.198819344),
    (125, -0.329668139, 0.457370576, -0.042288230, 0.176948517),
    (150, -0.967939266, 0.221335982, -0.353611020, 0.277533085),
    (200, -1.283989034, 0.150185257, -0.518361055, 0.150307102),
    (250, -1.364128411, 0.150192354, -0.461393173, 0.150282456),
    (300, -1.316911906, 0.150240616, -0.467884276, 0.150281123),
];

/// The points of a VTU file written by `--save-meshes` (ASCII, x y z per point).
fn vtu_points(path: &Path) -> Vec<[f64; 2]> {
    let text = std::fs::read_to_string(path).unwrap();
    let block = text.split("<Points>").nth(1).unwrap();
    let numbers = block.split_once('>').unwrap().1.split_once('<').unwrap().0;
    let values: Vec<f64> = numbers
        .split_whitespace()
        .map(|v| v.parse().unwrap())
        .collect();
    values.chunks(3).map(|p| [p[0], p[1]]).collect()
}

fn centre(points: &[[f64; 2]]) -> [f64; 2] {
    let n = points.len() as f64;
    [
        points.iter().map(|p| p[0]).sum::<f64>() / n,
        points.iter().map(|p| p[1]).sum::<f64>() / n,
    ]
}

#[test]
fn the_self_friction_replica_follows_the_tutorials_trajectory() {
    let dir = tempfile::tempdir().unwrap();
    let scene = format!(
        "{}/scenes/contact/self-friction-2d.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    // One frame per step, so every stored step has its mesh.
    let o = elasto(
        dir.path(),
        &[
            "run",
            &scene,
            "--no-render",
            "--save-meshes",
            "--quiet",
            "--set",
            "time.fps=100.0",
            "--set",
            "time.substeps=1",
            "--frames",
            "301",
            "--out",
            "run",
        ],
    );
    assert_code(&o, 0);
    let meshes = dir.path().join("run/meshes");
    for (step, top_x, top_y, bottom_x, bottom_y) in TUTORIAL {
        let points = vtu_points(&meshes.join(format!("frame_{step:04}.vtu")));
        assert_eq!(points.len(), 18, "two squares of 9 vertices");
        let top = centre(&points[..9]);
        let bottom = centre(&points[9..]);
        let dy = (top[1] - top_y).abs().max((bottom[1] - bottom_y).abs());
        let dx = (top[0] - top_x).abs().max((bottom[0] - bottom_x).abs());
        // Measured: dy at most 0.027 (step 150, the upper square sliding
        // off), dx at most 0.112 (step 200, after a slide of 1.3).
        assert!(
            dy < 0.03,
            "step {step}: heights {top:?} {bottom:?}, off by {dy}"
        );
        assert!(
            dx < 0.12,
            "step {step}: across {top:?} {bottom:?}, off by {dx}"
        );
        if step >= 200 {
            // Squeezed side by side under the plate at 0.3: measured 1.1e-3.
            assert!(dy < 2e-3, "step {step}: squeezed heights off by {dy}");
        }
    }
}
