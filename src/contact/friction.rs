//! Lagged smoothed Coulomb friction on a contact stencil (Li et al. 2020, "Incremental Potential Contact", §5).
//!
//! At the start of a time step every active contact stencil (and every
//! vertex within the ground's barrier) is frozen into a *friction stencil*:
//! the weights `w_a` of its closest points (the relative position of the
//! two closest points is `r(x) = sum_a w_a x_a`), the contact normal `n`
//! (the direction of `r` then), the normal force magnitude `lambda` the
//! barrier exerts then, and the friction coefficient `mu`. Over the step,
//! with `x^n` the positions the step starts from,
//!
//! ```text
//! u(x)  = P (r(x) - r(x^n)),      P = I - n n^T     (tangential slip over the step),
//! D(x)  = mu lambda f0(|u|),
//! grad_a D  = mu lambda w_a (f1(y) / y) u,          y = |u|,
//! hess_ab D = mu lambda w_a w_b H,   H = (f1 / y) P + f2 u u^T,
//! ```
//!
//! with IPC's mollifier of `|u|` over the slip threshold `eps = eps_v dt`
//! (the velocity threshold times the step):
//!
//! ```text
//! f0(y) = -y^3 / (3 eps^2) + y^2 / eps + eps / 3,  f1(y) = f0'(y) = 2 y / eps - y^2 / eps^2   (y < eps),
//! f0(y) = y,                                       f1(y) = 1                                  (y >= eps),
//! f2 = (f1'(y) y - f1(y)) / y^3 = -1 / (eps^2 y)  (y < eps),   -1 / y^3  (y >= eps).
//! ```
//!
//! `-grad D` is the friction force: opposite to the slip, of magnitude
//! `mu lambda` once the slip exceeds `eps` (Coulomb's law), growing
//! linearly from 0 below it (static friction, smoothed). `H` is positive
//! semi-definite by construction (in the tangent plane its eigenvalues are
//! `f1 / y > 0` across the slip and `f1' = 2 / eps - 2 y / eps^2 >= 0` along
//! it below `eps`, `1 / y` and `0` above), so no projection is needed: the
//! stencil's block `(w w^T) (x) H` is a congruence of it.
//!
//! **Why the tangent projector and not a basis.** The IPC toolkit stores a
//! `D x (D - 1)` tangent basis `T` per stencil and works with `T^T r`; every
//! quantity here depends only on `|T^T r| = |P r|` with `P = T T^T`, so the
//! projector gives the same potential with no choice of basis. The normal
//! is the closest points' direction for every distance type, as the
//! toolkit's bases are (point-point, point-edge, point-triangle and
//! edge-edge alike).
//!
//! **Units.** `D` is the work of friction over the step (force x length),
//! the IPC toolkit's velocity potential times `dt`: it joins the
//! incremental potential with the integrator's weight like any potential.
//! Elasto's own code: no crate offers IPC friction.

use super::barrier::barrier_derivative;
use super::distance::{
    edge_edge_closest_parameters, point_edge_closest_parameter, point_triangle_closest_barycentric,
};
use super::{ContactStencil, StencilKind};
use crate::math::{Matrix, Vector, Vector2, Vector3};

/// `f0(y)`: the mollified slip length (`y` beyond `eps`).
pub fn friction_f0(y: f64, eps: f64) -> f64 {
    if y < eps {
        -y * y * y / (3.0 * eps * eps) + y * y / eps + eps / 3.0
    } else {
        y
    }
}

/// `f1(y) = f0'(y)`: the friction force's fraction of `mu lambda`.
pub fn friction_f1(y: f64, eps: f64) -> f64 {
    if y < eps {
        2.0 * y / eps - y * y / (eps * eps)
    } else {
        1.0
    }
}

/// `f1(y) / y`, finite at `y = 0` (its limit `2 / eps`).
pub fn friction_f1_over_y(y: f64, eps: f64) -> f64 {
    if y < eps {
        2.0 / eps - y / (eps * eps)
    } else {
        1.0 / y
    }
}

/// `f2(y) y = (f1'(y) y - f1(y)) / y^2`, finite at `y = 0` (the factor of
/// `u u^T / y` in the Hessian).
fn friction_f2_times_y(y: f64, eps: f64) -> f64 {
    if y < eps {
        -1.0 / (eps * eps)
    } else {
        -1.0 / (y * y)
    }
}

/// The normal force magnitude `lambda = kappa |dB / dd| = -kappa b'(s) 2 d`
/// of a contact stencil at `x` (`s = d^2` against `s_hat = d_hat^2`, the
/// IPC toolkit's convention; without the edge-edge mollifier, as the
/// toolkit's friction has it); 0 at or beyond `d_hat`.
pub fn normal_force<const D: usize>(
    stencil: &ContactStencil,
    x: &[Vector<D>],
    squared_activation: f64,
    stiffness: f64,
) -> f64 {
    let s = stencil.distance_squared(x);
    if !(s < squared_activation) {
        return 0.0;
    }
    -stiffness * barrier_derivative(s, squared_activation) * 2.0 * s.sqrt()
}

/// A contact frozen at the start of a step: the slip of its closest points
/// resisted by `mu lambda`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrictionStencil<const D: usize> {
    /// The corners (simulation vertex ids; the first `count`).
    pub vertices: [usize; 4],
    /// How many corners: 1 (a vertex on the ground), 3 or 4.
    pub count: usize,
    /// `w_a`: the relative position of the closest points is `sum_a w_a x_a`.
    pub weights: [f64; 4],
    /// The contact normal at the step's start (unit).
    pub normal: Vector<D>,
    /// `r(x^n) = sum_a w_a x_a^n`.
    pub start: Vector<D>,
    /// `mu lambda`: the friction force's magnitude in full slip.
    pub force: f64,
}

/// What a friction stencil adds at a state: its potential, the gradient
/// per corner `w_a g` and the Hessian blocks `w_a w_b H`.
#[derive(Debug, Clone, Copy)]
pub struct FrictionDerivatives<const D: usize> {
    /// `mu lambda f0(y)`.
    pub value: f64,
    /// `g = mu lambda (f1 / y) u`.
    pub gradient: Vector<D>,
    /// `H` (times `mu lambda`), positive semi-definite.
    pub hessian: Matrix<D>,
}

impl<const D: usize> FrictionStencil<D> {
    /// A vertex against a fixed plane of unit `normal` (the ground), its
    /// slip measured from its position `x_start` at the step's start.
    pub fn vertex_on_plane(
        vertex: usize,
        x_start: &[Vector<D>],
        normal: Vector<D>,
        force: f64,
    ) -> Self {
        Self {
            vertices: [vertex, 0, 0, 0],
            count: 1,
            weights: [1.0, 0.0, 0.0, 0.0],
            normal,
            start: x_start[vertex],
            force,
        }
    }

    /// The stencil of contact pair `stencil` with its closest points and
    /// normal taken at the lagged state `lagged`, its slip measured from the
    /// step's start `x_start` (the same state, unless an outer friction pass
    /// lags it again at a solution), and the friction force
    /// `force = mu lambda`; `None` for primitives that touch (no normal).
    pub fn of_contact(
        stencil: &ContactStencil,
        lagged: &[Vector<D>],
        x_start: &[Vector<D>],
        force: f64,
    ) -> Option<Self> {
        let weights = closest_point_weights(stencil, lagged);
        let relative = |x: &[Vector<D>]| {
            let mut r = Vector::<D>::zeros();
            for (w, &v) in weights.iter().zip(stencil.corners()) {
                r += x[v] * *w;
            }
            r
        };
        let separation = relative(lagged);
        let length = separation.norm();
        (length > 0.0).then(|| Self {
            vertices: stencil.vertices,
            count: stencil.vertex_count(),
            weights,
            normal: separation / length,
            start: relative(x_start),
            force,
        })
    }

    /// The stencil's corners.
    pub fn corners(&self) -> &[usize] {
        &self.vertices[..self.count]
    }

    /// `u(x)`: the tangential slip of the closest points since the step's start.
    pub fn slip(&self, x: &[Vector<D>]) -> Vector<D> {
        let mut r = -self.start;
        for (w, &v) in self.weights.iter().zip(self.corners()) {
            r += x[v] * *w;
        }
        r - self.normal * self.normal.dot(&r)
    }

    /// `D(x) = mu lambda f0(|u|)` for the slip threshold `eps`.
    pub fn potential(&self, x: &[Vector<D>], eps: f64) -> f64 {
        self.force * friction_f0(self.slip(x).norm(), eps)
    }

    /// The work friction did on the stencil over a slip `u`, `mu lambda f1(y) y`
    /// (the force against the slip times its length).
    pub fn dissipated(&self, x: &[Vector<D>], eps: f64) -> f64 {
        let y = self.slip(x).norm();
        self.force * friction_f1(y, eps) * y
    }

    /// Value, gradient `g` and Hessian `H` of the module documentation.
    pub fn derivatives(&self, x: &[Vector<D>], eps: f64) -> FrictionDerivatives<D> {
        let u = self.slip(x);
        let y = u.norm();
        let projector = Matrix::<D>::identity() - self.normal * self.normal.transpose();
        let f1_over_y = friction_f1_over_y(y, eps);
        let mut hessian = projector * f1_over_y;
        if y > 0.0 {
            let direction = u / y;
            hessian += u * direction.transpose() * friction_f2_times_y(y, eps);
        }
        FrictionDerivatives {
            value: self.force * friction_f0(y, eps),
            gradient: u * (self.force * f1_over_y),
            hessian: hessian * self.force,
        }
    }
}

/// The weights `w_a` of a contact stencil's closest points at `x`:
/// point-edge `p - ((1 - t) e0 + t e1)`, point-triangle
/// `p - ((1 - b1 - b2) t0 + b1 t1 + b2 t2)`, edge-edge
/// `((1 - s) ea0 + s ea1) - ((1 - t) eb0 + t eb1)`.
fn closest_point_weights<const D: usize>(stencil: &ContactStencil, x: &[Vector<D>]) -> [f64; 4] {
    let v = &stencil.vertices;
    match stencil.kind {
        StencilKind::PointEdge => {
            let xy = |i: usize| Vector2::new(x[v[i]][0], x[v[i]][1]);
            let t = point_edge_closest_parameter(&xy(0), &xy(1), &xy(2));
            [1.0, t - 1.0, -t, 0.0]
        }
        StencilKind::PointTriangle => {
            let xyz = |i: usize| Vector3::new(x[v[i]][0], x[v[i]][1], x[v[i]][2]);
            let (b1, b2) = point_triangle_closest_barycentric(&xyz(0), &xyz(1), &xyz(2), &xyz(3));
            [1.0, b1 + b2 - 1.0, -b1, -b2]
        }
        StencilKind::EdgeEdge => {
            let xyz = |i: usize| Vector3::new(x[v[i]][0], x[v[i]][1], x[v[i]][2]);
            let (s, t) = edge_edge_closest_parameters(&xyz(0), &xyz(1), &xyz(2), &xyz(3));
            [1.0 - s, s, t - 1.0, -t]
        }
    }
}

#[cfg(test)]
mod tests;
