//! `elasto sweep`: plan every run, validate them all, then run them (N at a time) as child `elasto run`s and collect.
//!
//! 1. The plan: the scene (or the sweep file's scene), the varied keys
//!    expanded into runs, the sweep folder. Every run's scene is loaded and
//!    validated with all its overrides here, so one bad value stops the
//!    sweep with exit code 2 before anything runs.
//! 2. The run folders: a completed run (its record says `ok` and it is the
//!    same run) is skipped; a folder holding another run, or something not
//!    made by a sweep, is an error naming it (exit 2) unless `--force`.
//! 3. The runs: `--jobs` at a time, each a child `elasto run … --force
//!    --quiet` of this binary with `RAYON_NUM_THREADS` = cores / jobs. A run
//!    that fails does not stop the others.
//! 4. The sweep's table and images from the folders ([`collect`]); with
//!    `--shard` this is left to `--collect`, once every shard is done.

use super::AppError;
use super::cli::{SweepArgs, VideoChoice};
use super::process_clock::cores;
use super::progress::ProgressMode;
use super::run_command::videos;
use super::{scene_overrides, shortcut_overrides};
use crate::encode::VideoFormat;
use crate::scene::{Scene, SceneSource};
use crate::sweep::{
    ChildRun, CurrentRun, ProgressStyleChoice, RUN_RECORD_FILE, RunIdentity, RunRecord, RunSpec,
    RunStatus, SheetOptions, SweepDescription, SweepError, SweepFile, SweepProgress, VaryAxis,
    collect, expand, is_sweep_file, parse_vary,
};
use std::collections::{BTreeSet, VecDeque};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Duration;

/// Runs `elasto sweep`.
pub fn sweep(args: &SweepArgs) -> Result<(), AppError> {
    let plan = SweepPlan::new(args)?;
    if args.list {
        let mut list = String::new();
        for &i in &plan.selected {
            let run = &plan.runs[i];
            list.push_str(&format!(
                "{}\t{}\t{}\n",
                run.index,
                run.folder_name(),
                run.label()
            ));
        }
        return super::standard_output::print(&list);
    }
    if !args.force {
        plan.check_sweep_folder()?;
    }
    if args.collect {
        plan.check_collectable()?;
    }
    let actions = plan.check_folders(args.force && !args.collect)?;
    if !args.collect {
        std::fs::create_dir_all(&plan.out).map_err(|source| SweepError::Io {
            path: plan.out.clone(),
            source,
        })?;
        let to_run: Vec<usize> = actions
            .iter()
            .filter(|(_, action)| *action == Action::Run)
            .map(|(i, _)| *i)
            .collect();
        let skipped = actions.len() - to_run.len();
        let quiet = args.quiet;
        if !quiet && skipped > 0 {
            eprintln!(
                "sweep: {skipped} of {} runs already complete, skipped",
                actions.len()
            );
        }
        let failed = plan.run_all(&to_run, args)?;
        if let Some((shard, count)) = args.shard {
            if !quiet {
                eprintln!(
                    "sweep: shard {shard}/{count} done ({} runs); once every shard is done, \
                     `elasto sweep … --collect` writes sweep.csv and the contact sheet",
                    plan.selected.len()
                );
            }
            return finish(
                failed,
                to_run.len(),
                &plan.out.join(plan.runs[0].folder_name()),
            );
        }
        plan.collect(args)?;
        return finish(failed, to_run.len(), &plan.out.join("sweep.csv"));
    }
    let collected = plan.collect(args)?;
    let incomplete = collected
        .rows
        .iter()
        .filter(|r| r.status != crate::sweep::RowStatus::Ok)
        .count();
    finish(
        incomplete,
        collected.rows.len(),
        &plan.out.join("sweep.csv"),
    )
}

fn finish(failed: usize, total: usize, table: &Path) -> Result<(), AppError> {
    if failed > 0 {
        return Err(SweepError::RunsFailed {
            failed,
            total,
            table: table.to_owned(),
        }
        .into());
    }
    Ok(())
}

/// What to do with a run's folder.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Action {
    Run,
    Skip,
}

/// Everything decided before any run starts.
struct SweepPlan {
    name: String,
    scene: String,
    set: Vec<String>,
    axes: Vec<VaryAxis>,
    zip: bool,
    runs: Vec<RunSpec>,
    /// Per run: what it is (resolved scene and output flags).
    identities: Vec<RunIdentity>,
    /// Per run: its number of frames.
    frames: Vec<usize>,
    fps: f64,
    out: PathBuf,
    /// The runs of this invocation (the shard's, or all).
    selected: Vec<usize>,
    videos: Vec<VideoFormat>,
    render: bool,
}

impl SweepPlan {
    fn new(args: &SweepArgs) -> Result<Self, AppError> {
        let (scene, file_name, mut axes, file_zip, mut set) =
            if is_sweep_file(Path::new(&args.target)) {
                let file = SweepFile::read(Path::new(&args.target))?;
                (file.scene, Some(file.name), file.axes, file.zip, file.set)
            } else {
                (args.target.clone(), None, Vec::new(), false, Vec::new())
            };
        for vary in &args.vary {
            axes.push(parse_vary(vary)?);
        }
        let zip = file_zip || args.zip;
        set.extend(args.set.iter().cloned());
        let runs = expand(&axes, zip)?;

        if let Some(jobs) = args.jobs
            && jobs < 1
        {
            return Err(bad_flag(format!("--jobs {jobs}"), "must be at least 1"));
        }
        let source = SceneSource::resolve(Some(&scene))?;
        let shared = scene_overrides(&set)?;
        // A shortcut flag would replace a varied key in every run, while the
        // table reported the varied values.
        for (given, flag, keys) in [
            (
                args.frames.map(|n| format!("--frames {n}")),
                "--frames",
                &["time.frames", "time.duration"][..],
            ),
            (
                args.resolution
                    .map(|(w, h)| format!("--resolution {w}x{h}")),
                "--resolution",
                &["render.resolution"][..],
            ),
        ] {
            if let (Some(given), Some(axis)) =
                (given, axes.iter().find(|a| keys.contains(&a.key.as_str())))
            {
                return Err(bad_flag(
                    given,
                    format!(
                        "would replace the varied {} in every run: vary it or give {flag}, not both",
                        axis.key
                    ),
                ));
            }
        }
        let flags = shortcut_overrides(args.frames, args.resolution)?;
        let render = !args.no_render;
        let videos = if render {
            videos(args.video)
        } else {
            Vec::new()
        };
        let run_flags = run_flags(args);

        // Every run validated before any starts.
        let mut identities = Vec::with_capacity(runs.len());
        let mut frames = Vec::with_capacity(runs.len());
        let mut first: Option<Scene> = None;
        for run in &runs {
            let mut overrides = shared.clone();
            overrides.extend(run.overrides()?);
            overrides.extend(flags.iter().cloned());
            let (loaded, resolved) = Scene::load_resolved(&source, &overrides)?;
            frames.push(loaded.time().frames);
            identities.push(RunIdentity {
                resolved_scene: resolved,
                run_flags: run_flags.clone(),
            });
            first.get_or_insert(loaded);
        }
        let first = first.expect("a sweep has at least one run");
        if let Some(n) = args.sheet_frame {
            let fewest = frames.iter().copied().min().unwrap_or(0);
            if n < 0 || n as usize >= fewest {
                return Err(bad_flag(
                    format!("--sheet-frame {n}"),
                    format!(
                        "must be a frame of every run: 0 to {}",
                        fewest.saturating_sub(1)
                    ),
                ));
            }
            if args.no_render {
                return Err(bad_flag(
                    format!("--sheet-frame {n}"),
                    "there are no frames with --no-render",
                ));
            }
        }
        let name = file_name.unwrap_or_else(|| first.name().to_owned());
        let out = args
            .out
            .clone()
            .unwrap_or_else(|| Path::new("out").join("sweeps").join(&name));
        // --collect reads (and checks) every run, whatever the shard.
        let selected = match args.shard {
            Some((shard, count)) if !args.collect => {
                (0..runs.len()).filter(|i| i % count == shard).collect()
            }
            _ => (0..runs.len()).collect(),
        };
        Ok(Self {
            name,
            scene,
            set,
            axes,
            zip,
            runs,
            identities,
            frames,
            fps: first.time().fps,
            out,
            selected,
            videos,
            render,
        })
    }

    /// Decides, for every selected run, whether to run it; a folder that
    /// holds another run or something else is an error unless `force`.
    /// Refuses an output folder that holds files but is not a sweep's: one
    /// with neither `sweep.json` nor a run folder (a folder named like one of
    /// this sweep's runs, or being made under its staging name, as shards
    /// running at once do, or one holding a run record). A user's own `sweep.csv` must not be overwritten
    /// without `--force`; a run folder is checked on its own later.
    fn check_sweep_folder(&self) -> Result<(), SweepError> {
        let Ok(entries) = std::fs::read_dir(&self.out) else {
            // Missing (made later), or not a folder (refused by check_folders).
            return Ok(());
        };
        let run_folders: BTreeSet<String> = self.runs.iter().map(|run| run.folder_name()).collect();
        let mut empty = true;
        for entry in entries.flatten() {
            empty = false;
            let name = entry.file_name().to_string_lossy().into_owned();
            let is_folder = entry.file_type().is_ok_and(|kind| kind.is_dir());
            // A run folder being made is `.NAME.partial` (see `start_record`).
            let staged = name
                .strip_prefix('.')
                .and_then(|rest| rest.strip_suffix(".partial"))
                .unwrap_or(&name);
            let is_run_folder = is_folder
                && (run_folders.contains(staged) || entry.path().join(RUN_RECORD_FILE).is_file());
            if name == "sweep.json" || is_run_folder {
                return Ok(());
            }
        }
        if empty {
            return Ok(());
        }
        Err(SweepError::NotASweepFolder {
            folder: self.out.clone(),
        })
    }

    /// For `--collect`: the sweep's folder holds at least one run folder of
    /// this plan, and when some of the plan's runs are missing, no run of
    /// other values (a run folder holding a run record that is not among
    /// the plan's): missing runs beside another sweep's are the sign of
    /// other `--vary` values than the sweep's, not of a shard still to run.
    /// Else nothing is written (a table of runs that never ran would
    /// replace the real sweep's).
    fn check_collectable(&self) -> Result<(), SweepError> {
        let nothing = |reason: String| SweepError::NothingToCollect {
            folder: self.out.clone(),
            reason,
        };
        if !self.out.is_dir() {
            return Err(nothing("there is no sweep folder here".into()));
        }
        let planned: BTreeSet<String> = self.runs.iter().map(|run| run.folder_name()).collect();
        let missing: Vec<&String> = planned
            .iter()
            .filter(|name| !self.out.join(name).is_dir())
            .collect();
        if missing.len() == planned.len() {
            let empty = std::fs::read_dir(&self.out).is_ok_and(|mut e| e.next().is_none());
            return Err(nothing(if empty {
                "the folder is empty".into()
            } else {
                "it holds none of this sweep's runs".into()
            }));
        }
        if missing.is_empty() {
            return Ok(());
        }
        let mut others: Vec<String> = std::fs::read_dir(&self.out)
            .map(|entries| {
                entries
                    .flatten()
                    .filter(|entry| entry.path().join(RUN_RECORD_FILE).is_file())
                    .map(|entry| entry.file_name().to_string_lossy().into_owned())
                    .filter(|name| !planned.contains(name))
                    .collect()
            })
            .unwrap_or_default();
        if others.is_empty() {
            return Ok(());
        }
        others.sort();
        let list = |names: &[&String]| {
            let shown: Vec<&str> = names.iter().take(3).map(|n| n.as_str()).collect();
            let more = names.len().saturating_sub(shown.len());
            if more > 0 {
                format!("{} and {more} more", shown.join(", "))
            } else {
                shown.join(", ")
            }
        };
        Err(nothing(format!(
            "it holds runs of other values than these arguments describe ({}) while {} of \
             theirs never ran there ({}): the sweep was run with other --vary or --set values",
            list(&others.iter().collect::<Vec<_>>()),
            missing.len(),
            list(&missing)
        )))
    }

    fn check_folders(&self, force: bool) -> Result<Vec<(usize, Action)>, SweepError> {
        if self.out.exists() && !self.out.is_dir() {
            return Err(SweepError::ForeignFolder {
                folder: self.out.clone(),
            });
        }
        let mut actions = Vec::with_capacity(self.selected.len());
        for &i in &self.selected {
            let dir = self.out.join(self.runs[i].folder_name());
            let action = if !dir.exists() {
                Action::Run
            } else if !dir.is_dir() || dir.is_symlink() {
                return Err(SweepError::ForeignFolder { folder: dir });
            } else {
                match RunRecord::read(&dir)? {
                    Some(record) if record.identity != self.identities[i] => {
                        if force {
                            Action::Run
                        } else {
                            return Err(SweepError::ChangedRun {
                                what: difference(&record.identity, &self.identities[i]),
                                folder: dir,
                            });
                        }
                    }
                    Some(record) if record.status == RunStatus::Ok && !force => Action::Skip,
                    Some(_) => Action::Run,
                    None if force || is_empty(&dir) => Action::Run,
                    None => return Err(SweepError::ForeignFolder { folder: dir }),
                }
            };
            actions.push((i, action));
        }
        Ok(actions)
    }

    /// Runs `to_run` (`--jobs` at a time); returns how many failed.
    fn run_all(&self, to_run: &[usize], args: &SweepArgs) -> Result<usize, SweepError> {
        if to_run.is_empty() {
            return Ok(0);
        }
        let cores = cores();
        let jobs = (args.jobs.map_or(cores, |j| j as usize)).clamp(1, to_run.len());
        let threads = (cores / jobs).max(1);
        let program = std::env::current_exe().map_err(|source| SweepError::Io {
            path: PathBuf::from("elasto"),
            source,
        })?;
        let style = match ProgressMode::detect(args.quiet) {
            ProgressMode::Bar => ProgressStyleChoice::Bar,
            ProgressMode::Lines => ProgressStyleChoice::Lines,
            ProgressMode::Quiet => ProgressStyleChoice::Quiet,
        };
        let mut progress = SweepProgress::start(style, to_run.len());
        let queue = Mutex::new(to_run.iter().copied().collect::<VecDeque<_>>());
        let (sender, receiver) = crossbeam_channel::unbounded::<Event>();
        let mut failed = 0;
        std::thread::scope(|scope| {
            for _ in 0..jobs {
                let sender = sender.clone();
                let queue = &queue;
                let program = &program;
                scope.spawn(move || {
                    loop {
                        let next = queue.lock().expect("the queue lock").pop_front();
                        let Some(i) = next else { break };
                        let _ = sender.send(Event::Started(i));
                        let failure = self.run_one(i, program, threads, args);
                        let _ = sender.send(Event::Finished(i, failure));
                    }
                });
            }
            drop(sender);
            let mut running: BTreeSet<usize> = BTreeSet::new();
            loop {
                match receiver.recv_timeout(Duration::from_millis(250)) {
                    Ok(Event::Started(i)) => {
                        running.insert(i);
                    }
                    Ok(Event::Finished(i, outcome)) => {
                        running.remove(&i);
                        if outcome.0.is_some() {
                            failed += 1;
                        }
                        progress.finished(
                            &self.runs[i].folder_name(),
                            outcome.0.as_deref(),
                            outcome.1,
                        );
                    }
                    Err(crossbeam_channel::RecvTimeoutError::Timeout) => {}
                    Err(crossbeam_channel::RecvTimeoutError::Disconnected) => break,
                }
                let current: Vec<CurrentRun> = running
                    .iter()
                    .map(|&i| CurrentRun {
                        index: i,
                        frames_done: frames_written(&self.out.join(self.runs[i].folder_name())),
                        frames: self.frames[i],
                    })
                    .collect();
                progress.current(&current);
            }
        });
        progress.finish();
        Ok(failed)
    }

    /// Runs one run in its folder, recording its start and its end; returns
    /// why it failed (if it did) and its wall time.
    fn run_one(
        &self,
        i: usize,
        program: &Path,
        threads: usize,
        args: &SweepArgs,
    ) -> (Option<String>, f64) {
        let spec = &self.runs[i];
        let dir = self.out.join(spec.folder_name());
        let mut record = RunRecord {
            index: spec.index,
            values: spec
                .values
                .iter()
                .map(|(k, v)| (k.clone(), v.toml.clone()))
                .collect(),
            identity: self.identities[i].clone(),
            status: RunStatus::Running,
            exit_code: None,
            reason: None,
            wall_seconds: 0.0,
        };
        if let Err(e) = self.start_record(&dir, &record) {
            return (Some(e), 0.0);
        }
        let child = ChildRun {
            program: program.to_owned(),
            args: self.child_args(spec, &dir, args),
            dir: dir.clone(),
            threads,
        };
        let outcome = child.run();
        record.status = if outcome.failure.is_none() {
            RunStatus::Ok
        } else {
            RunStatus::Failed
        };
        record.exit_code = outcome.exit_code;
        record.reason = outcome.failure.clone();
        record.wall_seconds = outcome.wall_seconds;
        // Written last: with "ok" this is the completion marker.
        if let Err(e) = record.write(&dir) {
            return (Some(e.to_string()), outcome.wall_seconds);
        }
        (outcome.failure, outcome.wall_seconds)
    }

    /// Writes the "running" record of the run folder `dir`. A new folder is
    /// made under a hidden name with its record inside and then renamed, so
    /// a sweep killed at any instant never leaves a run folder without a
    /// record (which a resumed sweep would refuse as not its own).
    fn start_record(&self, dir: &Path, record: &RunRecord) -> Result<(), String> {
        if dir.is_dir() {
            return record.write(dir).map_err(|e| e.to_string());
        }
        let name = dir
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        let staging = dir.with_file_name(format!(".{name}.partial"));
        let cannot = |what: &str, path: &Path, e: std::io::Error| {
            format!("cannot {what} {}: {e}", path.display())
        };
        if staging.exists() {
            std::fs::remove_dir_all(&staging).map_err(|e| cannot("remove", &staging, e))?;
        }
        std::fs::create_dir_all(&staging).map_err(|e| cannot("create", &staging, e))?;
        record.write(&staging).map_err(|e| e.to_string())?;
        std::fs::rename(&staging, dir).map_err(|e| cannot("create", dir, e))
    }

    /// `run SCENE --out DIR --force --quiet [flags] --set … --set …`.
    fn child_args(&self, spec: &RunSpec, dir: &Path, args: &SweepArgs) -> Vec<String> {
        let mut child: Vec<String> = vec![
            "run".into(),
            self.scene.clone(),
            "--out".into(),
            dir.display().to_string(),
            "--force".into(),
            "--quiet".into(),
        ];
        child.extend(run_flags(args));
        if args.strict {
            child.push("--strict".into());
        }
        for set in &self.set {
            child.extend(["--set".into(), set.clone()]);
        }
        for (key, value) in &spec.values {
            child.extend(["--set".into(), format!("{key}={}", value.toml)]);
        }
        if let Some(frames) = args.frames {
            child.extend(["--frames".into(), frames.to_string()]);
        }
        if let Some((w, h)) = args.resolution {
            child.extend(["--resolution".into(), format!("{w}x{h}")]);
        }
        child
    }

    /// Writes the sweep's table and images from every run folder.
    fn collect(&self, args: &SweepArgs) -> Result<crate::sweep::Collected, SweepError> {
        let description = SweepDescription {
            name: &self.name,
            scene: &self.scene,
            zip: self.zip,
            set: &self.set,
            axes: &self.axes,
        };
        let sheet = self.render.then(|| SheetOptions {
            frame: args.sheet_frame.map(|n| n as usize),
            videos: self.videos.clone(),
            fps: self.fps,
        });
        let collected = collect(&self.out, &self.runs, description, sheet.as_ref())?;
        if !args.quiet {
            eprintln!(
                "sweep {}: {} runs; wrote {} in {}",
                self.name,
                self.runs.len(),
                collected.written.join(", "),
                self.out.display()
            );
        }
        Ok(collected)
    }
}

enum Event {
    Started(usize),
    Finished(usize, (Option<String>, f64)),
}

/// The flags of `elasto run` that shape a run's outputs (part of its identity).
fn run_flags(args: &SweepArgs) -> Vec<String> {
    if args.no_render {
        return vec!["--no-render".into()];
    }
    let video = match args.video {
        VideoChoice::Auto => "auto",
        VideoChoice::None => "none",
        VideoChoice::Apng => "apng",
        VideoChoice::Mp4 => "mp4",
        VideoChoice::Gif => "gif",
    };
    vec!["--video".into(), video.into()]
}

fn bad_flag(flag: String, reason: impl Into<String>) -> AppError {
    SweepError::BadFlag {
        flag,
        reason: reason.into(),
    }
    .into()
}

fn is_empty(dir: &Path) -> bool {
    std::fs::read_dir(dir).is_ok_and(|mut entries| entries.next().is_none())
}

/// Rows of a run's `stats.csv` so far (its frames done).
fn frames_written(dir: &Path) -> usize {
    std::fs::read_to_string(dir.join("stats.csv"))
        .map(|text| text.lines().count().saturating_sub(1))
        .unwrap_or(0)
}

/// The first difference between two runs, for the message.
fn difference(old: &RunIdentity, new: &RunIdentity) -> String {
    if old.run_flags != new.run_flags {
        return format!(
            "flags `{}` there, `{}` now",
            old.run_flags.join(" "),
            new.run_flags.join(" ")
        );
    }
    let old_lines: Vec<&str> = old.resolved_scene.lines().collect();
    let new_lines: Vec<&str> = new.resolved_scene.lines().collect();
    for k in 0..old_lines.len().max(new_lines.len()) {
        let (a, b) = (old_lines.get(k), new_lines.get(k));
        if a != b {
            return format!(
                "its resolved scene has `{}` where this sweep has `{}`; see {RUN_RECORD_FILE}",
                a.unwrap_or(&""),
                b.unwrap_or(&"")
            );
        }
    }
    "its record differs".into()
}
