//! The commands: `run`, `scenes`, `check`, `compare`, `sweep` and `study`, from parsed flags to outputs.
//!
//! [`run`] is what `main` calls. Every command first turns its flags and the
//! scene into validated settings (the scene validator: every value, at its
//! key), then checks what the run needs against this machine
//! (`preflight.rs`: memory, the adapter's image size), has the validator
//! mesh the bodies and check them as a whole, and checks what only the
//! built simulation knows (`preflight.rs`: the starting energy) — bad
//! input, [`AppError::exit_code`] 2 — and only then starts work (failures:
//! exit code 1). A finished run reports what went wrong without stopping it
//! in its [`RunHealth`] summary.

mod app_error;
mod check_command;
mod cli;
mod compare_command;
mod preflight;
mod process_clock;
mod progress;
mod render_stage;
mod run_command;
mod run_health;
mod run_profile;
mod scenes_command;
mod standard_output;
mod study_command;
mod sweep_command;
mod thread_count;

pub use app_error::AppError;
pub use cli::{
    CheckArgs, Cli, Command, CompareArgs, RunArgs, ScenesAction, ScenesArgs, StudyArgs, SweepArgs,
    VideoChoice,
};
pub use progress::{Progress, ProgressMode};
pub use run_health::RunHealth;

use crate::scene::{SceneConfig, SceneError, SceneOverride};
use crate::sim::Simulation;
use preflight::SceneInput;

/// Runs one command.
pub fn run(cli: Cli) -> Result<(), AppError> {
    thread_count::configure_threads()?;
    if let Some(reason) = crate::render::backend_variable_problem() {
        return Err(AppError::Environment {
            variable: format!(
                "{}={}",
                crate::render::BACKEND_VARIABLE,
                std::env::var_os(crate::render::BACKEND_VARIABLE)
                    .unwrap_or_default()
                    .to_string_lossy()
            ),
            reason,
        });
    }
    match cli.command {
        Command::Run(args) => run_command::run(&args),
        Command::Scenes(args) => standard_output::print(&scenes_command::scenes(&args)?),
        Command::Check(args) => standard_output::print(&check_command::check(&args)?),
        Command::Compare(args) => compare_command::compare(&args),
        Command::Sweep(args) => sweep_command::sweep(&args),
        Command::Study(args) => study_command::study(&args),
    }
}

/// Parses the `--set` arguments.
fn scene_overrides(set: &[String]) -> Result<Vec<SceneOverride>, SceneError> {
    set.iter().map(|s| s.parse()).collect()
}

/// The overrides the shortcut flags stand for: `--frames N` replaces
/// `time.duration` / `time.frames`, `--resolution WxH` sets
/// `render.resolution`; each reported as the flag the user typed.
fn shortcut_overrides(
    frames: Option<i64>,
    resolution: Option<(u32, u32)>,
) -> Result<Vec<SceneOverride>, SceneError> {
    let mut overrides = Vec::new();
    if let Some(frames) = frames {
        let flag = format!("--frames {frames}");
        overrides.push(SceneOverride::remove("time.duration", flag.clone())?);
        overrides.push(SceneOverride::set(
            "time.frames",
            &frames.to_string(),
            flag,
        )?);
    }
    if let Some((w, h)) = resolution {
        let flag = format!("--resolution {w}x{h}");
        overrides.push(SceneOverride::set(
            "render.resolution",
            &format!("[{w}, {h}]"),
            flag,
        )?);
    }
    Ok(overrides)
}

/// Builds a scene's meshes and simulation (no steps taken): first checks
/// that it fits in memory, then has the validator mesh the bodies and check
/// them as a whole (its second stage, [`SceneConfig::meshed_bodies`]), and
/// after building checks what only the simulation knows: a finite starting
/// energy. Every
/// problem is a scene error at its key; the simulation itself fails only in
/// setting up its solver.
fn build_simulation<const D: usize>(
    config: &SceneConfig<D>,
    input: SceneInput,
) -> Result<Simulation<D>, AppError> {
    preflight::check_simulation_memory(config, input)?;
    let bodies = config.meshed_bodies(input.source, input.overrides)?;
    let sim = Simulation::with_bodies(bodies, config.effects.clone(), config.simulation_settings())
        .map_err(|source| AppError::Setup {
            scene: config.name.clone(),
            source,
        })?;
    preflight::check_starting_energy(config, &sim, input)?;
    Ok(sim)
}
