//! Off-screen wgpu rendering of mesh frames to images and video.
//!
//! STUB: the public API below is the contract between the application layer
//! and the renderer; the rendering work replaces the bodies.

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

/// Settings of a render run.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderSettings {
    /// Image width in pixels (default: 1280).
    pub width: u32,
    /// Image height in pixels (default: 720).
    pub height: u32,
    /// Camera (default: Auto).
    pub camera: Camera,
    /// Colouring (default: scalar, automatic range).
    pub colouring: Colouring,
    /// Background colour, linear RGB.
    pub background: [f32; 3],
    /// Ground height along y, drawn when present.
    pub ground_height: Option<f32>,
    /// Draw mesh edges.
    pub draw_edges: bool,
    /// Draw the colour-bar legend.
    pub draw_legend: bool,
}

/// Video container to write besides the PNG frames.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VideoFormat {
    /// Animated PNG (`video.png`), always available.
    Apng,
    /// H.264 MP4 through ffmpeg (`video.mp4`).
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
    /// Not implemented yet.
    #[error("rendering is not implemented yet")]
    NotImplemented,
}

/// Renders every frame, writes PNG frames and the video. Calls `progress(i)`
/// after frame `i` is written.
pub fn render_sequence(
    _settings: &RenderSettings,
    _mesh: &RenderMesh,
    _frames: &[RenderFrame],
    _outputs: &RenderOutputs,
    _progress: &mut dyn FnMut(usize),
) -> Result<(), RenderError> {
    Err(RenderError::NotImplemented)
}
