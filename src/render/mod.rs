//! Off-screen wgpu rendering of mesh frames to images and video.
//!
//! The renderer draws what it is given: vertex positions and one scalar per
//! element, never materials or physics. A run goes
//! [`RenderMesh`] + [`RenderFrame`]s → [`Renderer`] (one whole
//! [`RgbaImage`](image::RgbaImage) per frame) → [`SequenceWriter`] (numbered
//! PNG frames from a pool of workers, APNG / MP4 / GIF video, one thread
//! each).
//!
//! The GPU is whatever wgpu finds, one device per process: a hardware
//! adapter when present, otherwise a software one (on a GPU-less Linux
//! machine, the GL backend over Mesa llvmpipe through EGL). `WGPU_BACKEND`
//! (e.g. `gl`, `vulkan`) restricts the backends tried. Images are rendered
//! into an sRGB target, with 4x MSAA in 3D and for the 2D backdrop. A frame
//! draws only the tile around what changes over the run's fixed backdrop: in
//! 2D the body (`body_tile`), with one sample per pixel and the
//! anti-aliasing computed in its shaders (`body_coverage`); in 3D the body
//! and its contact shadow, multisampled (`scene_tile`). So a software
//! rasteriser does not clear, shade and resolve four samples of the whole
//! image for every frame. The tile is pasted into the run's base image (the
//! backdrop with the legend), and the encoders see whole images.
//!
//! Colours: element scalars go through [`viridis`] over one range for the
//! whole run (automatic: min/max over all frames), so colours never flicker;
//! the automatic camera frames the bounds of all frames, so it never jumps.
//! Either needs the whole run before the first frame is drawn
//! ([`RenderSettings::needs_whole_run`]); with a fixed camera and a fixed
//! range (or flat colour) frames are rendered and written as they are
//! simulated.

mod body_coverage;
mod body_tile;
mod camera;
mod colormap;
mod export;
mod frame_shape;
mod frame_yuv;
mod gpu;
mod gpu_resources;
mod image_file;
mod image_video;
mod layers;
mod legend;
mod legend_stamp;
mod look;
mod mesh_view;
mod mp4_writer;
mod partial_file;
mod pixel_rect;
mod preparing;
mod readback;
mod render_targets;
mod renderer;
mod scene_tile;
mod sequence;
mod text;
mod tile_slot;
mod video;
mod video_writer;

pub use colormap::{linear_to_srgb, srgb_to_linear, viridis};
pub use export::{check_video_support, frame_file_name, write_png};
pub use gpu::{BACKEND_VARIABLE, adapter_description, backend_variable_problem, max_image_size};
pub use image_video::write_image_video;
pub use partial_file::{remove_partial_files, write_whole_file};
pub use preparing::PreparingRenderer;
pub use renderer::{FrameTimings, PreparedRenderer, Renderer};
pub use sequence::{FrameCost, SequenceWriter, render_sequence};
pub use text::{FONT_BYTES, draw_text, text_width};
pub use video::file_name as video_file_name;

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

/// Video container to write besides the PNG frames.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VideoFormat {
    /// Animated PNG (`video.png`), always available.
    Apng,
    /// H.264 MP4 (`video.mp4`), encoded in the process (OpenH264).
    Mp4,
    /// Animated GIF (`video.gif`).
    Gif,
}

/// Where a render run writes.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderOutputs {
    /// Folder for frame_0000.png, ...
    pub frames_dir: PathBuf,
    /// Folder for the video files (`video.png`, `video.mp4`, `video.gif`).
    pub video_dir: PathBuf,
    /// Videos to write (empty: none).
    pub videos: Vec<VideoFormat>,
    /// Frames per second of the video.
    pub fps: f64,
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
