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
//! # Terms that couple vertices sharing no element
//!
//! Contact between bodies adds Hessian blocks between vertices that share
//! no element, and which pairs those are changes as the motion goes on. The
//! pattern grows:
//!
//! 1. The pattern is the union of the **mesh pairs** (fixed at setup) and a
//!    set of **extra pairs** of vertices that terms declare at the start of
//!    each Newton iteration (`EnergyTerm::coupled_pairs`: the corners of the
//!    active contact stencils).
//! 2. [`SparseHessian::include_pairs`] looks each declared pair up in the
//!    pattern. Only if some pair is new does the pattern grow: the new
//!    entries are merged into each column, and since entries are only
//!    inserted, every stored entry keeps its gather sources (one pass, no
//!    sort); the elimination order is computed again in the kind the first
//!    analysis chose (nested dissection or AMD), **and the symbolic
//!    factorisation redone** ([`SparseHessian::analyses`] counts them). A
//!    grown pattern is exactly the one built with all its pairs at once.
//!    Pairs that fall out of range stay in the pattern with zero
//!    blocks, so a contact that flickers on and off costs no re-analysis, and
//!    once the pattern holds every pair a scene needs, an iteration allocates
//!    nothing for it.
//! 3. Stencil blocks are added by [`SparseHessian::add_stencil`] after the
//!    element gather, in the term's fixed stencil order, so the sum stays
//!    deterministic.
//!
//! Releasing pinned vertices ([`SparseHessian::with_free_index`]) keeps the
//! extra pairs.

mod nested_dissection;
mod sparse_cholesky;
mod sparse_hessian;

pub use sparse_cholesky::{FactorisationError, OrderKind, SparseCholesky};
pub use sparse_hessian::{SparseHessian, element_slot_index, element_slot_len};
