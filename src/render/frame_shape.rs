//! [`FrameShape`]: the input checks of a render run, so that mesh, frames
//! and settings that do not fit together are an error, never a panic or a
//! garbled image.
//!
//! The whole run is checked once when a [`Renderer`](super::Renderer) is made
//! ([`FrameShape::of_run`]: image size, dimension, mesh indices, every known
//! frame, the colour range, flat colour and ground height); each later frame
//! is checked against the shape found then ([`FrameShape::check`]).

use super::{Colouring, RenderError, RenderFrame, RenderMesh, RenderSettings};

/// What every frame of a run must hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct FrameShape {
    /// Vertex positions per frame (those of frame 0).
    vertex_count: usize,
    /// Element values per frame, when the colouring reads them.
    element_values: Option<usize>,
}

impl FrameShape {
    /// Checks that mesh, frames and settings fit together and returns the
    /// shape every frame must have.
    pub fn of_run(
        settings: &RenderSettings,
        mesh: &RenderMesh,
        frames: &[RenderFrame],
    ) -> Result<Self, RenderError> {
        let invalid = |message: String| Err(RenderError::InvalidInput(message));
        if settings.width == 0 || settings.height == 0 {
            return invalid(format!(
                "image size {}x{} has a zero side",
                settings.width, settings.height
            ));
        }
        if mesh.dimension != 2 && mesh.dimension != 3 {
            return invalid(format!(
                "meshes are 2D or 3D, this one says {}D",
                mesh.dimension
            ));
        }
        let Some(first) = frames.first() else {
            return invalid("there are no frames".into());
        };
        let vertex_count = first.positions.len();
        if mesh.triangle_element.len() != mesh.triangles.len() {
            return invalid(format!(
                "the mesh has {} triangles but {} triangle elements",
                mesh.triangles.len(),
                mesh.triangle_element.len()
            ));
        }
        if let Some(t) = mesh
            .triangles
            .iter()
            .chain(&mesh.obstacle_triangles)
            .flatten()
            .chain(mesh.edges.iter().chain(&mesh.obstacle_edges).flatten())
            .find(|&&v| v as usize >= vertex_count)
        {
            return invalid(format!(
                "the mesh refers to vertex {t}, but frames have {vertex_count} vertices"
            ));
        }
        if let Some(e) = mesh
            .triangle_element
            .iter()
            .find(|&&e| e as usize >= mesh.element_count)
        {
            return invalid(format!(
                "a triangle refers to element {e}, but the mesh has {} elements",
                mesh.element_count
            ));
        }
        let scalar = matches!(settings.colouring, Colouring::Scalar { .. });
        for (i, frame) in frames.iter().enumerate() {
            if frame.positions.len() != vertex_count {
                return invalid(format!(
                    "frame {i} has {} vertex positions, frame 0 has {vertex_count}",
                    frame.positions.len()
                ));
            }
            if scalar && frame.element_values.len() != mesh.element_count {
                return invalid(format!(
                    "frame {i} has {} element values, the mesh has {} elements",
                    frame.element_values.len(),
                    mesh.element_count
                ));
            }
        }
        if let Colouring::Scalar {
            range: Some([lo, hi]),
            ..
        } = settings.colouring
            && !(lo < hi && lo.is_finite() && hi.is_finite())
        {
            return invalid(format!(
                "colour range [{lo}, {hi}] must be finite and increasing"
            ));
        }
        if let Colouring::Flat(c) = settings.colouring
            && !c.iter().all(|v| v.is_finite())
        {
            return invalid(format!("flat colour {c:?} is not finite"));
        }
        if let Some(ground) = settings.ground_height
            && !ground.is_finite()
        {
            return invalid(format!("ground height {ground} is not finite"));
        }
        Ok(Self {
            vertex_count,
            element_values: scalar.then_some(mesh.element_count),
        })
    }

    /// Checks one frame against the run's shape.
    pub fn check(&self, frame: &RenderFrame) -> Result<(), RenderError> {
        if frame.positions.len() != self.vertex_count {
            return Err(RenderError::InvalidInput(format!(
                "a frame has {} vertex positions, the run has {}",
                frame.positions.len(),
                self.vertex_count
            )));
        }
        if let Some(element_count) = self.element_values
            && frame.element_values.len() != element_count
        {
            return Err(RenderError::InvalidInput(format!(
                "a frame has {} element values, the mesh has {element_count} elements",
                frame.element_values.len(),
            )));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangle() -> RenderMesh {
        RenderMesh {
            dimension: 2,
            triangles: vec![[0, 1, 2]],
            triangle_element: vec![0],
            edges: vec![[0, 1], [1, 2], [2, 0]],
            element_count: 1,
            obstacle_triangles: Vec::new(),
            obstacle_edges: Vec::new(),
        }
    }

    fn frame(vertices: usize, values: usize) -> RenderFrame {
        RenderFrame {
            positions: vec![[0.0; 3]; vertices],
            element_values: vec![0.5; values],
        }
    }

    #[test]
    fn later_frames_must_match_the_first() {
        let settings = RenderSettings::default();
        let shape = FrameShape::of_run(&settings, &triangle(), &[frame(3, 1)]).unwrap();
        assert!(shape.check(&frame(3, 1)).is_ok());
        let error = shape.check(&frame(4, 1)).unwrap_err().to_string();
        assert!(
            error.contains("a frame has 4 vertex positions, the run has 3"),
            "{error}"
        );
        let error = shape.check(&frame(3, 2)).unwrap_err().to_string();
        assert!(
            error.contains("a frame has 2 element values, the mesh has 1 elements"),
            "{error}"
        );
    }

    #[test]
    fn flat_colour_ignores_element_values() {
        let settings = RenderSettings {
            colouring: Colouring::Flat([0.5; 3]),
            ..RenderSettings::default()
        };
        let shape = FrameShape::of_run(&settings, &triangle(), &[frame(3, 0)]).unwrap();
        assert!(shape.check(&frame(3, 7)).is_ok());
        assert!(shape.check(&frame(2, 0)).is_err());
    }

    #[test]
    fn out_of_range_indices_are_rejected() {
        let settings = RenderSettings::default();
        let mut mesh = triangle();
        mesh.edges.push([0, 3]);
        let error = FrameShape::of_run(&settings, &mesh, &[frame(3, 1)])
            .unwrap_err()
            .to_string();
        assert!(error.contains("refers to vertex 3"), "{error}");
        // Obstacles index the same positions.
        let mut mesh = triangle();
        mesh.obstacle_triangles.push([0, 1, 5]);
        let error = FrameShape::of_run(&settings, &mesh, &[frame(3, 1)])
            .unwrap_err()
            .to_string();
        assert!(error.contains("refers to vertex 5"), "{error}");
        let mut mesh = triangle();
        mesh.obstacle_edges.push([4, 1]);
        assert!(FrameShape::of_run(&settings, &mesh, &[frame(3, 1)]).is_err());
    }
}
