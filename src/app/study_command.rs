//! `elasto study`: error against wall time over varied settings.
//!
//! 1. The runs: every `--series` (a set of overrides, default: the scene as
//!    it is) times every point of the `--vary` grid (cartesian, or `--zip`;
//!    the sweep's parser and expansion). Each run and the reference are
//!    validated before any is simulated (exit 2).
//! 2. The reference (see [`reference_overrides`]): by default the finest
//!    step of the study divided by 4, tolerance 1e-8, Newton and BDF2.
//! 3. Each run is simulated `--repeat K` times in this process, without
//!    writing files; the first repetition is compared frame by frame with
//!    the reference ([`crate::study`] defines the errors) and the wall time
//!    is the median over the repetitions (setup and stepping).
//! 4. `study.csv`, `study.md`, `study.png`, and the observed order of
//!    convergence in `dt` of each series printed on stdout.

use super::cli::{StudyArgs, StudyClock};
use super::preflight::SceneInput;
use super::progress::{Progress, ProgressMode};
use super::{AppError, build_simulation, scene_overrides, shortcut_overrides};
use crate::output::OutputDir;
use crate::scene::{Scene, SceneConfig, SceneOverride, SceneSource};
use crate::study::{
    PlotPoint, Reference, RunErrors, RunStatus, StudyRow, StudyTable, observed_order,
    work_precision_plot,
};
use crate::sweep::{expand, parse_vary};
use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// The files a study writes in its folder.
const STUDY_FILES: [&str; 3] = ["study.csv", "study.md", "study.png"];

/// Size of `study.png`, in pixels.
const PLOT_SIZE: (u32, u32) = (1200, 800);

/// Keys that name a series of the plot (with any key a `--series` sets).
const SERIES_KEYS: [&str; 2] = ["solver.method", "time.integrator"];

/// Keys that set the time step (left out when grouping runs by everything
/// but `dt` to measure the order of convergence).
const STEP_KEYS: [&str; 2] = ["time.substeps", "time.dt"];

/// Runs `elasto study`.
pub fn study(args: &StudyArgs) -> Result<(), AppError> {
    if !(1..=100).contains(&args.repeat) {
        return Err(AppError::Flag {
            flag: format!("--repeat {}", args.repeat),
            reason: "must be a whole number in 1..=100".into(),
        });
    }
    let source = SceneSource::resolve(Some(&args.scene))?;
    let mut common = scene_overrides(&args.set)?;
    common.extend(shortcut_overrides(args.frames, None)?);

    // 1. Every run, validated.
    let axes = args
        .vary
        .iter()
        .map(|a| parse_vary(a))
        .collect::<Result<Vec<_>, _>>()?;
    let points = expand(&axes, args.zip)?;
    let series = if args.series.is_empty() {
        vec![Vec::new()]
    } else {
        args.series
            .iter()
            .map(|s| parse_series(s))
            .collect::<Result<Vec<_>, _>>()?
    };
    let vary_keys: Vec<String> = axes.iter().map(|a| a.key.clone()).collect();
    let mut keys = vary_keys.clone();
    for overrides in &series {
        for o in overrides {
            if !keys.contains(&o.key()) {
                keys.push(o.key());
            }
        }
    }
    // A key a series sets wins over the grid's value, so a series can fix
    // the step (one run instead of one per point); runs that resolve to the
    // same scene as an earlier run are run once.
    let mut runs: Vec<PlannedRun> = Vec::new();
    for series_overrides in &series {
        for point in &points {
            let run = PlannedRun::new(
                &source,
                [common.clone(), point.overrides()?, series_overrides.clone()].concat(),
                &vary_keys,
            )?;
            if !runs.iter().any(|earlier| earlier.resolved == run.resolved) {
                runs.push(run);
            }
        }
    }
    let first = &runs[0];
    for run in &runs {
        if !run.timing.same_frames(&first.timing) {
            return Err(AppError::Flag {
                flag: run.flags(),
                reason: format!(
                    "a study compares runs at the same output frames, but this run has {} \
                     while run 0 has {} (vary time.substeps or time.dt to change the step)",
                    run.timing.describe(),
                    first.timing.describe()
                ),
            });
        }
    }
    let finest_substeps = runs.iter().map(|r| r.timing.substeps).max().unwrap_or(1);
    let reference_set = reference_overrides(finest_substeps, &args.reference)?;
    let reference = PlannedRun::new(&source, [common.clone(), reference_set].concat(), &[])?;
    if !reference.timing.same_frames(&first.timing) {
        return Err(AppError::Flag {
            flag: args.reference.join(" "),
            reason: format!(
                "the reference must write the runs' output frames ({}), not {}",
                first.timing.describe(),
                reference.timing.describe()
            ),
        });
    }

    let name = match &reference.scene {
        Scene::Two(c) => c.name.clone(),
        Scene::Three(c) => c.name.clone(),
    };
    let out_path = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out/studies").join(&name));
    let out = OutputDir::check(&out_path, args.force, &STUDY_FILES)?;

    // 2. The reference.
    let say = |line: String| {
        if !args.quiet {
            eprintln!("{line}");
        }
    };
    say(format!(
        "study: {} runs x {} repeat(s), reference first ({})",
        runs.len(),
        args.repeat,
        reference.overrides_text()
    ));
    // A bar per run on a terminal, a line at every 10% of a run in logs.
    let bar = ProgressMode::detect(args.quiet);
    let (reference_row, trajectory) = reference.measure(None, 1, bar)?;
    let trajectory = trajectory.expect("the reference keeps its trajectory");
    if let RunStatus::Failed(reason) = &reference_row.status {
        return Err(AppError::StudyReference {
            reason: reason.clone(),
        });
    }
    say(format!(
        "  reference: {:.0} ms, {:.1} iterations per step",
        reference_row.wall_ms,
        reference_row.iterations_per_step()
    ));

    // 3. The runs.
    let mut reference_row = reference.row_values(reference_row, &keys);
    reference_row.run = "reference".into();
    let mut rows = vec![reference_row];
    for (i, run) in runs.iter().enumerate() {
        let (row, _) = run.measure(Some(&trajectory), args.repeat, bar)?;
        let mut row = run.row_values(row, &keys);
        row.run = i.to_string();
        say(format!(
            "  run {}/{} ({}{}): {:.0} ms, {}",
            i + 1,
            runs.len(),
            row.series,
            if run.label.is_empty() {
                String::new()
            } else {
                format!("; {}", run.label)
            },
            row.wall_ms,
            match (&row.status, &row.errors) {
                (RunStatus::Ok, Some(e)) if row.unconverged_steps + row.stalled_steps > 0 =>
                    format!(
                        "error {:.2e}; {} of {} steps at the iteration cap, {} stalled",
                        e.trajectory, row.unconverged_steps, row.steps, row.stalled_steps
                    ),
                (RunStatus::Ok, Some(e)) => format!("error {:.2e}", e.trajectory),
                (RunStatus::Failed(reason), _) => format!("failed: {reason}"),
                _ => "no error".into(),
            }
        ));
        rows.push(row);
    }

    // 4. The outputs.
    let table = StudyTable { keys, rows };
    let _lock = out.prepare()?;
    out.write("study.csv", &table.csv())?;
    out.write("study.md", &table.markdown())?;
    let error_axis = match table.rows.iter().find_map(|r| r.errors) {
        Some(RunErrors {
            kind: crate::study::ErrorKind::CentreOfMass,
            ..
        }) => "centre-of-mass error",
        _ => "trajectory error (largest vertex distance)",
    };
    let plot_points: Vec<PlotPoint> = runs
        .iter()
        .zip(&table.rows[1..])
        .filter_map(|(run, row)| {
            let errors = row.errors?;
            Some(PlotPoint {
                series: row.series.clone(),
                label: run.short_label.clone(),
                time_ms: match args.clock {
                    StudyClock::Wall => row.wall_ms,
                    StudyClock::Cpu => row.cpu_ms,
                },
                error: errors.trajectory,
            })
        })
        .collect();
    let time_axis = match args.clock {
        StudyClock::Wall => "wall time (ms)",
        StudyClock::Cpu => "CPU time (ms, all threads)",
    };
    let pixels = work_precision_plot(
        &plot_points,
        &format!(
            "{name}: error against {}",
            &time_axis[..time_axis.find(" (").unwrap_or(time_axis.len())]
        ),
        (time_axis, error_axis),
        PLOT_SIZE,
    )
    .map_err(|reason| AppError::Plot { reason })?;
    let image = image::RgbImage::from_raw(PLOT_SIZE.0, PLOT_SIZE.1, pixels)
        .expect("the plot has width * height RGB pixels");
    let rgba = image::DynamicImage::ImageRgb8(image).into_rgba8();
    crate::encode::write_png(&out.join("study.png"), &rgba).map_err(AppError::Render)?;

    // The files are complete: a report that cannot be written is said last.
    let report_written = super::standard_output::print(&convergence_report(&table));
    say(format!(
        "study: wrote {} in {}",
        STUDY_FILES.join(", "),
        out.path().display()
    ));
    let failed = table.rows[1..]
        .iter()
        .filter(|r| r.status != RunStatus::Ok)
        .count();
    if failed > 0 {
        return Err(AppError::StudyRunsFailed {
            failed,
            total: runs.len(),
        });
    }
    report_written
}

/// The reference's overrides: the finest step divided by 4 (`time.substeps
/// = 4 x the largest`), tolerance 1e-8, Newton, BDF2; then the user's
/// `--reference KEY=VALUE` overrides, which win.
fn reference_overrides(
    finest_substeps: usize,
    user: &[String],
) -> Result<Vec<SceneOverride>, AppError> {
    let flag = "the study's reference";
    let mut overrides = vec![
        SceneOverride::remove("time.dt", flag)?,
        SceneOverride::set("time.substeps", &(4 * finest_substeps).to_string(), flag)?,
        SceneOverride::set("solver.method", "\"newton\"", flag)?,
        SceneOverride::remove("solver.step", flag)?,
        SceneOverride::remove("solver.max_iterations", flag)?,
        SceneOverride::set("solver.tolerance", "1e-8", flag)?,
        SceneOverride::set("time.integrator", "\"bdf2\"", flag)?,
    ];
    for argument in user {
        let (key, value) = argument.split_once('=').ok_or_else(|| AppError::Flag {
            flag: format!("--reference {argument}"),
            reason: "expected `KEY=VALUE`".into(),
        })?;
        overrides.push(SceneOverride::set(
            key.trim(),
            value.trim(),
            format!("--reference {argument}"),
        )?);
    }
    Ok(overrides)
}

/// Parses `--series 'KEY=VALUE;KEY=VALUE'`.
fn parse_series(argument: &str) -> Result<Vec<SceneOverride>, AppError> {
    let flag = format!("--series {argument}");
    let parts: Vec<&str> = argument
        .split(';')
        .map(str::trim)
        .filter(|p| !p.is_empty())
        .collect();
    if parts.is_empty() {
        return Err(AppError::Flag {
            flag,
            reason: "expected `KEY=VALUE[;KEY=VALUE...]`".into(),
        });
    }
    parts
        .into_iter()
        .map(|part| {
            let (key, value) = part.split_once('=').ok_or_else(|| AppError::Flag {
                flag: flag.clone(),
                reason: format!("`{part}` is not `KEY=VALUE`"),
            })?;
            Ok(SceneOverride::set(key.trim(), value.trim(), flag.clone())?)
        })
        .collect()
}

/// Output timing of a run: the frames it writes and its step.
#[derive(Debug, Clone, Copy)]
struct Timing {
    fps: f64,
    frames: usize,
    substeps: usize,
}

impl Timing {
    /// Whether both write the same output frames (times `k / fps`).
    fn same_frames(&self, other: &Timing) -> bool {
        self.fps == other.fps && self.frames == other.frames
    }

    fn describe(&self) -> String {
        format!(
            "{} frames at time.fps = {} ({} substeps)",
            self.frames, self.fps, self.substeps
        )
    }
}

/// One validated run (or the reference) of a study.
struct PlannedRun {
    source: SceneSource,
    overrides: Vec<SceneOverride>,
    scene: Scene,
    resolved: toml::Table,
    timing: Timing,
    /// Varied values, `key=value, ...`.
    label: String,
    /// Varied values without the series' keys and key prefixes (`substeps=10`), for the plot.
    short_label: String,
}

impl PlannedRun {
    /// Validates the scene with `overrides`; its labels show its values of
    /// the `--vary` keys, as resolved (a series may have fixed one).
    fn new(
        source: &SceneSource,
        overrides: Vec<SceneOverride>,
        vary_keys: &[String],
    ) -> Result<Self, AppError> {
        let (scene, resolved) = Scene::load_resolved(source, &overrides)?;
        let resolved: toml::Table = resolved.parse().expect("a resolved scene is valid TOML");
        let timing = match &scene {
            Scene::Two(c) => timing(c),
            Scene::Three(c) => timing(c),
        };
        let mut run = Self {
            source: source.clone(),
            overrides,
            scene,
            resolved,
            timing,
            label: String::new(),
            short_label: String::new(),
        };
        let values: Vec<(&String, String)> = vary_keys
            .iter()
            .map(|key| (key, run.value_of(key)))
            .collect();
        run.label = values
            .iter()
            .map(|(key, value)| format!("{key}={value}"))
            .collect::<Vec<_>>()
            .join(", ");
        run.short_label = values
            .iter()
            .filter(|(key, _)| !SERIES_KEYS.contains(&key.as_str()))
            .map(|(key, value)| {
                let leaf = key.rsplit('.').next().unwrap_or(key);
                format!("{leaf}={}", value.replace(' ', ""))
            })
            .collect::<Vec<_>>()
            .join(" ");
        Ok(run)
    }

    /// The flags that made this run, for messages.
    fn flags(&self) -> String {
        let mut flags: Vec<&str> = Vec::new();
        for o in &self.overrides {
            if !flags.contains(&o.flag.as_str()) {
                flags.push(&o.flag);
            }
        }
        flags.join(" ")
    }

    /// The reference's own settings, for the progress line.
    fn overrides_text(&self) -> String {
        [
            "time.substeps",
            "time.integrator",
            "solver.method",
            "solver.tolerance",
        ]
        .iter()
        .map(|key| format!("{key} = {}", self.value_of(key)))
        .collect::<Vec<_>>()
        .join(", ")
    }

    /// The resolved scene's value of a dotted key, as TOML text (`—` when
    /// absent); a part may index an array (`bodies[1].material.young`).
    fn value_of(&self, key: &str) -> String {
        let mut table = &self.resolved;
        let parts: Vec<&str> = key.split('.').collect();
        for (i, part) in parts.iter().enumerate() {
            let item = match part.strip_suffix(']').and_then(|p| p.split_once('[')) {
                Some((name, index)) => match (table.get(name), index.parse::<usize>()) {
                    (Some(toml::Value::Array(items)), Ok(index)) => items.get(index),
                    _ => None,
                },
                None => table.get(*part),
            };
            match item {
                Some(toml::Value::Table(inner)) if i + 1 < parts.len() => table = inner,
                Some(toml::Value::String(text)) if i + 1 == parts.len() => return text.clone(),
                Some(value) if i + 1 == parts.len() => return value.to_string(),
                _ => break,
            }
        }
        "—".into()
    }

    /// Fills in the row's varied values and series from the resolved scene.
    fn row_values(&self, mut row: StudyRow, keys: &[String]) -> StudyRow {
        row.values = keys.iter().map(|k| self.value_of(k)).collect();
        row.series = format!(
            "{} / {}",
            self.value_of("solver.method"),
            self.value_of("time.integrator")
        );
        row
    }

    /// Simulates the run `repeats` times: the first is compared with
    /// `reference` (or recorded as the reference when `None`).
    fn measure(
        &self,
        reference: Option<&Reference>,
        repeats: usize,
        progress: ProgressMode,
    ) -> Result<(StudyRow, Option<Reference>), AppError> {
        match &self.scene {
            Scene::Two(config) => self.measure_scene(config, reference, repeats, progress),
            Scene::Three(config) => self.measure_scene(config, reference, repeats, progress),
        }
    }

    fn measure_scene<const D: usize>(
        &self,
        config: &SceneConfig<D>,
        reference: Option<&Reference>,
        repeats: usize,
        progress: ProgressMode,
    ) -> Result<(StudyRow, Option<Reference>), AppError> {
        let input = SceneInput {
            source: &self.source,
            overrides: &self.overrides,
        };
        let mut times = Vec::with_capacity(repeats);
        let mut cpu_times = Vec::with_capacity(repeats);
        let mut first: Option<(StudyRow, Option<Reference>)> = None;
        for _ in 0..repeats {
            let cpu_before = process_cpu_time();
            let (row, time, recorded) = simulate(config, input, reference, progress)?;
            times.push(time);
            if let (Some(before), Some(after)) = (cpu_before, process_cpu_time()) {
                cpu_times.push(after.saturating_sub(before));
            }
            let failed = row.status != RunStatus::Ok;
            if first.is_none() {
                first = Some((row, recorded));
            }
            if failed {
                break;
            }
        }
        let (mut row, recorded) = first.expect("at least one repetition");
        row.wall_ms = median_ms(&mut times);
        row.cpu_ms = if cpu_times.is_empty() {
            f64::NAN
        } else {
            median_ms(&mut cpu_times)
        };
        row.repeats = times.len();
        Ok((row, recorded))
    }
}

/// The median of `times`, in milliseconds (the mean of the middle two for
/// an even count).
fn median_ms(times: &mut [Duration]) -> f64 {
    times.sort();
    let n = times.len();
    let middle = times[n / 2].as_secs_f64() * 1e3;
    if n.is_multiple_of(2) {
        0.5 * (middle + times[n / 2 - 1].as_secs_f64() * 1e3)
    } else {
        middle
    }
}

/// CPU time of this process so far, all threads, user and system
/// (`None` where the platform does not say).
#[cfg(unix)]
fn process_cpu_time() -> Option<Duration> {
    let mut usage = std::mem::MaybeUninit::<libc::rusage>::zeroed();
    // SAFETY: getrusage writes a whole `rusage` into the pointer it is
    // given, which points to one; it is read only when the call succeeded.
    let usage = unsafe {
        if libc::getrusage(libc::RUSAGE_SELF, usage.as_mut_ptr()) != 0 {
            return None;
        }
        usage.assume_init()
    };
    let time = |t: libc::timeval| {
        Duration::from_secs(t.tv_sec as u64) + Duration::from_micros(t.tv_usec as u64)
    };
    Some(time(usage.ru_utime) + time(usage.ru_stime))
}

#[cfg(not(unix))]
fn process_cpu_time() -> Option<Duration> {
    None
}

fn timing<const D: usize>(config: &SceneConfig<D>) -> Timing {
    Timing {
        fps: config.time.fps,
        frames: config.time.frames,
        substeps: config.time.substeps,
    }
}

/// One simulation of `config`: its row (errors against `reference`, or a
/// recorded reference when `None`) and its wall time (setup and stepping,
/// not the comparison).
fn simulate<const D: usize>(
    config: &SceneConfig<D>,
    input: SceneInput,
    reference: Option<&Reference>,
    progress: ProgressMode,
) -> Result<(StudyRow, Duration, Option<Reference>), AppError> {
    let mut progress = Progress::start(progress, "study run", config.time.frames);
    let started = Instant::now();
    let mut sim = build_simulation(config, input)?;
    let mut wall = started.elapsed();
    let rest = sim.mesh().rest_positions().to_vec();
    let mut recorded = reference.is_none().then(|| Reference::new(&rest));
    let mut tracker = reference.map(|r| r.tracker(&rest));
    let mut row = StudyRow {
        run: String::new(),
        values: Vec::new(),
        series: String::new(),
        dt: config.simulation_settings().dt,
        status: RunStatus::Ok,
        wall_ms: 0.0,
        cpu_ms: f64::NAN,
        repeats: 1,
        iterations: 0,
        steps: 0,
        unconverged_steps: 0,
        stalled_steps: 0,
        errors: None,
    };
    for frame in 0..config.time.frames {
        let stats = if frame == 0 {
            sim.frame_stats()
        } else {
            let started = Instant::now();
            let stats = sim.advance_frame(config.time.substeps);
            wall += started.elapsed();
            match stats {
                Ok(stats) => stats,
                Err(error) => {
                    progress.finish();
                    row.status = RunStatus::Failed(format!("frame {frame}: {error}"));
                    return Ok((row, wall, None));
                }
            }
        };
        row.iterations += stats.iterations;
        row.unconverged_steps += stats.unconverged_steps;
        row.stalled_steps += stats.stalled_steps;
        if frame > 0 {
            row.steps += config.time.substeps;
        }
        let energy = stats.energy.total();
        if let Some(reference) = &mut recorded {
            reference.push(sim.positions(), &stats.centre_of_mass, energy);
        }
        if let Some(tracker) = &mut tracker {
            tracker.observe(sim.positions(), &stats.centre_of_mass, energy);
        }
        progress.update(frame + 1, || format!("t = {:.3} s", stats.time));
    }
    progress.finish();
    row.errors = match tracker {
        Some(tracker) => tracker.finish(),
        None => Some(RunErrors {
            kind: crate::study::ErrorKind::Vertices,
            trajectory: 0.0,
            energy: 0.0,
        }),
    };
    Ok((row, wall, recorded))
}

/// The observed order of convergence in `dt` of every group of runs that
/// differ only in their step (same series, same other varied values).
fn convergence_report(table: &StudyTable) -> String {
    let step_columns: Vec<usize> = table
        .keys
        .iter()
        .enumerate()
        .filter(|(_, k)| STEP_KEYS.contains(&k.as_str()))
        .map(|(i, _)| i)
        .collect();
    let mut groups: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for row in &table.rows[1..] {
        let Some(errors) = row.errors else { continue };
        let others: Vec<String> = table
            .keys
            .iter()
            .zip(&row.values)
            .enumerate()
            .filter(|(i, (key, _))| {
                !step_columns.contains(i) && !SERIES_KEYS.contains(&key.as_str())
            })
            .map(|(_, (key, value))| format!("{key}={value}"))
            .collect();
        let name = if others.is_empty() {
            row.series.clone()
        } else {
            format!("{} ({})", row.series, others.join(", "))
        };
        match groups.iter_mut().find(|(n, _)| *n == name) {
            Some((_, points)) => points.push((row.dt, errors.trajectory)),
            None => groups.push((name, vec![(row.dt, errors.trajectory)])),
        }
    }
    let mut text =
        String::from("observed order of convergence in dt (slope of log error against log dt):\n");
    for (name, points) in &groups {
        let _ = match observed_order(points) {
            Some(order) => writeln!(text, "  {name}: {order:.2} ({} step sizes)", points.len()),
            None => writeln!(
                text,
                "  {name}: - (needs two step sizes with a nonzero error)"
            ),
        };
    }
    text
}
