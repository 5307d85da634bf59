//! Contact stencils: the pairs of surface primitives the barrier acts on, with their distance and the barrier's local derivatives.
//!
//! A stencil is a pair of primitives that share no vertex:
//!
//! * 2D: a surface vertex `p` and a surface edge `(e0, e1)`;
//! * 3D: a surface vertex `p` and a boundary triangle `(t0, t1, t2)`, or two
//!   surface edges `(ea0, ea1)`, `(eb0, eb1)`.
//!
//! Its energy is IPC's barrier on the squared distance `s = d^2`, against
//! `s_hat = d_hat^2` (the IPC toolkit's convention), times the edge-edge
//! mollifier `m` for nearly parallel edges (1 for the other kinds):
//!
//! ```text
//! E = m(x) b(s(x)),
//! grad E = m b'(s) grad s + b(s) grad m,
//! hess E = m (b''(s) grad s grad s^T + b'(s) hess s)
//!        + b'(s) (grad m grad s^T + grad s grad m^T) + b(s) hess m,
//! ```
//!
//! and its Hessian, a `6 x 6` (2D) or `12 x 12` (3D) matrix over the
//! stencil's stacked coordinates (vertex `a`'s axis `k` at `a D + k`), is
//! projected onto the positive semi-definite cone (its eigen-decomposition
//! with the negative eigenvalues set to zero) before it joins the global
//! matrix, so the Newton direction stays a descent direction. The
//! mollifier (Li et al. 2020, §4.3) makes the edge-edge energy smooth where
//! the edges turn parallel and the closest-point type changes; its scale
//! `eps_x = 1e-3 |ea|^2 |eb|^2` comes from the rest lengths.

use super::barrier::{barrier, barrier_derivative, barrier_second_derivative};
use super::distance::{
    StencilDerivatives, edge_edge_distance_squared, edge_edge_distance_squared_derivatives,
    edge_edge_mollifier, edge_edge_mollifier_derivatives, point_edge_distance_squared,
    point_edge_distance_squared_derivatives, point_triangle_distance_squared,
    point_triangle_distance_squared_derivatives,
};
use crate::math::{Vector, Vector2, Vector3};
use nalgebra::{SMatrix, SVector};

/// Which primitives a stencil pairs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum StencilKind {
    /// 2D: vertex `vertices[0]` against edge `vertices[1..3]`.
    PointEdge,
    /// 3D: vertex `vertices[0]` against triangle `vertices[1..4]`.
    PointTriangle,
    /// 3D: edge `vertices[0..2]` against edge `vertices[2..4]`.
    EdgeEdge,
}

/// One pair of primitives (simulation vertex ids).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactStencil {
    /// What the vertices mean.
    pub kind: StencilKind,
    /// The corners: 3 for a point-edge stencil, 4 for the others.
    pub vertices: [usize; 4],
    /// The edge-edge mollifier's threshold `eps_x` (0 for the other kinds).
    pub mollifier_threshold: f64,
}

/// The largest stencil: 4 vertices of 3 coordinates.
pub const MAX_STENCIL_COORDINATES: usize = 12;

/// Value, gradient and PSD-projected Hessian of a stencil's barrier energy;
/// in 2D only the leading `6` coordinates are used (the rest are zero).
#[derive(Debug, Clone, Copy)]
pub struct StencilEnergy {
    /// `m b(s)`.
    pub value: f64,
    /// Its gradient over the stacked coordinates.
    pub gradient: SVector<f64, MAX_STENCIL_COORDINATES>,
    /// Its Hessian, projected to be positive semi-definite.
    pub hessian: SMatrix<f64, MAX_STENCIL_COORDINATES, MAX_STENCIL_COORDINATES>,
}

impl ContactStencil {
    /// The number of vertices (3 or 4).
    pub fn vertex_count(&self) -> usize {
        match self.kind {
            StencilKind::PointEdge => 3,
            StencilKind::PointTriangle | StencilKind::EdgeEdge => 4,
        }
    }

    /// The stencil's vertices.
    pub fn corners(&self) -> &[usize] {
        &self.vertices[..self.vertex_count()]
    }

    /// The corners of its two primitives: the point and the edge or
    /// triangle, or the two edges.
    pub fn sides(&self) -> (&[usize], &[usize]) {
        let split = match self.kind {
            StencilKind::PointEdge | StencilKind::PointTriangle => 1,
            StencilKind::EdgeEdge => 2,
        };
        self.corners().split_at(split)
    }

    /// The squared distance between the two primitives at positions `x`.
    pub fn distance_squared<const D: usize>(&self, x: &[Vector<D>]) -> f64 {
        let v = &self.vertices;
        match self.kind {
            StencilKind::PointEdge => {
                point_edge_distance_squared(&xy(&x[v[0]]), &xy(&x[v[1]]), &xy(&x[v[2]]))
            }
            StencilKind::PointTriangle => point_triangle_distance_squared(
                &xyz(&x[v[0]]),
                &xyz(&x[v[1]]),
                &xyz(&x[v[2]]),
                &xyz(&x[v[3]]),
            ),
            StencilKind::EdgeEdge => edge_edge_distance_squared(
                &xyz(&x[v[0]]),
                &xyz(&x[v[1]]),
                &xyz(&x[v[2]]),
                &xyz(&x[v[3]]),
            ),
        }
    }

    /// The barrier energy `m b(s)` at `x` for `s_hat = d_hat^2` (0 at or
    /// beyond `d_hat`, `+inf` at contact).
    pub fn energy<const D: usize>(&self, x: &[Vector<D>], squared_activation: f64) -> f64 {
        let s = self.distance_squared(x);
        if s >= squared_activation {
            return 0.0;
        }
        let b = barrier(s, squared_activation);
        match self.kind {
            StencilKind::EdgeEdge => {
                let [a0, a1, b0, b1] = self.edge_edge_points(x);
                edge_edge_mollifier(&a0, &a1, &b0, &b1, self.mollifier_threshold) * b
            }
            _ => b,
        }
    }

    /// Value, gradient and projected Hessian of the barrier energy at `x`
    /// (`None` at or beyond `d_hat`, where all three are zero).
    pub fn energy_derivatives<const D: usize>(
        &self,
        x: &[Vector<D>],
        squared_activation: f64,
    ) -> Option<StencilEnergy> {
        let v = &self.vertices;
        match self.kind {
            StencilKind::PointEdge => {
                let s = point_edge_distance_squared_derivatives(
                    &xy(&x[v[0]]),
                    &xy(&x[v[1]]),
                    &xy(&x[v[2]]),
                );
                let (value, gradient, hessian) = barrier_of(&s, None, squared_activation)?;
                Some(widen(value, gradient, project_6(hessian)))
            }
            StencilKind::PointTriangle => {
                let s = point_triangle_distance_squared_derivatives(
                    &xyz(&x[v[0]]),
                    &xyz(&x[v[1]]),
                    &xyz(&x[v[2]]),
                    &xyz(&x[v[3]]),
                );
                let (value, gradient, hessian) = barrier_of(&s, None, squared_activation)?;
                Some(StencilEnergy {
                    value,
                    gradient,
                    hessian: project_12(hessian),
                })
            }
            StencilKind::EdgeEdge => {
                let [a0, a1, b0, b1] = self.edge_edge_points(x);
                let s = edge_edge_distance_squared_derivatives(&a0, &a1, &b0, &b1);
                if s.value >= squared_activation {
                    return None;
                }
                let m =
                    edge_edge_mollifier_derivatives(&a0, &a1, &b0, &b1, self.mollifier_threshold);
                let (value, gradient, hessian) = barrier_of(&s, Some(&m), squared_activation)?;
                Some(StencilEnergy {
                    value,
                    gradient,
                    hessian: project_12(hessian),
                })
            }
        }
    }

    fn edge_edge_points<const D: usize>(&self, x: &[Vector<D>]) -> [Vector3; 4] {
        self.vertices.map(|v| xyz(&x[v]))
    }
}

/// `m b(s)` with gradient and (unprojected) Hessian by the chain rule of the
/// module documentation; `mollifier` is `None` for `m = 1`.
fn barrier_of<const N: usize>(
    s: &StencilDerivatives<N>,
    mollifier: Option<&StencilDerivatives<N>>,
    squared_activation: f64,
) -> Option<(f64, SVector<f64, N>, SMatrix<f64, N, N>)> {
    if s.value >= squared_activation {
        return None;
    }
    let b = barrier(s.value, squared_activation);
    let db = barrier_derivative(s.value, squared_activation);
    let ddb = barrier_second_derivative(s.value, squared_activation);
    let mut gradient = s.gradient * db;
    let mut hessian = s.gradient * s.gradient.transpose() * ddb + s.hessian * db;
    let mut value = b;
    if let Some(m) = mollifier {
        value = m.value * b;
        let cross = m.gradient * s.gradient.transpose() * db;
        hessian = hessian * m.value + cross + cross.transpose() + m.hessian * b;
        gradient = gradient * m.value + m.gradient * b;
    }
    Some((value, gradient, hessian))
}

fn widen(value: f64, gradient: SVector<f64, 6>, hessian: SMatrix<f64, 6, 6>) -> StencilEnergy {
    let mut wide = StencilEnergy {
        value,
        gradient: SVector::zeros(),
        hessian: SMatrix::zeros(),
    };
    wide.gradient.fixed_rows_mut::<6>(0).copy_from(&gradient);
    wide.hessian
        .fixed_view_mut::<6, 6>(0, 0)
        .copy_from(&hessian);
    wide
}

/// The nearest PSD matrix: eigenvalues below zero set to zero.
fn project_6(h: SMatrix<f64, 6, 6>) -> SMatrix<f64, 6, 6> {
    let mut eigen = ((h + h.transpose()) * 0.5).symmetric_eigen();
    eigen.eigenvalues.iter_mut().for_each(|l| *l = l.max(0.0));
    eigen.recompose()
}

/// [`project_6`] for the 3D stencils.
fn project_12(h: SMatrix<f64, 12, 12>) -> SMatrix<f64, 12, 12> {
    let mut eigen = ((h + h.transpose()) * 0.5).symmetric_eigen();
    eigen.eigenvalues.iter_mut().for_each(|l| *l = l.max(0.0));
    eigen.recompose()
}

/// The first two coordinates of `p` (a 2D stencil's point).
pub(super) fn xy<const D: usize>(p: &Vector<D>) -> Vector2 {
    Vector2::new(p[0], p[1])
}

/// The first three coordinates of `p` (a 3D stencil's point).
pub(super) fn xyz<const D: usize>(p: &Vector<D>) -> Vector3 {
    Vector3::new(p[0], p[1], p[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Central differences of the stencil energy's value (for the gradient)
    /// and gradient (for the unprojected Hessian) at `x`.
    fn check_derivatives<const D: usize>(
        stencil: &ContactStencil,
        x: &[Vector<D>],
        activation: f64,
    ) {
        let n = stencil.vertex_count() * D;
        let energy = stencil.energy_derivatives(x, activation).expect("active");
        assert!((energy.value - stencil.energy(x, activation)).abs() <= 1e-12 * energy.value.abs());
        let h = 1e-7;
        let shifted = |i: usize, by: f64| {
            let mut y = x.to_vec();
            y[stencil.vertices[i / D]][i % D] += by;
            y
        };
        for i in 0..n {
            let fd = (stencil.energy(&shifted(i, h), activation)
                - stencil.energy(&shifted(i, -h), activation))
                / (2.0 * h);
            let scale = energy.gradient.amax().max(1e-300);
            assert!(
                (fd - energy.gradient[i]).abs() <= 1e-5 * scale,
                "{:?} gradient[{i}]: fd {fd}, exact {}",
                stencil.kind,
                energy.gradient[i]
            );
        }
        // The projected Hessian is symmetric positive semi-definite.
        let hessian = energy.hessian.fixed_view::<12, 12>(0, 0).into_owned();
        let eigen = hessian.symmetric_eigen();
        let largest = eigen.eigenvalues.amax();
        assert!(eigen.eigenvalues.iter().all(|&l| l >= -1e-9 * largest));
        assert!((hessian - hessian.transpose()).amax() <= 1e-12 * largest);
    }

    /// The unprojected Hessian of `m b(s)` against central differences of
    /// its gradient.
    fn check_unprojected_hessian<const N: usize>(
        s: impl Fn(&SVector<f64, N>) -> (StencilDerivatives<N>, Option<StencilDerivatives<N>>),
        x: SVector<f64, N>,
        activation: f64,
    ) {
        let at = |y: &SVector<f64, N>| {
            let (d, m) = s(y);
            barrier_of(&d, m.as_ref(), activation).expect("active")
        };
        let (_, _, hessian) = at(&x);
        let h = 1e-7;
        for j in 0..N {
            let mut up = x;
            up[j] += h;
            let mut down = x;
            down[j] -= h;
            let column = (at(&up).1 - at(&down).1) / (2.0 * h);
            let scale = hessian.amax();
            for i in 0..N {
                assert!(
                    (column[i] - hessian[(i, j)]).abs() <= 1e-5 * scale,
                    "hessian[{i}, {j}]: fd {}, exact {}",
                    column[i],
                    hessian[(i, j)]
                );
            }
        }
    }

    #[test]
    fn a_point_near_an_edge_has_the_barrier_s_derivatives() {
        let x = vec![
            Vector2::new(0.3, 0.004),
            Vector2::new(0.0, 0.0),
            Vector2::new(1.0, 0.001),
        ];
        let stencil = ContactStencil {
            kind: StencilKind::PointEdge,
            vertices: [0, 1, 2, usize::MAX],
            mollifier_threshold: 0.0,
        };
        let activation = 0.01f64.powi(2);
        check_derivatives(&stencil, &x, activation);
        let flat = SVector::<f64, 6>::from_iterator(x.iter().flat_map(|p| [p[0], p[1]]));
        check_unprojected_hessian(
            |y| {
                let p = |i: usize| Vector2::new(y[2 * i], y[2 * i + 1]);
                (
                    point_edge_distance_squared_derivatives(&p(0), &p(1), &p(2)),
                    None,
                )
            },
            flat,
            activation,
        );
        // Beyond d_hat the stencil is inactive and its energy zero.
        let far = vec![Vector2::new(0.3, 0.5), x[1], x[2]];
        assert!(stencil.energy_derivatives(&far, activation).is_none());
        assert_eq!(stencil.energy(&far, activation), 0.0);
    }

    #[test]
    fn point_triangle_and_mollified_edge_edge_stencils_have_the_barrier_s_derivatives() {
        let activation = 0.02f64.powi(2);
        let triangle = vec![
            Vector3::new(0.2, 0.01, 0.3),
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.002, 0.0),
            Vector3::new(0.0, -0.001, 1.0),
        ];
        let stencil = ContactStencil {
            kind: StencilKind::PointTriangle,
            vertices: [0, 1, 2, 3],
            mollifier_threshold: 0.0,
        };
        check_derivatives(&stencil, &triangle, activation);
        // Two nearly parallel edges 0.01 apart: the mollifier is active.
        let edges = vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.1, 0.01, 0.001),
            Vector3::new(0.9, 0.012, -0.002),
        ];
        let threshold = 1e-3 * 1.0 * 0.64;
        let stencil = ContactStencil {
            kind: StencilKind::EdgeEdge,
            vertices: [0, 1, 2, 3],
            mollifier_threshold: threshold,
        };
        let [a0, a1, b0, b1] = [edges[0], edges[1], edges[2], edges[3]];
        assert!(edge_edge_mollifier(&a0, &a1, &b0, &b1, threshold) < 1.0);
        check_derivatives(&stencil, &edges, activation);
        let flat = SVector::<f64, 12>::from_iterator(edges.iter().flat_map(|p| [p[0], p[1], p[2]]));
        check_unprojected_hessian(
            |y| {
                let p = |i: usize| Vector3::new(y[3 * i], y[3 * i + 1], y[3 * i + 2]);
                (
                    edge_edge_distance_squared_derivatives(&p(0), &p(1), &p(2), &p(3)),
                    Some(edge_edge_mollifier_derivatives(
                        &p(0),
                        &p(1),
                        &p(2),
                        &p(3),
                        threshold,
                    )),
                )
            },
            flat,
            activation,
        );
    }
}
