//! `elasto run`: validate everything, then simulate, write data, render.
//!
//! Frame `i` of a run is the state at time `i / fps`, for `i = 0 .. frames - 1`;
//! frame 0 is the initial state, so a run simulates `(frames - 1) * substeps`
//! steps and its video lasts `frames / fps` seconds.
//!
//! Data outputs are written as each frame is simulated, `stats.csv` among
//! them, whatever the rendering does: an interrupted run keeps the rows of
//! every frame simulated. Images are written as the frames come too when
//! the scene fixes the camera and the colour range; otherwise they are
//! rendered after the simulation (see [`RenderStage`]). `--profile` prints
//! the phases of every frame, rendering included, as a table at the end
//! ([`RunProfile`]).

use super::cli::{RunArgs, VideoChoice};
use super::preflight::{self, SceneInput};
use super::process_clock::{Stopwatch, cores};
use super::progress::{Progress, ProgressMode};
use super::render_stage::RenderStage;
use super::run_health::RunHealth;
use super::run_profile::{RunProfile, RunSpans};
use super::{AppError, build_simulation, scene_overrides, shortcut_overrides};
use crate::encode::{RenderOutputs, VideoFormat, check_video_support, video_file_name};
use crate::energy::ElementField;
use crate::output::{MeshSeriesWriter, OutputDir, StatsWriter, SurfaceFormat, SurfaceSeriesWriter};
use crate::render::{RenderFrame, RenderMesh};
use crate::scene::{FieldChoice, Scene, SceneConfig, SceneSource};
use crate::sim::Simulation;
use std::path::PathBuf;

/// Runs `elasto run`.
pub fn run(args: &RunArgs) -> Result<(), AppError> {
    let start = Stopwatch::start();
    // 1. Everything the user gave is validated before anything is written.
    let source = SceneSource::resolve(args.scene.as_deref())?;
    let mut overrides = scene_overrides(&args.set)?;
    overrides.extend(shortcut_overrides(args.frames, args.resolution)?);
    let (scene, resolved) = Scene::load_resolved(&source, &overrides)?;
    let videos = if args.no_render {
        Vec::new()
    } else {
        let videos = videos(args.video);
        let size = scene.render();
        check_video_support(&videos, size.width, size.height).map_err(|source| {
            AppError::Video {
                choice: format!("{:?}", args.video).to_lowercase(),
                source,
            }
        })?;
        videos
    };
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out").join(scene.name()));
    let plan = Plan {
        out,
        resolved,
        videos,
        render: !args.no_render,
        save_meshes: args.save_meshes,
        save_surface: args.save_surface,
        force: args.force,
        strict: args.strict,
        progress: ProgressMode::detect(args.quiet),
        profile: args.profile.then_some(start),
    };
    let input = SceneInput {
        source: &source,
        overrides: &overrides,
    };
    // A mesh file changed since the scene recorded it: --strict refuses.
    if args.strict
        && let Some((key, change)) = scene.changed_mesh_files().into_iter().next()
    {
        let reason = format!("{change} (--strict)");
        return Err(AppError::Scene(Scene::key_error(
            &source, &overrides, &key, reason,
        )));
    }
    for warning in scene.warnings() {
        eprintln!("elasto: warning: {warning}");
    }
    match &scene {
        Scene::Two(config) => run_scene(config, &plan, input),
        Scene::Three(config) => run_scene(config, &plan, input),
    }
}

/// What to do with a validated scene.
struct Plan {
    out: PathBuf,
    resolved: String,
    videos: Vec<VideoFormat>,
    render: bool,
    save_meshes: bool,
    save_surface: Option<SurfaceFormat>,
    force: bool,
    strict: bool,
    progress: ProgressMode,
    /// `--profile`: when the run started, and its CPU time then.
    profile: Option<Stopwatch>,
}

/// The videos to write: `auto` is APNG and MP4.
pub(super) fn videos(choice: VideoChoice) -> Vec<VideoFormat> {
    match choice {
        VideoChoice::Auto => vec![VideoFormat::Apng, VideoFormat::Mp4],
        VideoChoice::Apng => vec![VideoFormat::Apng],
        VideoChoice::None => Vec::new(),
        VideoChoice::Gif => vec![VideoFormat::Gif],
        VideoChoice::Mp4 => vec![VideoFormat::Mp4],
    }
}

impl Plan {
    /// The top-level names this run writes in its folder.
    fn writes(&self) -> Vec<&'static str> {
        let mut names = vec!["scene.toml", "stats.csv"];
        if self.save_meshes {
            names.push("meshes");
        }
        if self.save_surface.is_some() {
            names.push("surfaces");
        }
        if self.render {
            names.push("frames");
            names.extend(self.videos.iter().map(|v| video_file_name(*v)));
        }
        names
    }
}

/// The thread opening the graphics adapter while the run sets up, joined
/// when dropped: a run that stops early (a bad output folder, a failed
/// setup) must not exit while that thread is inside the graphics driver,
/// whose exit handlers then crash the process (SIGSEGV or SIGABRT instead
/// of exit code 2).
struct AdapterCheck(
    Option<std::thread::JoinHandle<Result<(u32, u64), crate::render::RenderError>>>,
);

impl Drop for AdapterCheck {
    fn drop(&mut self) {
        if let Some(thread) = self.0.take() {
            let _ = thread.join();
        }
    }
}

fn run_scene<const D: usize>(
    config: &SceneConfig<D>,
    plan: &Plan,
    input: SceneInput,
) -> Result<(), AppError> {
    let name = config.name.clone();
    if plan.render && config.render.needs_whole_run() {
        preflight::check_kept_frames(config, input)?;
    }
    // No graphics adapter, or an image it cannot hold: fail at once, not
    // after the simulation. Opening the adapter takes a while (about 60 ms
    // for llvmpipe), so it is opened on a thread of its own, and the
    // simulation starts meanwhile and stops at the first frame after the
    // answer if it is no.
    let mut adapter_check = AdapterCheck(
        plan.render
            .then(|| std::thread::spawn(crate::render::max_image_size)),
    );
    let mut check_adapter = |wait: bool| -> Result<(), AppError> {
        match adapter_check
            .0
            .take_if(|thread| wait || thread.is_finished())
        {
            Some(thread) => {
                let limits = thread
                    .join()
                    .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
                preflight::check_image_size(&config.render, input, limits)
            }
            None => Ok(()),
        }
    };
    let mut sim = build_simulation(config, input)?;
    let render_mesh = plan.render.then(|| render_view(&sim));

    // 2. The output folder: refused (untouched) when it holds anything, unless
    //    --force; even then links and things in the way of the outputs are.
    //    An earlier run there stays whole until this one is complete.
    let out = OutputDir::check(&plan.out, plan.force, &plan.writes())?;
    let mut out = out.begin_run()?;
    let mut kept_note = EarlierRunNote(out.replaces_earlier_run().then(|| out.path().to_owned()));
    out.write("scene.toml", &resolved_header(&plan.resolved))?;
    let mut stats = StatsWriter::create(&out.join("stats.csv"), &sim.energy_names())?;
    let mut profile = plan.profile.map(|_| RunProfile::default());
    let mut meshes = if plan.save_meshes {
        Some(MeshSeriesWriter::create(&out.join("meshes"))?)
    } else {
        None
    };
    let frames = config.time.frames;
    let surfaces = match plan.save_surface {
        Some(format) => {
            let obstacles: Vec<_> = sim.obstacles().iter().map(|o| &*o.surface).collect();
            let moves = sim.obstacles().iter().any(|o| o.motion.is_moving());
            Some(
                SurfaceSeriesWriter::create(&out.join("surfaces"), sim.mesh(), format, frames)?
                    .with_obstacles(&obstacles, moves),
            )
        }
        None => None,
    };
    let mut render = render_mesh.map(|render_mesh| {
        let settings = config.render.clone();
        let outputs = RenderOutputs {
            frames_dir: out.join("frames"),
            video_dir: out.writing_path().to_owned(),
            videos: plan.videos.clone(),
            fps: config.time.fps,
        };
        RenderStage::new(settings, render_mesh, outputs, frames)
    });

    // 3. Simulate frame by frame, streaming the data outputs (and the images
    //    when the renderer can take them now).
    let field = config.field.element_field();
    let field_name = match field {
        ElementField::EnergyDensity => "energy_density",
        ElementField::VonMises => "von_mises",
        ElementField::VolumeRatio => "volume_ratio",
    };
    let streaming = render.as_ref().is_some_and(RenderStage::is_streaming);
    let label = if streaming {
        "simulate+render"
    } else {
        "simulate"
    };
    let mut progress = Progress::start(plan.progress, label, frames);
    let mut health = RunHealth::new(sim.allows_inversion(), sim.is_closed());
    let mut unconverged_reported = false;
    let simulated = (|| -> Result<(), AppError> {
        for frame in 0..frames {
            check_adapter(false)?;
            let frame_stats = if frame == 0 {
                sim.frame_stats()
            } else {
                sim.advance_frame(config.time.substeps)
                    .map_err(|source| AppError::Simulation {
                        scene: name.clone(),
                        frame,
                        source,
                    })?
            };
            stats.write_frame(frame, &frame_stats)?;
            if let Some(profile) = &mut profile
                && frame > 0
            {
                let contact = frame_stats.contact.map(|c| {
                    [
                        c.broad_phase,
                        c.ccd,
                        c.assembly,
                        frame_stats.times.pattern_growth,
                    ]
                });
                profile.simulated(&frame_stats.times, frame_stats.wall_time, contact);
            }
            let steps = if frame == 0 { 0 } else { config.time.substeps };
            let touched_before = health.first_contact_failure().is_some();
            let energy_rose_before = health.energy_rise().is_some();
            health.add(frame, steps, &frame_stats);
            if !energy_rose_before && let Some((_, rise)) = health.energy_rise() {
                if plan.strict {
                    return Err(AppError::Unhealthy {
                        scene: name.clone(),
                        summary: rise,
                    });
                }
                eprintln!("elasto: warning: {rise}");
            }
            if frame_stats.unconverged_steps + frame_stats.stalled_steps > 0 {
                let blocked = frame_stats
                    .blocked_by
                    .map(|(term, blocker)| format!(" (no room for any step: {term}: {blocker})"))
                    .unwrap_or_default();
                let failed = format!(
                    "frame {frame} (t = {:.6} s): {} step(s) hit the iteration cap and {} \
                     stalled in the line search{blocked}, even as {} shorter steps",
                    frame_stats.time,
                    frame_stats.unconverged_steps,
                    frame_stats.stalled_steps,
                    1usize << config.solver.max_subdivisions,
                );
                if plan.strict {
                    return Err(AppError::Unhealthy {
                        scene: name.clone(),
                        summary: failed,
                    });
                }
                if !unconverged_reported {
                    unconverged_reported = true;
                    eprintln!(
                        "elasto: warning: {failed} (reported once; the health summary counts them all)"
                    );
                }
            }
            if !touched_before && let Some(first) = health.first_contact_failure() {
                eprintln!(
                    "elasto: warning: surfaces touched or crossed at frame {first} \
                     (t = {:.6} s): the contact barrier failed to keep them apart",
                    frame_stats.time
                );
            }
            if meshes.is_some() || render.is_some() || surfaces.is_some() {
                let values = sim.element_field(field);
                if let Some(writer) = &surfaces {
                    let shown = match config.field {
                        FieldChoice::Flat => None,
                        FieldChoice::Scalar(_) => Some((field_name, values.as_slice())),
                    };
                    writer.write_frame(frame, sim.positions(), shown)?;
                    writer.write_obstacles(frame, sim.obstacle_positions())?;
                }
                if let Some(writer) = &mut meshes {
                    let (contact, friction) = (sim.contact_forces(), sim.friction_forces());
                    let point_vectors: Vec<(&str, &[_])> = contact
                        .iter()
                        .map(|f| ("contact_force", f.as_slice()))
                        .chain(friction.iter().map(|f| ("friction_force", f.as_slice())))
                        .collect();
                    writer.write_frame(
                        frame,
                        frame_stats.time,
                        sim.mesh(),
                        sim.positions(),
                        &[(field_name, &values)],
                        &point_vectors,
                    )?;
                }
                if let Some(render) = &mut render {
                    render
                        .add(RenderFrame::from_positions(sim.drawn_positions(), &values))
                        .map_err(AppError::Render)?;
                }
            }
            progress.update(frame + 1, || {
                format!(
                    "t = {:.3} s, {} Newton iterations, {} backtracks",
                    frame_stats.time, frame_stats.iterations, frame_stats.backtracks
                )
            });
        }
        check_adapter(true)
    })();
    progress.finish();

    // 4. Complete the frames and the videos.
    let (mut rendering, mut frames_span) = (None, None);
    let rendered = simulated.and_then(|()| match render.take() {
        Some(render) => {
            let deferred = !render.is_streaming();
            let watch = Stopwatch::start();
            let (costs, frames) = render.finish(plan.progress).map_err(AppError::Render)?;
            rendering = deferred.then(|| watch.span());
            frames_span = frames;
            if let Some(profile) = &mut profile {
                costs.iter().for_each(|cost| profile.rendered(cost));
            }
            Ok(())
        }
        None => Ok(()),
    });
    if let Err(error) = rendered {
        // Dropping the renderer first removes its partial videos.
        drop(render);
        return Err(error);
    }
    // The run is complete: its outputs replace an earlier run's.
    kept_note.0 = None;
    out.complete()?;
    // A table that cannot be written is reported after the run's own lines:
    // its files are complete either way.
    let table_written = match (plan.profile, &profile) {
        (Some(start), Some(profile)) => {
            let spans = RunSpans {
                run: start.span(),
                rendering,
                frames: frames_span,
            };
            super::standard_output::print(&profile.table(&spans, cores()))
        }
        _ => Ok(()),
    };

    if plan.progress != ProgressMode::Quiet {
        let mut wrote = vec!["scene.toml".to_owned(), "stats.csv".to_owned()];
        if plan.save_meshes {
            wrote.push("meshes/".into());
        }
        if plan.save_surface.is_some() {
            wrote.push("surfaces/".into());
        }
        if plan.render {
            wrote.push("frames/".into());
            wrote.extend(plan.videos.iter().map(|v| video_file_name(*v).to_owned()));
        }
        eprintln!(
            "{name}: {frames} frames written to {}: {}",
            out.path().display(),
            wrote.join(", ")
        );
    }

    // 5. Say what went wrong without stopping the run (always, even when quiet).
    if health.has_problems() {
        let summary = health.summary(config.solver.max_iterations);
        if plan.strict {
            return Err(AppError::Unhealthy {
                scene: name,
                summary,
            });
        }
        eprintln!("warning: {name}: health: {summary}");
    }
    table_written
}

/// Says, when a run that was to replace an earlier one stops before it is
/// complete, that the earlier run is kept (its outputs are not this run's).
struct EarlierRunNote(Option<PathBuf>);

impl Drop for EarlierRunNote {
    fn drop(&mut self) {
        if let Some(folder) = &self.0 {
            use std::io::Write;
            let _ = writeln!(
                std::io::stderr(),
                "elasto: the earlier run in {} is kept as it was; this run's outputs are removed",
                folder.display()
            );
        }
    }
}

/// The resolved scene with a note on how to reuse it.
/// What the renderer draws of `sim`: its bodies, then its obstacles, whose
/// points follow the bodies' vertices in [`Simulation::drawn_positions`].
fn render_view<const D: usize>(sim: &Simulation<D>) -> RenderMesh {
    let mut view = RenderMesh::from_mesh(sim.mesh());
    let mut first_vertex = sim.mesh().vertex_count();
    for obstacle in sim.obstacles() {
        view.add_obstacle(first_vertex, obstacle.surface.facets(), &obstacle.fill);
        first_vertex += obstacle.surface.points().len();
    }
    view
}

fn resolved_header(resolved: &str) -> String {
    format!(
        "# The fully resolved scene of this run (defaults filled in, overrides applied).\n\
         # Reproduce the run with: elasto run path/to/this/scene.toml\n\n{resolved}"
    )
}
