//! Issue 33, items 2 and 9: the mesh readers trusted the counts a file's
//! header declares (10^12 nodes in a 100-byte file reserved memory for
//! millions before finding the end; a TetGen `attributes` of 2^64 - 1 wrapped
//! to 0 and the file was read as valid) and read files of any size. Now every
//! declared count is checked against what the rest of the file can hold
//! before anything is allocated, and a file over 2 GiB is refused unread:
//! exit 2, naming the file, the count and the limit.

use crate::cli_common as common;
use common::*;
use std::path::Path;

/// A one-body 3D scene reading its mesh from `path`.
fn mesh_scene(path: &str) -> String {
    format!(
        "dimension = 3\n[mesh]\ngenerator = \"file\"\npath = \"{path}\"\n\
         [material]\nmodel = \"neo-hookean\"\nyoung = 300.0\npoisson = 0.3\n"
    )
}

/// `check` of a scene reading `mesh` (written into `dir` with the other
/// `files`): exit 2, and the message holds each of `words`.
fn refused(files: &[(&str, &str)], mesh: &str, words: &[&str]) {
    let tmp = tempfile::tempdir().unwrap();
    for (name, text) in files {
        std::fs::write(tmp.path().join(name), text).unwrap();
    }
    std::fs::write(tmp.path().join("s.toml"), mesh_scene(mesh)).unwrap();
    let o = elasto(tmp.path(), &["check", "s.toml"]);
    assert_code(&o, 2);
    let err = stderr(&o);
    assert!(!err.contains("panicked"), "{err}");
    for word in words {
        assert!(err.contains(word), "{mesh}: no `{word}` in: {err}");
    }
}

const TERA: &str = "1000000000000";

#[test]
fn a_count_beyond_the_file_is_refused_in_every_format() {
    let beyond = |what: &str| format!("the file declares {TERA} {what}, more than the");
    refused(
        &[(
            "a.msh",
            &format!("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n{TERA}\n1 0 0 0\n$EndNodes\n"),
        )],
        "a.msh",
        &["a.msh:5:", &beyond("nodes")],
    );
    refused(
        &[(
            "b.msh",
            &format!(
                "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 {TERA} 1 1\n3 1 0 1\n1\n0 0 0\n$EndNodes\n"
            ),
        )],
        "b.msh",
        &["b.msh", &beyond("nodes")],
    );
    refused(
        &[(
            "c.msh",
            &format!(
                "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 0 0\n$EndNodes\n\
                 $Elements\n{TERA}\n1 15 0 1\n$EndElements\n"
            ),
        )],
        "c.msh",
        &["c.msh", &beyond("elements")],
    );
    refused(
        &[(
            "d.mesh",
            &format!("MeshVersionFormatted 1\nDimension 3\nVertices {TERA}\n0 0 0 0\nEnd\n"),
        )],
        "d.mesh",
        &["d.mesh:3:", &beyond("vertices")],
    );
    refused(
        &[
            ("e.node", &format!("{TERA} 3 0 0\n1 0 0 0\n")),
            ("e.ele", "1 4 0\n1 1 2 3 4\n"),
        ],
        "e.node",
        &["e.node:1:", &beyond("points of 4 numbers each")],
    );
    refused(
        &[
            ("f.node", "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"),
            ("f.ele", &format!("{TERA} 4 0\n1 1 2 3 4\n")),
        ],
        "f.ele",
        &["f.ele:1:", &beyond("elements of 5 numbers each")],
    );
}

#[test]
fn a_tetgen_count_of_two_to_the_64_does_not_wrap_to_zero() {
    let huge = u64::MAX.to_string();
    let declares = |what: &str| format!("the file declares {huge} {what}");
    // With one marker, attributes + markers wrapped to 0 and the file was read.
    refused(
        &[
            (
                "g.node",
                &format!("4 3 {huge} 1\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"),
            ),
            ("g.ele", "1 4 0\n1 1 2 3 4\n"),
        ],
        "g.node",
        &["g.node:1:", &declares("attributes per point")],
    );
    refused(
        &[
            ("h.node", "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"),
            ("h.ele", &format!("1 4 {huge}\n1 1 2 3 4\n")),
        ],
        "h.ele",
        &["h.ele:1:", &declares("attributes per element")],
    );
}

#[test]
fn a_mesh_file_over_two_gibibytes_is_refused_unread() {
    let tmp = tempfile::tempdir().unwrap();
    // Sparse: no disk space is used, and elasto must not read it.
    let big = std::fs::File::create(tmp.path().join("big.msh")).unwrap();
    big.set_len((2 << 30) + 1).unwrap();
    drop(big);
    std::fs::write(tmp.path().join("s.toml"), mesh_scene("big.msh")).unwrap();
    let o = elasto(Path::new(tmp.path()), &["check", "s.toml"]);
    assert_code(&o, 2);
    let err = stderr(&o);
    assert!(
        err.contains("cannot read mesh file")
            && err.contains("big.msh: it holds 2147483649 bytes, more than the 2 GiB"),
        "{err}"
    );
}
