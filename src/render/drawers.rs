//! [`Drawers`]: a run's frames drawn by one renderer per device at once,
//! each on a thread of its own, and handed back in frame order; and the
//! renderers prepared for them ([`PreparedRenderers`],
//! [`PreparingRenderers`]).
//!
//! On a machine with a GPU one device draws every frame. On Mesa's llvmpipe
//! drawing a frame is a chain of work on one core at a time: the drawing
//! thread shades the vertices and bins the triangles, the rasteriser shades
//! the fragments, then the tile is read back. Two devices opened by wgpu
//! share one rasteriser, so a second device with a rasteriser of its own
//! (`egl_gpu`) draws frames beside the first: each drawer takes the next
//! frame from one queue as soon as it is free, and the frames are put back
//! in order before they are encoded. Both devices are llvmpipe with the
//! same shaders, and the second renderer draws over the first's backdrop
//! and base (`PreparedRenderer::complete_with`), so a frame is the same
//! bytes whichever device draws it (`tests/integration/render_devices.rs`).
//!
//! The second device is prepared after the first, and joins the drawing
//! when it is ready: a run never waits for it.

use super::export::frame_file_name;
use super::frame_png::FramePngWriter;
use super::gpu::second_gpu;
use super::{FrameImage, FrameTimings, PreparedRenderer, RenderError, RenderFrame, RenderMesh};
use super::{RenderSettings, Renderer};
use crossbeam_channel::{Receiver, Sender, bounded, unbounded};
use std::collections::BTreeMap;
use std::ffi::OsStr;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, mpsc};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// The most devices that draw a run's frames.
pub(super) const MAX_DEVICES: usize = 2;

/// Frames per device that may be sent and not yet handed back before
/// [`Drawers::full`] says so. Frames come back in order, so a drawer that
/// finishes early can run ahead of one held up (by the scheduler, a file)
/// by up to this many instead of waiting: the default scene's frames took
/// 152 ms with 2 per device, 1.68 cores busy, and 142 ms with 16, 1.78
/// (medians of five alternating runs). A frame in flight is its positions
/// and, once drawn, its tile: a few hundred kilobytes at most.
const FRAMES_PER_DEVICE: usize = 16;

/// The environment variable that limits the devices to one (`1`).
pub const RENDER_DEVICES_VARIABLE: &str = "ELASTO_RENDER_DEVICES";

/// How many devices may draw a run's frames: 2, or 1 on a
/// machine with one core or when [`RENDER_DEVICES_VARIABLE`] says so.
/// Fails, with the reason, when that variable is set to anything but 1 or 2.
pub fn device_limit() -> Result<usize, String> {
    limit_of(
        std::env::var_os(RENDER_DEVICES_VARIABLE).as_deref(),
        cores(),
    )
}

/// [`device_limit`] with the variable's value `setting` on `cores` cores.
fn limit_of(setting: Option<&OsStr>, cores: usize) -> Result<usize, String> {
    let limit = match setting.map(|value| value.to_str().map(str::trim)) {
        None => MAX_DEVICES,
        Some(Some("1")) => 1,
        Some(Some("2")) => 2,
        Some(_) => {
            return Err(format!(
                "must be 1 (one device draws every frame) or 2 (a second software \
                 device draws beside the first when there is one), not `{}`",
                setting.unwrap_or_default().to_string_lossy()
            ));
        }
    };
    Ok(if cores < 2 { 1 } else { limit })
}

/// The number of rasteriser threads each llvmpipe device should have, for
/// `LP_NUM_THREADS` (see the binary's `main`): with two devices drawing
/// frames side by side each gets half the cores, one of them its drawing
/// thread, so none on 2 cores: the drawing thread rasterises, without a
/// hand-off to another thread per frame. `None` when one device draws
/// (Mesa's own default, a thread per core, then serves large frames best).
pub fn llvmpipe_threads() -> Option<usize> {
    threads_per_device(cores(), device_limit().ok()?)
}

/// [`llvmpipe_threads`] on `cores` cores with at most `devices` devices.
fn threads_per_device(cores: usize, devices: usize) -> Option<usize> {
    (devices == MAX_DEVICES).then(|| (cores / MAX_DEVICES).saturating_sub(1))
}

fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// Renderers prepared for a run: one on the shared device, and one on a
/// second device with a rasteriser of its own when there is one and it is
/// wanted ([`device_limit`]); that one may still be being prepared.
pub struct PreparedRenderers {
    first: PreparedRenderer,
    second: Second,
}

/// The second device's renderer.
enum Second {
    None,
    Ready(Box<PreparedRenderer>),
    /// Being prepared on another thread.
    Pending(PendingRenderer),
}

/// A renderer being prepared on a thread of its own; `None` if it could
/// not be, or was no longer wanted. The thread is joined when this is
/// dropped, so that no thread is left inside the graphics driver when the
/// process exits; it stops at its next step once told the renderer is not
/// wanted (see [`PendingRenderer::cancel`]), so a run that ends before the
/// second device is ready does not wait for all of its preparation (with
/// Mesa's shader cache off, about 0.4 s of shader compilation).
struct PendingRenderer {
    renderer: mpsc::Receiver<Option<PreparedRenderer>>,
    thread: Option<JoinHandle<()>>,
    unwanted: Arc<AtomicBool>,
}

impl PendingRenderer {
    /// Waits for the renderer.
    fn wait(self) -> Option<PreparedRenderer> {
        self.renderer.recv().ok().flatten()
    }

    /// What tells the preparing thread that the renderer is not wanted.
    fn cancel(&self) -> Arc<AtomicBool> {
        self.unwanted.clone()
    }
}

impl Drop for PendingRenderer {
    fn drop(&mut self) {
        self.unwanted.store(true, Ordering::Relaxed);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

impl PreparedRenderers {
    /// Opens the devices and makes what drawing `mesh` with `settings`
    /// needs before any frame is known (see [`Renderer::prepare`]), here
    /// and now, on as many devices as [`device_limit`] allows.
    pub fn prepare(settings: &RenderSettings, mesh: &RenderMesh) -> Result<Self, RenderError> {
        let limit = device_limit().map_err(|reason| {
            RenderError::InvalidInput(format!("{RENDER_DEVICES_VARIABLE}: {reason}"))
        })?;
        Self::prepare_with(settings, mesh, limit)
    }

    /// [`PreparedRenderers::prepare`] on at most `devices` devices (1 or 2;
    /// the second only where there is one, see `egl_gpu`).
    pub fn prepare_with(
        settings: &RenderSettings,
        mesh: &RenderMesh,
        devices: usize,
    ) -> Result<Self, RenderError> {
        let first = Renderer::prepare(settings, mesh)?;
        let second = match prepare_second(settings, mesh, devices) {
            Some(second) => Second::Ready(Box::new(second)),
            None => Second::None,
        };
        Ok(PreparedRenderers { first, second })
    }

    /// How many devices will draw the frames: 2 when a second one is
    /// prepared or being prepared.
    pub fn devices(&self) -> usize {
        match self.second {
            Second::None => 1,
            Second::Ready(_) | Second::Pending(_) => 2,
        }
    }

    /// The settings they were prepared for.
    pub fn settings(&self) -> &RenderSettings {
        self.first.settings()
    }

    /// Each renderer ready now warmed up with the run's first frame (see
    /// [`PreparedRenderer::warmed_up`]).
    pub fn warmed_up(mut self, first: &RenderFrame) -> Result<Self, RenderError> {
        self.first = self.first.warmed_up(first)?;
        if let Second::Ready(second) = self.second {
            self.second = warm_up_second(*second, first)
                .map_or(Second::None, |second| Second::Ready(Box::new(second)));
        }
        Ok(self)
    }

    /// The drawers of a run of `frames` (see [`Renderer::new`]): the first
    /// renderer is completed here, the second from it on its own thread
    /// once it is prepared. With `files`, each drawer writes the PNG file
    /// of every frame it draws.
    pub(super) fn start(
        self,
        frames: &[RenderFrame],
        files: Option<FrameFiles>,
    ) -> Result<Drawers, RenderError> {
        let first = self.first.with_frames(frames)?;
        let mut drawers = Drawers::new(files);
        if let Second::Pending(pending) = &self.second {
            drawers.cancel_preparation = Some(pending.cancel());
        }
        if !matches!(self.second, Second::None) {
            let (second, fixtures) = (self.second, first.fixtures());
            drawers.spawn(1, move || {
                let prepared = second.wait()?;
                let gpu = prepared.gpu().clone();
                let _current = gpu.enter();
                prepared.complete_with(fixtures).ok()
            });
        }
        drawers.spawn(0, move || Some(first));
        Ok(drawers)
    }
}

impl Second {
    /// The renderer, once it is prepared (if it can be).
    fn wait(self) -> Option<PreparedRenderer> {
        match self {
            Second::None => None,
            Second::Ready(prepared) => Some(*prepared),
            Second::Pending(pending) => pending.wait(),
        }
    }
}

/// The second device's renderer, if that device is wanted (`limit`), can
/// be opened and the renderer made: it only adds speed, so a failure
/// leaves the run to the first device.
fn prepare_second(
    settings: &RenderSettings,
    mesh: &RenderMesh,
    limit: usize,
) -> Option<PreparedRenderer> {
    if limit < 2 {
        return None;
    }
    let gpu = second_gpu().ok()??;
    let _current = gpu.enter();
    Renderer::prepare_on(gpu.clone(), settings, mesh).ok()
}

/// `second` dropped, with its device's context current (see `egl_gpu`).
fn drop_second(second: PreparedRenderer) {
    let gpu = second.gpu().clone();
    let _current = gpu.enter();
    drop(second);
}

/// `second` warmed up with `first` (see [`PreparedRenderer::warmed_up`]),
/// if it can draw it.
fn warm_up_second(second: PreparedRenderer, first: &RenderFrame) -> Option<PreparedRenderer> {
    let gpu = second.gpu().clone();
    let _current = gpu.enter();
    second.warmed_up(first).ok()
}

/// Renderers being prepared on a thread of their own, while the run
/// simulates: the first device's is handed out as soon as it is ready, the
/// second's after it.
pub struct PreparingRenderers {
    first: mpsc::Receiver<Result<PreparedRenderer, RenderError>>,
    second: PendingRenderer,
}

impl PreparingRenderers {
    /// Starts preparing. A frame from `warm_up`, if one comes, warms each
    /// renderer up (see [`PreparedRenderer::warmed_up`]); when `warm_up`
    /// closes without one the renderers are handed out as they are.
    pub fn start(
        settings: &RenderSettings,
        mesh: &RenderMesh,
        warm_up: Option<mpsc::Receiver<RenderFrame>>,
    ) -> Self {
        let (first_sender, first) = mpsc::channel();
        let (second_sender, second) = mpsc::channel();
        let unwanted = Arc::new(AtomicBool::new(false));
        let (settings, mesh) = (settings.clone(), mesh.clone());
        let cancelled = unwanted.clone();
        let thread = std::thread::spawn(move || {
            let wanted = || !cancelled.load(Ordering::Relaxed);
            let (prepared, limit) = match device_limit() {
                Ok(limit) => (Renderer::prepare(&settings, &mesh), limit),
                Err(reason) => (
                    Err(RenderError::InvalidInput(format!(
                        "{RENDER_DEVICES_VARIABLE}: {reason}"
                    ))),
                    1,
                ),
            };
            let prepared = match prepared {
                Ok(prepared) => prepared,
                Err(error) => {
                    let _ = first_sender.send(Err(error));
                    return;
                }
            };
            let frame = warm_up.and_then(|frames| frames.recv().ok());
            let prepared = match &frame {
                Some(frame) => prepared.warmed_up(frame),
                None => Ok(prepared),
            };
            let first_ready = prepared.is_ok();
            let _ = first_sender.send(prepared);
            if !first_ready || !wanted() {
                return;
            }
            let second = prepare_second(&settings, &mesh, limit);
            let second = match (second, &frame) {
                (Some(second), Some(_)) if !wanted() => {
                    drop_second(second);
                    None
                }
                (Some(second), Some(frame)) => warm_up_second(second, frame),
                (second, _) => second,
            };
            let _ = second_sender.send(second);
        });
        PreparingRenderers {
            first,
            second: PendingRenderer {
                renderer: second,
                thread: Some(thread),
                unwanted,
            },
        }
    }

    /// The renderers, once the first is ready.
    pub fn wait(mut self) -> Result<PreparedRenderers, RenderError> {
        let first = match self.first.recv() {
            Ok(first) => first?,
            Err(_) => {
                // The thread panicked before it handed the renderer out.
                if let Some(Err(panic)) = self.second.thread.take().map(JoinHandle::join) {
                    std::panic::resume_unwind(panic);
                }
                return Err(RenderError::Gpu {
                    during: "preparing the renderer",
                    message: "the preparing thread stopped".into(),
                });
            }
        };
        // Prepared already (or found missing): no need to wait later.
        let second = match self.second.renderer.try_recv() {
            Ok(Some(second)) => Second::Ready(Box::new(second)),
            Ok(None) | Err(mpsc::TryRecvError::Disconnected) => Second::None,
            Err(mpsc::TryRecvError::Empty) => Second::Pending(self.second),
        };
        Ok(PreparedRenderers { first, second })
    }
}

/// A frame drawn, with its PNG file's cost when the drawer writes it.
pub(super) struct DrawnFrame {
    pub image: FrameImage,
    pub timings: FrameTimings,
    /// Writing the frame's PNG file, when the drawers write them
    /// ([`FrameFiles`]): how long it took, or why it failed.
    pub png: Option<Result<Duration, RenderError>>,
}

type Drawn = Result<DrawnFrame, RenderError>;

/// Where the frames' PNG files go, and how they are named.
#[derive(Clone)]
pub(super) struct FrameFiles {
    pub dir: PathBuf,
    pub frame_count: usize,
}

impl FrameFiles {
    /// Writes frame `index` with `png`, and says how long it took.
    pub fn write(
        &self,
        png: &mut FramePngWriter,
        index: usize,
        image: &FrameImage,
    ) -> Result<Duration, RenderError> {
        let start = Instant::now();
        let path = self.dir.join(frame_file_name(index, self.frame_count));
        png.write(&path, image).map(|()| start.elapsed())
    }
}

/// One renderer per device, each on its own thread (see the module
/// documentation).
pub(super) struct Drawers {
    /// The queue every drawer takes its next frame from, with its index.
    frames: Option<Sender<(usize, RenderFrame)>>,
    frame_queue: Receiver<(usize, RenderFrame)>,
    /// Each frame drawn, with its index and the drawer that drew it.
    drawn_sender: Option<Sender<(usize, usize, Drawn)>>,
    drawn: Receiver<(usize, usize, Drawn)>,
    threads: Vec<JoinHandle<()>>,
    /// Set when the run cannot complete: the drawers take no more frames.
    stopped: Arc<AtomicBool>,
    /// Tells the second device's preparation, if still under way, that it
    /// is no longer wanted: set when the drawers are dropped.
    cancel_preparation: Option<Arc<AtomicBool>>,
    /// Where each drawer writes the PNG files of its frames, if it does.
    files: Option<FrameFiles>,
    /// Frames drawn ahead of the one handed back next.
    ahead: BTreeMap<usize, (usize, Drawn)>,
    /// Frames sent, and frames handed back (in order).
    sent: usize,
    received: usize,
}

impl Drawers {
    fn new(files: Option<FrameFiles>) -> Self {
        let (frames, frame_queue) = bounded(FRAMES_PER_DEVICE * MAX_DEVICES);
        let (drawn_sender, drawn) = unbounded();
        Drawers {
            frames: Some(frames),
            frame_queue,
            drawn_sender: Some(drawn_sender),
            drawn,
            threads: Vec::new(),
            stopped: Arc::new(AtomicBool::new(false)),
            cancel_preparation: None,
            files,
            ahead: BTreeMap::new(),
            sent: 0,
            received: 0,
        }
    }

    /// Starts drawer number `drawer`, whose renderer `make` makes on its
    /// thread (none: the drawer does not draw).
    fn spawn(&mut self, drawer: usize, make: impl FnOnce() -> Option<Renderer> + Send + 'static) {
        let frames = self.frame_queue.clone();
        let drawn = self
            .drawn_sender
            .clone()
            .expect("drawers are spawned first");
        let files = self.files.clone();
        let stopped = self.stopped.clone();
        self.threads.push(std::thread::spawn(move || {
            let Some(mut renderer) = make() else { return };
            let gpu = renderer.gpu().clone();
            // Current for the thread's life: making a context current and
            // releasing it flushes and revalidates it, too much per frame.
            let _current = gpu.enter();
            let mut png = FramePngWriter::default();
            for (index, frame) in frames {
                if stopped.load(Ordering::Relaxed) {
                    break;
                }
                let rendered = renderer
                    .render_timed(&frame)
                    .map_err(|error| RenderError::Frame {
                        index,
                        error: Box::new(error),
                    });
                let result = rendered.map(|(image, timings)| {
                    let png = files
                        .as_ref()
                        .map(|files| files.write(&mut png, index, &image));
                    DrawnFrame {
                        image,
                        timings,
                        png,
                    }
                });
                let failed = match &result {
                    Ok(drawn) => matches!(drawn.png, Some(Err(_))),
                    Err(_) => true,
                };
                if failed {
                    // The frames after it are not drawn or written.
                    stopped.store(true, Ordering::Relaxed);
                }
                if drawn.send((index, drawer, result)).is_err() || failed {
                    break;
                }
            }
            drop(renderer);
        }));
    }

    /// Stops the drawers: they draw no frame they have not started.
    pub fn stop(&self) {
        self.stopped.store(true, Ordering::Relaxed);
    }

    /// Frames sent and not yet handed back.
    pub fn in_flight(&self) -> usize {
        self.sent - self.received
    }

    /// Whether as many frames are in flight as may be: hand one back before
    /// sending another.
    pub fn full(&self) -> bool {
        self.in_flight() >= FRAMES_PER_DEVICE * MAX_DEVICES
    }

    /// Queues the next frame for the first drawer free. Fails when every
    /// drawer has stopped (each on an error that [`Drawers::receive`] hands
    /// back in its frame's place).
    pub fn send(&mut self, frame: RenderFrame) -> Result<(), RenderError> {
        // The drawers hold their own senders of drawn frames from now on:
        // once they have all stopped, `receive` hears of it.
        self.drawn_sender = None;
        let sent = self
            .frames
            .as_ref()
            .is_some_and(|frames| frames.send((self.sent, frame)).is_ok());
        if !sent {
            return Err(stopped());
        }
        self.sent += 1;
        Ok(())
    }

    /// The next frame in order and the drawer that drew it, waiting for it
    /// to be drawn.
    pub fn receive(&mut self) -> (usize, Drawn) {
        debug_assert!(self.in_flight() > 0);
        loop {
            if let Some(drawn) = self.ahead.remove(&self.received) {
                self.received += 1;
                return drawn;
            }
            match self.drawn.recv() {
                Ok((index, drawer, drawn)) => {
                    self.ahead.insert(index, (drawer, drawn));
                }
                Err(_) => {
                    self.received += 1;
                    return (0, Err(stopped()));
                }
            }
        }
    }

    /// The next frame in order, if it is drawn already.
    pub fn try_receive(&mut self) -> Option<(usize, Drawn)> {
        while let Ok((index, drawer, drawn)) = self.drawn.try_recv() {
            self.ahead.insert(index, (drawer, drawn));
        }
        let drawn = self.ahead.remove(&self.received)?;
        self.received += 1;
        Some(drawn)
    }
}

/// The error of a frame no drawer is left to draw.
fn stopped() -> RenderError {
    RenderError::Gpu {
        during: "drawing a frame",
        message: "every drawing thread stopped".into(),
    }
}

impl Drop for Drawers {
    /// Closes the queue and waits for the drawers to draw what it holds
    /// (nothing, once stopped); each drops its renderer with its device's
    /// context current.
    fn drop(&mut self) {
        self.frames = None;
        if let Some(unwanted) = &self.cancel_preparation {
            unwanted.store(true, Ordering::Relaxed);
        }
        for thread in self.threads.drain(..) {
            let _ = thread.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_device_limit_is_two_unless_set_to_one_or_on_one_core() {
        let limit = |value: Option<&str>, cores| limit_of(value.map(OsStr::new), cores);
        assert_eq!(limit(None, 2), Ok(2));
        assert_eq!(limit(Some("1"), 2), Ok(1));
        assert_eq!(limit(Some(" 2 "), 8), Ok(2));
        assert_eq!(limit(None, 1), Ok(1));
        assert_eq!(limit(Some("2"), 1), Ok(1));
        for bad in ["0", "3", "two", ""] {
            let error = limit(Some(bad), 2).unwrap_err();
            assert!(error.contains(&format!("not `{bad}`")), "{error}");
        }
    }

    #[test]
    fn each_of_two_devices_rasterises_on_half_the_cores_less_its_drawing_thread() {
        assert_eq!(threads_per_device(2, 2), Some(0));
        assert_eq!(threads_per_device(3, 2), Some(0));
        assert_eq!(threads_per_device(4, 2), Some(1));
        assert_eq!(threads_per_device(16, 2), Some(7));
        assert_eq!(threads_per_device(1, 2), Some(0));
        assert_eq!(threads_per_device(8, 1), None, "one device: Mesa's default");
    }
}
