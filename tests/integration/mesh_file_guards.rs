//! Hostile or changed mesh files: compressed VTU bombs, header counts the
//! file cannot hold, and a mesh file that changed since the run recorded it.
//!
//! Each `mod regression_*` here guards one fixed bug and is named after it
//! (`cargo test --test integration regression_` selects them all).

/// Issue 33 ("compressed VTU bombs"): vtkio allocates what the header of a
/// compressed VTU data array declares (`nb` blocks of `nu` bytes) before it
/// decompresses anything, so a file of a few kilobytes could make elasto
/// allocate gigabytes, or abort when the allocation failed. Now the headers
/// are read first and such a file is refused (exit 2) with a message naming
/// the file and the array, before any allocation: more blocks than the data
/// can list, more than zlib can inflate the data to (1032 to 1), or more
/// than the 2 GiB elasto reads from a mesh file in all.
mod regression_compressed_vtu_bomb {
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
}

/// Issue 33, items 2 and 9: the mesh readers trusted the counts a file's
/// header declares (10^12 nodes in a 100-byte file reserved memory for
/// millions before finding the end; a TetGen `attributes` of 2^64 - 1 wrapped
/// to 0 and the file was read as valid) and read files of any size. Now every
/// declared count is checked against what the rest of the file can hold
/// before anything is allocated, and a file over 2 GiB is refused unread:
/// exit 2, naming the file, the count and the limit.
mod regression_mesh_header_counts_trusted {
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
                &format!(
                    "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n{TERA}\n1 0 0 0\n$EndNodes\n"
                ),
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
}

/// Issue 33, item 22: a run's `scene.toml` named its mesh files by path
/// only, so running it again after a file had changed silently gave other
/// results. Now it records each mesh file's size and XXH3 checksum
/// (`mesh.file_size`, `mesh.file_checksum`); a scene that carries them and
/// meets a changed file is warned about before the run, by `check` and
/// `run`, and refused (exit 2) by `run --strict`.
mod regression_changed_mesh_file_went_unnoticed {
    use crate::cli_common as common;
    use common::*;
    use std::path::Path;

    /// A 2D scene reading `sq.msh` (the test square), and the square beside it.
    fn scene_with_mesh_file(dir: &Path) {
        std::fs::copy(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/meshes/square_v2_ascii.msh"),
            dir.join("sq.msh"),
        )
        .unwrap();
        std::fs::write(
            dir.join("s.toml"),
            "dimension = 2\n[mesh]\ngenerator = \"file\"\npath = \"sq.msh\"\n\
         translate = [0.0, 1.0]\n[material]\nmodel = \"stvk\"\nyoung = 300.0\n\
         poisson = 0.3\n[time]\nframes = 3\n[effects.gravity]\n\
         acceleration = [0.0, -1.0]\n[effects.ground]\nheight = 0.0\n",
        )
        .unwrap();
    }

    /// `mesh.file_size` and `mesh.file_checksum` of a run's scene.toml.
    fn recorded(folder: &Path) -> (i64, String) {
        let scene: toml::Table = std::fs::read_to_string(folder.join("scene.toml"))
            .unwrap()
            .parse()
            .unwrap();
        let mesh = &scene["mesh"];
        (
            mesh["file_size"].as_integer().unwrap(),
            mesh["file_checksum"].as_str().unwrap().to_owned(),
        )
    }

    #[test]
    fn a_changed_mesh_file_is_warned_about_and_refused_with_strict() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        scene_with_mesh_file(dir);
        let run = |args: &[&str]| elasto(dir, &[&["run", "--no-render", "-q"][..], args].concat());
        assert_code(&run(&["s.toml", "-o", "a"]), 0);
        let (size, checksum) = recorded(&dir.join("a"));
        assert_eq!(
            size as u64,
            std::fs::metadata(dir.join("sq.msh")).unwrap().len()
        );
        assert!(
            checksum.starts_with("xxh3:") && checksum.len() == 21,
            "{checksum}"
        );
        // The same file: the recorded scene runs without a word, --strict too,
        // and records the same values.
        let o = run(&["a/scene.toml", "-o", "b", "--strict"]);
        assert_code(&o, 0);
        assert_eq!(stderr(&o), "");
        assert_eq!(recorded(&dir.join("b")), (size, checksum.clone()));

        // One byte more (a blank line: the mesh reads the same).
        let mut bytes = std::fs::read(dir.join("sq.msh")).unwrap();
        bytes.push(b'\n');
        std::fs::write(dir.join("sq.msh"), &bytes).unwrap();
        let changed = format!(
            "mesh.path: {} has changed since this scene was written ({size} bytes, {checksum} then, \
         {} bytes, ",
            dir.join("sq.msh").display(),
            size + 1
        );
        let o = run(&["a/scene.toml", "-o", "c"]);
        assert_code(&o, 0);
        assert!(
            stderr(&o).starts_with(&format!("elasto: warning: {changed}")),
            "{}",
            stderr(&o)
        );
        let o = elasto(dir, &["check", "a/scene.toml"]);
        assert_code(&o, 0);
        assert!(stdout(&o).contains(&changed), "{}", stdout(&o));
        let o = run(&["a/scene.toml", "-o", "d", "--strict"]);
        assert_code(&o, 2);
        assert!(
            stderr(&o).contains("`mesh.path`: ") && stderr(&o).contains("(--strict)"),
            "{}",
            stderr(&o)
        );
        assert!(!dir.join("d").exists());

        // The same size, other bytes: the checksum tells.
        let last = bytes.len() - 1;
        bytes[last] = b' ';
        std::fs::write(dir.join("sq.msh"), &bytes).unwrap();
        let o = run(&[
            "a/scene.toml",
            "-o",
            "e",
            "--strict",
            "--set",
            "mesh.file_size=1376",
        ]);
        assert_code(&o, 2);
        assert!(stderr(&o).contains("has changed"), "{}", stderr(&o));
    }

    #[test]
    fn recorded_values_are_checked_like_any_key() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        scene_with_mesh_file(dir);
        for (set, expected) in [
            (
                "mesh.file_checksum=\"md5:1234\"",
                "must be `xxh3:` and 16 hexadecimal digits",
            ),
            ("mesh.file_size=-1", "must be a whole number of bytes >= 0"),
        ] {
            let o = elasto(dir, &["check", "s.toml", "--set", set]);
            assert_code(&o, 2);
            assert!(stderr(&o).contains(expected), "{set}: {}", stderr(&o));
        }
        // A box has no file to record.
        let o = elasto(
            dir,
            &["check", "report-drop-2d", "--set", "mesh.file_size=3"],
        );
        assert_code(&o, 2);
        assert!(
            stderr(&o).contains("is only used with generator = \"file\""),
            "{}",
            stderr(&o)
        );
    }
}
