//! Sparse Cholesky `H = L L^T` with faer: one symbolic analysis per pattern, a numeric refactorisation per Newton iteration.
//!
//! The elimination order is the caller's (the nested dissection of
//! [`super::nested_dissection`], through `SymmetricOrdering::Custom`) or
//! faer's approximate minimum degree (AMD), whichever gives the factor with
//! fewer stored entries: both are analysed (a symbolic analysis costs a small
//! fraction of the setup) and the smaller factor is kept. Nested dissection
//! wins on 3D meshes (7.8 M against 8.3 M entries for a 16³-cell box), AMD
//! on small 2D ones (169 k against 234 k at 40 x 40 cells, where the
//! factorisation is about 10% faster with it). The factorisation is forced
//! supernodal: the separators become dense blocks, which faer factorises
//! with dense kernels (the simplicial variant works one column at a time and
//! was 2–3 times slower on every mesh measured). Without an order (an empty
//! matrix), AMD alone is used.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::perm::PermRef;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

/// The factorisation failed: the pattern could not be analysed, or the
/// matrix is not numerically positive definite.
#[derive(Debug, Clone, thiserror::Error)]
#[error("sparse Cholesky factorisation failed: {0}")]
pub struct FactorisationError(pub String);

/// The symbolic factorisation of a lower-triangle pattern, with the storage
/// for its numeric factor and the solver's workspace.
pub struct SparseCholesky {
    symbolic: SymbolicCholesky<usize>,
    /// Which elimination order the analysis kept.
    order_kind: OrderKind,
    factor_values: Vec<f64>,
    workspace: MemBuffer,
}

/// The kind of elimination order a [`SparseCholesky`] was analysed in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OrderKind {
    /// The caller's order (the nested dissection).
    Given,
    /// faer's approximate minimum degree.
    Amd,
}

/// The supernodal symbolic factorisation of `pattern` in the elimination order `ordering`.
pub(super) fn analyse_symbolic(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    ordering: SymmetricOrdering<'_, usize>,
) -> Result<SymbolicCholesky<usize>, FactorisationError> {
    factorize_symbolic_cholesky(
        pattern,
        Side::Lower,
        ordering,
        CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        },
    )
    .map_err(|e| {
        FactorisationError(match e {
            faer::sparse::FaerError::OutOfMemory => {
                "not enough memory for the symbolic factorisation".to_owned()
            }
            faer::sparse::FaerError::IndexOverflow => {
                "the factor has more entries than an index can count".to_owned()
            }
            _ => "the symbolic factorisation failed".to_owned(),
        })
    })
}

impl SparseCholesky {
    /// Stored non-zeros of the factor `L` (its storage is 8 bytes each).
    pub fn factor_non_zeros(&self) -> usize {
        self.factor_values.len()
    }
}

impl SparseCholesky {
    /// Analyses the `dofs x dofs` lower-triangle pattern `(col_ptr, row_idx)`
    /// for the elimination order `order = (forward, inverse)` (`forward[k]`
    /// is the unknown eliminated `k`-th) and for AMD, and keeps the order
    /// whose factor is smaller (`None`: AMD alone).
    pub fn analyse(
        dofs: usize,
        col_ptr: &[usize],
        row_idx: &[usize],
        order: Option<(&[usize], &[usize])>,
    ) -> Result<Self, FactorisationError> {
        let pattern = SymbolicSparseColMatRef::new_checked(dofs, dofs, col_ptr, None, row_idx);
        let amd = analyse_symbolic(pattern, SymmetricOrdering::Amd)?;
        let (symbolic, order_kind) = match order {
            Some((forward, inverse)) => {
                let given = analyse_symbolic(
                    pattern,
                    SymmetricOrdering::Custom(PermRef::new_checked(forward, inverse, dofs)),
                )?;
                // Ties go to the given order (deterministic either way).
                if amd.len_val() < given.len_val() {
                    (amd, OrderKind::Amd)
                } else {
                    (given, OrderKind::Given)
                }
            }
            None => (amd, OrderKind::Amd),
        };
        Ok(Self::with_symbolic(symbolic, order_kind))
    }

    /// The analysis of a grown pattern (a superset of the one analysed, as
    /// when contact pairs join it) in the same kind of order as this one:
    /// the given `order` if that kept it (an order must then be given),
    /// else AMD. One symbolic analysis instead of two: the pattern grows by
    /// a few pairs at a time, which does not change which kind fills less.
    pub fn reanalyse(
        &self,
        dofs: usize,
        col_ptr: &[usize],
        row_idx: &[usize],
        order: Option<(&[usize], &[usize])>,
    ) -> Result<Self, FactorisationError> {
        let pattern = SymbolicSparseColMatRef::new_checked(dofs, dofs, col_ptr, None, row_idx);
        let ordering = match (self.order_kind, order) {
            (OrderKind::Given, Some((forward, inverse))) => {
                SymmetricOrdering::Custom(PermRef::new_checked(forward, inverse, dofs))
            }
            _ => SymmetricOrdering::Amd,
        };
        let symbolic = analyse_symbolic(pattern, ordering)?;
        let kind = match ordering {
            SymmetricOrdering::Custom(_) => OrderKind::Given,
            _ => OrderKind::Amd,
        };
        Ok(Self::with_symbolic(symbolic, kind))
    }

    /// Which kind of elimination order the analysis kept.
    pub fn order_kind(&self) -> OrderKind {
        self.order_kind
    }

    fn with_symbolic(symbolic: SymbolicCholesky<usize>, order_kind: OrderKind) -> Self {
        let factor_values = vec![0.0; symbolic.len_val()];
        let workspace = MemBuffer::new(
            symbolic
                .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default())
                .or(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq)),
        );
        Self {
            symbolic,
            order_kind,
            factor_values,
            workspace,
        }
    }

    /// Factorises `matrix` (same pattern as analysed), keeping `L` for
    /// [`Self::solve`]. Sequential: faer's parallel variant splits only the
    /// dense kernels of each supernode (supernodes are eliminated in order),
    /// and on this project's 2-core machine it gave bitwise the same factor
    /// but took 1.4–1.8 times as long (16³ and 21³-cell boxes: 124 against
    /// 70 ms, 350 against 250 ms), so one thread is both deterministic and
    /// faster here.
    pub fn factorise(
        &mut self,
        matrix: SparseColMatRef<'_, usize, f64>,
    ) -> Result<(), FactorisationError> {
        self.factorise_if_positive_definite(matrix)
            .map_err(|pivot| {
                FactorisationError(format!(
                    "the system matrix is not positive definite in floating point (pivot {} of \
                     {} is not positive): the masses are lost to round-off beside dt² times the \
                     stiffness, or a barrier's curvature swamps the rest; a larger \
                     material.density, a smaller time step or a barrier closer to its default \
                     may help",
                    pivot + 1,
                    matrix.nrows()
                ))
            })
    }

    /// [`Self::factorise`], answering a matrix that is not numerically
    /// positive definite with the index of its first non-positive pivot and
    /// nothing else: no message is built, so a caller that expects such
    /// matrices (Newton trying the unprojected Hessian first) allocates
    /// nothing. The factor is then not usable.
    pub fn factorise_if_positive_definite(
        &mut self,
        matrix: SparseColMatRef<'_, usize, f64>,
    ) -> Result<(), usize> {
        let stack = MemStack::new(&mut self.workspace);
        self.symbolic
            .factorize_numeric_llt::<f64>(
                &mut self.factor_values,
                matrix,
                Side::Lower,
                LltRegularization::default(),
                Par::Seq,
                stack,
                Default::default(),
            )
            .map(|_| ())
            .map_err(
                |faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index }| index,
            )
    }

    /// Solves `matrix x = rhs` in place with the factor of the last
    /// successful [`Self::factorise`] (two triangular solves).
    pub fn solve(&mut self, rhs: &mut [f64]) {
        let llt = LltRef::<'_, usize, f64>::new(&self.symbolic, &self.factor_values);
        let stack = MemStack::new(&mut self.workspace);
        let n = rhs.len();
        llt.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, 1),
            Par::Seq,
            stack,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lower-triangle pattern of the 7-point Laplacian on an `n³` grid
    /// (unknown `x + n y + n² z`).
    fn grid_pattern(n: usize) -> (Vec<usize>, Vec<usize>) {
        let (mut col_ptr, mut row_idx) = (vec![0], Vec::new());
        for col in 0..n * n * n {
            row_idx.push(col);
            for stride in [1, n, n * n] {
                if col / stride % n + 1 < n {
                    row_idx.push(col + stride);
                }
            }
            col_ptr.push(row_idx.len());
        }
        (col_ptr, row_idx)
    }

    fn factor_entries(n: usize, order: Option<&[usize]>) -> (usize, usize) {
        let (col_ptr, row_idx) = grid_pattern(n);
        let dofs = n * n * n;
        let pattern = SymbolicSparseColMatRef::new_checked(dofs, dofs, &col_ptr, None, &row_idx);
        let inverse = order.map(|forward| {
            let mut inverse = vec![0; dofs];
            for (k, &unknown) in forward.iter().enumerate() {
                inverse[unknown] = k;
            }
            inverse
        });
        let alone = match (order, &inverse) {
            (Some(forward), Some(inverse)) => analyse_symbolic(
                pattern,
                SymmetricOrdering::Custom(PermRef::new_checked(forward, inverse, dofs)),
            ),
            _ => analyse_symbolic(pattern, SymmetricOrdering::Amd),
        }
        .unwrap()
        .len_val();
        let chosen =
            SparseCholesky::analyse(dofs, &col_ptr, &row_idx, order.zip(inverse.as_deref()))
                .unwrap()
                .factor_non_zeros();
        (alone, chosen)
    }

    /// The 7-point matrix of an `n³` grid with `diagonal` on the diagonal
    /// and -1 off it: positive definite for a diagonal above 6, indefinite
    /// below 6 - 6 cos(pi / (n + 1)) (its smallest eigenvalue is
    /// `diagonal - 6 cos(pi / (n + 1))`).
    fn grid_matrix(n: usize, diagonal: f64) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
        let (col_ptr, row_idx) = grid_pattern(n);
        let values = (0..n * n * n)
            .flat_map(|col| {
                let rows = &row_idx[col_ptr[col]..col_ptr[col + 1]];
                rows.iter()
                    .map(move |&row| if row == col { diagonal } else { -1.0 })
            })
            .collect();
        (col_ptr, row_idx, values)
    }

    #[test]
    fn an_indefinite_matrix_is_answered_with_its_first_bad_pivot() {
        let n = 4;
        let dofs = n * n * n;
        let (col_ptr, row_idx, _) = grid_matrix(n, 0.0);
        let mut cholesky = SparseCholesky::analyse(dofs, &col_ptr, &row_idx, None).unwrap();
        let pattern = SymbolicSparseColMatRef::new_checked(dofs, dofs, &col_ptr, None, &row_idx);
        // Smallest eigenvalue 6.5 - 6 cos(pi/5) = 1.646: positive definite,
        // and the solve inverts the matrix.
        let (_, _, definite) = grid_matrix(n, 6.5);
        let a = SparseColMatRef::new(pattern, &definite);
        assert_eq!(cholesky.factorise_if_positive_definite(a), Ok(()));
        let mut x = vec![1.0; dofs];
        cholesky.solve(&mut x);
        // A x = 1 for x = A^-1 1: check the residual through the full
        // symmetric product.
        let mut product = vec![0.0; dofs];
        for col in 0..dofs {
            for t in col_ptr[col]..col_ptr[col + 1] {
                let row = row_idx[t];
                product[row] += definite[t] * x[col];
                if row != col {
                    product[col] += definite[t] * x[row];
                }
            }
        }
        assert!(
            product.iter().all(|p| (p - 1.0).abs() < 1e-12),
            "{product:?}"
        );
        // Smallest eigenvalue 4 - 6 cos(pi/5) = -0.854: some pivot is not
        // positive, and both calls say so (the second in words).
        let (_, _, indefinite) = grid_matrix(n, 4.0);
        let a = SparseColMatRef::new(pattern, &indefinite);
        let pivot = cholesky.factorise_if_positive_definite(a).unwrap_err();
        assert!(pivot < dofs, "{pivot}");
        let message = cholesky.factorise(a).unwrap_err().to_string();
        assert!(
            message.contains(&format!("pivot {} of {dofs}", pivot + 1)),
            "{message}"
        );
        // Every pivot of a negative definite matrix is negative: the first fails.
        let (_, _, negative) = grid_matrix(n, -6.5);
        let a = SparseColMatRef::new(pattern, &negative);
        assert_eq!(cholesky.factorise_if_positive_definite(a), Err(0));
    }

    #[test]
    fn the_order_with_the_smaller_factor_is_kept() {
        let n = 16;
        let (amd, _) = factor_entries(n, None);
        // The natural (banded) order fills far more than AMD: AMD is kept.
        let natural: Vec<usize> = (0..n * n * n).collect();
        let (banded, chosen) = factor_entries(n, Some(&natural));
        assert!(banded > amd + amd / 4, "banded {banded}, AMD {amd}");
        assert_eq!(chosen, amd);
    }
}
