//! Squared distances between contact primitives, with their closest-feature
//! classification, closed-form gradients and Hessians, closest points, and
//! IPC's edge-edge mollifier: the IPC toolkit's `distance/` folder, in Rust.
//!
//! All distances are **squared** (as in ipctk): `s = d^2` is a polynomial
//! over a polynomial, smooth wherever the closest features do not change.
//!
//! # Classification, then a primitive
//!
//! The distance between a point and an edge, a point and a triangle, or two
//! edges is the distance between their closest *features* (vertex, edge
//! interior, face interior). Each stencil function first decides which
//! features are closest (the `*_distance_type` functions, with ipctk's
//! rules: [`point_edge_distance_type`], [`point_triangle_distance_type`],
//! [`edge_edge_distance_type`]) and then evaluates one of four primitive
//! squared distances ([`primitives`]):
//!
//! ```text
//! point-point  |p - q|^2
//! point-line   |e x r|^2 / |e|^2             e = e1 - e0, r = p - e0
//!                                            (2D: e x r = e_x r_y - e_y r_x)
//! point-plane  ((u x v) . w)^2 / |u x v|^2    u = t1 - t0, v = t2 - t0, w = p - t0
//! line-line    ((u x v) . w)^2 / |u x v|^2    u = ea1 - ea0, v = eb1 - eb0, w = eb0 - ea0
//! ```
//!
//! Point-plane and line-line are the same function of their local vectors:
//! the squared distance from `w` to the plane spanned by `u` and `v`. The
//! gradient and Hessian of a stencil's distance are those of its primitive,
//! placed in the rows of the vertices the primitive uses (zeros for the
//! others); the squared distance is C^1 across a change of type (the
//! minimiser is unique), its Hessian is not.
//!
//! # Derivatives
//!
//! Each primitive is differentiated with respect to its local difference
//! vectors, then moved onto the stencil's vertices: for `u_k = x_i - x_j`,
//! `grad_{x_i} += grad_{u_k}`, `grad_{x_j} -= grad_{u_k}`, and each Hessian
//! block `H_{u_k u_l}` is added to the four vertex blocks with the product of
//! the signs. The building blocks (`[a]x` is the cross-product matrix,
//! `[a]x b = a x b`):
//!
//! ```text
//! quotient   f = A / B:
//!            grad f = (grad A - f grad B) / B
//!            hess f = (hess A - f hess B - grad f grad B^T - grad B grad f^T) / B
//! square     (a^2)' = 2 a grad a,   hess a^2 = 2 grad a grad a^T + 2 a hess a
//! triple     a = (u x v) . w:       grad a = (v x w, w x u, u x v),
//!            hess a: H_uv = -[w]x, H_uw = [v]x, H_vw = -[u]x (transposes below,
//!            zero diagonal blocks: a is linear in each vector)
//! cross      b = |u x v|^2 = |u|^2 |v|^2 - (u.v)^2,  n = u x v:
//!            grad b = (2 v x n, 2 n x u),
//!            H_uu = 2 (|v|^2 I - v v^T), H_vv = 2 (|u|^2 I - u u^T),
//!            H_uv = 4 u v^T - 2 v u^T - 2 (u.v) I
//! ```
//!
//! so point-plane and line-line are `quotient(square(triple), cross)`,
//! point-line in 3D is `quotient(cross(e, r), |e|^2)` and in 2D
//! `quotient(square(e x r), |e|^2)` with `grad (e x r) = (r_y, -r_x, -e_y, e_x)`.
//! Gradients are formed from cross products (as above) rather than by
//! expanding Lagrange's identity, which would cancel when the point nearly
//! touches the line or plane; the value `|e x r|^2 / |e|^2` likewise avoids
//! `|r|^2 - (e.r)^2 / |e|^2`.
//!
//! # Mollifier
//!
//! Nearly parallel edges switch between line-line and point-edge types
//! where the distance's Hessian jumps; IPC multiplies the edge-edge barrier
//! by ([`edge_edge_mollifier`], Li et al. 2020, §4.3)
//!
//! ```text
//! c = |(ea1 - ea0) x (eb1 - eb0)|^2,   eps_x = 1e-3 |ea_rest|^2 |eb_rest|^2,
//! m(c) = (2 - c / eps_x) c / eps_x  for c < eps_x,  1 otherwise,
//! grad m = m'(c) grad c,   hess m = m'(c) hess c + m''(c) grad c grad c^T,
//! ```
//!
//! with `c` the `cross` building block above; `m` is C^1 at `c = eps_x`.
//!
//! # Closest points
//!
//! [`point_edge_closest_parameter`], [`point_triangle_closest_barycentric`]
//! and [`edge_edge_closest_parameters`] give the closest points (for
//! friction) consistent with the classification: corners for vertex types,
//! clamped projections for edge types, and the lines' or plane's closest
//! point for the interior types.
//!
//! No Rust crate offers these (geometry crates such as parry give distances
//! but not ipctk's classification with second derivatives), and autodiff
//! would cost at run time what the closed forms above do not; ipctk's
//! numbers are stored in the tests as references.

mod edge_edge;
mod edge_edge_mollifier;
mod point_edge;
mod point_triangle;
pub mod primitives;

#[cfg(test)]
mod ipctk_reference;
#[cfg(test)]
pub(crate) mod test_support;

pub use edge_edge::{
    EdgeEdgeDistanceType, edge_edge_closest_parameters, edge_edge_distance_squared,
    edge_edge_distance_squared_derivatives, edge_edge_distance_type,
    edge_edge_parallel_distance_type,
};
pub use edge_edge_mollifier::{
    edge_edge_cross_squared_norm, edge_edge_mollifier, edge_edge_mollifier_derivatives,
    edge_edge_mollifier_threshold,
};
pub use point_edge::{
    PointEdgeDistanceType, point_edge_closest_parameter, point_edge_distance_squared,
    point_edge_distance_squared_derivatives, point_edge_distance_type,
};
pub use point_triangle::{
    PointTriangleDistanceType, point_triangle_closest_barycentric, point_triangle_distance_squared,
    point_triangle_distance_squared_derivatives, point_triangle_distance_type,
};
pub use primitives::StencilDerivatives;
