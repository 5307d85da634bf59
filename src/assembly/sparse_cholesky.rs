//! Sparse Cholesky `H = L L^T` with faer: one symbolic analysis per pattern, a numeric refactorisation per Newton iteration.
//!
//! The elimination order is the caller's (the nested dissection of
//! [`super::nested_dissection`], through `SymmetricOrdering::Custom`), and
//! the factorisation is forced supernodal: with a nested-dissection order
//! the separators become dense blocks, which faer factorises with dense
//! kernels (the simplicial variant works one column at a time). Without an
//! order (an empty matrix), faer's AMD is used.

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
    factor_values: Vec<f64>,
    workspace: MemBuffer,
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
    /// is the unknown eliminated `k`-th; `None`: AMD).
    pub fn analyse(
        dofs: usize,
        col_ptr: &[usize],
        row_idx: &[usize],
        order: Option<(&[usize], &[usize])>,
    ) -> Result<Self, FactorisationError> {
        let pattern = SymbolicSparseColMatRef::new_checked(dofs, dofs, col_ptr, None, row_idx);
        let ordering = match order {
            Some((forward, inverse)) => {
                SymmetricOrdering::Custom(PermRef::new_checked(forward, inverse, dofs))
            }
            None => SymmetricOrdering::Amd,
        };
        let symbolic = factorize_symbolic_cholesky(
            pattern,
            Side::Lower,
            ordering,
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
                ..Default::default()
            },
        )
        .map_err(|e| FactorisationError(format!("{e:?}")))?;
        let factor_values = vec![0.0; symbolic.len_val()];
        let workspace = MemBuffer::new(
            symbolic
                .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default())
                .or(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq)),
        );
        Ok(Self {
            symbolic,
            factor_values,
            workspace,
        })
    }

    /// Factorises `matrix` (same pattern as analysed), keeping `L` for
    /// [`Self::solve`]. Sequential, so results do not depend on the thread
    /// count.
    pub fn factorise(
        &mut self,
        matrix: SparseColMatRef<'_, usize, f64>,
    ) -> Result<(), FactorisationError> {
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
            .map_err(|e| FactorisationError(format!("{e:?}")))?;
        Ok(())
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
