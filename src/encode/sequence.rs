//! Writing a run frame by frame: numbered PNG frames and videos.
//!
//! A [`SequenceWriter`] is fed one [`RenderFrame`] at a time, as the
//! simulation produces them or from a finished run. [`SequenceWriter::push`]
//! starts drawing the frame ([`Renderer::start`]) and hands the frame
//! before it, read back meanwhile ([`Renderer::finish`]), as a whole image
//! to:
//! - a pool of PNG workers, through one bounded queue (so memory stays flat
//!   however long the run), each encoding whole images with the `png` crate
//!   (fast compression) and writing each frame under a hidden temporary
//!   name, renamed once complete;
//! - one thread per video format, through its own bounded queue, in frame
//!   order.
//!
//! A full queue makes `push` wait, so neither rendering nor the simulation
//! feeding it can run ahead of the encoders by more than a few frames.
//! The first error stops the run: no frame after it is started, and the
//! frames before it are written. Videos are renamed to their final names
//! only by [`SequenceWriter::finish`] after every frame and every video
//! succeeded; it also hands out each frame's [`FrameCost`] (draw, readback,
//! legend, PNG, videos). A writer dropped unfinished (the simulation
//! failed) writes the frames already pushed and removes its partial
//! videos; the frames written stay, each one complete. On SIGINT or SIGTERM
//! the binary removes partial frames and videos through
//! [`remove_partial_files`](super::remove_partial_files).

use super::export::{check_video_support, frame_file_name, write_png};
use super::partial_file::PartialFile;
use super::video;
use super::video_writer::{VideoSpec, VideoWriter};
use super::{RenderError, RenderOutputs, VideoFormat};
use crate::render::{
    FRAMES_IN_FLIGHT, FrameTimings, PreparedRenderer, RenderFrame, RenderMesh, RenderSettings,
    Renderer, linear_to_srgb8,
};
use crossbeam_channel::{Receiver, Sender, bounded, unbounded};
use image::RgbaImage;
use std::path::Path;
use std::sync::Arc;
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

/// A frame as the encoders take it: its whole image.
type Image = Arc<RgbaImage>;

/// Renders frames one at a time and writes them as PNG files and videos.
pub struct SequenceWriter {
    renderer: Renderer,
    frame_count: usize,
    /// Frames started, and handed to the encoders.
    pushed: usize,
    drawn: usize,
    /// The PNG workers' queue, until the run is finished.
    png: Option<Sender<(usize, Image)>>,
    png_done: Receiver<Result<(usize, Duration), RenderError>>,
    png_workers: Vec<JoinHandle<()>>,
    videos: Vec<VideoThread>,
    /// Frames (in order, one per video) each video thread has written, with the time it took.
    video_done: Receiver<(usize, Duration)>,
    costs: Vec<FrameCost>,
    /// Which frames' PNG files are written, and how many from the start in a row.
    written: Vec<bool>,
    written_in_order: usize,
    /// The first error of an encoder, once reported, until `push` or
    /// `finish` returns it.
    error: Option<RenderError>,
    /// A frame or video failed: the run can no longer complete.
    failed: bool,
}

struct VideoThread {
    /// The video's file; removed unless published.
    partial: Option<PartialFile>,
    sender: Option<Sender<Image>>,
    thread: Option<JoinHandle<Result<(), RenderError>>>,
}

impl SequenceWriter {
    /// Starts writing a run of `frame_count` frames to `outputs`.
    ///
    /// `known_frames` frame the camera and the colour range (see
    /// [`Renderer::new`]). When [`RenderSettings::needs_whole_run`] is true
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
        // Bad frames are reported before the device is opened.
        Renderer::check(settings, mesh, known_frames)?;
        let prepared = Renderer::prepare(settings, mesh)?;
        Self::create_prepared(prepared, frame_count, known_frames, outputs)
    }

    /// [`SequenceWriter::create`] with a renderer prepared beforehand (see
    /// [`Renderer::prepare`]).
    pub fn create_prepared(
        prepared: PreparedRenderer,
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
        let renderer = prepared.with_frames(known_frames)?;
        Self::start(renderer, frame_count, outputs)
    }

    /// Starts the encoders of a run drawn by `renderer`.
    fn start(
        renderer: Renderer,
        frame_count: usize,
        outputs: &RenderOutputs,
    ) -> Result<Self, RenderError> {
        let settings = renderer.settings();
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
        let (png, png_receiver) = bounded::<(usize, Image)>(2 * workers);
        let (done_sender, png_done) = unbounded();
        let png_workers = (0..workers)
            .map(|_| {
                let (frames, done) = (png_receiver.clone(), done_sender.clone());
                let dir = outputs.frames_dir.clone();
                std::thread::spawn(move || png_worker(&dir, frame_count, frames, done))
            })
            .collect();

        Ok(Self {
            renderer,
            frame_count,
            pushed: 0,
            drawn: 0,
            png: Some(png),
            png_done,
            png_workers,
            videos,
            video_done,
            costs: vec![FrameCost::default(); frame_count],
            written: vec![false; frame_count],
            written_in_order: 0,
            error: None,
            failed: false,
        })
    }

    /// Starts drawing the next frame and hands the one before it to the
    /// encoders (they encode and write it while later frames are pushed);
    /// waits while their queues are full. Fails with the frame's own error,
    /// or the first error of any PNG file or video reported so far; the
    /// frames before a failed one are written all the same.
    pub fn push(&mut self, frame: &RenderFrame) -> Result<(), RenderError> {
        let result = self.send(frame);
        if result.is_err() {
            self.failed = true;
            while self.renderer.frames_in_flight() > 0 && self.hand_out().is_ok() {}
            self.close_png_queue();
        }
        result
    }

    fn send(&mut self, frame: &RenderFrame) -> Result<(), RenderError> {
        // The first error an encoder reported is the one the run stops
        // with, with its file and cause; only later pushes get the generic
        // refusal.
        while let Ok(done) = self.png_done.try_recv() {
            self.record(done);
        }
        if let Some(error) = self.error.take() {
            return Err(error);
        }
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
        let index = self.pushed;
        self.renderer
            .start(frame)
            .map_err(|error| frame_error(index, error))?;
        self.pushed += 1;
        if self.renderer.frames_in_flight() == FRAMES_IN_FLIGHT {
            self.hand_out()?;
        }
        Ok(())
    }

    /// Reads the oldest frame in flight back and hands it to the encoders.
    fn hand_out(&mut self) -> Result<(), RenderError> {
        let index = self.drawn;
        let Some((image, timings)) = self
            .renderer
            .finish()
            .map_err(|error| frame_error(index, error))?
        else {
            return Ok(());
        };
        self.costs[index].timings = timings;
        let image = Arc::new(image);
        let sent = self.videos.iter().all(|video| video.send(image.clone()))
            && self
                .png
                .as_ref()
                .is_some_and(|png| png.send((index, image)).is_ok());
        if !sent {
            return Err(self.encoder_error());
        }
        self.drawn += 1;
        Ok(())
    }

    /// How many frames, from frame 0 on, are drawn and handed to the encoders.
    pub fn frames_drawn(&self) -> usize {
        self.drawn
    }

    /// How many frames, from frame 0 on without a gap, are written to disk.
    pub fn frames_written(&mut self) -> usize {
        while let Ok(done) = self.png_done.try_recv() {
            self.record(done);
        }
        self.written_in_order
    }

    /// Keeps the first error; the run can no longer complete.
    fn fail(&mut self, error: RenderError) {
        self.failed = true;
        self.error.get_or_insert(error);
    }

    /// Waits for every queued frame and video, then gives the videos their
    /// final names. Fails if fewer frames were pushed than the run has.
    pub fn finish(self) -> Result<(), RenderError> {
        self.finish_with_costs().map(|_| ())
    }

    /// [`SequenceWriter::finish`], also handing out the cost of every frame,
    /// in frame order.
    pub fn finish_with_costs(mut self) -> Result<Vec<FrameCost>, RenderError> {
        while self.renderer.frames_in_flight() > 0 {
            if let Err(error) = self.hand_out() {
                self.fail(error);
                break;
            }
        }
        // The encoders finish the frames queued.
        self.close_png_queue();
        let video_errors: Vec<RenderError> = self
            .videos
            .iter_mut()
            .filter_map(|video| video.join().err())
            .collect();
        for error in video_errors {
            self.fail(error);
        }
        while let Ok((index, time)) = self.video_done.try_recv() {
            self.costs[index].video += time;
        }
        let mut first_error = self.error.take();
        if first_error.is_none() && self.failed {
            first_error = Some(RenderError::InvalidInput(
                "a frame failed earlier; the videos are incomplete".into(),
            ));
        }
        if first_error.is_none() && self.pushed != self.frame_count {
            first_error = Some(RenderError::InvalidInput(format!(
                "the run has {} frames but only {} were rendered",
                self.frame_count, self.pushed
            )));
        }
        if let Some(error) = first_error {
            return Err(error);
        }
        for video in std::mem::take(&mut self.videos) {
            video.publish()?;
        }
        Ok(std::mem::take(&mut self.costs))
    }

    /// Closes the PNG workers' queue and waits for them to write what it
    /// holds.
    fn close_png_queue(&mut self) {
        self.png = None;
        for done in self.png_done.clone().iter() {
            self.record(done);
        }
        for worker in std::mem::take(&mut self.png_workers) {
            if let Err(panic) = worker.join() {
                std::panic::resume_unwind(panic);
            }
        }
    }

    /// Notes the time of frame `done`'s PNG file, or keeps its error.
    fn record(&mut self, done: Result<(usize, Duration), RenderError>) {
        match done {
            Ok((index, time)) => {
                self.costs[index].png = time;
                self.written[index] = true;
                while self.written.get(self.written_in_order) == Some(&true) {
                    self.written_in_order += 1;
                }
            }
            Err(error) => self.fail(error),
        }
    }

    /// After an encoder stopped taking frames: the error of whichever
    /// stopped (the queues are closed, so that the others stop too).
    fn encoder_error(&mut self) -> RenderError {
        self.png = None;
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

/// The error of frame `index`.
fn frame_error(index: usize, error: RenderError) -> RenderError {
    RenderError::Frame {
        index,
        error: Box::new(error),
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
    /// An unfinished run: the frames pushed are written, then partial
    /// videos are removed.
    fn drop(&mut self) {
        while self.renderer.frames_in_flight() > 0 && self.hand_out().is_ok() {}
        self.png = None;
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
        let (sender, receiver) = bounded::<Image>(3);
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

    /// Queues the next frame; false once the video has stopped (on an error).
    fn send(&self, image: Image) -> bool {
        self.sender
            .as_ref()
            .is_some_and(|sender| sender.send(image).is_ok())
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

fn create_dir(dir: &Path) -> Result<(), RenderError> {
    std::fs::create_dir_all(dir).map_err(|source| RenderError::Io {
        path: dir.to_owned(),
        source,
    })
}

fn png_worker(
    dir: &Path,
    frame_count: usize,
    frames: Receiver<(usize, Image)>,
    done: Sender<Result<(usize, Duration), RenderError>>,
) {
    for (index, image) in frames {
        let start = Instant::now();
        let path = dir.join(frame_file_name(index, frame_count));
        let result = write_png(&path, &image).map(|()| (index, start.elapsed()));
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
