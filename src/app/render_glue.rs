//! From the scene's render settings to the renderer's.

use crate::render::{Colouring, RenderSettings};
use crate::scene::{FieldChoice, RenderConfig};

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
