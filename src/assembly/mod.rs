//! Global assembly: the sparsity pattern over the free unknowns, the deterministic gather of element blocks, and the sparse Cholesky solve.
//!
//! # What lives here
//!
//! * [`SparseHessian`]: a symmetric block-sparse matrix over the free
//!   (unpinned) vertices, `D x D` blocks, lower triangle stored in compressed
//!   columns. Its pattern holds every pair of free vertices that share an
//!   element, plus the diagonal blocks.
//! * The **gather**: element Hessians are written into per-element slots
//!   (in parallel, one slot per element, so no two threads write the same
//!   number) and every stored entry then sums its contributions from those
//!   slots in an order fixed when the pattern was built. The sum therefore does
//!   not depend on the thread count: results are bitwise reproducible.
//! * [`SparseCholesky`]: faer's supernodal sparse `L L^T`, in the
//!   nested-dissection order of `nested_dissection.rs` (geometric, on the
//!   vertex graph). The symbolic factorisation
//!   (ordering, elimination tree, supernodes) is computed once per pattern;
//!   each Newton iteration only refills values and refactors numerically. A
//!   non-positive pivot is a typed [`FactorisationError`], never a panic.
//!
//! # Terms that couple vertices sharing no element (design)
//!
//! Contact between bodies, or friction between a vertex and an edge, adds
//! Hessian blocks between vertices that share no element, and which pairs
//! those are changes as the motion goes on. The pattern is designed to grow:
//!
//! 1. The pattern is the union of the **mesh pairs** (fixed at setup) and a
//!    set of **extra pairs** `(u, w)` that terms declare at the start of each
//!    Newton iteration (the candidate pairs within their activation distance).
//! 2. Before assembly, the declared pairs are compared with the pairs already
//!    in the pattern. Only if some pair is new is the pattern rebuilt (column
//!    pointers, row indices, gather lists) **and the symbolic factorisation
//!    redone**; pairs that fall out of range stay in the pattern with zero
//!    blocks until the next rebuild, so a contact that flickers on and off
//!    does not trigger re-analysis every iteration.
//! 3. Extra blocks are added through their own entry lists (pair -> stored
//!    entries, computed at rebuild), after the element gather and in pair
//!    order, so the sum stays deterministic.
//!
//! No term declares extra pairs yet (the ground barrier only touches diagonal
//! blocks), so step 1's set is empty and the symbolic factorisation is done
//! exactly once, in [`SparseHessian::new`].

mod nested_dissection;
mod sparse_cholesky;
mod sparse_hessian;

pub use sparse_cholesky::{FactorisationError, SparseCholesky};
pub use sparse_hessian::{SparseHessian, element_slot_index, element_slot_len};
