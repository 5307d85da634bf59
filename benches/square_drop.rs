//! Time per step of the square-drop scene (`scenes/bench/square-drop.toml`,
//! issue 13) at 10 x 10, 20 x 20 and 40 x 40 cells, as a user runs it: the
//! scene file is loaded with `mesh.cells` overridden exactly as
//! `--set mesh.cells=[N,N]` does, and every one of its 200 steps is a full
//! `Simulation::step` (solve plus the per-step statistics).
//!
//! Run with `cargo bench --bench square_drop`. Each row is the median over
//! `RUNS` complete runs of (run time / steps); the iterations per step and
//! the final centre of mass show that a faster run still computes the same
//! motion. Set `ELASTO_BENCH_QUICK=1` for one run per size.

use elasto::scene::{Scene, SceneConfig, SceneOverride, SceneSource};
use elasto::sim::{Body, Simulation};
use std::path::Path;
use std::time::Instant;

const RUNS: usize = 5;

fn simulation(config: &SceneConfig<2>) -> Simulation<2> {
    let bodies = config
        .bodies
        .iter()
        .map(|body| Body {
            mesh: body.mesh.build().expect("the box meshes"),
            material: body.material.material,
            density: body.material.density,
            velocity: body.initial_velocity,
            pinned: body.pinned,
        })
        .collect();
    Simulation::with_bodies(bodies, config.effects.clone(), config.simulation_settings())
        .expect("the scene sets up")
}

fn main() {
    let quick = std::env::var_os("ELASTO_BENCH_QUICK").is_some();
    let runs = if quick { 1 } else { RUNS };
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/bench/square-drop.toml");
    let source = SceneSource::from_file(&path).expect("the benchmark scene exists");
    println!(
        "square drop, ms per step, median of {runs} runs, {} rayon threads",
        rayon::current_num_threads()
    );
    println!(
        "{:>8} {:>6} {:>10} {:>10} {:>10} {:>10} {:>10}  centre of mass at the end",
        "cells", "steps", "ms/step", "its/step", "assembly", "fac+solve", "line srch"
    );
    for n in [10usize, 20, 40] {
        let cells = SceneOverride::set("mesh.cells", &format!("[{n}, {n}]"), "--set")
            .expect("a valid override");
        let Scene::Two(config) = Scene::load(&source, &[cells]).expect("the scene is valid") else {
            panic!("the square drop is 2D");
        };
        let steps = config.time.frames * config.time.substeps;
        let mut per_step = Vec::new();
        let (mut iterations, mut phases, mut com) = (0, [0.0; 3], elasto::math::Vector2::zeros());
        for _ in 0..runs {
            let mut sim = simulation(&config);
            let start = Instant::now();
            (iterations, phases) = (0, [0.0; 3]);
            for _ in 0..steps {
                let step = sim.step().expect("the step succeeds");
                iterations += step.solver.iterations;
                let t = step.solver.times;
                phases[0] += t.assembly.as_secs_f64();
                phases[1] += (t.factorisation + t.solve).as_secs_f64();
                phases[2] += t.line_search.as_secs_f64();
                com = step.centre_of_mass;
            }
            per_step.push(start.elapsed().as_secs_f64() * 1e3 / steps as f64);
        }
        per_step.sort_by(f64::total_cmp);
        let ms = |s: f64| s * 1e3 / steps as f64;
        println!(
            "{:>8} {steps:>6} {:>10.3} {:>10.2} {:>10.3} {:>10.3} {:>10.3}  ({:.12}, {:.12})",
            format!("{n}x{n}"),
            per_step[per_step.len() / 2],
            iterations as f64 / steps as f64,
            ms(phases[0]),
            ms(phases[1]),
            ms(phases[2]),
            com.x,
            com.y,
        );
    }
}
