//! The commands: `run`, `scenes`, `check` and `compare`, from parsed flags to outputs.
//!
//! [`run`] is what `main` calls. Every command first turns its flags and the
//! scene into validated settings (bad input: [`AppError::exit_code`] 2),
//! and only then starts work (failures: exit code 1).

mod app_error;
mod check_command;
mod cli;
mod compare_command;
mod progress;
mod render_stage;
mod run_command;
mod scenes_command;

pub use app_error::AppError;
pub use cli::{
    CheckArgs, Cli, Command, CompareArgs, RunArgs, ScenesAction, ScenesArgs, VideoChoice,
};
pub use progress::{Progress, ProgressMode};

use crate::scene::{SceneConfig, SceneError, SceneOverride};
use crate::sim::Simulation;

/// Runs one command.
pub fn run(cli: Cli) -> Result<(), AppError> {
    match cli.command {
        Command::Run(args) => run_command::run(&args),
        Command::Scenes(args) => {
            print!("{}", scenes_command::scenes(&args)?);
            Ok(())
        }
        Command::Check(args) => {
            print!("{}", check_command::check(&args)?);
            Ok(())
        }
        Command::Compare(args) => compare_command::compare(&args),
    }
}

/// Parses the `--set` arguments.
fn scene_overrides(set: &[String]) -> Result<Vec<SceneOverride>, SceneError> {
    set.iter().map(|s| s.parse()).collect()
}

/// Builds a scene's mesh and simulation (no steps taken); mesh and setup
/// errors name the scene.
fn build_simulation<const D: usize>(config: &SceneConfig<D>) -> Result<Simulation<D>, AppError> {
    let mesh = config.mesh.build().map_err(|source| AppError::Mesh {
        scene: config.name.clone(),
        source,
    })?;
    Simulation::new(
        mesh,
        config.material.material,
        config.material.density,
        config.effects.clone(),
        config.simulation_settings(),
        config.initial_velocity,
    )
    .map_err(|source| AppError::Setup {
        scene: config.name.clone(),
        source,
    })
}
