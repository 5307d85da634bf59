//! [`PreparingRenderer`]: a renderer prepared on a thread of its own while
//! the run simulates, and warmed up with the run's first frame when one comes.

use super::{PreparedRenderer, RenderError, RenderFrame, RenderMesh, RenderSettings, Renderer};
use std::sync::mpsc;
use std::thread::JoinHandle;

/// A renderer being prepared on its own thread ([`Renderer::prepare`], then
/// [`PreparedRenderer::warmed_up`]). The thread is joined when this is
/// dropped, so that no thread is left inside the graphics driver when the
/// process exits.
pub struct PreparingRenderer {
    prepared: mpsc::Receiver<Result<PreparedRenderer, RenderError>>,
    thread: Option<JoinHandle<()>>,
}

impl PreparingRenderer {
    /// Starts preparing. A frame from `warm_up`, if one comes, warms the
    /// renderer up; when `warm_up` closes without one the renderer is
    /// handed out as it is.
    pub fn start(
        settings: &RenderSettings,
        mesh: &RenderMesh,
        warm_up: Option<mpsc::Receiver<RenderFrame>>,
    ) -> Self {
        let (sender, prepared) = mpsc::channel();
        let (settings, mesh) = (settings.clone(), mesh.clone());
        let thread = std::thread::spawn(move || {
            let prepared = Renderer::prepare(&settings, &mesh).and_then(|prepared| {
                match warm_up.and_then(|frames| frames.recv().ok()) {
                    Some(frame) => prepared.warmed_up(&frame),
                    None => Ok(prepared),
                }
            });
            let _ = sender.send(prepared);
        });
        PreparingRenderer {
            prepared,
            thread: Some(thread),
        }
    }

    /// The renderer, once it is ready.
    pub fn wait(mut self) -> Result<PreparedRenderer, RenderError> {
        match self.prepared.recv() {
            Ok(prepared) => prepared,
            Err(_) => {
                // The thread panicked before it handed the renderer out.
                if let Some(Err(panic)) = self.thread.take().map(JoinHandle::join) {
                    std::panic::resume_unwind(panic);
                }
                Err(RenderError::Gpu {
                    during: "preparing the renderer",
                    message: "the preparing thread stopped".into(),
                })
            }
        }
    }
}

impl Drop for PreparingRenderer {
    fn drop(&mut self) {
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}
