//! Issue 33 ("compressed VTU bombs"): vtkio allocates what the header of a
//! compressed VTU data array declares (`nb` blocks of `nu` bytes) before it
//! decompresses anything, so a file of a few kilobytes could make elasto
//! allocate gigabytes, or abort when the allocation failed. Now the headers
//! are read first and such a file is refused (exit 2) with a message naming
//! the file and the array, before any allocation: more blocks than the data
//! can list, more than zlib can inflate the data to (1032 to 1), or more
//! than the 2 GiB elasto reads from a mesh file in all.

use crate::cli_common as common;
use base64::Engine;
use common::*;
use std::path::Path;

const B64: base64::engine::GeneralPurpose = base64::engine::general_purpose::STANDARD;

/// `tests/data/meshes/cube.vtu` (zlib, 32-bit headers) with the header of
/// its `Points` array replaced by `header` and `extra` base64 data after it.
fn cube_with_points_header(header: &[u32], extra: &str) -> String {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/meshes/cube.vtu"),
    )
    .unwrap();
    let original = "AQAAAACAAAA4BAAAtgAAAA==";
    assert!(text.contains(original));
    let bytes: Vec<u8> = header.iter().flat_map(|n| n.to_le_bytes()).collect();
    text.replacen(original, &format!("{}{extra}", B64.encode(bytes)), 1)
}

/// Runs `check` on a scene reading `m.vtu` holding `vtu`; returns stderr.
fn check_refuses(vtu: &str) -> String {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("m.vtu"), vtu).unwrap();
    std::fs::write(
        tmp.path().join("s.toml"),
        "dimension = 3\n[mesh]\ngenerator = \"file\"\npath = \"m.vtu\"\ntranslate = [0, 1, 0]\n\
         [material]\nmodel = \"neo-hookean\"\nyoung = 300.0\npoisson = 0.3\n",
    )
    .unwrap();
    let o = elasto_within(
        tmp.path(),
        &["check", "s.toml"],
        std::time::Duration::from_secs(60),
    );
    assert_code(&o, 2);
    let err = stderr(&o);
    assert!(
        err.contains("m.vtu (byte ") && err.contains("the data array `Points`"),
        "{err}"
    );
    assert!(err.contains("refused before decompressing"), "{err}");
    err
}

#[test]
fn the_cube_as_shipped_still_reads() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(
        tmp.path().join("m.vtu"),
        cube_with_points_header(&[1, 32768, 1080, 182], ""),
    )
    .unwrap();
    std::fs::write(
        tmp.path().join("s.toml"),
        "dimension = 3\n[mesh]\ngenerator = \"file\"\npath = \"m.vtu\"\ntranslate = [0, 1, 0]\n\
         [material]\nmodel = \"neo-hookean\"\nyoung = 300.0\npoisson = 0.3\n",
    )
    .unwrap();
    let o = elasto(tmp.path(), &["check", "s.toml"]);
    assert_code(&o, 0);
}

#[test]
fn a_block_declared_far_larger_than_its_data_is_refused() {
    // One block of 2 GiB from 182 compressed bytes.
    let err = check_refuses(&cube_with_points_header(&[1, 1 << 31, 1 << 31, 182], ""));
    assert!(
        err.contains("declares 2147483648 bytes once decompressed from at most")
            && err.contains("more than the 1032 to 1 that zlib can inflate"),
        "{err}"
    );
}

#[test]
fn more_blocks_than_the_data_can_list_are_refused() {
    // A million blocks: the list of their sizes alone would take 4 MB.
    let err = check_refuses(&cube_with_points_header(&[1 << 20, 1 << 31, 0], ""));
    assert!(err.contains("declares 1048576 compressed blocks"), "{err}");
}

#[test]
fn arrays_declaring_more_than_the_mesh_cap_in_all_are_refused() {
    // 65 537 blocks of 32 KiB (2 GiB + 32 KiB), with 32 bytes of data each:
    // within zlib's ratio, beyond the 2 GiB elasto reads from a mesh file.
    let blocks = 65_537u32;
    let mut header = vec![blocks, 32768, 32768];
    header.extend(std::iter::repeat_n(32, blocks as usize));
    let data = "A".repeat(blocks as usize * 32 / 3 * 4);
    let err = check_refuses(&cube_with_points_header(&header, &data));
    assert!(
        err.contains("declares 2147516416 bytes once decompressed")
            && err.contains("more than the 2 GiB elasto reads from a mesh file"),
        "{err}"
    );
}
