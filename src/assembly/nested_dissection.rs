//! A fill-reducing elimination order for the sparse Cholesky: geometric nested dissection of the vertex graph.
//!
//! Eliminating the unknowns of a mesh in a good order is what keeps the
//! Cholesky factor sparse. Nested dissection (George 1973) finds a small
//! set of vertices, a **separator**, whose removal splits the graph into two
//! halves that share no edge; it orders each half first (recursively) and
//! the separator last. Eliminating a vertex of one half then never creates
//! fill in the other, and for a 3D mesh of `n` vertices the factor has
//! `O(n^{4/3})` non-zeros and costs `O(n^2)` flops, against `O(n^{5/3})` and
//! `O(n^{7/3})` for a banded or minimum-degree order of a cube (the order AMD
//! finds is close to banded there).
//!
//! The separators here are geometric, from the vertices' rest positions
//! (recursive coordinate bisection), which suits meshes: a vertex's
//! neighbours are near it.
//!
//! 1. Split the current vertex set at the median of its longest
//!    bounding-box axis (ties broken by vertex index, so the order is
//!    deterministic) into a low half `L` and a high half `H`.
//! 2. The vertices of `L` with a neighbour in `H`, and those of `H` with a
//!    neighbour in `L`, both separate `L` from `H`; take the smaller set `S`.
//!    No edge joins `L \ S` and `H \ S`.
//! 3. Order `L \ S`, then `H \ S` (each recursively), then `S`.
//!
//! Sets of at most `LEAF_SIZE` vertices are kept in their original
//! (mesh) order. The order is computed on the **vertex** graph (`D` times
//! fewer nodes than unknowns, `D^2` times fewer edges) and expanded to the
//! unknowns with each vertex's `D` components consecutive
//! ([`expand_to_unknowns`]); faer then uses it through
//! `SymmetricOrdering::Custom` with its supernodal factorisation, whose
//! dense blocks are the separators.
//!
//! A maintained METIS binding (`metis` on crates.io) builds the C library
//! (and needs a C toolchain and bindgen) at compile time; the geometric
//! dissection needs neither and is as good on the meshes elasto generates.

use crate::math::Vector;

/// Vertex sets at most this large are not split further.
const LEAF_SIZE: usize = 64;

/// The vertex graph: `neighbours[offsets[v]..offsets[v + 1]]` are the
/// vertices sharing an element with `v` (itself excluded).
pub struct VertexGraph<'a> {
    /// Start of each vertex's neighbour list (`vertex count + 1` entries).
    pub offsets: &'a [usize],
    /// The neighbour lists, one after the other.
    pub neighbours: &'a [usize],
}

impl VertexGraph<'_> {
    fn neighbours_of(&self, v: usize) -> &[usize] {
        &self.neighbours[self.offsets[v]..self.offsets[v + 1]]
    }
}

/// The nested-dissection elimination order of the vertices of `graph`
/// placed at `positions`: `order[k]` is the vertex eliminated `k`-th.
pub fn nested_dissection<const D: usize>(
    graph: &VertexGraph<'_>,
    positions: &[Vector<D>],
) -> Vec<usize> {
    let count = positions.len();
    let mut order = Vec::with_capacity(count);
    // Which part of the current split a vertex is in (scratch, per vertex).
    let mut side = vec![Side::Outside; count];
    let mut stack = vec![Task::Split((0..count).collect())];
    while let Some(task) = stack.pop() {
        match task {
            Task::Emit(vertices) => order.extend(vertices),
            Task::Split(vertices) if vertices.len() <= LEAF_SIZE => order.extend(vertices),
            Task::Split(mut vertices) => {
                let (low, high, separator) = bisect(graph, positions, &mut vertices, &mut side);
                // A stack: push in reverse of the order wanted.
                stack.push(Task::Emit(separator));
                stack.push(Task::Split(high));
                stack.push(Task::Split(low));
            }
        }
    }
    debug_assert_eq!(order.len(), count);
    order
}

/// A pending piece of work of the dissection.
enum Task {
    /// Order these vertices (split them further if large).
    Split(Vec<usize>),
    /// Append these vertices as they are (a separator).
    Emit(Vec<usize>),
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Side {
    Outside,
    Low,
    High,
}

/// Splits `vertices` at the median of their longest axis; returns the low
/// part, the high part (both without the separator) and the separator.
fn bisect<const D: usize>(
    graph: &VertexGraph<'_>,
    positions: &[Vector<D>],
    vertices: &mut [usize],
    side: &mut [Side],
) -> (Vec<usize>, Vec<usize>, Vec<usize>) {
    let (mut min, mut max) = (positions[vertices[0]], positions[vertices[0]]);
    for &v in vertices.iter() {
        min = min.inf(&positions[v]);
        max = max.sup(&positions[v]);
    }
    let axis = (max - min).imax();
    let middle = vertices.len() / 2;
    vertices.select_nth_unstable_by(middle, |&u, &w| {
        positions[u][axis]
            .total_cmp(&positions[w][axis])
            .then(u.cmp(&w))
    });
    let (low, high) = vertices.split_at(middle);
    low.iter().for_each(|&v| side[v] = Side::Low);
    high.iter().for_each(|&v| side[v] = Side::High);
    let touches = |v: usize, other: Side| graph.neighbours_of(v).iter().any(|&w| side[w] == other);
    let low_boundary: Vec<usize> = low
        .iter()
        .copied()
        .filter(|&v| touches(v, Side::High))
        .collect();
    let high_boundary: Vec<usize> = high
        .iter()
        .copied()
        .filter(|&v| touches(v, Side::Low))
        .collect();
    vertices.iter().for_each(|&v| side[v] = Side::Outside);
    let take_low = low_boundary.len() <= high_boundary.len();
    let separator = if take_low {
        low_boundary
    } else {
        high_boundary
    };
    let (mut low, mut high) = (low.to_vec(), high.to_vec());
    let split = if take_low { &mut low } else { &mut high };
    // Both lists are in `vertices` order: a merge-like removal.
    let mut in_separator = separator.iter().peekable();
    split.retain(|&v| {
        if in_separator.peek() == Some(&&v) {
            in_separator.next();
            false
        } else {
            true
        }
    });
    // Keep the mesh order inside the parts (deterministic, cache-friendly).
    low.sort_unstable();
    high.sort_unstable();
    let mut separator = separator;
    separator.sort_unstable();
    (low, high, separator)
}

/// The order of the unknowns from the order of the vertices, `D` unknowns per
/// vertex kept together: `(forward, inverse)` with `forward[k]` the unknown
/// eliminated `k`-th and `inverse[forward[k]] = k`.
pub fn expand_to_unknowns<const D: usize>(vertex_order: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let forward: Vec<usize> = vertex_order
        .iter()
        .flat_map(|&v| (0..D).map(move |k| v * D + k))
        .collect();
    let mut inverse = vec![0; forward.len()];
    for (k, &unknown) in forward.iter().enumerate() {
        inverse[unknown] = k;
    }
    (forward, inverse)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vector2;

    /// The 4-neighbour grid graph of `n x n` vertices.
    fn grid(n: usize) -> (Vec<usize>, Vec<usize>, Vec<Vector2>) {
        let (mut offsets, mut neighbours, mut positions) = (vec![0], Vec::new(), Vec::new());
        for j in 0..n {
            for i in 0..n {
                positions.push(Vector2::new(i as f64, j as f64));
                if i > 0 {
                    neighbours.push(j * n + i - 1);
                }
                if i + 1 < n {
                    neighbours.push(j * n + i + 1);
                }
                if j > 0 {
                    neighbours.push((j - 1) * n + i);
                }
                if j + 1 < n {
                    neighbours.push((j + 1) * n + i);
                }
                offsets.push(neighbours.len());
            }
        }
        (offsets, neighbours, positions)
    }

    #[test]
    fn the_order_is_a_permutation_and_the_top_separator_is_a_grid_line() {
        let n = 30;
        let (offsets, neighbours, positions) = grid(n);
        let graph = VertexGraph {
            offsets: &offsets,
            neighbours: &neighbours,
        };
        let order = nested_dissection(&graph, &positions);
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..n * n).collect::<Vec<_>>());
        // The last n vertices eliminated are the first separator: one full
        // grid line (a cut of a square needs n vertices, no fewer).
        let last: Vec<Vector2> = order[n * n - n..].iter().map(|&v| positions[v]).collect();
        let same_x = last.iter().all(|p| p.x == last[0].x);
        let same_y = last.iter().all(|p| p.y == last[0].y);
        assert!(
            same_x || same_y,
            "top separator is not a grid line: {last:?}"
        );
        // Removing it leaves two halves no edge joins: every vertex before it
        // lies strictly on one side.
        let (axis, at) = if same_x {
            (0, last[0].x)
        } else {
            (1, last[0].y)
        };
        for &v in &order[..n * n - n] {
            assert_ne!(positions[v][axis], at);
        }
    }

    #[test]
    fn unknowns_keep_each_vertex_together() {
        let (forward, inverse) = expand_to_unknowns::<3>(&[2, 0, 1]);
        assert_eq!(forward, vec![6, 7, 8, 0, 1, 2, 3, 4, 5]);
        for (k, &u) in forward.iter().enumerate() {
            assert_eq!(inverse[u], k);
        }
    }
}
