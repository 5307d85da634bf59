//! The global sparse Hessian over the free degrees of freedom: pattern, element slots and the deterministic gather.
//!
//! The sparsity pattern (vertex pairs that share an element, and the diagonal
//! blocks) is fixed by the mesh, so it is built once together with the
//! symbolic Cholesky factorisation ([`SparseCholesky`]); each Newton iteration
//! only refills the values and refactors numerically. Only the lower triangle
//! is stored. Pinned vertices are eliminated: they own no rows or columns.
//! See the [module documentation](super) for the gather and for how the
//! pattern grows for terms that couple vertices sharing no element.

use super::nested_dissection::{VertexGraph, expand_to_unknowns, nested_dissection};
use super::{FactorisationError, OrderKind, SparseCholesky};
use crate::math::{Matrix, Vector};
use crate::mesh::Mesh;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use rayon::prelude::*;

/// Entries per rayon task in the gather.
const ENTRIES_PER_TASK: usize = 4096;
/// Below this many stored entries the gather runs on the calling thread: a
/// rayon dispatch (waking a worker, tens of microseconds) would cost more
/// than the sums. The result is the same either way (each entry's sum has a
/// fixed order).
const PARALLEL_MIN_ENTRIES: usize = 4 * ENTRIES_PER_TASK;

/// Marker for an upper-triangle entry of a diagonal block (not stored).
const NOT_STORED: usize = usize::MAX;

/// Numbers per element Hessian slot: the lower triangle of the symmetric
/// `D(D+1)`-square element Hessian, packed by columns
/// ([`element_slot_index`]): 21 in 2D, 78 in 3D (not 36 and 144).
pub const fn element_slot_len(d: usize) -> usize {
    let size = d * (d + 1);
    size * (size + 1) / 2
}

/// Where the entry `(p, q)`, `p >= q`, of an element Hessian of size
/// `size` sits in its packed lower-triangle slot (column `q` holds rows
/// `q..size`, columns one after the other).
pub const fn element_slot_index(size: usize, p: usize, q: usize) -> usize {
    q * size - q * q.saturating_sub(1) / 2 + (p - q)
}

/// A symmetric sparse matrix over the free degrees of freedom of a mesh.
pub struct SparseHessian<const D: usize> {
    /// Vertex -> free vertex index.
    free_index: Vec<Option<usize>>,
    dofs: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    values: Vec<f64>,
    /// Per free vertex, `D x D` value indices of its diagonal block (column-major), lower part only.
    diagonal_block_entries: Vec<usize>,
    /// Element Hessian slots, [`element_slot_len`] per element (packed lower triangle).
    element_buffer: Vec<f64>,
    /// Element gradient slots, `D + 1` vectors per element (the energy terms
    /// fill them in the same pass as the Hessian slots and sum them per vertex).
    element_gradients: Vec<Vector<D>>,
    /// For each stored value, its sources in `element_buffer` (CSR; `u32`
    /// halves the largest list: 78 sources per tetrahedron).
    gather_offsets: Vec<usize>,
    gather_sources: Vec<u32>,
    cholesky: SparseCholesky,
    /// What the pattern is built from, kept to rebuild it when it grows.
    source: PatternSource<D>,
    /// Symbolic factorisations since construction (the first one included).
    analyses: usize,
}

/// The mesh's connectivity and rest positions (for the elimination order),
/// and the vertex pairs coupled beyond the mesh (contact stencils), as
/// simulation vertex ids `(low, high)`, sorted.
#[derive(Clone)]
struct PatternSource<const D: usize> {
    simplices: Vec<usize>,
    rest_positions: Vec<Vector<D>>,
    extra_pairs: Vec<(usize, usize)>,
}

impl<const D: usize> PatternSource<D> {
    fn simplices(&self) -> impl ExactSizeIterator<Item = &[usize]> + '_ {
        self.simplices.chunks_exact(D + 1)
    }

    fn element_count(&self) -> usize {
        self.simplices.len() / (D + 1)
    }
}

impl<const D: usize> SparseHessian<D> {
    /// The pattern of `mesh` with the vertices for which `free_index` is `Some` as unknowns.
    pub fn new(mesh: &Mesh<D>, free_index: Vec<Option<usize>>) -> Result<Self, FactorisationError> {
        Self::with_unattached_vertices(mesh, &[], free_index)
    }

    /// The pattern of `mesh` and of further vertices in no element (an
    /// obstacle's points, numbered after the mesh's, at rest at `extra`),
    /// with the vertices for which `free_index` is `Some` as unknowns.
    pub fn with_unattached_vertices(
        mesh: &Mesh<D>,
        extra: &[Vector<D>],
        free_index: Vec<Option<usize>>,
    ) -> Result<Self, FactorisationError> {
        let source = PatternSource {
            simplices: mesh.simplices().flatten().copied().collect(),
            rest_positions: [mesh.rest_positions(), extra].concat(),
            extra_pairs: Vec::new(),
        };
        Self::build(source, free_index, 0)
    }

    /// The same pattern with other vertices free (pinned vertices released):
    /// the mesh pairs and every extra pair declared so far are kept.
    pub fn with_free_index(
        &self,
        free_index: Vec<Option<usize>>,
    ) -> Result<Self, FactorisationError> {
        Self::build(self.source.clone(), free_index, self.analyses)
    }

    /// Makes sure the pattern holds the blocks coupling each pair of
    /// simulation vertices in `pairs` (pairs with a pinned vertex need
    /// none). Only when some pair is new is the pattern rebuilt, with the
    /// symbolic factorisation: returns whether it was. Pairs stay in the
    /// pattern once added (a contact that flickers costs no re-analysis).
    /// The values are cleared by a rebuild.
    pub fn include_pairs(
        &mut self,
        pairs: impl IntoIterator<Item = (usize, usize)>,
    ) -> Result<bool, FactorisationError> {
        let mut new_pairs = Vec::new();
        for (u, w) in pairs {
            let (Some(fu), Some(fw)) = (self.free_index[u], self.free_index[w]) else {
                continue;
            };
            if fu == fw || self.find_entry(fu.max(fw) * D, fu.min(fw) * D).is_some() {
                continue;
            }
            new_pairs.push((u.min(w), u.max(w)));
        }
        if new_pairs.is_empty() {
            return Ok(false);
        }
        new_pairs.sort_unstable();
        new_pairs.dedup();
        self.grow(&new_pairs)?;
        Ok(true)
    }

    /// Symbolic factorisations so far (1 for a pattern that never grew).
    pub fn analyses(&self) -> usize {
        self.analyses
    }

    /// The stored index of entry `(row, col)`, `row >= col`, if in the pattern.
    fn find_entry(&self, row: usize, col: usize) -> Option<usize> {
        let column = &self.row_idx[self.col_ptr[col]..self.col_ptr[col + 1]];
        column
            .binary_search(&row)
            .ok()
            .map(|k| self.col_ptr[col] + k)
    }

    /// Adds a stencil's Hessian block: `local` over the stacked coordinates
    /// of `vertices` (vertex `a`'s axis `k` at `a D + k`); rows and columns of
    /// pinned vertices are dropped. Every pair of free vertices of the stencil
    /// must be in the pattern ([`Self::include_pairs`]).
    ///
    /// # Panics
    /// When a pair of the stencil is not in the pattern.
    pub fn add_stencil<const N: usize>(
        &mut self,
        vertices: &[usize],
        local: &nalgebra::SMatrix<f64, N, N>,
    ) {
        for (b, &vb) in vertices.iter().enumerate() {
            let Some(fb) = self.free_index[vb] else {
                continue;
            };
            for (a, &va) in vertices.iter().enumerate() {
                let Some(fa) = self.free_index[va] else {
                    continue;
                };
                for k in 0..D {
                    for i in 0..D {
                        let (row, col) = (fa * D + i, fb * D + k);
                        if row < col {
                            continue;
                        }
                        let entry = self
                            .find_entry(row, col)
                            .expect("stencil pair declared with include_pairs");
                        self.values[entry] += local[(a * D + i, b * D + k)];
                    }
                }
            }
        }
    }

    fn build(
        source: PatternSource<D>,
        free_index: Vec<Option<usize>>,
        analyses: usize,
    ) -> Result<Self, FactorisationError> {
        let free_count = free_index.iter().flatten().count();
        let dofs = free_count * D;
        // Neighbouring free vertices with a larger or equal free index, per free vertex.
        let mut neighbours: Vec<Vec<usize>> = (0..free_count).map(|f| vec![f]).collect();
        for simplex in source.simplices() {
            for &u in simplex {
                for &w in simplex {
                    if let (Some(fu), Some(fw)) = (free_index[u], free_index[w])
                        && fw > fu
                    {
                        neighbours[fu].push(fw);
                    }
                }
            }
        }
        for &(u, w) in &source.extra_pairs {
            if let (Some(fu), Some(fw)) = (free_index[u], free_index[w]) {
                neighbours[fu.min(fw)].push(fu.max(fw));
            }
        }
        for list in &mut neighbours {
            list.sort_unstable();
            list.dedup();
        }
        let mut col_ptr = Vec::with_capacity(dofs + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for (fv, list) in neighbours.iter().enumerate() {
            for k in 0..D {
                let col = fv * D + k;
                for &fw in list {
                    for i in 0..D {
                        let row = fw * D + i;
                        if row >= col {
                            row_idx.push(row);
                        }
                    }
                }
                col_ptr.push(row_idx.len());
            }
        }
        let entry = |row: usize, col: usize| -> usize {
            let column = &row_idx[col_ptr[col]..col_ptr[col + 1]];
            col_ptr[col] + column.binary_search(&row).expect("entry in pattern")
        };
        let diagonal_block_entries = diagonal_block_entries::<D>(&col_ptr, &row_idx);
        // Gather lists: element-local entry (p, q) -> stored entry (row >= col),
        // read from the packed lower triangle (the element Hessian is symmetric).
        let size = D * (D + 1);
        let slot_len = element_slot_len(D);
        let element_count = source.element_count();
        if element_count.saturating_mul(slot_len) > u32::MAX as usize {
            return Err(FactorisationError(format!(
                "{element_count} elements are more than the assembly can index"
            )));
        }
        let mut contributions: Vec<(usize, u32)> = Vec::new();
        for (e, simplex) in source.simplices().enumerate() {
            for q in 0..size {
                let Some(fb) = free_index[simplex[q / D]] else {
                    continue;
                };
                let col = fb * D + q % D;
                for p in 0..size {
                    let Some(fa) = free_index[simplex[p / D]] else {
                        continue;
                    };
                    let row = fa * D + p % D;
                    if row >= col {
                        let (high, low) = (p.max(q), p.min(q));
                        let source = e * slot_len + element_slot_index(size, high, low);
                        contributions.push((entry(row, col), source as u32));
                    }
                }
            }
        }
        // A counting sort by target, stable: each entry's sources keep the
        // element order (O(n), where a comparison sort of the million
        // contributions of a 12k-tetrahedron mesh took tens of milliseconds).
        let mut gather_offsets = vec![0usize; row_idx.len() + 1];
        for &(target, _) in &contributions {
            gather_offsets[target + 1] += 1;
        }
        for t in 0..row_idx.len() {
            gather_offsets[t + 1] += gather_offsets[t];
        }
        let mut gather_sources = vec![0u32; contributions.len()];
        let mut fill = gather_offsets.clone();
        for &(target, source) in &contributions {
            gather_sources[fill[target]] = source;
            fill[target] += 1;
        }
        drop(contributions);

        let vertex_order = free_vertex_order(&source, &free_index, free_count);
        let (forward, inverse) = expand_to_unknowns::<D>(&vertex_order);
        let cholesky = SparseCholesky::analyse(
            dofs,
            &col_ptr,
            &row_idx,
            (dofs > 0).then_some((&forward[..], &inverse[..])),
        )?;
        let values = vec![0.0; row_idx.len()];
        Ok(Self {
            free_index,
            dofs,
            col_ptr,
            row_idx,
            values,
            diagonal_block_entries,
            element_buffer: vec![0.0; element_count * slot_len],
            element_gradients: vec![Vector::<D>::zeros(); element_count * (D + 1)],
            gather_offsets,
            gather_sources,
            cholesky,
            source,
            analyses: analyses + 1,
        })
    }

    /// Adds `new_pairs` (simulation vertex ids `(low, high)`, sorted, both
    /// free, none in the pattern yet) to the pattern. Entries are only
    /// inserted, so every stored entry keeps its sources and their order: the
    /// gather lists are carried over by one merge per column instead of
    /// being built again, and the symbolic factorisation is redone in the
    /// kind of elimination order the first analysis chose.
    fn grow(&mut self, new_pairs: &[(usize, usize)]) -> Result<(), FactorisationError> {
        let free = |v: usize| self.free_index[v].expect("pairs of free vertices");
        // The new neighbours of each free vertex with a larger free index.
        let mut added: Vec<(usize, usize)> = new_pairs
            .iter()
            .map(|&(u, w)| {
                let (fu, fw) = (free(u), free(w));
                (fu.min(fw), fu.max(fw))
            })
            .collect();
        added.sort_unstable();
        let mut col_ptr = Vec::with_capacity(self.col_ptr.len());
        let mut row_idx = Vec::with_capacity(self.row_idx.len() + added.len() * D * D);
        let mut gather_offsets =
            Vec::with_capacity(self.gather_offsets.len() + added.len() * D * D);
        col_ptr.push(0);
        gather_offsets.push(0);
        let mut next = 0;
        for col in 0..self.dofs {
            let fv = col / D;
            let start = next;
            while next < added.len() && added[next].0 == fv {
                next += 1;
            }
            let mut inserted = added[start..next]
                .iter()
                .flat_map(|&(_, fw)| (0..D).map(move |i| fw * D + i))
                .peekable();
            if col % D != D - 1 {
                next = start;
            }
            let mut old = (self.col_ptr[col]..self.col_ptr[col + 1]).peekable();
            loop {
                let take_old = match (old.peek(), inserted.peek()) {
                    (Some(&t), Some(&row)) => self.row_idx[t] < row,
                    (Some(_), None) => true,
                    (None, Some(_)) => false,
                    (None, None) => break,
                };
                let sources = if take_old {
                    let t = old.next().expect("peeked");
                    row_idx.push(self.row_idx[t]);
                    self.gather_offsets[t + 1] - self.gather_offsets[t]
                } else {
                    row_idx.push(inserted.next().expect("peeked"));
                    0
                };
                gather_offsets.push(gather_offsets.last().copied().unwrap_or(0) + sources);
            }
            col_ptr.push(row_idx.len());
        }
        self.source.extra_pairs.extend_from_slice(new_pairs);
        self.source.extra_pairs.sort_unstable();
        self.source.extra_pairs.dedup();
        self.col_ptr = col_ptr;
        self.row_idx = row_idx;
        self.gather_offsets = gather_offsets;
        self.values = vec![0.0; self.row_idx.len()];
        self.diagonal_block_entries = diagonal_block_entries::<D>(&self.col_ptr, &self.row_idx);
        let vertex_order = (self.cholesky.order_kind() == OrderKind::Given)
            .then(|| free_vertex_order(&self.source, &self.free_index, self.dofs / D));
        let order = vertex_order.as_deref().map(expand_to_unknowns::<D>);
        self.cholesky = self.cholesky.reanalyse(
            self.dofs,
            &self.col_ptr,
            &self.row_idx,
            order.as_ref().map(|(f, i)| (&f[..], &i[..])),
        )?;
        self.analyses += 1;
        Ok(())
    }

    /// Number of scalar unknowns.
    pub fn dofs(&self) -> usize {
        self.dofs
    }

    /// Stored non-zeros of the Cholesky factor `L`.
    pub fn factor_non_zeros(&self) -> usize {
        self.cholesky.factor_non_zeros()
    }

    /// Stored (lower-triangle) non-zeros.
    pub fn non_zeros(&self) -> usize {
        self.row_idx.len()
    }

    /// Vertex -> free vertex index.
    pub fn free_index(&self) -> &[Option<usize>] {
        &self.free_index
    }

    /// Sets every value to zero (the pattern stays).
    pub fn clear(&mut self) {
        self.values.fill(0.0);
    }

    /// Adds `block` to the diagonal block of `vertex` (ignored for a pinned vertex).
    pub fn add_vertex_block(&mut self, vertex: usize, block: &Matrix<D>) {
        let Some(fv) = self.free_index[vertex] else {
            return;
        };
        for j in 0..D {
            for i in j..D {
                self.values[self.diagonal_block_entries[fv * D * D + j * D + i]] += block[(i, j)];
            }
        }
    }

    /// Per-element slots for element Hessians: [`element_slot_len`] values
    /// per element, the lower triangle packed by columns
    /// ([`element_slot_index`]), local unknown `a D + k` for vertex `a`, axis `k`.
    pub fn element_buffer_mut(&mut self) -> &mut [f64] {
        &mut self.element_buffer
    }

    /// The element Hessian slots (as [`Self::element_buffer_mut`]) and the
    /// element gradient slots (`D + 1` vectors per element), to fill in one pass.
    pub fn element_slots_mut(&mut self) -> (&mut [f64], &mut [Vector<D>]) {
        (&mut self.element_buffer, &mut self.element_gradients)
    }

    /// Adds the element slots into the stored values (deterministic; in
    /// parallel for large matrices).
    pub fn gather_element_buffer(&mut self) {
        let (offsets, sources, buffer) = (
            &self.gather_offsets,
            &self.gather_sources,
            &self.element_buffer,
        );
        let gather = |(t, value): (usize, &mut f64)| {
            for &source in &sources[offsets[t]..offsets[t + 1]] {
                *value += buffer[source as usize];
            }
        };
        if self.values.len() < PARALLEL_MIN_ENTRIES {
            self.values.iter_mut().enumerate().for_each(gather);
        } else {
            self.values
                .par_iter_mut()
                .with_min_len(ENTRIES_PER_TASK)
                .enumerate()
                .for_each(gather);
        }
    }

    /// The full symmetric matrix as dense (for tests and small problems).
    pub fn to_dense(&self) -> nalgebra::DMatrix<f64> {
        let mut dense = nalgebra::DMatrix::zeros(self.dofs, self.dofs);
        for col in 0..self.dofs {
            for t in self.col_ptr[col]..self.col_ptr[col + 1] {
                let row = self.row_idx[t];
                dense[(row, col)] = self.values[t];
                dense[(col, row)] = self.values[t];
            }
        }
        dense
    }

    /// Copies per-vertex vectors of free vertices into a flat unknown vector.
    pub fn gather_free(&self, per_vertex: &[Vector<D>], flat: &mut [f64]) {
        for (v, fv) in self.free_index.iter().enumerate() {
            if let Some(fv) = fv {
                flat[fv * D..fv * D + D].copy_from_slice(per_vertex[v].as_slice());
            }
        }
    }

    /// Spreads a flat unknown vector to per-vertex vectors (zero for pinned vertices).
    pub fn scatter_free(&self, flat: &[f64], per_vertex: &mut [Vector<D>]) {
        for (v, fv) in self.free_index.iter().enumerate() {
            per_vertex[v] = match fv {
                Some(fv) => Vector::<D>::from_column_slice(&flat[fv * D..fv * D + D]),
                None => Vector::<D>::zeros(),
            };
        }
    }

    /// Factorises the current values (reusing the symbolic factorisation).
    /// Sequential, so results do not depend on the thread count.
    pub fn factorise(&mut self) -> Result<(), FactorisationError> {
        let matrix = compressed_columns(self.dofs, &self.col_ptr, &self.row_idx, &self.values);
        self.cholesky.factorise(matrix)
    }

    /// Factorises the current values if they are numerically positive
    /// definite and says whether they were; an indefinite matrix is an
    /// answer here, not an error, and costs no allocation (Newton with
    /// projection on demand tries the unprojected Hessian this way). After
    /// `false` there is no usable factor until the next factorisation.
    pub fn factorise_if_positive_definite(&mut self) -> bool {
        let matrix = compressed_columns(self.dofs, &self.col_ptr, &self.row_idx, &self.values);
        self.cholesky.factorise_if_positive_definite(matrix).is_ok()
    }

    /// Solves `H x = rhs` in place with the factor of the last successful
    /// [`Self::factorise`].
    pub fn solve(&mut self, rhs: &mut [f64]) {
        self.cholesky.solve(rhs);
    }

    /// Factorises the current values and solves `H x = rhs` in place.
    pub fn factor_and_solve(&mut self, rhs: &mut [f64]) -> Result<(), FactorisationError> {
        self.factorise()?;
        self.solve(rhs);
        Ok(())
    }

    /// The stored lower triangle in compressed columns: `(col_ptr, row_idx,
    /// values)` (to write the matrix out, e.g. for benchmarks).
    pub fn lower_triangle(&self) -> (&[usize], &[usize], &[f64]) {
        (&self.col_ptr, &self.row_idx, &self.values)
    }
}

/// Per free vertex, the stored indices of its `D x D` diagonal block
/// (column-major; [`NOT_STORED`] above the diagonal) in the lower-triangle
/// pattern `(col_ptr, row_idx)`, which holds every diagonal block.
fn diagonal_block_entries<const D: usize>(col_ptr: &[usize], row_idx: &[usize]) -> Vec<usize> {
    let entry = |row: usize, col: usize| -> usize {
        let column = &row_idx[col_ptr[col]..col_ptr[col + 1]];
        col_ptr[col]
            + column
                .binary_search(&row)
                .expect("diagonal block in pattern")
    };
    let free_count = (col_ptr.len() - 1) / D;
    let mut entries = vec![NOT_STORED; free_count * D * D];
    for fv in 0..free_count {
        for j in 0..D {
            for i in j..D {
                entries[fv * D * D + j * D + i] = entry(fv * D + i, fv * D + j);
            }
        }
    }
    entries
}

/// A stored lower triangle as faer's compressed-column matrix.
fn compressed_columns<'a>(
    dofs: usize,
    col_ptr: &'a [usize],
    row_idx: &'a [usize],
    values: &'a [f64],
) -> SparseColMatRef<'a, usize, f64> {
    SparseColMatRef::new(
        SymbolicSparseColMatRef::new_checked(dofs, dofs, col_ptr, None, row_idx),
        values,
    )
}

/// The nested-dissection order of the free vertices (by free index), from
/// their rest positions and the graph of free vertices sharing an element
/// (or an extra pair).
fn free_vertex_order<const D: usize>(
    source: &PatternSource<D>,
    free_index: &[Option<usize>],
    free_count: usize,
) -> Vec<usize> {
    let mut adjacent: Vec<Vec<usize>> = vec![Vec::new(); free_count];
    for &(u, w) in &source.extra_pairs {
        if let (Some(fu), Some(fw)) = (free_index[u], free_index[w]) {
            adjacent[fu].push(fw);
            adjacent[fw].push(fu);
        }
    }
    for simplex in source.simplices() {
        for &u in simplex {
            for &w in simplex {
                if let (Some(fu), Some(fw)) = (free_index[u], free_index[w])
                    && fu != fw
                {
                    adjacent[fu].push(fw);
                }
            }
        }
    }
    let mut offsets = Vec::with_capacity(free_count + 1);
    let mut neighbours = Vec::new();
    offsets.push(0);
    for mut list in adjacent {
        list.sort_unstable();
        list.dedup();
        neighbours.extend(list);
        offsets.push(neighbours.len());
    }
    let mut positions = vec![Vector::<D>::zeros(); free_count];
    for (v, fv) in free_index.iter().enumerate() {
        if let Some(fv) = fv {
            positions[*fv] = source.rest_positions[v];
        }
    }
    let graph = VertexGraph {
        offsets: &offsets,
        neighbours: &neighbours,
    };
    nested_dissection(&graph, &positions)
}

#[cfg(test)]
mod tests;
