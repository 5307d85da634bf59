//! How the frames of a run reach the renderer.
//!
//! With a fixed camera and a fixed colour range (or a flat colour) each frame
//! is rendered and handed to the PNG and video encoders as soon as it is
//! simulated, so encoding overlaps with the simulation and nothing piles up.
//! The automatic camera and colour range need the whole motion first
//! ([`RenderSettings::needs_whole_run`]); then frames are kept (positions and
//! one value per element, no images) and rendered after the simulation.
//! Keeping the frames is the cheap first pass: the simulation runs once, and
//! its frames are drawn after it exactly as they would have been while it
//! ran (`tests/integration/render_streaming.rs` checks both give the same files).
//!
//! The renderer's device, pipelines and buffers need no frame: they are
//! made on a thread of their own from the moment the stage is made
//! ([`PreparingRenderer`]). For a deferred run the run's first frame (the
//! initial state, there before the first step) is then drawn with it and
//! thrown away ([`crate::render::PreparedRenderer::warmed_up`]), so that
//! while the simulation runs, a core it does not use builds them and
//! llvmpipe compiles their shaders (about 0.2 s for the default scene), and
//! the first image follows the last step without that wait.
//!
//! The stage hands out, in frame order, the cost of every frame written
//! ([`FrameCost`]) once the run is complete, for `--profile`. `stats.csv`
//! does not wait for it: its rows are written as the frames are simulated.

use super::process_clock::{Span, Stopwatch};
use super::progress::{Progress, ProgressMode};
use crate::encode::{FrameCost, RenderOutputs, SequenceWriter};
use crate::render::{
    PreparedRenderer, PreparingRenderer, RenderError, RenderFrame, RenderMesh, RenderSettings,
    Renderer,
};
use std::sync::mpsc::{self, Sender};

/// The renderer's side of a run.
pub struct RenderStage {
    settings: RenderSettings,
    mesh: RenderMesh,
    outputs: RenderOutputs,
    frame_count: usize,
    /// Where a deferred run's first frame goes to warm the renderer up,
    /// until it is sent. Declared before `preparing`, so that it is
    /// dropped first: the preparing thread, which dropping `preparing`
    /// waits for, may be waiting for that frame.
    warm_up_frame: Option<Sender<RenderFrame>>,
    /// The renderer being prepared, until the first frame is drawn.
    preparing: Option<PreparingRenderer>,
    pending: Pending,
}

enum Pending {
    /// Frames are written as they come; the writer starts with frame 0.
    Streaming(Option<Box<SequenceWriter>>),
    /// Frames are kept until the run is complete.
    Deferred(Vec<RenderFrame>),
}

impl RenderStage {
    /// Prepares to render a run of `frame_count` frames.
    pub fn new(
        settings: RenderSettings,
        mesh: RenderMesh,
        outputs: RenderOutputs,
        frame_count: usize,
    ) -> Self {
        let pending = if settings.needs_whole_run() {
            // Grown as frames come, never reserved by the frame count: the
            // run checked beforehand that all of them fit in memory.
            Pending::Deferred(Vec::new())
        } else {
            Pending::Streaming(None)
        };
        // A streamed run draws its first frame at once: drawing it once
        // more beforehand would only add to it.
        let (warm_up_frame, first_frame) = match pending {
            Pending::Deferred(_) => {
                let (sender, receiver) = mpsc::channel();
                (Some(sender), Some(receiver))
            }
            Pending::Streaming(_) => (None, None),
        };
        // Without a first frame (the run ended before it) the renderer
        // is not needed warm.
        let preparing = PreparingRenderer::start(&settings, &mesh, first_frame);
        Self {
            settings,
            mesh,
            outputs,
            frame_count,
            preparing: Some(preparing),
            warm_up_frame,
            pending,
        }
    }

    /// The renderer prepared on its thread (waiting for it if need be).
    fn prepared(
        preparing: &mut Option<PreparingRenderer>,
        settings: &RenderSettings,
        mesh: &RenderMesh,
    ) -> Result<PreparedRenderer, RenderError> {
        match preparing.take() {
            Some(preparing) => preparing.wait(),
            None => Renderer::prepare(settings, mesh),
        }
    }

    /// Whether frames are rendered while the run is simulated.
    pub fn is_streaming(&self) -> bool {
        matches!(self.pending, Pending::Streaming(_))
    }

    /// Takes the next frame of the run.
    pub fn add(&mut self, frame: RenderFrame) -> Result<(), RenderError> {
        match &mut self.pending {
            Pending::Deferred(frames) => {
                if let Some(warm_up) = self.warm_up_frame.take() {
                    // The thread may be gone (it failed): the run hears of
                    // it when it asks for the renderer.
                    let _ = warm_up.send(frame.clone());
                }
                frames.push(frame);
            }
            Pending::Streaming(writer) => {
                let writer = match writer {
                    Some(writer) => writer,
                    None => {
                        let prepared =
                            Self::prepared(&mut self.preparing, &self.settings, &self.mesh)?;
                        writer.insert(Box::new(SequenceWriter::create_prepared(
                            prepared,
                            self.frame_count,
                            std::slice::from_ref(&frame),
                            &self.outputs,
                        )?))
                    }
                };
                writer.push(&frame)?;
            }
        }
        Ok(())
    }

    /// Completes the frames and videos: waits for the encoders of a streamed
    /// run, or renders a deferred one with its own progress. Returns the
    /// cost of every frame, in frame order, and for a deferred run the
    /// stretch from its first frame sent to be drawn to its last written.
    pub fn finish(
        mut self,
        progress_mode: ProgressMode,
    ) -> Result<(Vec<FrameCost>, Option<Span>), RenderError> {
        // A run without frames never sent one: the warm-up must not wait.
        drop(self.warm_up_frame.take());
        match self.pending {
            Pending::Streaming(Some(writer)) => Ok((writer.finish_with_costs()?, None)),
            Pending::Streaming(None) => Err(RenderError::InvalidInput(
                "the run ended before its first frame".into(),
            )),
            Pending::Deferred(frames) => {
                let mut progress = Progress::start(progress_mode, "render", frames.len());
                let prepared = Self::prepared(&mut self.preparing, &self.settings, &self.mesh)?;
                let mut writer = SequenceWriter::create_prepared(
                    prepared,
                    frames.len(),
                    &frames,
                    &self.outputs,
                )?;
                let frames_watch = Stopwatch::start();
                let mut reported = 0;
                let mut report = |written: usize| {
                    if written > reported {
                        reported = written;
                        progress.update(written, || format!("frame_{:04}.png", written - 1));
                    }
                };
                for frame in &frames {
                    writer.push(frame)?;
                    report(writer.frames_written());
                }
                let costs = writer.finish_with_costs()?;
                let frames_span = frames_watch.span();
                report(frames.len());
                progress.finish();
                Ok((costs, Some(frames_span)))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    /// A run that ends before its first frame (the simulation failed, or
    /// the adapter check said no) drops its stage: the preparing thread,
    /// which the drop waits for, must not wait for a frame that never
    /// comes. With or without an adapter.
    #[test]
    fn a_stage_dropped_before_its_first_frame_does_not_wait_for_it() {
        let dir = tempfile::tempdir().unwrap();
        let outputs = RenderOutputs {
            frames_dir: dir.path().join("frames"),
            video_dir: dir.path().to_owned(),
            videos: Vec::new(),
            fps: 10.0,
        };
        let mesh = RenderMesh {
            dimension: 2,
            triangles: vec![[0, 1, 2]],
            triangle_element: vec![0],
            edges: vec![[0, 1], [1, 2], [0, 2]],
            element_count: 1,
            obstacle_triangles: Vec::new(),
            obstacle_edges: Vec::new(),
        };
        let (dropped, done) = mpsc::channel();
        std::thread::spawn(move || {
            let stage = RenderStage::new(RenderSettings::default(), mesh, outputs, 3);
            assert!(
                !stage.is_streaming(),
                "the automatic camera waits for the run"
            );
            drop(stage);
            let _ = dropped.send(());
        });
        done.recv_timeout(Duration::from_secs(120))
            .expect("dropping the stage returned");
        assert!(!dir.path().join("frames").exists(), "nothing written");
    }
}
