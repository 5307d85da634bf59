//! Mesh generation, rest data, lumped masses, boundary extraction and bad-element rejection.

use elasto::math::determinant;
use elasto::math::{Vector, Vector2, Vector3};
use elasto::mesh::{Mesh, MeshError, edge_matrix};

fn boxed<const D: usize>(cells: [usize; D]) -> Mesh<D> {
    Mesh::axis_aligned_box(
        Vector::<D>::zeros(),
        Vector::<D>::from_fn(|k, _| 1.0 + k as f64),
        cells,
    )
    .unwrap()
}

#[test]
fn box_generators_have_the_expected_counts_volume_and_mass() {
    let square = boxed::<2>([5, 5]);
    assert_eq!(square.vertex_count(), 36);
    assert_eq!(square.element_count(), 50);
    assert!((square.rest_volume() - 2.0).abs() < 1e-12);
    let cube = boxed::<3>([2, 3, 4]);
    assert_eq!(cube.vertex_count(), 3 * 4 * 5);
    assert_eq!(cube.element_count(), 6 * 24);
    assert!((cube.rest_volume() - 6.0).abs() < 1e-12);
    let masses = cube.lumped_masses(2.5);
    assert!((masses.iter().sum::<f64>() - 15.0).abs() < 1e-12);
    assert!(masses.iter().all(|m| *m > 0.0));
}

#[test]
fn every_generated_element_is_positively_oriented_with_its_rest_data() {
    let cube = boxed::<3>([3, 2, 2]);
    for (e, simplex) in cube.simplices().enumerate() {
        let dm = edge_matrix(cube.rest_positions(), simplex);
        let rest = cube.rest_elements()[e];
        assert!(determinant(&dm) > 0.0);
        assert!((rest.volume - determinant(&dm) / 6.0).abs() < 1e-14);
        assert!((rest.dm_inv * dm - elasto::math::Matrix::<3>::identity()).amax() < 1e-12);
    }
}

#[test]
fn boundary_facets_cover_the_surface_with_outward_normals() {
    // 2D: the boundary edges of a 3 x 2 box are 2 * (3 + 2) = 10, counter-clockwise:
    // the signed area from the shoelace formula over them is the box area.
    let square = Mesh::axis_aligned_box(Vector2::zeros(), Vector2::new(3.0, 2.0), [3, 2]).unwrap();
    let edges = square.boundary_facets();
    assert_eq!(edges.len(), 10);
    let x = square.rest_positions();
    let area: f64 = edges
        .iter()
        .map(|[a, b]| 0.5 * (x[*a].x * x[*b].y - x[*b].x * x[*a].y))
        .sum();
    assert!((area - 6.0).abs() < 1e-12, "signed area {area}");
    // 3D: 2 triangles per boundary cell face; the divergence theorem with
    // outward normals gives the volume.
    let cube =
        Mesh::axis_aligned_box(Vector3::zeros(), Vector3::new(1.0, 2.0, 3.0), [2, 2, 3]).unwrap();
    let faces = cube.boundary_facets();
    assert_eq!(faces.len(), 2 * 2 * (2 * 2 + 2 * 3 + 2 * 3));
    let x = cube.rest_positions();
    let volume: f64 = faces
        .iter()
        .map(|[a, b, c]| x[*a].dot(&x[*b].cross(&x[*c])) / 6.0)
        .sum();
    assert!((volume - 6.0).abs() < 1e-12, "enclosed volume {volume}");
}

#[test]
fn degenerate_and_inverted_rest_elements_are_rejected_by_name() {
    let x = vec![
        Vector2::new(0.0, 0.0),
        Vector2::new(1.0, 0.0),
        Vector2::new(0.0, 1.0),
        Vector2::new(2.0, 0.0),
    ];
    let inverted = Mesh::new(x.clone(), vec![vec![0, 1, 2], vec![0, 2, 1]]).unwrap_err();
    assert!(
        matches!(
            &inverted,
            MeshError::BadRestElement {
                element: 1,
                kind: "inverted",
                ..
            }
        ),
        "{inverted:?}"
    );
    assert!(
        inverted
            .to_string()
            .contains("element 1 with vertices [0, 2, 1] is inverted"),
        "{inverted}"
    );
    let degenerate = Mesh::new(x.clone(), vec![vec![0, 1, 3]]).unwrap_err();
    assert!(
        matches!(
            &degenerate,
            MeshError::BadRestElement {
                element: 0,
                kind: "degenerate",
                ..
            }
        ),
        "{degenerate:?}"
    );
    let out_of_range = Mesh::new(x, vec![vec![0, 1, 7]]).unwrap_err();
    assert_eq!(
        out_of_range,
        MeshError::VertexOutOfRange {
            element: 0,
            vertex: 7,
            vertex_count: 4
        }
    );
    assert!(Mesh::<2>::axis_aligned_box(Vector2::zeros(), Vector2::new(1.0, 1.0), [0, 3]).is_err());
    assert!(
        Mesh::<2>::axis_aligned_box(Vector2::zeros(), Vector2::new(-1.0, 1.0), [2, 3]).is_err()
    );
}

/// Regression: `Mesh::new` panicked on a simplex with the wrong number of
/// vertices although it returns a `Result`.
#[test]
fn a_simplex_with_the_wrong_vertex_count_is_an_error_not_a_panic() {
    let x = vec![
        Vector2::new(0.0, 0.0),
        Vector2::new(1.0, 0.0),
        Vector2::new(0.0, 1.0),
        Vector2::new(1.0, 1.0),
    ];
    let error = Mesh::new(x, vec![vec![0, 1, 2], vec![1, 3, 2, 0]]).unwrap_err();
    assert_eq!(
        error,
        MeshError::WrongVertexCount {
            element: 1,
            count: 4,
            expected: 3
        }
    );
    assert_eq!(
        error.to_string(),
        "element 1 lists 4 vertices, but a simplex here has 3"
    );
}
