//! The commands: `run`, `scenes`, `check`, `compare`, `sweep` and `study`, from parsed flags to outputs.
//!
//! [`run`] is what `main` calls. Every command first turns its flags and the
//! scene into validated settings, then checks what the run needs against
//! this machine and the built simulation (`preflight.rs`: memory, the
//! adapter's image size, the starting energy, the barrier stiffness) — bad
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
use crate::sim::{Body, SimError, Simulation};
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

/// Builds a scene's mesh and simulation (no steps taken), after checking
/// that it fits in memory, and checks what only the built meshes and
/// simulation know: masses not lost beside the stiffness, the barrier
/// stiffness against the automatic one and a finite starting energy. Every problem is a scene error at its key.
fn build_simulation<const D: usize>(
    config: &SceneConfig<D>,
    input: SceneInput,
) -> Result<Simulation<D>, AppError> {
    preflight::check_simulation_memory(config, input)?;
    let mut bodies = Vec::with_capacity(config.bodies.len());
    for body in &config.bodies {
        let mesh = body.mesh.build().map_err(|source| {
            input.error(
                &format!("{}mesh", body.key_prefix),
                format!("cannot be meshed: {source}"),
            )
        })?;
        preflight::check_mass_against_stiffness(config, body, &mesh, input)?;
        bodies.push(Body {
            mesh,
            material: body.material.material,
            density: body.material.density,
            velocity: body.initial_velocity,
            pinned: body.pinned,
        });
    }
    let sim = Simulation::with_bodies(bodies, config.effects.clone(), config.simulation_settings())
        .map_err(|source| setup_error(config, input, source))?;
    preflight::check_starting_energy(config, &sim, input)?;
    preflight::check_barrier_stiffness(config, &sim, input)?;
    Ok(sim)
}

/// A setting the simulation refuses, at its scene key when it has one
/// (validation rejects these first; this keeps the message located).
fn setup_error<const D: usize>(
    config: &SceneConfig<D>,
    input: SceneInput,
    source: SimError,
) -> AppError {
    let key = match &source {
        SimError::InvalidSetting { key, .. } => match *key {
            "density" if config.bodies.len() > 1 => Some("bodies"),
            "pinned" if config.bodies.len() > 1 => Some("bodies"),
            "density" => Some("material.density"),
            "dt" => Some("time.dt"),
            "tolerance" | "max_iterations" | "step" => Some("solver"),
            "pinned" => Some("effects.pinned"),
            "a" | "kappa" => Some("effects.ground"),
            "contact" => Some("effects.contact"),
            "obstacles" => Some("obstacles"),
            _ => None,
        },
        SimError::BelowGround { .. } if config.bodies.len() > 1 => Some("bodies"),
        SimError::BelowGround { .. } => Some("mesh.offset"),
        SimError::ContactAtStart { bodies, .. } if bodies.contains("obstacle") => Some("obstacles"),
        SimError::ContactAtStart { .. } => Some("effects.contact"),
        SimError::BodyInsideBody { .. } => Some("bodies"),
        _ => None,
    };
    match key {
        Some(key) => input.error(key, source.to_string()),
        None => AppError::Setup {
            scene: config.name.clone(),
            source,
        },
    }
}
