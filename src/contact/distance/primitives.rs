//! The four primitive squared distances (point-point, point-line,
//! point-plane, line-line) with closed-form gradients and Hessians.
//!
//! Each derivative is first taken with respect to a few *local* difference
//! vectors (an edge vector, a point relative to a vertex, ...), where the
//! formulas are short (see the parent module's documentation), and then
//! `scatter` moves it onto the stencil's vertices: a local vector
//! `u_k = x_plus - x_minus` adds its gradient block to `x_plus`'s rows and
//! subtracts it from `x_minus`'s, and likewise for the Hessian blocks with the
//! product of the two signs.

use crate::math::{Vector, Vector2, Vector3};
use nalgebra::{Matrix3, SMatrix, SVector};

/// Value, gradient and Hessian of a scalar function of a stencil's `N`
/// stacked coordinates (vertex `a`'s coordinate `k` at index `a * D + k`,
/// vertices in argument order).
#[derive(Debug, Clone, Copy)]
pub struct StencilDerivatives<const N: usize> {
    /// The function's value.
    pub value: f64,
    /// Its gradient with respect to the stacked coordinates.
    pub gradient: SVector<f64, N>,
    /// Its (symmetric) Hessian with respect to the stacked coordinates.
    pub hessian: SMatrix<f64, N, N>,
}

impl<const N: usize> StencilDerivatives<N> {
    /// A constant function: `value` with zero gradient and Hessian.
    pub fn constant(value: f64) -> Self {
        Self {
            value,
            gradient: SVector::zeros(),
            hessian: SMatrix::zeros(),
        }
    }
}

/// `|p - q|^2`.
pub fn point_point_distance_squared<const D: usize>(p: &Vector<D>, q: &Vector<D>) -> f64 {
    (p - q).norm_squared()
}

/// `|e x (p - e0)|^2 / |e|^2` with `e = e1 - e0`: the squared distance from
/// `p` to the infinite line through `e0` and `e1` (the 2D cross product is
/// the scalar `e_x r_y - e_y r_x`). Written with the cross product rather
/// than `|r|^2 - (e.r)^2 / |e|^2`, which cancels catastrophically when `p`
/// is close to the line.
pub fn point_line_distance_squared<const D: usize>(
    p: &Vector<D>,
    e0: &Vector<D>,
    e1: &Vector<D>,
) -> f64 {
    let e = e1 - e0;
    cross_squared_norm(&e, &(p - e0)) / e.norm_squared()
}

/// `((p - t0) . n)^2 / |n|^2` with `n = (t1 - t0) x (t2 - t0)`: the squared
/// distance from `p` to the plane of the triangle.
pub fn point_plane_distance_squared(p: &Vector3, t0: &Vector3, t1: &Vector3, t2: &Vector3) -> f64 {
    plane_distance_squared(&(t1 - t0), &(t2 - t0), &(p - t0))
}

/// `((eb0 - ea0) . n)^2 / |n|^2` with `n = (ea1 - ea0) x (eb1 - eb0)`: the
/// squared distance between the two infinite lines.
pub fn line_line_distance_squared(
    ea0: &Vector3,
    ea1: &Vector3,
    eb0: &Vector3,
    eb1: &Vector3,
) -> f64 {
    plane_distance_squared(&(ea1 - ea0), &(eb1 - eb0), &(eb0 - ea0))
}

/// [`point_point_distance_squared`] of stencil vertices `at = [p, q]`,
/// placed in an `N`-coordinate stencil.
pub fn point_point_derivatives<const D: usize, const N: usize>(
    p: &Vector<D>,
    q: &Vector<D>,
    at: [usize; 2],
) -> StencilDerivatives<N> {
    let u = p - q;
    let local = StencilDerivatives::<D> {
        value: u.norm_squared(),
        gradient: u * 2.0,
        hessian: SMatrix::<f64, D, D>::identity() * 2.0,
    };
    scatter::<D, D, N>(&local, &[(at[0], at[1])])
}

/// [`point_line_distance_squared`] in 2D of stencil vertices
/// `at = [p, e0, e1]`, placed in an `N`-coordinate stencil.
pub fn point_line_derivatives_2d<const N: usize>(
    p: &Vector2,
    e0: &Vector2,
    e1: &Vector2,
    at: [usize; 3],
) -> StencilDerivatives<N> {
    let (e, r) = (e1 - e0, p - e0);
    // a = e x r, linear in each of e and r.
    let a = StencilDerivatives::<4> {
        value: e.x * r.y - e.y * r.x,
        gradient: SVector::<f64, 4>::new(r.y, -r.x, -e.y, e.x),
        hessian: SMatrix::<f64, 4, 4>::new(
            0.0, 0.0, 0.0, 1.0, //
            0.0, 0.0, -1.0, 0.0, //
            0.0, -1.0, 0.0, 0.0, //
            1.0, 0.0, 0.0, 0.0,
        ),
    };
    let local = quotient(&square(&a), &edge_length_squared::<2, 4>(&e));
    scatter::<2, 4, N>(&local, &[(at[2], at[1]), (at[0], at[1])])
}

/// [`point_line_distance_squared`] in 3D of stencil vertices
/// `at = [p, e0, e1]`, placed in an `N`-coordinate stencil.
pub fn point_line_derivatives_3d<const N: usize>(
    p: &Vector3,
    e0: &Vector3,
    e1: &Vector3,
    at: [usize; 3],
) -> StencilDerivatives<N> {
    let e = e1 - e0;
    let local = quotient(
        &cross_squared_norm_derivatives(&e, &(p - e0)),
        &edge_length_squared::<3, 6>(&e),
    );
    scatter::<3, 6, N>(&local, &[(at[2], at[1]), (at[0], at[1])])
}

/// [`point_plane_distance_squared`] over the stencil `(p, t0, t1, t2)`.
pub fn point_plane_derivatives(
    p: &Vector3,
    t0: &Vector3,
    t1: &Vector3,
    t2: &Vector3,
) -> StencilDerivatives<12> {
    let local = plane_distance_squared_derivatives(&(t1 - t0), &(t2 - t0), &(p - t0));
    scatter::<3, 9, 12>(&local, &[(2, 1), (3, 1), (0, 1)])
}

/// [`line_line_distance_squared`] over the stencil `(ea0, ea1, eb0, eb1)`.
pub fn line_line_derivatives(
    ea0: &Vector3,
    ea1: &Vector3,
    eb0: &Vector3,
    eb1: &Vector3,
) -> StencilDerivatives<12> {
    let local = plane_distance_squared_derivatives(&(ea1 - ea0), &(eb1 - eb0), &(eb0 - ea0));
    scatter::<3, 9, 12>(&local, &[(1, 0), (3, 2), (2, 0)])
}

/// `|u x v|^2` in 2D (the scalar cross product squared) or 3D.
pub(super) fn cross_squared_norm<const D: usize>(u: &Vector<D>, v: &Vector<D>) -> f64 {
    match D {
        2 => (u[0] * v[1] - u[1] * v[0]).powi(2),
        3 => Vector3::new(u[0], u[1], u[2])
            .cross(&Vector3::new(v[0], v[1], v[2]))
            .norm_squared(),
        _ => unimplemented!("cross product in {D} dimensions"),
    }
}

/// `|u x v|^2` over the local variables `(u, v)`:
/// gradient `(2 v x n, 2 n x u)` with `n = u x v`, and Hessian blocks
/// `H_uu = 2 (|v|^2 I - v v^T)`, `H_vv = 2 (|u|^2 I - u u^T)`,
/// `H_uv = 4 u v^T - 2 v u^T - 2 (u.v) I` (from Lagrange's identity
/// `|u x v|^2 = |u|^2 |v|^2 - (u.v)^2`).
pub(super) fn cross_squared_norm_derivatives(u: &Vector3, v: &Vector3) -> StencilDerivatives<6> {
    let n = u.cross(v);
    let mut d = StencilDerivatives::<6>::constant(n.norm_squared());
    d.gradient
        .fixed_rows_mut::<3>(0)
        .copy_from(&(v.cross(&n) * 2.0));
    d.gradient
        .fixed_rows_mut::<3>(3)
        .copy_from(&(n.cross(u) * 2.0));
    let identity = Matrix3::identity();
    let h_uu = (identity * v.norm_squared() - v * v.transpose()) * 2.0;
    let h_vv = (identity * u.norm_squared() - u * u.transpose()) * 2.0;
    let h_uv = u * v.transpose() * 4.0 - v * u.transpose() * 2.0 - identity * (2.0 * u.dot(v));
    d.hessian.fixed_view_mut::<3, 3>(0, 0).copy_from(&h_uu);
    d.hessian.fixed_view_mut::<3, 3>(3, 3).copy_from(&h_vv);
    d.hessian.fixed_view_mut::<3, 3>(0, 3).copy_from(&h_uv);
    d.hessian
        .fixed_view_mut::<3, 3>(3, 0)
        .copy_from(&h_uv.transpose());
    d
}

/// `((u x v) . w)^2 / |u x v|^2`: the squared distance from `w` to the plane
/// spanned by `u` and `v` through the origin.
fn plane_distance_squared(u: &Vector3, v: &Vector3, w: &Vector3) -> f64 {
    let n = u.cross(v);
    n.dot(w).powi(2) / n.norm_squared()
}

/// [`plane_distance_squared`] over the local variables `(u, v, w)`, as
/// `a^2 / b` with the triple product `a = (u x v) . w` (gradient
/// `(v x w, w x u, u x v)`, Hessian blocks `H_uv = -[w]x`, `H_uw = [v]x`,
/// `H_vw = -[u]x`, zero diagonal) and `b = |u x v|^2`.
fn plane_distance_squared_derivatives(
    u: &Vector3,
    v: &Vector3,
    w: &Vector3,
) -> StencilDerivatives<9> {
    let mut a = StencilDerivatives::<9>::constant(u.cross(v).dot(w));
    a.gradient.fixed_rows_mut::<3>(0).copy_from(&v.cross(w));
    a.gradient.fixed_rows_mut::<3>(3).copy_from(&w.cross(u));
    a.gradient.fixed_rows_mut::<3>(6).copy_from(&u.cross(v));
    for (row, col, block) in [
        (0, 3, -w.cross_matrix()),
        (0, 6, v.cross_matrix()),
        (3, 6, -u.cross_matrix()),
    ] {
        a.hessian.fixed_view_mut::<3, 3>(row, col).copy_from(&block);
        a.hessian
            .fixed_view_mut::<3, 3>(col, row)
            .copy_from(&block.transpose());
    }
    let cross = cross_squared_norm_derivatives(u, v);
    let mut b = StencilDerivatives::<9>::constant(cross.value);
    b.gradient.fixed_rows_mut::<6>(0).copy_from(&cross.gradient);
    b.hessian
        .fixed_view_mut::<6, 6>(0, 0)
        .copy_from(&cross.hessian);
    quotient(&square(&a), &b)
}

/// `|e|^2` over local variables whose first `D` are `e` (the rest unused).
fn edge_length_squared<const D: usize, const M: usize>(e: &Vector<D>) -> StencilDerivatives<M> {
    let mut b = StencilDerivatives::<M>::constant(e.norm_squared());
    b.gradient.fixed_rows_mut::<D>(0).copy_from(&(e * 2.0));
    b.hessian.fixed_view_mut::<D, D>(0, 0).fill_diagonal(2.0);
    b
}

/// `a^2`: gradient `2 a grad a`, Hessian `2 grad a grad a^T + 2 a hess a`.
fn square<const M: usize>(a: &StencilDerivatives<M>) -> StencilDerivatives<M> {
    StencilDerivatives {
        value: a.value * a.value,
        gradient: a.gradient * (2.0 * a.value),
        hessian: a.gradient * a.gradient.transpose() * 2.0 + a.hessian * (2.0 * a.value),
    }
}

/// `f = A / B`: `grad f = (grad A - f grad B) / B`,
/// `hess f = (hess A - f hess B - grad f grad B^T - grad B grad f^T) / B`.
fn quotient<const M: usize>(
    numerator: &StencilDerivatives<M>,
    denominator: &StencilDerivatives<M>,
) -> StencilDerivatives<M> {
    let b = denominator.value;
    let value = numerator.value / b;
    let gradient = (numerator.gradient - denominator.gradient * value) / b;
    let mixed = gradient * denominator.gradient.transpose();
    let hessian = (numerator.hessian - denominator.hessian * value - mixed - mixed.transpose()) / b;
    StencilDerivatives {
        value,
        gradient,
        hessian,
    }
}

/// Moves derivatives with respect to `M / D` local difference vectors onto
/// an `N`-coordinate stencil: local vector `k` is
/// `x[differences[k].0] - x[differences[k].1]` (stencil vertex indices).
pub(super) fn scatter<const D: usize, const M: usize, const N: usize>(
    local: &StencilDerivatives<M>,
    differences: &[(usize, usize)],
) -> StencilDerivatives<N> {
    debug_assert_eq!(differences.len() * D, M);
    let mut out = StencilDerivatives::<N>::constant(local.value);
    for (k, &(plus_k, minus_k)) in differences.iter().enumerate() {
        let g = local.gradient.fixed_rows::<D>(k * D);
        let mut plus = out.gradient.fixed_rows_mut::<D>(plus_k * D);
        plus += g;
        let mut minus = out.gradient.fixed_rows_mut::<D>(minus_k * D);
        minus -= g;
        for (l, &(plus_l, minus_l)) in differences.iter().enumerate() {
            let h = local.hessian.fixed_view::<D, D>(k * D, l * D);
            for (row, col, sign) in [
                (plus_k, plus_l, 1.0),
                (plus_k, minus_l, -1.0),
                (minus_k, plus_l, -1.0),
                (minus_k, minus_l, 1.0),
            ] {
                let mut block = out.hessian.fixed_view_mut::<D, D>(row * D, col * D);
                block += h * sign;
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_values() {
        let (o, x, y) = (Vector3::zeros(), Vector3::x(), Vector3::y());
        let p = Vector3::new(0.3, -4.0, 3.0);
        assert_eq!(point_point_distance_squared(&p, &o), 25.09);
        assert_eq!(point_line_distance_squared(&p, &o, &(x * 2.0)), 25.0);
        assert_eq!(point_plane_distance_squared(&p, &o, &x, &y), 9.0);
        let q = Vector2::new(0.5, 1.5);
        assert_eq!(
            point_line_distance_squared(&q, &Vector2::zeros(), &Vector2::new(1.0, 1.0)),
            0.5
        );
        // The x axis and the line through (0, 0, 2) along y are 2 apart.
        let line_b = [Vector3::new(0.0, 0.0, 2.0), Vector3::new(0.0, 3.0, 2.0)];
        assert_eq!(
            line_line_distance_squared(&o, &x, &line_b[0], &line_b[1]),
            4.0
        );
        // Placed in a stencil: the point-point gradient lands on rows 0..3 and 6..9.
        let d: StencilDerivatives<12> = point_point_derivatives(&p, &o, [0, 2]);
        assert_eq!(d.gradient.fixed_rows::<3>(0), p * 2.0);
        assert_eq!(d.gradient.fixed_rows::<3>(6), -p * 2.0);
        assert_eq!(d.hessian[(0, 6)], -2.0);
        assert_eq!(d.hessian.fixed_view::<3, 3>(3, 3).amax(), 0.0);
    }
}
