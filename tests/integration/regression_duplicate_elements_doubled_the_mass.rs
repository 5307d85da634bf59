//! Issue 33, item 7: duplicated elements in a mesh file were accepted and
//! doubled the mass and stiffness (every tetrahedron listed twice: gravity
//! energy 2.0 instead of 1.0), and a repeated piece with vertices of its
//! own became a second body overlapping the first. Now an element whose
//! corners are at the same positions as an earlier one's (in any order) is
//! dropped and counted in the import summary.

use crate::cli_common as common;
use common::*;

/// Two tetrahedra sharing a face as MEDIT text, with `extra` elements
/// appended; vertices 6-9 repeat the positions of vertices 1-4.
fn medit(extra: &[&str]) -> String {
    let mut elements = vec!["1 2 3 4", "2 3 4 5"];
    elements.extend(extra);
    let mut text = String::from(
        "MeshVersionFormatted 2\nDimension 3\nVertices\n9\n\
         0 0 1 0\n1 0 1 0\n0 1 1 0\n0 0 2 0\n1 1 2 0\n\
         0 0 1 0\n1 0 1 0\n0 1 1 0\n0 0 2 0\n",
    );
    text.push_str(&format!("Tetrahedra\n{}\n", elements.len()));
    for e in elements {
        text.push_str(&format!("{e} 0\n"));
    }
    text.push_str("End\n");
    text
}

const SCENE: &str = r#"dimension = 3

[mesh]
generator = "file"
path = "m.mesh"

[material]
model = "neo-hookean"
young = 100.0
poisson = 0.3
density = 1.0

[effects.gravity]
acceleration = [0.0, -10.0, 0.0]
"#;

/// `elasto check`'s output for the mesh text `mesh`.
fn check(dir: &std::path::Path, mesh: &str) -> String {
    std::fs::write(dir.join("m.mesh"), mesh).unwrap();
    std::fs::write(dir.join("s.toml"), SCENE).unwrap();
    let o = elasto(dir, &["check", "s.toml"]);
    assert_code(&o, 0);
    stdout(&o)
}

fn energy_line(summary: &str) -> &str {
    summary
        .lines()
        .find(|l| l.contains("energy at t = 0"))
        .unwrap_or_else(|| panic!("{summary}"))
}

#[test]
fn duplicate_elements_are_dropped_and_counted() {
    let tmp = tempfile::tempdir().unwrap();
    let single = check(tmp.path(), &medit(&[]));
    // The first listed again, again with its corners in another order (an
    // inverted copy, re-oriented first), and as a copy with its own vertices.
    let doubled = check(tmp.path(), &medit(&["1 2 3 4", "4 3 2 1", "6 7 8 9"]));
    assert!(
        doubled.contains("2 tetrahedra")
            && doubled
                .contains("dropped 3 duplicate tetrahedra (the same corners as an earlier one)")
            && doubled.contains("dropped 4 unreferenced vertices"),
        "{doubled}"
    );
    assert!(!single.contains("duplicate"), "{single}");
    // The same mass: the same gravity energy.
    assert_eq!(energy_line(&doubled), energy_line(&single));
}
