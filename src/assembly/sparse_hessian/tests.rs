//! Tests of `sparse_hessian`.

use super::*;
use crate::assembly::sparse_cholesky::analyse_symbolic;
use faer::perm::PermRef;
use faer::sparse::SymbolicSparseColMatRef;
use faer::sparse::linalg::cholesky::SymmetricOrdering;

/// Two triangles that share no vertex: vertices 0-2 and 3-5.
fn two_triangles() -> Mesh<2> {
    let x = |a: f64, b: f64| Vector::<2>::new(a, b);
    Mesh::new(
        vec![
            x(0., 0.),
            x(1., 0.),
            x(0., 1.),
            x(3., 0.),
            x(4., 0.),
            x(3., 1.),
        ],
        vec![vec![0, 1, 2], vec![3, 4, 5]],
    )
    .unwrap()
}

/// A pattern grown pair by pair is the pattern built with all its pairs
/// at once: the same entries, gather lists, diagonal blocks and factor,
/// so the assembled matrix and its solution are the same bits.
fn grown_equals_built<const D: usize>(cells: [usize; D], pairs: &[(usize, usize)]) {
    let mesh =
        Mesh::axis_aligned_box(Vector::<D>::zeros(), Vector::<D>::repeat(1.0), cells).unwrap();
    let n = mesh.vertex_count();
    // Pin vertex 0 so that free and simulation ids differ.
    let free: Vec<Option<usize>> = (0..n).map(|v| v.checked_sub(1)).collect();
    let mut grown = SparseHessian::new(&mesh, free.clone()).unwrap();
    for chunk in pairs.chunks(3) {
        grown.include_pairs(chunk.iter().copied()).unwrap();
    }
    let mut built = SparseHessian::new(&mesh, free).unwrap();
    let mut source = built.source.clone();
    source.extra_pairs = grown.source.extra_pairs.clone();
    built = SparseHessian::build(source, built.free_index.clone(), 0).unwrap();
    assert!(
        grown.non_zeros()
            > SparseHessian::new(&mesh, built.free_index.clone())
                .unwrap()
                .non_zeros()
    );
    assert_eq!(grown.col_ptr, built.col_ptr);
    assert_eq!(grown.row_idx, built.row_idx);
    assert_eq!(grown.gather_offsets, built.gather_offsets);
    assert_eq!(grown.gather_sources, built.gather_sources);
    assert_eq!(grown.diagonal_block_entries, built.diagonal_block_entries);
    assert_eq!(grown.factor_non_zeros(), built.factor_non_zeros());
    // The same values assemble and solve to the same bits.
    let fill = |h: &mut SparseHessian<D>| {
        for (k, v) in h.element_buffer_mut().iter_mut().enumerate() {
            *v = ((k * 7919) % 101) as f64 * 1e-3;
        }
        h.clear();
        h.gather_element_buffer();
        for v in 1..n {
            h.add_vertex_block(v, &(Matrix::<D>::identity() * 10.0));
        }
        let mut rhs: Vec<f64> = (0..h.dofs()).map(|i| (i as f64).sin()).collect();
        h.factor_and_solve(&mut rhs).unwrap();
        rhs
    };
    assert_eq!(fill(&mut grown), fill(&mut built));
}

#[test]
fn a_grown_pattern_is_the_pattern_built_with_its_pairs() {
    // Pairs across the box (far in the mesh), some repeated, some
    // already in the pattern, one with the pinned vertex 0.
    grown_equals_built::<2>(
        [4, 3],
        &[
            (1, 19),
            (0, 7),
            (2, 13),
            (19, 1),
            (3, 4),
            (5, 18),
            (6, 17),
            (10, 16),
        ],
    );
    grown_equals_built::<3>(
        [3, 3, 2],
        &[
            (1, 40),
            (2, 33),
            (0, 41),
            (5, 30),
            (40, 1),
            (7, 8),
            (11, 29),
            (3, 44),
            (9, 35),
        ],
    );
}

#[test]
fn a_new_pair_grows_the_pattern_once_and_stencil_blocks_land_on_it() {
    let mesh = two_triangles();
    let free: Vec<Option<usize>> = (0..6).map(Some).collect();
    let mut hessian = SparseHessian::new(&mesh, free).unwrap();
    let before = hessian.non_zeros();
    assert_eq!(hessian.analyses(), 1);
    // Pairs within a triangle are in the pattern already.
    assert!(!hessian.include_pairs([(0, 1), (4, 5)]).unwrap());
    // A point-edge stencil (vertex 2 against edge 3-4) couples the two.
    assert!(hessian.include_pairs([(2, 3), (2, 4), (3, 4)]).unwrap());
    assert_eq!(hessian.analyses(), 2);
    // Two new 2x2 blocks in the lower triangle.
    assert_eq!(hessian.non_zeros(), before + 8);
    assert!(!hessian.include_pairs([(3, 2), (4, 2)]).unwrap());
    assert_eq!(hessian.analyses(), 2);
    // A stencil block over (2, 3, 4): local entry (a D + i, b D + k).
    let local = nalgebra::SMatrix::<f64, 6, 6>::from_fn(|r, c| {
        if r == c {
            10.0 + r as f64
        } else {
            1.0 / (1.0 + (r + c) as f64)
        }
    });
    hessian.clear();
    hessian.add_stencil(&[2, 3, 4], &local);
    let dense = hessian.to_dense();
    let vertices = [2, 3, 4];
    for (a, &va) in vertices.iter().enumerate() {
        for (b, &vb) in vertices.iter().enumerate() {
            for i in 0..2 {
                for k in 0..2 {
                    assert_eq!(
                        dense[(va * 2 + i, vb * 2 + k)],
                        local[(a * 2 + i, b * 2 + k)]
                    );
                }
            }
        }
    }
    assert_eq!(dense[(0, 0)], 0.0);
    // Releasing pins keeps the declared pairs: pin vertex 0, then free it again.
    let pinned = hessian
        .with_free_index(vec![None, Some(0), Some(1), Some(2), Some(3), Some(4)])
        .unwrap();
    assert_eq!(pinned.dofs(), 10);
    let mut released = pinned.with_free_index((0..6).map(Some).collect()).unwrap();
    assert_eq!(released.non_zeros(), before + 8);
    assert!(!released.include_pairs([(2, 3)]).unwrap());
    assert_eq!(released.analyses(), 4);
}

#[test]
fn packed_slots_number_the_lower_triangle_by_columns() {
    for d in [2, 3] {
        let size = d * (d + 1);
        let mut next = 0;
        for q in 0..size {
            for p in q..size {
                assert_eq!(element_slot_index(size, p, q), next);
                next += 1;
            }
        }
        assert_eq!(next, element_slot_len(d));
    }
}

/// Factor entries of the Hessian pattern of a box with `cells`: with the
/// nested dissection alone, with AMD alone, and as kept.
fn factor_entries<const D: usize>(cells: [usize; D]) -> (usize, usize, usize) {
    let mesh = Mesh::axis_aligned_box(Vector::<D>::zeros(), Vector::<D>::from_element(1.0), cells)
        .unwrap();
    let free: Vec<Option<usize>> = (0..mesh.vertex_count()).map(Some).collect();
    let hessian = SparseHessian::new(&mesh, free.clone()).unwrap();
    let dofs = hessian.dofs();
    let pattern =
        SymbolicSparseColMatRef::new_checked(dofs, dofs, &hessian.col_ptr, None, &hessian.row_idx);
    let (forward, inverse) = expand_to_unknowns::<D>(&free_vertex_order(
        &hessian.source,
        &free,
        mesh.vertex_count(),
    ));
    let dissection = analyse_symbolic(
        pattern,
        SymmetricOrdering::Custom(PermRef::new_checked(&forward, &inverse, dofs)),
    )
    .unwrap()
    .len_val();
    let amd = analyse_symbolic(pattern, SymmetricOrdering::Amd)
        .unwrap()
        .len_val();
    (dissection, amd, hessian.factor_non_zeros())
}

#[test]
fn the_elimination_order_with_the_smaller_factor_is_kept() {
    // 3D: the nested dissection fills less and is kept.
    let (dissection, amd, kept) = factor_entries([10, 10, 10]);
    assert!(
        dissection < amd,
        "nested dissection {dissection}, AMD {amd}"
    );
    assert_eq!(kept, dissection);
    // A small 2D mesh: AMD fills less and is kept.
    let (dissection, amd, kept) = factor_entries([40, 40]);
    assert!(
        amd < dissection,
        "nested dissection {dissection}, AMD {amd}"
    );
    assert_eq!(kept, amd);
}
