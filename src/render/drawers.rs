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
//! in order before they are encoded (by the PNG workers and the video
//! threads, see `sequence`). Both devices are llvmpipe with the
//! same shaders, and the second renderer draws over the first's backdrop
//! and base (`PreparedRenderer::complete_with`), so a frame is the same
//! bytes whichever device draws it (`tests/integration/render_devices.rs`).
//!
//! The second device is prepared after the first, and joins the drawing
//! when it is ready: a run never waits for it.

use super::gpu::second_gpu;
use super::{FrameImage, FrameTimings, PreparedRenderer, RenderError, RenderFrame, RenderMesh};
use super::{RenderSettings, Renderer};
use crossbeam_channel::{Receiver, Sender, bounded, unbounded};
use std::collections::BTreeMap;
use std::ffi::OsStr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, mpsc};
use std::thread::JoinHandle;

/// The most devices that draw a run's frames.
pub(super) const MAX_DEVICES: usize = 2;

/// Frames per device that may be sent and not yet handed on before
/// [`Drawers::send`] waits. Frames are handed on in order, so a drawer that
/// finishes early can run ahead of one held up (by the scheduler, a slow
/// frame) by up to this many instead of waiting: the default scene's
/// frames took 184 ms with 2 per device, 1.87 cores busy, and 180 ms with
/// 16, 1.90 (medians of nine alternating runs). A frame in flight is its
/// positions and, once drawn, its tile: a few hundred kilobytes at most.
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
    /// once it is prepared.
    pub(super) fn start(self, frames: &[RenderFrame]) -> Result<Drawers, RenderError> {
        let first = self.first.with_frames(frames)?;
        let mut drawers = Drawers::new();
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
        // The drawers hold the senders of what they draw: once they have all
        // finished, the frames drawn end.
        drawers.drawn_sender = None;
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

/// A frame drawn, or why it could not be.
pub(super) type Drawn = Result<(FrameImage, FrameTimings), RenderError>;

/// A frame drawn: its index in the run, the drawer that drew it, and the
/// frame or why it could not be drawn.
type Numbered = (usize, usize, Drawn);

/// One renderer per device, each on its own thread (see the module
/// documentation): the side that sends frames. [`DrawnFrames`] is the side
/// that takes them back in order.
pub(super) struct Drawers {
    /// The queue every drawer takes its next frame from, with its index.
    frames: Option<Sender<(usize, RenderFrame)>>,
    frame_queue: Receiver<(usize, RenderFrame)>,
    /// Where the drawers send what they drew, until they are all started.
    drawn_sender: Option<Sender<Numbered>>,
    /// The other ends, until [`Drawers::drawn_frames`] takes them.
    drawn: Option<(Receiver<Numbered>, Sender<()>)>,
    /// One slot per frame that may be in flight: taken to send a frame,
    /// given back when the frame is handed on in order.
    slots: Receiver<()>,
    threads: Vec<JoinHandle<()>>,
    /// Set when the run cannot complete: the drawers take no more frames.
    stopped: Arc<AtomicBool>,
    /// Tells the second device's preparation, if still under way, that it
    /// is no longer wanted: set when the drawers are dropped.
    cancel_preparation: Option<Arc<AtomicBool>>,
    /// Frames sent.
    sent: usize,
}

impl Drawers {
    fn new() -> Self {
        let in_flight = FRAMES_PER_DEVICE * MAX_DEVICES;
        let (frames, frame_queue) = bounded(in_flight);
        let (drawn_sender, drawn) = unbounded();
        let (slot_returns, slots) = bounded(in_flight);
        for _ in 0..in_flight {
            slot_returns.send(()).expect("the slots fit their queue");
        }
        Drawers {
            frames: Some(frames),
            frame_queue,
            drawn_sender: Some(drawn_sender),
            drawn: Some((drawn, slot_returns)),
            slots,
            threads: Vec::new(),
            stopped: Arc::new(AtomicBool::new(false)),
            cancel_preparation: None,
            sent: 0,
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
        let stopped = self.stopped.clone();
        self.threads.push(std::thread::spawn(move || {
            let Some(mut renderer) = make() else { return };
            let gpu = renderer.gpu().clone();
            // Current for the thread's life: making a context current and
            // releasing it flushes and revalidates it, too much per frame.
            let _current = gpu.enter();
            for (index, frame) in frames {
                if stopped.load(Ordering::Relaxed) {
                    break;
                }
                let result = renderer
                    .render_timed(&frame)
                    .map_err(|error| RenderError::Frame {
                        index,
                        error: Box::new(error),
                    });
                let failed = result.is_err();
                if failed {
                    // The frames after it are not drawn.
                    stopped.store(true, Ordering::Relaxed);
                }
                if drawn.send((index, drawer, result)).is_err() || failed {
                    break;
                }
            }
            drop(renderer);
        }));
    }

    /// The frames drawn, in order (once; see [`DrawnFrames`]).
    pub fn drawn_frames(&mut self) -> DrawnFrames {
        let (drawn, slots) = self.drawn.take().expect("taken once");
        DrawnFrames {
            drawn,
            ahead: BTreeMap::new(),
            next: 0,
            slots,
        }
    }

    /// What [`Drawers::stop`] sets, for whoever else stops the run.
    pub fn stop_flag(&self) -> Arc<AtomicBool> {
        self.stopped.clone()
    }

    /// Stops the drawers: they draw no frame they have not started.
    pub fn stop(&self) {
        self.stopped.store(true, Ordering::Relaxed);
    }

    /// Queues the next frame for the first drawer free, waiting while as
    /// many frames are in flight as may be. Fails when the frames drawn are
    /// no longer taken (the run stopped on an error).
    pub fn send(&mut self, frame: RenderFrame) -> Result<(), RenderError> {
        let sent = self.slots.recv().is_ok()
            && self
                .frames
                .as_ref()
                .is_some_and(|frames| frames.send((self.sent, frame)).is_ok());
        if !sent {
            return Err(RenderError::Gpu {
                during: "drawing a frame",
                message: "the frames are no longer drawn".into(),
            });
        }
        self.sent += 1;
        Ok(())
    }

    /// No more frames: the drawers draw those queued and finish.
    pub fn close(&mut self) {
        self.frames = None;
    }
}

impl Drop for Drawers {
    /// Closes the queue and waits for the drawers to draw what it holds
    /// (nothing, once stopped); each drops its renderer with its device's
    /// context current.
    fn drop(&mut self) {
        self.close();
        if let Some(unwanted) = &self.cancel_preparation {
            unwanted.store(true, Ordering::Relaxed);
        }
        for thread in self.threads.drain(..) {
            let _ = thread.join();
        }
    }
}

/// The frames drawn, in frame order, each with the drawer that drew it;
/// the end comes when the drawers have all finished (or stopped) and the
/// next frame was not drawn. Each frame handed on frees a slot for another
/// to be sent ([`Drawers::send`]).
pub(super) struct DrawnFrames {
    drawn: Receiver<Numbered>,
    /// Frames drawn ahead of the one handed on next.
    ahead: BTreeMap<usize, (usize, Drawn)>,
    next: usize,
    slots: Sender<()>,
}

impl Iterator for DrawnFrames {
    type Item = Numbered;

    fn next(&mut self) -> Option<Numbered> {
        loop {
            if let Some((drawer, drawn)) = self.ahead.remove(&self.next) {
                let index = self.next;
                self.next += 1;
                let _ = self.slots.send(());
                return Some((index, drawer, drawn));
            }
            let (index, drawer, drawn) = self.drawn.recv().ok()?;
            self.ahead.insert(index, (drawer, drawn));
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
