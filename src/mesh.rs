//! Simplicial meshes: vertices and linear simplices, with their rest-shape data.
//!
//! For a simplex with vertices `x_0 .. x_D` the edge matrix is
//! `D_s = [x_1 - x_0, ..., x_D - x_0]`. At rest it is `D_m`; the deformation
//! gradient of the linear (constant-strain) element is `F = D_s D_m^{-1}` and its
//! rest volume is `|det D_m| / D!`. A rest element with `det D_m <= 0` (inverted
//! or degenerate) is rejected.
//!
//! Lumped masses: each vertex receives `rho * V_e / (D + 1)` from every element
//! `e` around it.
//!
//! [`SurfaceMesh`] (`mesh/surface_mesh.rs`): points and facets without
//! volume, the shape of an obstacle.

use crate::math::{Matrix, Vector, determinant, inverse, simplex_vertices};
use std::collections::HashMap;

mod surface_mesh;

pub use surface_mesh::{SurfaceError, SurfaceMesh};

/// Errors raised while building a mesh.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum MeshError {
    /// A simplex has zero or negative rest volume.
    #[error(
        "element {element} with vertices {vertices:?} is {kind} at rest (signed volume {volume:.3e})"
    )]
    BadRestElement {
        /// Element index.
        element: usize,
        /// Its vertex indices.
        vertices: Vec<usize>,
        /// "degenerate" or "inverted".
        kind: &'static str,
        /// Signed rest volume.
        volume: f64,
    },
    /// A simplex names a vertex that does not exist.
    #[error(
        "element {element} refers to vertex {vertex}, but the mesh has only {vertex_count} vertices"
    )]
    VertexOutOfRange {
        /// Element index.
        element: usize,
        /// The bad vertex index.
        vertex: usize,
        /// Number of vertices.
        vertex_count: usize,
    },
    /// A simplex lists the wrong number of vertices for the dimension.
    #[error("element {element} lists {count} vertices, but a simplex here has {expected}")]
    WrongVertexCount {
        /// Element index.
        element: usize,
        /// Vertices it lists.
        count: usize,
        /// `D + 1`.
        expected: usize,
    },
    /// A generator was given a non-positive size or zero cells.
    #[error("invalid box: {0}")]
    InvalidBox(String),
    /// The mesh has no elements.
    #[error("the mesh has no elements")]
    Empty,
}

/// Rest-shape data of one element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RestElement<const D: usize> {
    /// Inverse of the rest edge matrix `D_m`.
    pub dm_inv: Matrix<D>,
    /// Rest volume (area in 2D).
    pub volume: f64,
}

/// A mesh of linear simplices in `D` dimensions.
#[derive(Debug, Clone)]
pub struct Mesh<const D: usize> {
    rest_positions: Vec<Vector<D>>,
    /// Vertex indices, `D + 1` per simplex.
    simplices: Vec<usize>,
    rest_elements: Vec<RestElement<D>>,
}

impl<const D: usize> Mesh<D> {
    /// Number of vertices per simplex.
    pub const NODES: usize = simplex_vertices(D);

    /// Builds a mesh from rest positions and simplices, checking every element.
    pub fn new(
        rest_positions: Vec<Vector<D>>,
        simplices: Vec<Vec<usize>>,
    ) -> Result<Self, MeshError> {
        if simplices.is_empty() {
            return Err(MeshError::Empty);
        }
        let mut flat = Vec::with_capacity(simplices.len() * Self::NODES);
        let mut rest_elements = Vec::with_capacity(simplices.len());
        for (element, simplex) in simplices.iter().enumerate() {
            if simplex.len() != Self::NODES {
                return Err(MeshError::WrongVertexCount {
                    element,
                    count: simplex.len(),
                    expected: Self::NODES,
                });
            }
            for &vertex in simplex {
                if vertex >= rest_positions.len() {
                    return Err(MeshError::VertexOutOfRange {
                        element,
                        vertex,
                        vertex_count: rest_positions.len(),
                    });
                }
            }
            let dm = edge_matrix(&rest_positions, simplex);
            let volume = determinant(&dm) / factorial(D);
            let scale = (0..D).map(|c| dm.column(c).norm()).product::<f64>() / factorial(D);
            if !(volume > 1e-12 * scale) {
                let kind = if volume < 0.0 && volume.abs() > 1e-12 * scale {
                    "inverted"
                } else {
                    "degenerate"
                };
                return Err(MeshError::BadRestElement {
                    element,
                    vertices: simplex.clone(),
                    kind,
                    volume,
                });
            }
            let dm_inv = inverse(&dm).expect("non-degenerate edge matrix is invertible");
            flat.extend_from_slice(simplex);
            rest_elements.push(RestElement { dm_inv, volume });
        }
        Ok(Self {
            rest_positions,
            simplices: flat,
            rest_elements,
        })
    }

    /// An axis-aligned box from `min` to `max` with `cells[i]` cells along axis `i`.
    ///
    /// Each cell is split into `D!` simplices by the Kuhn (Freudenthal)
    /// triangulation: one simplex per permutation of the axes, walking from the
    /// cell's lowest corner to its highest. In 2D that is 2 triangles per cell,
    /// in 3D 6 tetrahedra; neighbouring cells share faces conformingly.
    pub fn axis_aligned_box(
        min: Vector<D>,
        max: Vector<D>,
        cells: [usize; D],
    ) -> Result<Self, MeshError> {
        for axis in 0..D {
            if cells[axis] == 0 {
                return Err(MeshError::InvalidBox(format!("axis {axis} has zero cells")));
            }
            if !(max[axis] > min[axis]) || !max[axis].is_finite() || !min[axis].is_finite() {
                return Err(MeshError::InvalidBox(format!(
                    "axis {axis}: max {} must exceed min {}",
                    max[axis], min[axis]
                )));
            }
        }
        let points_per_axis: [usize; D] = std::array::from_fn(|a| cells[a] + 1);
        let index_of = |ijk: &[usize; D]| -> usize {
            let mut index = 0;
            for axis in (0..D).rev() {
                index = index * points_per_axis[axis] + ijk[axis];
            }
            index
        };
        let vertex_count: usize = points_per_axis.iter().product();
        let mut rest_positions = Vec::with_capacity(vertex_count);
        for linear in 0..vertex_count {
            let ijk = unravel(linear, &points_per_axis);
            rest_positions.push(Vector::<D>::from_fn(|axis, _| {
                min[axis] + (max[axis] - min[axis]) * ijk[axis] as f64 / cells[axis] as f64
            }));
        }
        let permutations = permutations(D);
        let cell_count: usize = cells.iter().product();
        let mut simplices = Vec::with_capacity(cell_count * permutations.len());
        for linear in 0..cell_count {
            let corner = unravel(linear, &cells);
            for permutation in &permutations {
                let mut ijk = corner;
                let mut simplex = vec![index_of(&ijk)];
                for &axis in permutation {
                    ijk[axis] += 1;
                    simplex.push(index_of(&ijk));
                }
                if determinant(&edge_matrix(&rest_positions, &simplex)) < 0.0 {
                    simplex.swap(1, 2);
                }
                simplices.push(simplex);
            }
        }
        Self::new(rest_positions, simplices)
    }

    /// Rest positions of the vertices.
    pub fn rest_positions(&self) -> &[Vector<D>] {
        &self.rest_positions
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.rest_positions.len()
    }

    /// Number of simplices.
    pub fn element_count(&self) -> usize {
        self.rest_elements.len()
    }

    /// The `D + 1` vertex indices of element `e`.
    pub fn simplex(&self, e: usize) -> &[usize] {
        &self.simplices[e * Self::NODES..(e + 1) * Self::NODES]
    }

    /// Iterates over all simplices.
    pub fn simplices(&self) -> impl ExactSizeIterator<Item = &[usize]> + '_ {
        self.simplices.chunks_exact(Self::NODES)
    }

    /// Rest data of every element.
    pub fn rest_elements(&self) -> &[RestElement<D>] {
        &self.rest_elements
    }

    /// Total rest volume (area in 2D).
    pub fn rest_volume(&self) -> f64 {
        self.rest_elements.iter().map(|e| e.volume).sum()
    }

    /// Lumped vertex masses for a uniform density.
    pub fn lumped_masses(&self, density: f64) -> Vec<f64> {
        let mut masses = vec![0.0; self.vertex_count()];
        for (simplex, rest) in self.simplices().zip(&self.rest_elements) {
            let share = density * rest.volume / Self::NODES as f64;
            for &v in simplex {
                masses[v] += share;
            }
        }
        masses
    }

    /// The deformation gradient `F = D_s D_m^{-1}` of element `e` at positions `x`.
    pub fn deformation_gradient(&self, e: usize, x: &[Vector<D>]) -> Matrix<D> {
        edge_matrix(x, self.simplex(e)) * self.rest_elements[e].dm_inv
    }

    /// Boundary facets (`D` vertices each) with outward orientation: edges in
    /// 2D, triangles in 3D. A facet is on the boundary when exactly one simplex
    /// holds it. The order is deterministic (element order, then local facet).
    pub fn boundary_facets(&self) -> Vec<[usize; D]> {
        self.boundary().into_iter().map(|f| f.vertices).collect()
    }

    /// The boundary facets as [`Self::boundary_facets`], each with the
    /// element that holds it: the one place where elasto finds a mesh's
    /// boundary (the collision mesh, the renderer and the surface writer all
    /// start from it).
    pub fn boundary(&self) -> Vec<BoundaryFacet<D>> {
        let facet_of = |simplex: &[usize], opposite: usize| -> [usize; D] {
            let mut facet = [0; D];
            let mut k = 0;
            for (i, &v) in simplex.iter().enumerate() {
                if i != opposite {
                    facet[k] = v;
                    k += 1;
                }
            }
            facet
        };
        let sorted = |mut facet: [usize; D]| {
            facet.sort_unstable();
            facet
        };
        let mut count: HashMap<[usize; D], usize> = HashMap::new();
        for simplex in self.simplices() {
            for opposite in 0..Self::NODES {
                *count
                    .entry(sorted(facet_of(simplex, opposite)))
                    .or_insert(0) += 1;
            }
        }
        let mut facets = Vec::new();
        for (element, simplex) in self.simplices().enumerate() {
            for opposite in 0..Self::NODES {
                let mut facet = facet_of(simplex, opposite);
                if count[&sorted(facet)] != 1 {
                    continue;
                }
                // Orient so that (facet, opposite vertex) is negatively oriented,
                // i.e. the facet normal points away from the opposite vertex.
                let mut with_apex = [0; 4];
                with_apex[..D].copy_from_slice(&facet);
                with_apex[D] = simplex[opposite];
                if determinant(&edge_matrix(&self.rest_positions, &with_apex[..=D]))
                    * sign_for_dimension(D)
                    < 0.0
                {
                    facet.swap(0, 1);
                }
                facets.push(BoundaryFacet {
                    vertices: facet,
                    element,
                });
            }
        }
        facets
    }
}

/// A facet on a mesh's boundary (an edge in 2D, a triangle in 3D), oriented
/// outward, and the element that holds it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BoundaryFacet<const D: usize> {
    /// The facet's vertices, counter-clockwise seen from outside (3D) or with
    /// the body on the left (2D).
    pub vertices: [usize; D],
    /// The element the facet belongs to.
    pub element: usize,
}

/// Orientation convention: for an outward facet `f` and interior apex `p`, the
/// simplex `(f_0, .., f_{D-1}, p)` has this sign times a positive determinant
/// when `f` is counter-clockwise seen from outside.
fn sign_for_dimension(d: usize) -> f64 {
    if d.is_multiple_of(2) { 1.0 } else { -1.0 }
}

/// The edge matrix `[x_1 - x_0, ..., x_D - x_0]` of a simplex.
pub fn edge_matrix<const D: usize>(x: &[Vector<D>], simplex: &[usize]) -> Matrix<D> {
    let origin = x[simplex[0]];
    Matrix::<D>::from_fn(|row, col| x[simplex[col + 1]][row] - origin[row])
}

fn factorial(n: usize) -> f64 {
    (1..=n).product::<usize>() as f64
}

fn unravel<const D: usize>(mut linear: usize, extents: &[usize; D]) -> [usize; D] {
    std::array::from_fn(|axis| {
        let value = linear % extents[axis];
        linear /= extents[axis];
        value
    })
}

fn permutations(n: usize) -> Vec<Vec<usize>> {
    if n == 0 {
        return vec![vec![]];
    }
    let mut out = Vec::new();
    for rest in permutations(n - 1) {
        for position in 0..=rest.len() {
            let mut p = rest.clone();
            p.insert(position, n - 1);
            out.push(p);
        }
    }
    out.sort();
    out
}
