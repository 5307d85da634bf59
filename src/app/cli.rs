//! The command line, as clap derive structs (the `///` lines are the `--help` text).

use clap::{Args, Parser, Subcommand, ValueEnum};
use std::path::PathBuf;

/// Simulate elastic solids with linear finite elements and render them headless.
#[derive(Debug, Parser)]
#[command(name = "elasto", version, about, long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Simulate a scene and write its outputs (scene.toml, stats.csv, frames, video).
    Run(RunArgs),
    /// List the built-in scenes, or print one with `scenes show NAME`.
    Scenes(ScenesArgs),
    /// Validate a scene and print a summary, without simulating.
    Check(CheckArgs),
    /// Compare rendered frames with golden images (FLIP); exit 1 if any frame fails.
    Compare(CompareArgs),
}

/// Arguments of `elasto run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// Scene file or built-in scene name (default: report-drop-2d).
    pub scene: Option<String>,
    /// Output folder (default: out/SCENE_NAME).
    #[arg(long, short, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Override a scene key, e.g. `--set material.young=500` (repeatable; the value is TOML).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Number of output frames, replacing `time.frames` / `time.duration`.
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub frames: Option<i64>,
    /// Only simulate: write scene.toml and stats.csv (and meshes), no images.
    #[arg(long)]
    pub no_render: bool,
    /// Also write every frame's mesh as VTK (meshes/frame_NNNN.vtu and meshes/frames.pvd).
    #[arg(long)]
    pub save_meshes: bool,
    /// Also write every frame's boundary surface as OBJ or binary PLY (surfaces/surface_NNNN.obj|ply, numbered like the frames; PLY carries the render field per vertex).
    #[arg(long, value_name = "obj|ply")]
    pub save_surface: Option<crate::output::SurfaceFormat>,
    /// Print nothing but errors and the health warning (no progress).
    #[arg(long, short)]
    pub quiet: bool,
    /// Write into an existing non-empty output folder, replacing elasto's files there.
    #[arg(long)]
    pub force: bool,
    /// Image size in pixels, replacing `render.resolution`, e.g. `640x360`.
    #[arg(long, value_name = "WxH", value_parser = parse_resolution, allow_hyphen_values = true)]
    pub resolution: Option<(u32, u32)>,
    /// Exit with code 1 when the run's health summary reports a problem (steps at the
    /// iteration cap or stalled, inverted elements, a vertex on the ground).
    #[arg(long)]
    pub strict: bool,
    /// Video to write besides the PNG frames: auto = APNG, plus MP4 when ffmpeg is available.
    #[arg(long, value_enum, default_value_t = VideoChoice::Auto)]
    pub video: VideoChoice,
    /// At the end, print where the time went per frame: a table of solver and rendering
    /// phases (median ms per frame, total s).
    #[arg(long)]
    pub profile: bool,
}

/// Arguments of `elasto check`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// Scene file or built-in scene name.
    pub scene: String,
    /// Override a scene key, e.g. `--set material.young=500` (repeatable; the value is TOML).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

/// Arguments of `elasto scenes`.
#[derive(Debug, Args)]
pub struct ScenesArgs {
    /// `show NAME` prints a built-in scene's TOML.
    #[command(subcommand)]
    pub action: Option<ScenesAction>,
}

/// Subcommands of `elasto scenes`.
#[derive(Debug, Subcommand)]
pub enum ScenesAction {
    /// Print a built-in scene's TOML (redirect it to a file to start your own scene).
    Show {
        /// Built-in scene name.
        name: String,
    },
}

/// Arguments of `elasto compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// Folder of golden PNG frames.
    #[arg(long, value_name = "DIR")]
    pub golden: PathBuf,
    /// Folder of rendered PNG frames to check.
    #[arg(long, value_name = "DIR")]
    pub frames: PathBuf,
    /// Folder for the difference images (default: FRAMES/../diff).
    #[arg(long, value_name = "DIR")]
    pub diff: Option<PathBuf>,
    /// Largest accepted mean FLIP error per frame, in [0, 1] (default 0.02).
    #[arg(long, value_name = "X", allow_hyphen_values = true)]
    pub threshold_mean: Option<f64>,
    /// Largest accepted FLIP error at the checked percentile, in [0, 1] (default 0.1).
    #[arg(long, value_name = "Y", allow_hyphen_values = true)]
    pub threshold_percentile: Option<f64>,
    /// The percentile of the FLIP error map that `--threshold-percentile` bounds, in (0, 1) (default 0.999).
    #[arg(long, value_name = "P", allow_hyphen_values = true)]
    pub percentile: Option<f64>,
}

/// The `--video` choices.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum VideoChoice {
    /// APNG always, plus MP4 when ffmpeg with libx264 is on PATH.
    Auto,
    /// No video, PNG frames only.
    None,
    /// Animated PNG (video.png).
    Apng,
    /// H.264 MP4 through ffmpeg (video.mp4); an error when ffmpeg is missing.
    Mp4,
    /// Animated GIF (video.gif).
    Gif,
}

/// Parses `WIDTHxHEIGHT`.
fn parse_resolution(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("`{s}` is not WIDTHxHEIGHT (e.g. 640x360)"))?;
    let side = |v: &str| -> Result<u32, String> {
        match v.trim().parse::<u32>() {
            Ok(n) if (1..=crate::scene::MAX_RESOLUTION).contains(&n) => Ok(n),
            _ => Err(format!(
                "`{s}`: each side must be a whole number of pixels in 1..={}",
                crate::scene::MAX_RESOLUTION
            )),
        }
    };
    Ok((side(w)?, side(h)?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resolution_parses_and_rejects() {
        assert_eq!(parse_resolution("160x120"), Ok((160, 120)));
        assert_eq!(parse_resolution("1920X1080"), Ok((1920, 1080)));
        for bad in ["160", "0x10", "ax3", "10x-1", "99999x10"] {
            assert!(parse_resolution(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn the_command_line_is_consistent() {
        use clap::CommandFactory;
        Cli::command().debug_assert();
    }
}
