//! What the renderer sees of a simulation mesh, through the public
//! conversions (`RenderMesh::from_mesh`, `add_obstacle`,
//! `RenderFrame::from_positions`): every 2D triangle with unique edges, the
//! closed outward 3D boundary coloured by its tetrahedra, obstacles after the
//! bodies' vertices, and frames padded to 3D.

use elasto::math::{Vector2, Vector3};
use elasto::mesh::Mesh;
use elasto::render::{RenderFrame, RenderMesh};

#[test]
fn square_2d_has_all_triangles_and_unique_edges() {
    let mesh =
        Mesh::<2>::axis_aligned_box(Vector2::zeros(), Vector2::new(2.0, 1.0), [2, 1]).unwrap();
    let view = RenderMesh::from_mesh(&mesh);
    assert_eq!(view.dimension, 2);
    assert_eq!(view.triangles.len(), 4);
    assert_eq!(view.triangle_element, vec![0, 1, 2, 3]);
    assert_eq!(view.element_count, 4);
    // 2x1 cells: 7 grid edges + 2 diagonals.
    assert_eq!(view.edges.len(), 9);
    assert!(view.edges.iter().all(|e| e[0] < e[1]));
}

#[test]
fn obstacles_follow_the_bodies_vertices_with_their_own_triangles_and_edges() {
    let mesh =
        Mesh::<2>::axis_aligned_box(Vector2::zeros(), Vector2::new(1.0, 1.0), [1, 1]).unwrap();
    let mut view = RenderMesh::from_mesh(&mesh);
    // 2D: a quad outline of 4 facets, filled by 2 triangles, after 4 body vertices.
    view.add_obstacle(
        4,
        &[[0, 1], [1, 2], [2, 3], [3, 0]],
        &[[0, 1, 2], [0, 2, 3]],
    );
    assert_eq!(view.obstacle_triangles, vec![[4, 5, 6], [4, 6, 7]]);
    assert_eq!(view.obstacle_edges, vec![[4, 5], [5, 6], [6, 7], [7, 4]]);
    // 3D: a tetrahedron's 4 faces shaded, its 6 edges drawn once each.
    let mesh =
        Mesh::<3>::axis_aligned_box(Vector3::zeros(), Vector3::repeat(1.0), [1, 1, 1]).unwrap();
    let mut view = RenderMesh::from_mesh(&mesh);
    let faces = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
    view.add_obstacle(8, &faces, &[]);
    assert_eq!(view.obstacle_triangles[0], [8, 10, 9]);
    assert_eq!(view.obstacle_triangles.len(), 4);
    assert_eq!(
        view.obstacle_edges,
        vec![[8, 9], [8, 10], [8, 11], [9, 10], [9, 11], [10, 11]]
    );
}

#[test]
fn cube_3d_boundary_is_closed_outward_and_owned() {
    let mesh =
        Mesh::<3>::axis_aligned_box(Vector3::zeros(), Vector3::repeat(1.0), [2, 2, 2]).unwrap();
    let view = RenderMesh::from_mesh(&mesh);
    assert_eq!(view.dimension, 3);
    // 6 faces x 2x2 squares x 2 triangles.
    assert_eq!(view.triangles.len(), 48);
    assert_eq!(view.element_count, 48);
    // Closed surface: V - E + F = 2 with V = 26 boundary vertices.
    assert_eq!(26 - view.edges.len() as i64 + 48, 2);
    let x = mesh.rest_positions();
    let centre = Vector3::repeat(0.5);
    for (t, &e) in view.triangles.iter().zip(&view.triangle_element) {
        let p = t.map(|i| x[i as usize]);
        let normal = (p[1] - p[0]).cross(&(p[2] - p[0]));
        let mid = (p[0] + p[1] + p[2]) / 3.0;
        assert!(
            normal.dot(&(mid - centre)) > 0.0,
            "triangle {t:?} points inward"
        );
        // The owning tetrahedron holds all three vertices.
        let simplex = mesh.simplex(e as usize);
        assert!(
            t.iter().all(|&v| simplex.contains(&(v as usize))),
            "{t:?} not in element {e}"
        );
    }
}

#[test]
fn frame_from_2d_positions_pads_z() {
    let frame = RenderFrame::from_positions(&[Vector2::new(1.5, -2.0)], &[0.25]);
    assert_eq!(frame.positions, vec![[1.5, -2.0, 0.0]]);
    assert_eq!(frame.element_values, vec![0.25]);
}
