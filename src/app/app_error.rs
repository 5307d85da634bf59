//! Errors of the commands, each with its exit code (2: bad input, 1: failure).

use crate::compare::CompareError;
use crate::output::OutputError;
use crate::render::RenderError;
use crate::scene::SceneError;
use crate::sim::SimError;
use crate::sweep::SweepError;

/// Why a command stopped.
#[derive(Debug, thiserror::Error)]
pub enum AppError {
    /// The scene could not be found, parsed or validated.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// A flag's value is out of range.
    #[error("`{flag}`: {reason}")]
    Flag {
        /// The flag and its value as typed, e.g. `--threshold-mean -1`.
        flag: String,
        /// What is wrong.
        reason: String,
    },
    /// Setting up the simulation's solver failed (exit 1): the scene was
    /// valid (the validator refuses bad input before this, exit 2).
    #[error("cannot set up scene `{scene}`")]
    Setup {
        /// Scene name.
        scene: String,
        /// Why.
        source: SimError,
    },
    /// An environment variable elasto reads has a value it cannot take.
    #[error("`{variable}`: {reason}")]
    Environment {
        /// The variable and its value, e.g. `ELASTO_THREADS=0`.
        variable: String,
        /// What is wrong.
        reason: String,
    },
    /// The requested video cannot be written (e.g. MP4 frames over 3840x2160).
    #[error("--video {choice} is not available")]
    Video {
        /// The flag value.
        choice: String,
        /// Why.
        source: RenderError,
    },
    /// The output folder cannot be used or a file cannot be written.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// The solver failed while producing an output frame.
    #[error("simulation of scene `{scene}` failed while computing frame {frame}")]
    Simulation {
        /// Scene name.
        scene: String,
        /// Output frame being computed.
        frame: usize,
        /// The solver error (names the step).
        source: SimError,
    },
    /// The run finished, but its health summary reports a problem and
    /// `--strict` was given.
    #[error("scene `{scene}` ran with problems (--strict): {summary}")]
    Unhealthy {
        /// Scene name.
        scene: String,
        /// The health summary.
        summary: String,
    },
    /// Rendering failed.
    #[error("rendering failed")]
    Render(#[source] RenderError),
    /// Image comparison could not start (missing folders, unreadable images).
    #[error("cannot compare frames")]
    Compare(#[source] CompareError),
    /// A sweep could not be planned (exit 2) or some of its runs failed (exit 1).
    #[error(transparent)]
    Sweep(#[from] SweepError),
    /// Some frames differ from their golden images.
    #[error("{failed} of {total} frames differ from the golden images")]
    FramesDiffer {
        /// Frames that did not pass.
        failed: usize,
        /// Frames compared.
        total: usize,
    },
    /// The reference run of a study failed, so no run can be measured.
    #[error("the study's reference run failed: {reason}")]
    StudyReference {
        /// Why.
        reason: String,
    },
    /// Some runs of a study failed (the others are measured and written).
    #[error("{failed} of {total} study runs failed (see study.csv)")]
    StudyRunsFailed {
        /// Runs that failed.
        failed: usize,
        /// Runs in the study.
        total: usize,
    },
    /// The command's report could not be written to standard output (a full
    /// disk, a closed pipe); the files it wrote are kept.
    #[error("cannot write to standard output: {source}")]
    Stdout {
        /// The I/O error.
        source: std::io::Error,
    },
    /// The work-precision plot could not be drawn.
    #[error("cannot draw study.png: {reason}")]
    Plot {
        /// Why.
        reason: String,
    },
}

impl AppError {
    /// True when standard output is a pipe whose reader has gone (`elasto
    /// scenes | head -1`): the command has nothing left to say and ends
    /// quietly.
    pub fn is_broken_pipe(&self) -> bool {
        matches!(self, AppError::Stdout { source } if source.kind() == std::io::ErrorKind::BrokenPipe)
    }

    /// The process exit code: 2 for bad input (scene, flags, mesh, an
    /// existing output folder, comparison inputs), 1 for a failure while
    /// working (solver, renderer, writing a file, frames that differ).
    pub fn exit_code(&self) -> i32 {
        match self {
            AppError::Sweep(error) => error.exit_code(),
            AppError::Scene(_)
            | AppError::Flag { .. }
            | AppError::Environment { .. }
            | AppError::Video { .. } => 2,
            AppError::Compare(CompareError::Write { .. }) => 1,
            AppError::Compare(_) => 2,
            AppError::Output(
                OutputError::NotEmpty { .. }
                | OutputError::NotADirectory { .. }
                | OutputError::Symlink { .. }
                | OutputError::InTheWay { .. }
                | OutputError::InUse { .. },
            ) => 2,
            AppError::Output(OutputError::Io { .. }) => 1,
            AppError::Simulation { .. }
            | AppError::Setup { .. }
            | AppError::Unhealthy { .. }
            | AppError::Render(_)
            | AppError::FramesDiffer { .. }
            | AppError::StudyReference { .. }
            | AppError::StudyRunsFailed { .. }
            | AppError::Plot { .. }
            | AppError::Stdout { .. } => 1,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A failure of the solver's setup (the symbolic factorisation) is a
    /// failure while working (exit 1), not bad input (exit 2).
    #[test]
    fn a_solver_setup_failure_exits_1() {
        let setup = |source| AppError::Setup {
            scene: "s".into(),
            source,
        };
        let failure = setup(SimError::SetupFailure {
            reason: "sparse Cholesky factorisation failed: analysis".into(),
        });
        assert_eq!(failure.exit_code(), 1);
        assert!(!failure.to_string().contains("step 0"));
    }
}
