//! The collision-free step of a line search: the largest fraction of `x -> x + dx` no stencil crosses.
//!
//! Every candidate stencil of the swept segment is queried with additive CCD
//! ([`super::ccd`]), each query bounded by the smallest step found so far
//! (a query may stop as soon as it proves that bound safe). The minimum is
//! conservative because each query is: it never exceeds the stencil's true
//! time of impact, and it keeps a fraction of the remaining gap. A query
//! whose iteration budget runs out returns the safe step it reached and is
//! counted ([`CollisionFreeStep::budget_exhausted`]), never an allocation or a
//! hang.

use super::ccd::{CcdOutcome, CcdSettings, edge_edge_ccd, point_edge_ccd, point_triangle_ccd};
use super::stencil::{xy, xyz};
use super::{ContactStencil, StencilKind};
use crate::math::{Vector, Vector3};

/// The answer of [`collision_free_step`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CollisionFreeStep {
    /// The largest safe fraction of the step, in `[0, 1]`.
    pub step: f64,
    /// Queries whose iteration budget ran out (their safe step was used).
    pub budget_exhausted: usize,
    /// The stencil that set the step, when one limited it below 1.
    pub limiting: Option<ContactStencil>,
}

/// The largest `t <= 1` such that no stencil of `stencils` touches along
/// `x -> x + t dx`.
pub fn collision_free_step<const D: usize>(
    stencils: &[ContactStencil],
    x: &[Vector<D>],
    dx: &[Vector<D>],
    settings: &CcdSettings,
) -> CollisionFreeStep {
    let mut step = 1.0f64;
    let mut budget_exhausted = 0;
    let mut limiting = None;
    for stencil in stencils {
        let v = &stencil.vertices;
        let moves = stencil
            .corners()
            .iter()
            .any(|&c| dx[c] != Vector::<D>::zeros());
        if !moves {
            continue;
        }
        let outcome: CcdOutcome = match stencil.kind {
            StencilKind::PointEdge => {
                let p = |i: usize| xy(&x[v[i]]);
                let d = |i: usize| xy(&dx[v[i]]);
                point_edge_ccd(&p(0), &p(1), &p(2), &d(0), &d(1), &d(2), step, settings)
            }
            StencilKind::PointTriangle | StencilKind::EdgeEdge => {
                // The two 3D queries take the same arguments.
                type Query = fn(
                    &Vector3,
                    &Vector3,
                    &Vector3,
                    &Vector3,
                    &Vector3,
                    &Vector3,
                    &Vector3,
                    &Vector3,
                    f64,
                    &CcdSettings,
                ) -> CcdOutcome;
                let query: Query = if stencil.kind == StencilKind::PointTriangle {
                    point_triangle_ccd
                } else {
                    edge_edge_ccd
                };
                let p = |i: usize| xyz(&x[v[i]]);
                let d = |i: usize| xyz(&dx[v[i]]);
                query(
                    &p(0),
                    &p(1),
                    &p(2),
                    &p(3),
                    &d(0),
                    &d(1),
                    &d(2),
                    &d(3),
                    step,
                    settings,
                )
            }
        };
        budget_exhausted += usize::from(outcome.budget_exhausted);
        if outcome.step < step {
            step = outcome.step;
            limiting = Some(*stencil);
        }
        if step <= 0.0 {
            break;
        }
    }
    CollisionFreeStep {
        step: step.max(0.0),
        budget_exhausted,
        limiting,
    }
}
