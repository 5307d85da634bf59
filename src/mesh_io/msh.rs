//! gmsh `.msh` files: versions 2.2 and 4.1, each ASCII and binary.
//!
//! Hand-written: the one Rust crate for MSH (`mshio` 0.4.2) reads only 4.1,
//! has not changed since 2020, and panics on some malformed headers (an
//! unsupported integer size, an empty `$Nodes` section), where elasto must
//! answer with an error naming the file and the place.
//!
//! Layout (gmsh reference manual, "MSH file format"): a `$MeshFormat` header
//! (`version file-type data-size`, then in binary files the integer 1 to fix
//! the byte order), then sections `$Name ... $EndName`. elasto reads `$Nodes`
//! and `$Elements` and skips every other section.
//!
//! * 2.2: `$Nodes`: count, then `tag x y z` per node. `$Elements`: count,
//!   then `tag type ntags tag... node...` per element (ASCII); in binary,
//!   blocks of `type count ntags` followed by `count` elements of
//!   `tag tag... node...`, all 4-byte integers; counts stay text lines.
//! * 4.1: `$Nodes`: `blocks nodes min max`, then per block `dim entity
//!   parametric count`, `count` tags, `count` coordinate triples (plus
//!   `dim` parametric coordinates each when `parametric = 1`). `$Elements`:
//!   `blocks elements min max`, then per block `dim entity type count` and
//!   `count` lines of `tag node...`. In binary every number is binary: tags
//!   and counts `size_t` (data-size bytes), `dim entity parametric type`
//!   4-byte integers, coordinates doubles.

use super::cursor::{Cursor, Endian, text_bytes};
use super::imported_mesh::{MeshBuilder, Numbering, Shape};
use super::{ImportedMesh, MeshImportError};
use std::collections::HashMap;
use std::path::Path;

const FORMAT: &str = "gmsh MSH";

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Version {
    V2,
    V41,
}

/// Numbers in ASCII or in binary of one byte order.
struct Reader<'a> {
    cursor: Cursor<'a>,
    endian: Option<Endian>,
    /// Bytes of a `size_t` (4.1 binary).
    size_t: usize,
}

impl Reader<'_> {
    fn int(&mut self, what: impl Fn() -> String) -> Result<i64, MeshImportError> {
        match self.endian {
            None => self.cursor.number(what),
            Some(endian) => Ok(endian.signed(self.cursor.bytes(4, what)?)),
        }
    }

    fn size(&mut self, what: impl Fn() -> String) -> Result<u64, MeshImportError> {
        match self.endian {
            None => self.cursor.number(what),
            Some(endian) => Ok(endian.unsigned(self.cursor.bytes(self.size_t, what)?)),
        }
    }

    /// A `size_t` used as a tag: must fit an `i64`.
    fn tag(&mut self, what: impl Fn() -> String) -> Result<i64, MeshImportError> {
        let value = self.size(&what)?;
        i64::try_from(value).map_err(|_| {
            self.cursor
                .syntax(format!("{} {value} is out of range", what()))
        })
    }

    fn float(&mut self, what: impl Fn() -> String) -> Result<f64, MeshImportError> {
        match self.endian {
            None => self.cursor.number(what),
            Some(endian) => Ok(endian.f64(self.cursor.bytes(8, what)?)),
        }
    }

    /// Refuses a declared `count` of items that the rest of the file cannot
    /// hold, before anything is allocated for them: each item is at least
    /// `numbers` numbers as text, or `binary_bytes` bytes in a binary file.
    fn declared(
        &self,
        count: usize,
        numbers: u64,
        binary_bytes: u64,
        what: impl FnOnce() -> String,
    ) -> Result<(), MeshImportError> {
        let bytes_each = match self.endian {
            None => text_bytes(numbers),
            Some(_) => binary_bytes,
        };
        self.cursor.declared_count(count as u64, bytes_each, what)
    }

    /// Bytes of `n` `size_t` numbers.
    fn size_ts(&self, n: u64) -> u64 {
        n.saturating_mul(self.size_t as u64)
    }

    /// A count from the file, as `usize`.
    fn count(&mut self, what: impl Fn() -> String) -> Result<usize, MeshImportError> {
        let value = self.size(&what)?;
        usize::try_from(value).map_err(|_| {
            self.cursor
                .syntax(format!("{} {value} is too large", what()))
        })
    }
}

/// Reads a `.msh` file held in `bytes`.
pub(crate) fn read(
    path: &Path,
    bytes: &[u8],
    dimension: usize,
) -> Result<ImportedMesh, MeshImportError> {
    let not_a_mesh = |reason: String| MeshImportError::NotAMesh {
        path: path.to_owned(),
        format: FORMAT,
        reason,
    };
    let mut cursor = Cursor::new(bytes, path, None);
    match cursor.token() {
        Some("$MeshFormat") => {}
        Some(_) => {
            return Err(not_a_mesh(
                "it does not start with `$MeshFormat`".to_owned(),
            ));
        }
        None => return Err(not_a_mesh("the file is empty".to_owned())),
    }
    let version_text = cursor.expect_token(|| "the format version".into())?;
    let version = match version_text {
        "4.1" => Version::V41,
        v if v == "2" || v.starts_with("2.") => Version::V2,
        v if v.parse::<f64>().is_ok() => {
            return Err(MeshImportError::UnsupportedVersion {
                path: path.to_owned(),
                format: FORMAT,
                version: v.to_owned(),
                hint: "save the mesh again from gmsh as version 4.1 or 2.2 (`gmsh FILE -save -format msh41`)",
            });
        }
        v => {
            return Err(cursor.syntax(format!(
                "expected the format version after `$MeshFormat`, found `{v}`"
            )));
        }
    };
    let file_type: u8 = cursor.number(|| "the file type (0 ASCII, 1 binary)".into())?;
    let data_size: usize = cursor.number(|| "the data size".into())?;
    let binary = match file_type {
        0 => false,
        1 => true,
        other => {
            return Err(cursor.syntax(format!(
                "file type must be 0 (ASCII) or 1 (binary), found {other}"
            )));
        }
    };
    let size_t = match (version, data_size) {
        (Version::V2, 8) => 8,
        (Version::V41, 4 | 8) => data_size,
        (Version::V2, _) => {
            return Err(cursor.syntax(format!(
                "data size must be 8 (bytes of a double), found {data_size}"
            )));
        }
        (Version::V41, _) => {
            return Err(cursor.syntax(format!(
                "data size (bytes of a size_t) must be 4 or 8, found {data_size}"
            )));
        }
    };
    let endian = if binary {
        cursor.skip_line_end();
        let one = cursor.bytes(4, || "the binary byte-order test integer".into())?;
        let endian = if Endian::Little.signed(one) == 1 {
            Endian::Little
        } else if Endian::Big.signed(one) == 1 {
            Endian::Big
        } else {
            return Err(cursor.syntax(
                "the byte-order test integer after the header is not 1 in either byte order",
            ));
        };
        cursor.set_binary();
        Some(endian)
    } else {
        None
    };
    cursor.keyword("$EndMeshFormat")?;
    let format = format!(
        "{FORMAT} {} {}",
        match version {
            Version::V2 => "2.2",
            Version::V41 => "4.1",
        },
        if binary { "binary" } else { "ASCII" }
    );
    let mut builder = MeshBuilder::new(
        path.to_owned(),
        format,
        dimension,
        Numbering::Tags(HashMap::new()),
    );
    let mut reader = Reader {
        cursor,
        endian,
        size_t,
    };
    let (mut nodes_seen, mut elements_seen) = (false, false);
    while let Some(token) = reader.cursor.token() {
        let Some(name) = token.strip_prefix('$') else {
            return Err(reader.cursor.syntax(format!(
                "expected a section such as `$Nodes`, found `{token}`"
            )));
        };
        match name {
            "Nodes" | "Elements" => {
                let seen = if name == "Nodes" {
                    &mut nodes_seen
                } else {
                    &mut elements_seen
                };
                if *seen {
                    return Err(reader.cursor.syntax(format!("a second `${name}` section")));
                }
                *seen = true;
                match (name, version) {
                    ("Nodes", Version::V2) => nodes_v2(&mut reader, &mut builder)?,
                    ("Nodes", Version::V41) => nodes_v41(&mut reader, &mut builder)?,
                    (_, Version::V2) => elements_v2(&mut reader, &mut builder)?,
                    (_, Version::V41) => elements_v41(&mut reader, &mut builder)?,
                }
                reader.cursor.keyword(&format!("$End{name}"))?;
            }
            _ => {
                let end = format!("$End{name}");
                if !reader.cursor.skip_past(end.as_bytes()) {
                    return Err(reader.cursor.truncated(format!("`{end}`")));
                }
            }
        }
    }
    for (seen, section) in [(nodes_seen, "$Nodes"), (elements_seen, "$Elements")] {
        if !seen {
            return Err(not_a_mesh(format!("it has no `{section}` section")));
        }
    }
    builder.finish()
}

/// Before binary data: the rest of the current text line.
fn start_binary(reader: &mut Reader) {
    if reader.endian.is_some() {
        reader.cursor.skip_line_end();
    }
}

fn nodes_v2(reader: &mut Reader, builder: &mut MeshBuilder) -> Result<(), MeshImportError> {
    // The count is a text line even in binary files.
    let count: usize = reader.cursor.number(|| "the number of nodes".into())?;
    // `tag x y z`: an integer and three doubles in binary.
    reader.declared(count, 4, 4 + 3 * 8, || "nodes".into())?;
    builder.reserve_points(count);
    start_binary(reader);
    for k in 0..count {
        let what = || format!("node {} of {count}", k + 1);
        let tag = reader.int(what)?;
        let mut p = [0.0; 3];
        for c in &mut p {
            *c = reader.float(what)?;
        }
        builder
            .add_point(tag, p)
            .map_err(|reason| reader.cursor.syntax(reason))?;
    }
    Ok(())
}

fn elements_v2(reader: &mut Reader, builder: &mut MeshBuilder) -> Result<(), MeshImportError> {
    let count: usize = reader.cursor.number(|| "the number of elements".into())?;
    // At least `tag type tags node` as text, `tag node` in a binary block.
    reader.declared(count, 4, 2 * 4, || "elements".into())?;
    start_binary(reader);
    let mut nodes = Vec::new();
    let mut read = 0;
    while read < count {
        let what = || format!("element {} of {count}", read + 1);
        // ASCII: one element per line; binary: a block header, then elements.
        let (element_type, in_block, tags) = if reader.endian.is_some() {
            let element_type = reader.int(what)?;
            let in_block = reader.int(what)?;
            let tags = reader.int(what)?;
            if in_block < 1 || in_block as usize > count - read || !(0..=1000).contains(&tags) {
                return Err(reader.cursor.syntax(format!(
                    "bad element block header (type {element_type}, {in_block} elements, {tags} tags) at element {} of {count}",
                    read + 1
                )));
            }
            (element_type, in_block as usize, tags as usize)
        } else {
            (0, 1, 0)
        };
        for _ in 0..in_block {
            let what = || format!("element {} of {count}", read + 1);
            let label = reader.int(what)?;
            let (element_type, tags) = if reader.endian.is_some() {
                (element_type, tags)
            } else {
                let element_type = reader.int(what)?;
                let tags = reader.int(what)?;
                let tags = usize::try_from(tags).map_err(|_| {
                    reader
                        .cursor
                        .syntax(format!("element {label} has a negative tag count {tags}"))
                })?;
                (element_type, tags)
            };
            let (node_count, shape) = element_kind(element_type).ok_or_else(|| {
                reader.cursor.syntax(format!(
                    "element {label} has the unknown gmsh element type {element_type}"
                ))
            })?;
            for _ in 0..tags {
                reader.int(what)?;
            }
            nodes.clear();
            for _ in 0..node_count {
                nodes.push(reader.int(what)?);
            }
            builder.add_element(shape, label, &nodes);
            read += 1;
        }
    }
    Ok(())
}

fn nodes_v41(reader: &mut Reader, builder: &mut MeshBuilder) -> Result<(), MeshImportError> {
    start_binary(reader);
    let blocks = reader.count(|| "the number of node blocks".into())?;
    let total = reader.count(|| "the number of nodes".into())?;
    reader.size(|| "the smallest node tag".into())?;
    reader.size(|| "the largest node tag".into())?;
    // A block header is `dim entity parametric count`; a node is its tag
    // and three coordinates.
    let block_header = 3 * 4 + reader.size_ts(1);
    let node_bytes = reader.size_ts(1) + 3 * 8;
    reader.declared(blocks, 4, block_header, || "node blocks".into())?;
    reader.declared(total, 4, node_bytes, || "nodes".into())?;
    builder.reserve_points(total);
    let mut tags = Vec::new();
    for block in 0..blocks {
        let what = || format!("the header of node block {} of {blocks}", block + 1);
        let entity_dim = reader.int(what)?;
        reader.int(what)?;
        let parametric = reader.int(what)?;
        let in_block = reader.count(what)?;
        let extra = match parametric {
            0 => 0,
            1 => usize::try_from(entity_dim.clamp(0, 3)).unwrap_or(0),
            other => {
                return Err(reader.cursor.syntax(format!(
                    "node block {}: `parametric` must be 0 or 1, found {other}",
                    block + 1
                )));
            }
        };
        reader.declared(
            in_block,
            4 + extra as u64,
            node_bytes + 8 * extra as u64,
            || format!("nodes in node block {}", block + 1),
        )?;
        tags.clear();
        for k in 0..in_block {
            tags.push(
                reader
                    .tag(|| format!("tag {} of {in_block} in node block {}", k + 1, block + 1))?,
            );
        }
        for (k, &tag) in tags.iter().enumerate() {
            let what = || format!("the coordinates of node {tag} (node block {})", block + 1);
            let mut p = [0.0; 3];
            for c in &mut p {
                *c = reader.float(what)?;
            }
            for _ in 0..extra {
                reader.float(what)?;
            }
            builder
                .add_point(tag, p)
                .map_err(|reason| reader.cursor.syntax(format!("{reason} (node {})", k + 1)))?;
        }
    }
    Ok(())
}

fn elements_v41(reader: &mut Reader, builder: &mut MeshBuilder) -> Result<(), MeshImportError> {
    start_binary(reader);
    let blocks = reader.count(|| "the number of element blocks".into())?;
    let total = reader.count(|| "the number of elements".into())?;
    reader.size(|| "the smallest element tag".into())?;
    reader.size(|| "the largest element tag".into())?;
    // A block header is `dim entity type count`; an element is its tag and
    // at least one node.
    let block_header = 3 * 4 + reader.size_ts(1);
    reader.declared(blocks, 4, block_header, || "element blocks".into())?;
    reader.declared(total, 2, reader.size_ts(2), || "elements".into())?;
    let mut nodes = Vec::new();
    for block in 0..blocks {
        let what = || format!("the header of element block {} of {blocks}", block + 1);
        reader.int(what)?;
        reader.int(what)?;
        let element_type = reader.int(what)?;
        let in_block = reader.count(what)?;
        let (node_count, shape) = element_kind(element_type).ok_or_else(|| {
            reader.cursor.syntax(format!(
                "element block {} has the unknown gmsh element type {element_type}",
                block + 1
            ))
        })?;
        let numbers = 1 + node_count as u64;
        reader.declared(in_block, numbers, reader.size_ts(numbers), || {
            format!("elements in element block {}", block + 1)
        })?;
        for k in 0..in_block {
            let what = || {
                format!(
                    "element {} of {in_block} in element block {}",
                    k + 1,
                    block + 1
                )
            };
            let label = reader.tag(what)?;
            nodes.clear();
            for _ in 0..node_count {
                nodes.push(reader.tag(what)?);
            }
            builder.add_element(shape.clone(), label, &nodes);
        }
    }
    Ok(())
}

/// Number of nodes and shape of a gmsh element type (`GmshDefines.h`).
fn element_kind(element_type: i64) -> Option<(usize, Shape)> {
    let other = |name: &str| Shape::Other(name.to_owned());
    Some(match element_type {
        1 => (2, other("line")),
        2 => (3, Shape::Triangle),
        3 => (4, other("quadrangle")),
        4 => (4, Shape::Tetrahedron),
        5 => (8, other("hexahedron")),
        6 => (6, other("prism")),
        7 => (5, other("pyramid")),
        8 => (3, other("3-node line")),
        9 => (6, other("6-node triangle")),
        10 => (9, other("9-node quadrangle")),
        11 => (10, other("10-node tetrahedron")),
        12 => (27, other("27-node hexahedron")),
        13 => (18, other("18-node prism")),
        14 => (14, other("14-node pyramid")),
        15 => (1, other("point")),
        16 => (8, other("8-node quadrangle")),
        17 => (20, other("20-node hexahedron")),
        18 => (15, other("15-node prism")),
        19 => (13, other("13-node pyramid")),
        20 => (9, other("9-node triangle")),
        21 => (10, other("10-node triangle")),
        22 => (12, other("12-node triangle")),
        23 | 24 => (15, other("15-node triangle")),
        25 => (21, other("21-node triangle")),
        26 => (4, other("4-node line")),
        27 => (5, other("5-node line")),
        28 => (6, other("6-node line")),
        29 => (20, other("20-node tetrahedron")),
        30 => (35, other("35-node tetrahedron")),
        31 => (56, other("56-node tetrahedron")),
        92 => (64, other("64-node hexahedron")),
        93 => (125, other("125-node hexahedron")),
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const TWO_TETS_V2: &str = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n\
        $PhysicalNames\n1\n3 1 \"body\"\n$EndPhysicalNames\n\
        $Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n7 1 1 1\n$EndNodes\n\
        $Elements\n4\n1 15 2 0 1 1\n2 2 2 0 1 1 2 3\n3 4 2 1 1 1 2 3 4\n4 4 2 1 1 2 3 4 7\n$EndElements\n";

    fn read_str(text: &str, dimension: usize) -> Result<ImportedMesh, MeshImportError> {
        read(Path::new("t.msh"), text.as_bytes(), dimension)
    }

    #[test]
    fn version_2_ascii_with_tags_and_sparse_node_numbers() {
        let mesh = read_str(TWO_TETS_V2, 3).unwrap();
        assert_eq!(mesh.format, "gmsh MSH 2.2 ASCII");
        assert_eq!(mesh.points.len(), 5);
        assert_eq!(mesh.simplices, vec![0, 1, 2, 3, 1, 2, 3, 4]);
        assert_eq!(mesh.simplex_labels, vec![3, 4]);
        assert_eq!(mesh.ignored.get("point"), Some(&1));
        assert_eq!(mesh.ignored.get("triangle"), Some(&1));
    }

    #[test]
    fn version_4_0_is_refused_with_a_hint() {
        let err = read_str("$MeshFormat\n4 0 8\n$EndMeshFormat\n", 3).unwrap_err();
        assert!(
            matches!(err, MeshImportError::UnsupportedVersion { .. }),
            "{err}"
        );
        assert!(err.to_string().contains("msh41"), "{err}");
    }

    #[test]
    fn an_unknown_element_type_is_named() {
        let text = TWO_TETS_V2.replace("2 2 2 0 1 1 2 3", "2 99 2 0 1 1 2 3");
        let err = read_str(&text, 3).unwrap_err();
        assert_eq!(
            err.to_string(),
            "t.msh:19: element 2 has the unknown gmsh element type 99"
        );
    }

    #[test]
    fn a_missing_end_of_section_is_a_truncation() {
        let cut = &TWO_TETS_V2[..TWO_TETS_V2.find("$EndPhysicalNames").unwrap()];
        let err = read_str(cut, 3).unwrap_err();
        assert!(matches!(err, MeshImportError::Truncated { .. }), "{err}");
        assert!(err.to_string().contains("`$EndPhysicalNames`"), "{err}");
    }
}
