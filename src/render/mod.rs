//! Off-screen wgpu rendering of mesh frames to images.
//!
//! The renderer draws what it is given: vertex positions and one scalar per
//! element, never materials or physics. A run goes [`RenderMesh`] +
//! [`RenderFrame`]s → [`Renderer`] → one whole [`RgbaImage`](image::RgbaImage)
//! per frame, which the encoders (`crate::encode`) write as PNG frames and
//! videos.
//!
//! The GPU is whatever wgpu finds, one device per process: a hardware
//! adapter when present, otherwise a software one (on a GPU-less Linux
//! machine, the GL backend over Mesa llvmpipe through EGL). `WGPU_BACKEND`
//! (e.g. `gl`, `vulkan`) restricts the backends tried.
//!
//! One path draws 2D and 3D (`renderer`): the run's look is fixed when it
//! starts (`look`: camera, colours, ground, shadow, edges, legend), the
//! backdrop — the image without the bodies — is drawn once, and each frame
//! draws only the tile around what changes (`frame_target`), in one pass of
//! the layers of its dimension (`pipelines`): 4x MSAA with depth in 3D, one
//! sample per pixel in 2D with the bodies anti-aliased in their shaders
//! (`body_coverage`). Tiles are read back through a ring of staging
//! buffers, so a frame is read while the next is drawn, and pasted into the
//! backdrop with the legend.
//!
//! Colours: element scalars go through [`viridis`] over one range for the
//! whole run (automatic: min/max over all frames), so colours never flicker;
//! the automatic camera frames the bounds of all frames, so it never jumps.
//! Either needs the whole run before the first frame is drawn
//! ([`RenderSettings::needs_whole_run`]); with a fixed camera and a fixed
//! range (or flat colour) frames are rendered and written as they are
//! simulated. Obstacles are drawn in one neutral colour, in the camera's
//! view with the bodies.

mod body_coverage;
mod camera;
mod colormap;
mod frame_shape;
mod frame_target;
mod gpu;
mod legend;
mod look;
mod mesh_view;
mod pipelines;
mod pixel_rect;
mod preparing;
mod renderer;
mod text;

pub use colormap::{linear_to_srgb, linear_to_srgb8, srgb_to_linear, viridis};
pub use frame_target::FRAMES_IN_FLIGHT;
pub use gpu::{BACKEND_VARIABLE, adapter_description, backend_variable_problem, max_image_size};
pub use look::{OBSTACLE_FILL_OPACITY, OBSTACLE_SRGB};
#[cfg(test)]
pub(crate) use pixel_rect::noise;
pub use preparing::PreparingRenderer;
pub use renderer::{FrameTimings, PreparedRenderer, Renderer};
pub use text::{FONT_BYTES, draw_text, text_width};

use std::path::PathBuf;

/// The geometry the renderer draws, independent of physics.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderMesh {
    /// 2 or 3.
    pub dimension: usize,
    /// Triangles to fill: every triangle of a 2D mesh, or the outward-oriented
    /// boundary triangles of a 3D tetrahedral mesh (counter-clockwise seen from outside).
    pub triangles: Vec<[u32; 3]>,
    /// For each triangle, the element whose scalar colours it.
    pub triangle_element: Vec<u32>,
    /// Edges to draw as thin lines (2D: all mesh edges; 3D: boundary edges).
    pub edges: Vec<[u32; 2]>,
    /// Number of elements (length of every frame's `element_values`).
    pub element_count: usize,
    /// Obstacles' surfaces (issue 32): indices into the same positions array, whose obstacle
    /// vertices come after the bodies'. 2D: triangles filled semi-transparent, edges outlined;
    /// 3D: triangles shaded in a flat colour (two-sided: obstacles may be open surfaces), edges
    /// drawn like the bodies'.
    pub obstacle_triangles: Vec<[u32; 3]>,
    /// The obstacles' edges (see `obstacle_triangles`).
    pub obstacle_edges: Vec<[u32; 2]>,
}

/// One frame of motion to draw.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderFrame {
    /// Vertex positions; in 2D the z component is 0.
    pub positions: Vec<[f32; 3]>,
    /// One scalar per element (colour mapped); ignored with flat colouring.
    pub element_values: Vec<f32>,
}

/// Where the camera looks from. In 2D an orthographic view of the xy plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Camera {
    /// Frame automatically from the bounds of the whole motion (default).
    Auto,
    /// 2D: centre of the view and visible height, in scene units.
    Orthographic {
        /// Centre of the view.
        center: [f32; 2],
        /// Visible height.
        height: f32,
    },
    /// 3D: a perspective camera.
    Perspective {
        /// Eye position.
        eye: [f32; 3],
        /// Point looked at.
        target: [f32; 3],
        /// Vertical field of view, in degrees.
        fov_degrees: f32,
    },
}

/// How triangles are coloured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Colouring {
    /// Element scalar through viridis, over a fixed range for the whole run
    /// (`None`: the min/max over all frames).
    Scalar {
        /// Fixed range, or `None` for automatic.
        range: Option<[f32; 2]>,
        /// Legend title, e.g. "strain energy density".
        label: &'static str,
    },
    /// One flat colour (linear RGB).
    Flat([f32; 3]),
}

/// Settings of a render run. A scene's `[render]` table is validated into
/// this type directly (`crate::scene`), so the scene and the renderer share
/// one definition; its defaults are the scene file's.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderSettings {
    /// Image width in pixels (default: 1280).
    pub width: u32,
    /// Image height in pixels (default: 720).
    pub height: u32,
    /// Camera (default: [`Camera::Auto`]).
    pub camera: Camera,
    /// Colouring (default: scalar, automatic range, label "value").
    pub colouring: Colouring,
    /// Background colour, linear RGB (default: `[0.95; 3]`, a light grey, as in scene files).
    /// 3D scenes shade it into a soft vertical gradient.
    pub background: [f32; 3],
    /// Ground height along y, in length units, drawn when present (default: none).
    pub ground_height: Option<f32>,
    /// Draw mesh edges (default: true).
    pub draw_edges: bool,
    /// Draw the colour-bar legend with scalar colouring (default: true).
    pub draw_legend: bool,
}

impl RenderSettings {
    /// Whether drawing the first frame needs every frame of the run: the
    /// automatic camera frames the bounds of all of them, the automatic
    /// colour range spans all of their values. With a fixed camera and a
    /// fixed range (or a flat colour) frames can be drawn as they come.
    pub fn needs_whole_run(&self) -> bool {
        let auto_range = matches!(self.colouring, Colouring::Scalar { range: None, .. });
        self.camera == Camera::Auto || auto_range
    }
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 1280,
            height: 720,
            camera: Camera::Auto,
            colouring: Colouring::Scalar {
                range: None,
                label: "value",
            },
            // A light, paper-like grey: the scene files' default.
            background: [0.95; 3],
            ground_height: None,
            draw_edges: true,
            draw_legend: true,
        }
    }
}

/// Errors of the renderer.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// No graphics adapter could be found.
    #[error(
        "no graphics adapter found (backends tried: {backends}); install a GPU driver or Mesa \
         (llvmpipe, EGL) for software rendering, or set WGPU_BACKEND to another backend"
    )]
    NoAdapter {
        /// The backends that were tried.
        backends: String,
    },
    /// The adapter refused to create a device.
    #[error("cannot open the graphics device on {adapter}: {message}")]
    Device {
        /// The adapter description.
        adapter: String,
        /// What wgpu reported.
        message: String,
    },
    /// The GPU reported an error while rendering.
    #[error("the GPU failed while {during}: {message}")]
    Gpu {
        /// What the renderer was doing.
        during: &'static str,
        /// What wgpu reported.
        message: String,
    },
    /// Mesh, frames or settings do not fit together.
    #[error("cannot render: {0}")]
    InvalidInput(String),
    /// Drawing one frame failed.
    #[error("frame {index}: {error}")]
    Frame {
        /// The frame's number in the run, from 0.
        index: usize,
        /// Why.
        error: Box<RenderError>,
    },
    /// The requested image is larger than the adapter allows.
    #[error("image size {width}x{height} exceeds the adapter's limit of {max} pixels per side")]
    ImageTooLarge {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
        /// The adapter's maximum texture side.
        max: u32,
    },
    /// A file or folder could not be written.
    #[error("cannot write {}: {source}", path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// An image or video encoder failed.
    #[error("cannot encode {}: {message}", path.display())]
    Encode {
        /// The file being written.
        path: PathBuf,
        /// What the encoder reported.
        message: String,
    },
    /// The run is being interrupted (SIGINT or SIGTERM): no new file is started.
    #[error("interrupted")]
    Interrupted,
}
