//! Conversions from the simulation's meshes and scene settings to the renderer's types.
//!
//! TEMPORARY: `RenderMesh::from_mesh`, `RenderFrame::from_positions` and
//! `render::check_video_support` are being added by the renderer work; until
//! they are on main this module holds equivalent private versions.

use crate::math::Vector;
use crate::mesh::Mesh;
use crate::render::{Colouring, RenderFrame, RenderMesh, RenderSettings, VideoFormat};
use crate::scene::{FieldChoice, RenderConfig};
use std::collections::{BTreeSet, HashMap};

/// The triangles, their elements and the edges to draw.
pub fn render_mesh<const D: usize>(mesh: &Mesh<D>) -> RenderMesh {
    let (triangles, triangle_element): (Vec<[u32; 3]>, Vec<u32>) = if D == 2 {
        mesh.simplices()
            .enumerate()
            .map(|(e, s)| ([s[0] as u32, s[1] as u32, s[2] as u32], e as u32))
            .unzip()
    } else {
        let mut owner: HashMap<[usize; 3], u32> = HashMap::new();
        for (e, s) in mesh.simplices().enumerate() {
            for skip in 0..s.len() {
                let mut f: Vec<usize> = s
                    .iter()
                    .enumerate()
                    .filter(|&(i, _)| i != skip)
                    .map(|(_, &v)| v)
                    .collect();
                f.sort_unstable();
                owner.insert([f[0], f[1], f[2]], e as u32);
            }
        }
        mesh.boundary_facets()
            .iter()
            .map(|f| {
                let mut key = [f[0], f[1], f[2]];
                key.sort_unstable();
                ([f[0] as u32, f[1] as u32, f[2] as u32], owner[&key])
            })
            .unzip()
    };
    let mut edges = BTreeSet::new();
    for t in &triangles {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            edges.insert([a.min(b), a.max(b)]);
        }
    }
    RenderMesh {
        dimension: D,
        triangles,
        triangle_element,
        edges: edges.into_iter().collect(),
        element_count: mesh.element_count(),
    }
}

/// One frame for the renderer.
pub fn render_frame<const D: usize>(positions: &[Vector<D>], values: &[f64]) -> RenderFrame {
    RenderFrame {
        positions: positions
            .iter()
            .map(|p| std::array::from_fn(|c| if c < D { p[c] as f32 } else { 0.0 }))
            .collect(),
        element_values: values.iter().map(|&v| v as f32).collect(),
    }
}

/// The renderer's settings for a scene.
pub fn render_settings(config: &RenderConfig, ground_height: Option<f64>) -> RenderSettings {
    let colouring = match config.field {
        FieldChoice::Flat => Colouring::Flat(config.colour.map(|c| c as f32)),
        field => Colouring::Scalar {
            range: config.range.map(|r| r.map(|x| x as f32)),
            label: field.label(),
        },
    };
    RenderSettings {
        width: config.resolution[0],
        height: config.resolution[1],
        camera: config.camera,
        colouring,
        background: config.background.map(|c| c as f32),
        ground_height: ground_height.map(|h| h as f32),
        draw_edges: config.edges,
        draw_legend: config.legend,
    }
}

/// Whether ffmpeg with the libx264 encoder is on PATH.
pub fn mp4_available() -> bool {
    std::process::Command::new("ffmpeg")
        .args(["-hide_banner", "-encoders"])
        .stdin(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .output()
        .is_ok_and(|o| o.status.success() && String::from_utf8_lossy(&o.stdout).contains("libx264"))
}

/// The file name a video format is written to.
pub fn video_file_name(format: VideoFormat) -> &'static str {
    match format {
        VideoFormat::Apng => "video.png",
        VideoFormat::Mp4 => "video.mp4",
        VideoFormat::Gif => "video.gif",
    }
}
