//! Surface meshes: points and facets (segments in 2D, triangles in 3D), the shape of an obstacle.
//!
//! A surface has no volume and no elements: it is what a body can touch. It
//! may be closed (the boundary of a solid: every segment end shared by two
//! segments in 2D, every triangle edge by two triangles in 3D) or open (a
//! ramp, a bowl, a plate). Facets are checked on construction: every index
//! in range, no repeated corner, no zero-length segment or zero-area
//! triangle.

use super::Mesh;
use crate::math::Vector;
use std::collections::HashMap;

/// Errors raised while building a surface.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SurfaceError {
    /// The surface has no facets.
    #[error("the surface has no {}", if *.0 == 2 { "segments" } else { "triangles" })]
    Empty(usize),
    /// A facet names a point that does not exist.
    #[error("facet {facet} refers to point {point}, but the surface has only {point_count} points")]
    PointOutOfRange {
        /// Facet index.
        facet: usize,
        /// The bad point index.
        point: usize,
        /// Number of points.
        point_count: usize,
    },
    /// A facet has zero length or area (or repeats a corner).
    #[error("facet {facet} with points {points:?} is degenerate (its {measure} is {size:.3e})")]
    Degenerate {
        /// Facet index.
        facet: usize,
        /// Its point indices.
        points: Vec<usize>,
        /// "length" or "area".
        measure: &'static str,
        /// Its length or area.
        size: f64,
    },
}

/// Points and facets: `D` points per facet.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceMesh<const D: usize> {
    points: Vec<Vector<D>>,
    facets: Vec<[usize; D]>,
}

impl<const D: usize> SurfaceMesh<D> {
    /// A surface of `points` and `facets`, checked (see the module
    /// documentation). Points no facet uses are kept (a volume mesh's
    /// interior points, for drawing it filled); they touch nothing.
    pub fn new(points: Vec<Vector<D>>, facets: Vec<[usize; D]>) -> Result<Self, SurfaceError> {
        if facets.is_empty() {
            return Err(SurfaceError::Empty(D));
        }
        for (facet, corners) in facets.iter().enumerate() {
            if let Some(&point) = corners.iter().find(|&&p| p >= points.len()) {
                return Err(SurfaceError::PointOutOfRange {
                    facet,
                    point,
                    point_count: points.len(),
                });
            }
            let (measure, size) = measure(&points, corners);
            // Relative to the facet's longest edge, as the elements' check.
            let longest = (0..D)
                .flat_map(|a| (a + 1..D).map(move |b| (a, b)))
                .map(|(a, b)| (points[corners[a]] - points[corners[b]]).norm())
                .fold(0.0, f64::max);
            if !(size > 1e-12 * longest.powi(D as i32 - 1)) || !size.is_finite() {
                return Err(SurfaceError::Degenerate {
                    facet,
                    points: corners.to_vec(),
                    measure,
                    size,
                });
            }
        }
        Ok(Self { points, facets })
    }

    /// The boundary of a volume mesh (outward oriented), as a surface on
    /// all of the mesh's points.
    pub fn boundary_of(mesh: &Mesh<D>) -> Self {
        Self::new(mesh.rest_positions().to_vec(), mesh.boundary_facets())
            .expect("a mesh's boundary facets are a valid surface")
    }

    /// The points.
    pub fn points(&self) -> &[Vector<D>] {
        &self.points
    }

    /// The facets: segments in 2D, triangles in 3D.
    pub fn facets(&self) -> &[[usize; D]] {
        &self.facets
    }

    /// The same facets on `points` moved by `place` (a rigid motion or a
    /// scene's placement).
    pub fn mapped(&self, place: impl Fn(&Vector<D>) -> Vector<D>) -> Self {
        Self {
            points: self.points.iter().map(place).collect(),
            facets: self.facets.clone(),
        }
    }

    /// Whether the surface is closed: every facet side (a segment's end, a
    /// triangle's edge) is shared by exactly two facets.
    pub fn is_closed(&self) -> bool {
        let mut sides: HashMap<Vec<usize>, usize> = HashMap::new();
        for facet in &self.facets {
            for skip in 0..D {
                let mut side: Vec<usize> =
                    (0..D).filter(|&k| k != skip).map(|k| facet[k]).collect();
                side.sort_unstable();
                *sides.entry(side).or_insert(0) += 1;
            }
        }
        sides.values().all(|&count| count == 2)
    }
}

/// A facet's length (2D) or area (3D).
fn measure<const D: usize>(points: &[Vector<D>], corners: &[usize; D]) -> (&'static str, f64) {
    let p = |k: usize| points[corners[k]];
    if D == 2 {
        ("length", (p(1) - p(0)).norm())
    } else {
        let (u, w) = (p(1) - p(0), p(2) - p(0));
        let uu = u.dot(&u);
        let ww = w.dot(&w);
        let uw = u.dot(&w);
        ("area", 0.5 * (uu * ww - uw * uw).max(0.0).sqrt())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_box_boundary_is_closed_and_a_ramp_is_open() {
        let cube =
            Mesh::<3>::axis_aligned_box(Vector::<3>::zeros(), Vector::<3>::repeat(1.0), [1, 1, 1])
                .unwrap();
        let surface = SurfaceMesh::boundary_of(&cube);
        assert_eq!(surface.facets().len(), 12);
        assert_eq!(surface.points().len(), 8);
        assert!(surface.is_closed());
        // A finer box keeps its inner points, on no facet.
        let cells =
            Mesh::<3>::axis_aligned_box(Vector::<3>::zeros(), Vector::<3>::repeat(1.0), [2, 2, 2])
                .unwrap();
        let surface = SurfaceMesh::boundary_of(&cells);
        assert_eq!(surface.points().len(), 27);
        assert!(surface.is_closed());
        let ramp = SurfaceMesh::new(
            vec![
                Vector::<3>::new(0.0, 0.0, 0.0),
                Vector::<3>::new(1.0, 0.5, 0.0),
                Vector::<3>::new(1.0, 0.5, 1.0),
                Vector::<3>::new(0.0, 0.0, 1.0),
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        )
        .unwrap();
        assert!(!ramp.is_closed());
        let square =
            Mesh::<2>::axis_aligned_box(Vector::<2>::zeros(), Vector::<2>::repeat(1.0), [2, 2])
                .unwrap();
        let outline = SurfaceMesh::boundary_of(&square);
        assert_eq!(outline.facets().len(), 8);
        assert!(outline.is_closed());
        let polyline = SurfaceMesh::new(
            vec![
                Vector::<2>::new(0.0, 0.0),
                Vector::<2>::new(1.0, 0.0),
                Vector::<2>::new(2.0, 1.0),
            ],
            vec![[0, 1], [1, 2]],
        )
        .unwrap();
        assert!(!polyline.is_closed());
    }

    #[test]
    fn bad_facets_are_named() {
        let points = vec![
            Vector::<3>::new(0.0, 0.0, 0.0),
            Vector::<3>::new(1.0, 0.0, 0.0),
            Vector::<3>::new(2.0, 0.0, 0.0),
            Vector::<3>::new(5.0, 5.0, 5.0),
        ];
        assert_eq!(
            SurfaceMesh::new(points.clone(), vec![[0, 1, 7]]),
            Err(SurfaceError::PointOutOfRange {
                facet: 0,
                point: 7,
                point_count: 4
            })
        );
        // Collinear corners, a repeated corner.
        for facet in [[0, 1, 2], [0, 1, 1]] {
            assert!(matches!(
                SurfaceMesh::new(points.clone(), vec![[0, 1, 3], facet]),
                Err(SurfaceError::Degenerate { facet: 1, .. })
            ));
        }
        assert_eq!(
            SurfaceMesh::<2>::new(vec![Vector::<2>::zeros()], vec![]),
            Err(SurfaceError::Empty(2))
        );
        // Unused points are kept.
        let used = SurfaceMesh::new(points, vec![[3, 1, 0]]).unwrap();
        assert_eq!(used.points().len(), 4);
    }
}
