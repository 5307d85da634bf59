//! TetGen `.node` + `.ele` files (and Triangle's, their 2D sibling).
//!
//! Hand-written: no maintained Rust crate reads them. `.node`: a header
//! `points dimension attributes markers`, then per point its number, its
//! `dimension` coordinates, its attributes and (when `markers = 1`) a
//! boundary marker. `.ele`: a header `elements nodes-per-element attributes`,
//! then per element its number, its vertex numbers and its attributes. Numbers
//! start at 0 or 1 (the first point's number decides; TetGen's `-z`) and run
//! consecutively. `#` starts a comment. Elements with 10 (TetGen `-o2`) or 6
//! (Triangle `-o2`) nodes list their corners first: elasto keeps the corners
//! and the mid-edge nodes are left unreferenced (and so dropped).

use super::cursor::{Cursor, text_bytes};
use super::imported_mesh::{MeshBuilder, Numbering, Shape};
use super::{ImportedMesh, MeshImportError};
use std::path::{Path, PathBuf};

/// Reads `STEM.node` and `STEM.ele`; `path` is either of them.
pub(crate) fn read(path: &Path, dimension: usize) -> Result<ImportedMesh, MeshImportError> {
    let node_path = path.with_extension("node");
    let ele_path = path.with_extension("ele");
    let node_bytes = super::read_file(&node_path)?;
    let ele_bytes = super::read_file(&ele_path)?;

    let mut cursor = Cursor::new(&node_bytes, &node_path, Some(b'#'));
    let not_a_mesh = |path: &PathBuf, reason: &str| MeshImportError::NotAMesh {
        path: path.clone(),
        format: "TetGen",
        reason: reason.to_owned(),
    };
    if cursor.peek().is_none() {
        return Err(not_a_mesh(&node_path, "the file is empty"));
    }
    let header = |c: &mut Cursor, what: &'static str| {
        c.number::<usize>(|| format!("{what} in the header"))
            .map_err(|e| match e {
                MeshImportError::Syntax { .. } => not_a_mesh(
                    &node_path,
                    "the first line is not `points dimension attributes markers`",
                ),
                e => e,
            })
    };
    let count = header(&mut cursor, "the number of points")?;
    let file_dimension = header(&mut cursor, "the dimension")?;
    let attributes = header(&mut cursor, "the number of attributes")?;
    let markers = header(&mut cursor, "the number of boundary markers")?;
    if file_dimension != 2 && file_dimension != 3 {
        return Err(cursor.syntax(format!("dimension must be 2 or 3, found {file_dimension}")));
    }
    if markers > 1 {
        return Err(cursor.syntax(format!(
            "the number of boundary markers must be 0 or 1, found {markers}"
        )));
    }
    // Each attribute takes a number on every point's line; checked before
    // the sum below, which it could overflow.
    cursor.declared_count(attributes as u64, text_bytes(1), || {
        "attributes per point".into()
    })?;
    let extra_per_point = attributes + markers;
    let numbers_per_point = 1 + file_dimension + extra_per_point;
    cursor.declared_count(count as u64, text_bytes(numbers_per_point as u64), || {
        format!("points of {numbers_per_point} numbers each")
    })?;
    let format = if file_dimension == 3 {
        "TetGen .node/.ele"
    } else {
        "Triangle .node/.ele"
    };
    let mut builder: Option<MeshBuilder> = None;
    for k in 0..count {
        let what = || format!("point {} of {count}", k + 1);
        let label: i64 = cursor.number(what)?;
        let builder = builder.get_or_insert_with(|| {
            MeshBuilder::new(
                path.to_owned(),
                format.to_owned(),
                dimension,
                Numbering::Consecutive { first: label },
            )
        });
        if k == 0 {
            builder.reserve_points(count);
            if label != 0 && label != 1 {
                return Err(
                    cursor.syntax(format!("point numbers must start at 0 or 1, found {label}"))
                );
            }
        }
        let mut p = [0.0; 3];
        for c in p.iter_mut().take(file_dimension) {
            *c = cursor.number(what)?;
        }
        for _ in 0..extra_per_point {
            cursor.number::<f64>(what)?;
        }
        builder
            .add_point(label, p)
            .map_err(|reason| cursor.syntax(reason))?;
    }
    let mut builder = builder.unwrap_or_else(|| {
        MeshBuilder::new(
            path.to_owned(),
            format.to_owned(),
            dimension,
            Numbering::Consecutive { first: 1 },
        )
    });

    let mut cursor = Cursor::new(&ele_bytes, &ele_path, Some(b'#'));
    if cursor.peek().is_none() {
        return Err(not_a_mesh(&ele_path, "the file is empty"));
    }
    let count: usize = cursor.number(|| "the number of elements in the header".into())?;
    let nodes: usize = cursor.number(|| "the nodes per element in the header".into())?;
    let attributes: usize = cursor.number(|| "the number of attributes in the header".into())?;
    let (shape, corners) = match (file_dimension, nodes) {
        (3, 4 | 10) => (Shape::Tetrahedron, 4),
        (2, 3 | 6) => (Shape::Triangle, 3),
        _ => {
            return Err(cursor.syntax(format!(
                "a {file_dimension}D mesh needs {} nodes per element, found {nodes}",
                if file_dimension == 3 {
                    "4 or 10"
                } else {
                    "3 or 6"
                }
            )));
        }
    };
    cursor.declared_count(attributes as u64, text_bytes(1), || {
        "attributes per element".into()
    })?;
    let numbers_per_element = 1 + nodes + attributes;
    cursor.declared_count(count as u64, text_bytes(numbers_per_element as u64), || {
        format!("elements of {numbers_per_element} numbers each")
    })?;
    let mut vertices = vec![0i64; nodes];
    for k in 0..count {
        let what = || format!("element {} of {count}", k + 1);
        let label: i64 = cursor.number(what)?;
        for v in vertices.iter_mut() {
            *v = cursor.number(what)?;
        }
        for _ in 0..attributes {
            cursor.number::<f64>(what)?;
        }
        builder.add_element(shape.clone(), label, &vertices[..corners]);
    }
    builder.finish()
}
