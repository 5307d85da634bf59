//! Writing a run frame by frame: numbered PNG frames and videos.
//!
//! A [`SequenceWriter`] is fed one [`RenderFrame`] at a time, as the
//! simulation produces them or from a finished run. It sends each frame to
//! the drawers (`drawers`: one renderer per graphics device, each on a
//! thread of its own), and a collector thread takes the drawn frames back
//! in frame order and hands each image to:
//! - PNG workers, through a bounded queue (so memory stays flat however long
//!   the run), which encode with fast compression (a frame over its base
//!   reuses the base's rows compressed once, see `frame_png`) and write each
//!   frame under a hidden temporary name, renamed once complete;
//! - one thread per video format, through its own bounded queue, in frame
//!   order.
//!
//! A full queue makes the collector wait, and the drawers and then
//! [`SequenceWriter::push`] with it, so neither rendering nor the
//! simulation feeding it can run ahead of the encoders by more than a few
//! dozen frames. Each frame's [`FrameCost`] (draw, readback, legend, PNG,
//! videos, and which device drew it) is handed out by
//! [`SequenceWriter::take_costs`] once the frame is in the PNG file and in
//! every video, in frame order. The first error stops the run: no frame after
//! it is started. Videos are renamed to their final names only by
//! [`SequenceWriter::finish`] after every frame and every video succeeded. A
//! writer dropped unfinished (the simulation failed) writes the frames
//! already pushed and removes its partial videos; the frames written stay,
//! each one complete. On SIGINT or SIGTERM the binary removes partial frames
//! and videos through [`remove_partial_files`](super::remove_partial_files).

use super::colormap::linear_to_srgb8;
use super::drawers::{Drawers, DrawnFrames, PreparedRenderers};
use super::export::{check_video_support, frame_file_name};
use super::frame_image::FrameImage;
use super::frame_png::FramePngWriter;
use super::frame_shape::FrameShape;
use super::partial_file::PartialFile;
use super::video::{self, VideoSpec, VideoWriter};
use super::{
    FrameTimings, RenderError, RenderFrame, RenderMesh, RenderOutputs, RenderSettings, VideoFormat,
};
use crossbeam_channel::{Receiver, Sender, bounded, unbounded};
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Where the time of one written frame went.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FrameCost {
    /// Drawing, readback and legend, on the thread that pushed the frame.
    pub timings: FrameTimings,
    /// Encoding and writing the frame's PNG file, on a PNG worker.
    pub png: Duration,
    /// Encoding and writing the frame into every video, on the video threads.
    pub video: Duration,
    /// Which device drew it: 0 the shared one, 1 the second (see `drawers`).
    pub drawer: usize,
}

impl FrameCost {
    /// Drawing, readback and legend: the frame until it is an image.
    pub fn render(&self) -> Duration {
        self.timings.draw + self.timings.readback + self.timings.overlay
    }

    /// PNG and video encoding and writing: the image until it is on disk.
    pub fn encode(&self) -> Duration {
        self.png + self.video
    }
}

/// Renders frames one at a time and writes them as PNG files and videos.
pub struct SequenceWriter {
    drawers: Drawers,
    /// The thread that hands the frames drawn, in order, to the encoders.
    collector: Option<JoinHandle<()>>,
    /// What the collector reports, frame by frame.
    collected: Receiver<Collected>,
    frame_count: usize,
    /// Frames sent to the drawers, and frames drawn and handed to the
    /// encoders (in order).
    pushed: usize,
    queued: usize,
    png_done: Receiver<Result<(usize, Duration), RenderError>>,
    png_workers: Vec<JoinHandle<()>>,
    videos: Vec<VideoThread>,
    /// Frames (in order, one per video) each video thread has written, with the time it took.
    video_done: Receiver<(usize, Duration)>,
    /// Which frames are written, and how many from the start in a row.
    written: Vec<bool>,
    written_in_order: usize,
    /// Per frame: its cost so far, and how many videos have written it.
    costs: Vec<FrameCost>,
    videos_written: Vec<usize>,
    /// Frames whose costs [`SequenceWriter::take_costs`] has handed out.
    costs_taken: usize,
    /// The first error of a frame or an encoder, once reported, until
    /// `push` or `finish` returns it.
    error: Option<RenderError>,
    /// A frame or video failed: the run can no longer complete.
    failed: bool,
}

/// What the collector reports of each frame, in order.
enum Collected {
    /// The frame was drawn by `drawer` and handed to the encoders.
    Queued {
        index: usize,
        drawer: usize,
        timings: FrameTimings,
    },
    /// The frame could not be drawn; no later frame is handed on.
    Failed(RenderError),
    /// An encoder stopped taking frames (its own error says why).
    EncoderStopped,
}

struct VideoThread {
    /// The video's file; removed unless published.
    partial: Option<PartialFile>,
    sender: Option<Sender<Arc<FrameImage>>>,
    thread: Option<JoinHandle<Result<(), RenderError>>>,
}

impl SequenceWriter {
    /// Starts writing a run of `frame_count` frames to `outputs`.
    ///
    /// `known_frames` frame the camera and the colour range (see
    /// [`super::Renderer::new`]). When [`RenderSettings::needs_whole_run`] is true
    /// they must be the whole run; otherwise the first frame is enough, and
    /// the rest can be pushed as they are simulated.
    pub fn create(
        settings: &RenderSettings,
        mesh: &RenderMesh,
        frame_count: usize,
        known_frames: &[RenderFrame],
        outputs: &RenderOutputs,
    ) -> Result<Self, RenderError> {
        check_request(settings, frame_count, known_frames, outputs)?;
        // Bad frames are reported before the devices are opened.
        FrameShape::of_run(settings, mesh, known_frames)?;
        let prepared = PreparedRenderers::prepare(settings, mesh)?;
        Self::create_prepared(prepared, frame_count, known_frames, outputs)
    }

    /// [`SequenceWriter::create`] with renderers prepared beforehand (see
    /// [`PreparedRenderers::prepare`]).
    pub fn create_prepared(
        prepared: PreparedRenderers,
        frame_count: usize,
        known_frames: &[RenderFrame],
        outputs: &RenderOutputs,
    ) -> Result<Self, RenderError> {
        let settings = prepared.settings().clone();
        check_request(&settings, frame_count, known_frames, outputs)?;
        create_dir(&outputs.frames_dir)?;
        if !outputs.videos.is_empty() {
            create_dir(&outputs.video_dir)?;
        }
        let drawers = prepared.start(known_frames)?;
        Self::start(drawers, &settings, frame_count, outputs)
    }

    /// Starts the encoders of a run drawn by `drawers` with `settings`.
    fn start(
        mut drawers: Drawers,
        settings: &RenderSettings,
        frame_count: usize,
        outputs: &RenderOutputs,
    ) -> Result<Self, RenderError> {
        let (width, height) = (settings.width, settings.height);
        let mut videos: Vec<VideoThread> = Vec::new();
        let (video_done_sender, video_done) = unbounded();
        let mut formats: Vec<VideoFormat> = Vec::new();
        for &format in &outputs.videos {
            if formats.contains(&format) {
                continue;
            }
            formats.push(format);
            let path = outputs.video_dir.join(video::file_name(format));
            let spec = VideoSpec {
                path: &path,
                width,
                height,
                frame_count,
                fps: outputs.fps,
                background: linear_to_srgb8(settings.background),
            };
            // A failure here drops the threads started so far, which removes their files.
            let partial = PartialFile::new(&path)?;
            let writer = video::open(format, &spec, &partial)?;
            videos.push(VideoThread::spawn(
                partial,
                writer,
                video_done_sender.clone(),
            ));
        }

        let workers = std::thread::available_parallelism()
            .map_or(2, |n| n.get())
            .clamp(1, 4);
        let (png_sender, png_receiver) = bounded::<(usize, Arc<FrameImage>)>(2 * workers);
        let (done_sender, png_done) = unbounded();
        let png_workers = (0..workers)
            .map(|_| {
                let (frames, done) = (png_receiver.clone(), done_sender.clone());
                let dir = outputs.frames_dir.clone();
                std::thread::spawn(move || png_worker(&dir, frame_count, frames, done))
            })
            .collect();

        // The collector holds the only senders to the encoders: once it
        // ends, they finish.
        let video_senders = videos
            .iter_mut()
            .filter_map(|video| video.sender.take())
            .collect();
        let (report, collected) = unbounded();
        let (drawn, stop) = (drawers.drawn_frames(), drawers.stop_flag());
        let collector = std::thread::spawn(move || {
            collect(drawn, video_senders, png_sender, report, &stop);
        });

        Ok(Self {
            drawers,
            collector: Some(collector),
            collected,
            frame_count,
            pushed: 0,
            queued: 0,
            png_done,
            png_workers,
            videos,
            video_done,
            written: vec![false; frame_count],
            written_in_order: 0,
            costs: vec![FrameCost::default(); frame_count],
            videos_written: vec![0; frame_count],
            costs_taken: 0,
            error: None,
            failed: false,
        })
    }

    /// Sends the next frame to be drawn (it is drawn, encoded and written
    /// while later frames are pushed); waits while as many frames are in
    /// flight as may be. Fails with the first error of any frame or video
    /// reported so far (a frame's own error may come with a later push, or
    /// with `finish`).
    pub fn push(&mut self, frame: &RenderFrame) -> Result<(), RenderError> {
        let result = self.send(frame);
        if result.is_err() {
            self.failed = true;
            self.drawers.stop();
        }
        result
    }

    fn send(&mut self, frame: &RenderFrame) -> Result<(), RenderError> {
        if self.failed {
            return Err(RenderError::InvalidInput(
                "an earlier frame failed; the run cannot continue".into(),
            ));
        }
        if self.pushed == self.frame_count {
            return Err(RenderError::InvalidInput(format!(
                "the run has {} frames, cannot add another",
                self.frame_count
            )));
        }
        self.take_reports();
        if let Some(error) = self.error.take() {
            return Err(error);
        }
        if self.drawers.send(frame.clone()).is_err() {
            // The collector stopped: it said why.
            self.join_collector();
            self.take_reports();
            return Err(self.error.take().unwrap_or_else(stopped_silently));
        }
        self.pushed += 1;
        Ok(())
    }

    /// Records what the collector and the PNG workers have reported.
    fn take_reports(&mut self) {
        while let Ok(report) = self.collected.try_recv() {
            match report {
                Collected::Queued {
                    index,
                    drawer,
                    timings,
                } => {
                    self.costs[index].timings = timings;
                    self.costs[index].drawer = drawer;
                    self.queued += 1;
                }
                Collected::Failed(error) => self.fail(error),
                Collected::EncoderStopped => {
                    let error = self.encoder_error();
                    self.fail(error);
                }
            }
        }
        while let Ok(done) = self.png_done.try_recv() {
            self.record(done);
        }
    }

    /// Keeps the first error; the run can no longer complete.
    fn fail(&mut self, error: RenderError) {
        self.failed = true;
        self.drawers.stop();
        self.error.get_or_insert(error);
    }

    /// Waits for the collector to hand on every frame the drawers draw.
    fn join_collector(&mut self) {
        if let Some(collector) = self.collector.take()
            && let Err(panic) = collector.join()
        {
            std::panic::resume_unwind(panic);
        }
    }

    /// How many frames, from frame 0 on without a gap, are written to disk.
    pub fn frames_written(&self) -> usize {
        self.written_in_order
    }

    /// The costs of the frames completely written (PNG and every video)
    /// since the last call, in frame order, without gaps: frame `k` is
    /// handed out only after frames `0..k`.
    pub fn take_costs(&mut self) -> Vec<FrameCost> {
        // An error is kept and reported by the next push or by finish.
        self.take_reports();
        self.collect_costs()
    }

    fn collect_costs(&mut self) -> Vec<FrameCost> {
        while let Ok((index, time)) = self.video_done.try_recv() {
            self.costs[index].video += time;
            self.videos_written[index] += 1;
        }
        let start = self.costs_taken;
        while self.costs_taken < self.written_in_order
            && self.videos_written[self.costs_taken] == self.videos.len()
        {
            self.costs_taken += 1;
        }
        self.costs[start..self.costs_taken].to_vec()
    }

    /// Waits for every queued frame and video, then gives the videos their
    /// final names. Fails if fewer frames were pushed than the run has.
    pub fn finish(self) -> Result<(), RenderError> {
        self.finish_with_costs().map(|_| ())
    }

    /// [`SequenceWriter::finish`], also handing out the costs of the frames
    /// [`SequenceWriter::take_costs`] has not.
    pub fn finish_with_costs(mut self) -> Result<Vec<FrameCost>, RenderError> {
        // The frames pushed are drawn and handed on; then the encoders,
        // whose queues the collector held, finish.
        self.drawers.close();
        self.join_collector();
        self.take_reports();
        for done in self.png_done.clone().iter() {
            self.record(done);
        }
        join_all(std::mem::take(&mut self.png_workers));
        let video_errors: Vec<RenderError> = self
            .videos
            .iter_mut()
            .filter_map(|video| video.join().err())
            .collect();
        for error in video_errors {
            self.fail(error);
        }
        let mut first_error = self.error.take();
        if first_error.is_none() && self.failed {
            first_error = Some(RenderError::InvalidInput(
                "a frame failed earlier; the videos are incomplete".into(),
            ));
        }
        if first_error.is_none() && self.queued != self.frame_count {
            first_error = Some(RenderError::InvalidInput(format!(
                "the run has {} frames but only {} were rendered",
                self.frame_count, self.queued
            )));
        }
        if let Some(error) = first_error {
            return Err(error);
        }
        let costs = self.collect_costs();
        for video in std::mem::take(&mut self.videos) {
            video.publish()?;
        }
        Ok(costs)
    }

    /// Marks frame `done` written, or keeps its error.
    fn record(&mut self, done: Result<(usize, Duration), RenderError>) {
        match done {
            Ok((index, time)) => {
                self.written[index] = true;
                self.costs[index].png = time;
                while self.written_in_order < self.frame_count
                    && self.written[self.written_in_order]
                {
                    self.written_in_order += 1;
                }
            }
            Err(error) => self.fail(error),
        }
    }

    /// After an encoder stopped taking frames: the error of whichever
    /// stopped (the collector has stopped and dropped their queues).
    fn encoder_error(&mut self) -> RenderError {
        self.join_collector();
        for done in self.png_done.clone().iter() {
            if let Err(error) = done {
                return error;
            }
        }
        for video in &mut self.videos {
            if let Err(error) = video.join() {
                return error;
            }
        }
        RenderError::Gpu {
            during: "writing frames",
            message: "an output thread stopped without an error".into(),
        }
    }
}

/// The error of a run whose collector stopped without saying why.
fn stopped_silently() -> RenderError {
    RenderError::Gpu {
        during: "drawing a frame",
        message: "the frames stopped being handed on without an error".into(),
    }
}

/// The collector: hands the frames drawn, in order, to each video's thread
/// and to the PNG workers, and reports each to the writer. It stops at the
/// first frame that could not be drawn or the first encoder that stops
/// taking frames (and stops the drawers), and when the drawers are done.
fn collect(
    drawn: DrawnFrames,
    videos: Vec<Sender<Arc<FrameImage>>>,
    png: Sender<(usize, Arc<FrameImage>)>,
    report: Sender<Collected>,
    stop: &AtomicBool,
) {
    for (index, drawer, drawn) in drawn {
        let (image, timings) = match drawn {
            Ok(drawn) => drawn,
            Err(error) => {
                stop.store(true, Ordering::Relaxed);
                let _ = report.send(Collected::Failed(error));
                return;
            }
        };
        let _ = report.send(Collected::Queued {
            index,
            drawer,
            timings,
        });
        let image = Arc::new(image);
        let sent = videos.iter().all(|video| video.send(image.clone()).is_ok())
            && png.send((index, image)).is_ok();
        if !sent {
            stop.store(true, Ordering::Relaxed);
            let _ = report.send(Collected::EncoderStopped);
            return;
        }
    }
}

/// Checks what a run asks for before any work: the videos can be written at
/// the image size,
/// their frame rate is valid, and an automatic camera or colour range has the
/// whole run.
fn check_request(
    settings: &RenderSettings,
    frame_count: usize,
    known_frames: &[RenderFrame],
    outputs: &RenderOutputs,
) -> Result<(), RenderError> {
    check_video_support(&outputs.videos, settings.width, settings.height)?;
    let fps_valid = outputs.fps > 0.0 && outputs.fps.is_finite();
    if !outputs.videos.is_empty() && !fps_valid {
        return Err(RenderError::InvalidInput(format!(
            "video frame rate {} must be positive",
            outputs.fps
        )));
    }
    if settings.needs_whole_run() && known_frames.len() != frame_count {
        return Err(RenderError::InvalidInput(format!(
            "the automatic camera or colour range needs all {frame_count} frames up front, got {}",
            known_frames.len()
        )));
    }
    Ok(())
}

impl Drop for SequenceWriter {
    /// An unfinished run: the frames pushed are drawn and written (unless
    /// a frame failed), then partial videos are removed.
    fn drop(&mut self) {
        if self.failed {
            self.drawers.stop();
        }
        self.drawers.close();
        self.join_collector();
        for worker in std::mem::take(&mut self.png_workers) {
            let _ = worker.join();
        }
        // Each video thread is joined, and its partial file removed, as it drops.
    }
}

impl VideoThread {
    fn spawn(
        partial: PartialFile,
        mut writer: Box<dyn VideoWriter>,
        done: Sender<(usize, Duration)>,
    ) -> Self {
        let (sender, receiver) = bounded::<Arc<FrameImage>>(3);
        let thread = std::thread::spawn(move || -> Result<(), RenderError> {
            for (index, image) in receiver.into_iter().enumerate() {
                let start = Instant::now();
                writer.push(&image)?;
                let _ = done.send((index, start.elapsed()));
            }
            writer.finish()
        });
        Self {
            partial: Some(partial),
            sender: Some(sender),
            thread: Some(thread),
        }
    }

    /// Closes the queue and waits for the video; the first call returns its result.
    fn join(&mut self) -> Result<(), RenderError> {
        self.sender = None;
        match self.thread.take() {
            Some(thread) => thread
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic)),
            None => Ok(()),
        }
    }

    /// Renames the complete video to its final name.
    fn publish(mut self) -> Result<(), RenderError> {
        match self.partial.take() {
            Some(partial) => partial.publish(),
            None => Ok(()),
        }
    }
}

impl Drop for VideoThread {
    /// A video not published is partial: wait for its thread (whose writer
    /// stops its encoder), then remove its file.
    fn drop(&mut self) {
        self.sender = None;
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
        self.partial = None;
    }
}

fn join_all(threads: Vec<JoinHandle<()>>) {
    for thread in threads {
        if let Err(panic) = thread.join() {
            std::panic::resume_unwind(panic);
        }
    }
}

fn create_dir(dir: &Path) -> Result<(), RenderError> {
    std::fs::create_dir_all(dir).map_err(|source| RenderError::Io {
        path: dir.to_owned(),
        source,
    })
}

fn png_worker(
    dir: &Path,
    frame_count: usize,
    frames: Receiver<(usize, Arc<FrameImage>)>,
    done: Sender<Result<(usize, Duration), RenderError>>,
) {
    let mut png = FramePngWriter::default();
    for (index, image) in frames {
        let start = Instant::now();
        let path = dir.join(frame_file_name(index, frame_count));
        let result = png.write(&path, &image).map(|()| (index, start.elapsed()));
        let failed = result.is_err();
        let _ = done.send(result);
        if failed {
            break;
        }
    }
}

/// Renders every frame of a finished run, writes PNG frames and the video
/// (a [`SequenceWriter`] fed every frame). Calls `progress(i)` after frame
/// `i` is written.
///
/// Frames go to `frames_dir/frame_0000.png`, `frame_0001.png`, ... (more
/// digits past 10000 frames); videos to `video_dir/video.{png,mp4,gif}`. Every
/// file appears under its final name only once complete. `progress` is
/// called in frame order, on the calling thread.
pub fn render_sequence(
    settings: &RenderSettings,
    mesh: &RenderMesh,
    frames: &[RenderFrame],
    outputs: &RenderOutputs,
    progress: &mut dyn FnMut(usize),
) -> Result<(), RenderError> {
    let mut writer = SequenceWriter::create(settings, mesh, frames.len(), frames, outputs)?;
    let mut reported = 0;
    let mut report = |written: usize, progress: &mut dyn FnMut(usize)| {
        while reported < written {
            progress(reported);
            reported += 1;
        }
    };
    for frame in frames {
        writer.push(frame)?;
        report(writer.frames_written(), progress);
    }
    writer.finish()?;
    report(frames.len(), progress);
    Ok(())
}
