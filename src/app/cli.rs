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
    /// Run a scene many times with some keys varied: one folder per run, a summary table, a contact sheet.
    Sweep(SweepArgs),
    /// Measure error against wall time over varied settings (a work-precision study).
    Study(StudyArgs),
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
    /// Video to write besides the PNG frames: auto = APNG and MP4.
    #[arg(long, value_enum, default_value_t = VideoChoice::Auto)]
    pub video: VideoChoice,
    /// At the end, print where the time went per frame: a table of solver and rendering
    /// phases (median ms per frame, total s).
    #[arg(long)]
    pub profile: bool,
}

/// Arguments of `elasto study`.
#[derive(Debug, Args)]
pub struct StudyArgs {
    /// Scene file or built-in scene name.
    pub scene: String,
    /// Vary a scene key over values: `KEY=V1,V2,...`, `KEY=linspace(A,B,N)` or
    /// `KEY=logspace(A,B,N)` (repeatable; all combinations are run).
    #[arg(long, value_name = "KEY=VALUES")]
    pub vary: Vec<String>,
    /// Pair the `--vary` lists value by value instead of running every combination.
    #[arg(long)]
    pub zip: bool,
    /// A series: overrides `KEY=VALUE;KEY=VALUE...` applied to every point of the
    /// `--vary` grid (repeatable; default: one series, the scene as it is).
    #[arg(long, value_name = "KEY=VALUE;...")]
    pub series: Vec<String>,
    /// Change the reference run (default: the finest step / 4, `solver.tolerance`
    /// 1e-8, Newton, BDF2), e.g. `--reference mesh.cells=[40,40]` (repeatable).
    #[arg(long, value_name = "KEY=VALUE")]
    pub reference: Vec<String>,
    /// Override a scene key in every run and the reference (repeatable; the value is TOML).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Number of output frames, replacing `time.frames` / `time.duration`.
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub frames: Option<i64>,
    /// Time every run this many times and report the median wall time (1 to 100).
    #[arg(long, value_name = "K", default_value_t = 1)]
    pub repeat: usize,
    /// The time study.png plots errors against: wall time, or the process's CPU
    /// time (all threads; steadier on a shared machine).
    #[arg(long, value_enum, default_value_t = StudyClock::Wall)]
    pub clock: StudyClock,
    /// Output folder (default: out/studies/SCENE_NAME).
    #[arg(long, short, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Write into an existing non-empty output folder, replacing the study's files there.
    #[arg(long)]
    pub force: bool,
    /// Print only the observed orders and errors (no progress lines).
    #[arg(long, short)]
    pub quiet: bool,
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

/// Arguments of `elasto sweep`.
#[derive(Debug, Args)]
pub struct SweepArgs {
    /// Scene file or built-in scene name, or a sweep file (TOML with `scene = ...` and `[vary]`).
    pub target: String,
    /// A varied key and its values: `KEY=V1,V2,...`, `KEY=linspace(A,B,N)` or `KEY=logspace(A,B,N)` (repeatable; values are TOML, split at commas outside [], {} and quotes).
    #[arg(long, value_name = "KEY=VALUES", allow_hyphen_values = true)]
    pub vary: Vec<String>,
    /// Pair the lists value by value (all the same length) instead of running every combination.
    #[arg(long)]
    pub zip: bool,
    /// Override a scene key in every run, e.g. `--set time.frames=60` (repeatable; the value is TOML).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Sweep folder (default: out/sweeps/NAME).
    #[arg(long, short, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Runs at a time (default: the machine's cores; the cores are shared between the runs).
    #[arg(long, short = 'j', value_name = "N", allow_negative_numbers = true)]
    pub jobs: Option<i64>,
    /// Only the runs whose index is I modulo N (0 <= I < N), e.g. `--shard 2/8`; collect afterwards with --collect.
    #[arg(long, value_name = "I/N", value_parser = parse_shard, allow_hyphen_values = true)]
    pub shard: Option<(usize, usize)>,
    /// Print the runs (index, folder, values) and exit, running nothing.
    #[arg(long)]
    pub list: bool,
    /// Run nothing: rebuild sweep.csv, sweep.json, the contact sheet and the comparison video from the run folders.
    #[arg(long)]
    pub collect: bool,
    /// Redo every run, even completed ones or folders with other parameters.
    #[arg(long)]
    pub force: bool,
    /// The frame shown in contact_sheet.png (default: each run's last).
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub sheet_frame: Option<i64>,
    /// Number of output frames of every run, replacing `time.frames` / `time.duration`.
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub frames: Option<i64>,
    /// Image size of every run, replacing `render.resolution`, e.g. `320x180`.
    #[arg(long, value_name = "WxH", value_parser = parse_resolution, allow_hyphen_values = true)]
    pub resolution: Option<(u32, u32)>,
    /// Only simulate: each run writes scene.toml and stats.csv, no images (no contact sheet).
    #[arg(long)]
    pub no_render: bool,
    /// Video of each run and of the comparison: auto = APNG and MP4.
    #[arg(long, value_enum, default_value_t = VideoChoice::Auto)]
    pub video: VideoChoice,
    /// A run whose health summary reports a problem fails (like `elasto run --strict`).
    #[arg(long)]
    pub strict: bool,
    /// Print nothing but errors (no progress).
    #[arg(long, short)]
    pub quiet: bool,
}

/// Parses `I/N` with `0 <= I < N`.
fn parse_shard(s: &str) -> Result<(usize, usize), String> {
    let (i, n) = s
        .split_once('/')
        .ok_or_else(|| format!("`{s}` is not I/N (e.g. 0/4)"))?;
    match (i.trim().parse::<usize>(), n.trim().parse::<usize>()) {
        (Ok(i), Ok(n)) if n >= 1 && i < n => Ok((i, n)),
        _ => Err(format!(
            "`{s}`: I and N must be whole numbers with 0 <= I < N (shards are numbered from 0)"
        )),
    }
}

/// The `--clock` choices of `elasto study`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum StudyClock {
    /// Wall time: what a user waits.
    Wall,
    /// CPU time of the process, all threads.
    Cpu,
}

/// The `--video` choices.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum VideoChoice {
    /// APNG and MP4 (video.png and video.mp4).
    Auto,
    /// No video, PNG frames only.
    None,
    /// Animated PNG (video.png).
    Apng,
    /// H.264 MP4 (video.mp4), encoded in the process: no ffmpeg needed.
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
    fn shard_parses_and_rejects() {
        assert_eq!(parse_shard("0/4"), Ok((0, 4)));
        assert_eq!(parse_shard("3/4"), Ok((3, 4)));
        for bad in ["4/4", "1", "-1/4", "1/0", "a/b"] {
            assert!(parse_shard(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn the_command_line_is_consistent() {
        use clap::CommandFactory;
        Cli::command().debug_assert();
    }
}
