//! Issue 33, item 8: an overflowing coordinate (a vertex at 1e308 in the
//! file, `scale = 1e300`, `translate = [0, 1e39, 0]`) was reported as a
//! "degenerate element (signed volume 2.083e-2)". Now the vertex and its
//! coordinate are named, with the limit (the renderer's 32-bit floats) and,
//! when the file itself is fine, the transforms that moved it there.

use crate::cli_common as common;
use common::*;

/// Two tetrahedra as MEDIT text, vertex 5 at `x`.
fn medit(x: &str) -> String {
    format!(
        "MeshVersionFormatted 2\nDimension 3\nVertices\n5\n\
         0 0 1 0\n1 0 1 0\n0 1 1 0\n0 0 2 0\n{x} 1 2 0\n\
         Tetrahedra\n2\n1 2 3 4 0\n2 3 4 5 0\nEnd\n"
    )
}

fn scene(mesh_keys: &str) -> String {
    format!(
        "dimension = 3\n\n[mesh]\ngenerator = \"file\"\npath = \"m.mesh\"\n{mesh_keys}\n\
         [material]\nmodel = \"neo-hookean\"\nyoung = 100.0\npoisson = 0.3\n"
    )
}

#[test]
fn a_coordinate_beyond_the_renderers_range_is_named() {
    let tmp = tempfile::tempdir().unwrap();
    let cases = [
        ("1e308", "", "vertex 5 lies at 1e308, beyond ±3.4e38"),
        (
            "1",
            "scale = 1e300\n",
            "lies at 1e300 after scale, rotate and translate",
        ),
        (
            "1",
            "translate = [0.0, 1e39, 0.0]\n",
            "vertex 1 lies at 1e39 after scale, rotate and translate",
        ),
    ];
    for (x, keys, expected) in cases {
        std::fs::write(tmp.path().join("m.mesh"), medit(x)).unwrap();
        std::fs::write(tmp.path().join("s.toml"), scene(keys)).unwrap();
        let o = elasto(tmp.path(), &["check", "s.toml"]);
        assert_code(&o, 2);
        let err = stderr(&o);
        assert!(
            err.contains(expected) && err.contains("32-bit floats") && !err.contains("degenerate"),
            "{x} {keys}: {err}"
        );
    }
}
