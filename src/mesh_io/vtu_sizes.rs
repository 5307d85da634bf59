//! The sizes a compressed `.vtu` file declares for its data arrays, checked
//! before `vtkio` allocates them.
//!
//! A compressed data array starts with a header `[nb][nu][np][nc_1 … nc_nb]`:
//! `nb` blocks of `nu` bytes each once decompressed (the last one `np`
//! bytes), and their compressed sizes. `vtkio` trusts it: it allocates
//! `nu (nb − 1) + np` bytes and a list of `nb` offsets before it
//! decompresses anything, so a file of a few hundred bytes that declares a
//! terabyte makes the process abort (an allocation failure is not a panic
//! that the reader could catch), and a real zlib bomb (1000:1) of a few
//! megabytes fills gigabytes. Here every compressed array's header is read
//! first — inline (`format="binary"`, base64) and appended (raw or base64) —
//! and the file is refused, naming the array, when a header holds more
//! blocks than the data after it could, when an array declares more than
//! [`MAX_COMPRESSION_RATIO`] times the bytes its data can hold (more than
//! zlib can inflate them to), or when the arrays together declare more than
//! [`MAX_MESH_FILE_BYTES`], the most elasto reads from a mesh file. So a
//! file can make elasto allocate at most about a thousand times its size,
//! and never more than 2 GiB. Arrays that are not compressed need no check:
//! their size is bounded by the file's.

use super::{Location, MeshImportError};
use crate::input_file::MAX_MESH_FILE_BYTES;
use base64::Engine;
use std::path::Path;

/// The most one byte of compressed data can become: deflate (zlib) inflates
/// by at most 1032 to 1 (a 258-byte match per 2 bits), LZ4 by about 255 to
/// 1; LZMA, which can do more, is not read (vtkio is built without it).
pub(crate) const MAX_COMPRESSION_RATIO: u64 = 1032;

/// Lenient base64 (padding optional, trailing bits allowed): it decodes at
/// least what `vtkio` decodes, so no header `vtkio` reads escapes the check.
const BASE64: base64::engine::GeneralPurpose = base64::engine::GeneralPurpose::new(
    &base64::alphabet::STANDARD,
    base64::engine::GeneralPurposeConfig::new()
        .with_decode_padding_mode(base64::engine::DecodePaddingMode::Indifferent)
        .with_decode_allow_trailing_bits(true),
);

/// How the file's compressed headers are written (`<VTKFile …>`).
#[derive(Clone, Copy)]
struct HeaderFormat {
    /// Bytes per header number: 4 (`UInt32`, the default) or 8 (`UInt64`).
    width: usize,
    big_endian: bool,
}

impl HeaderFormat {
    /// Header number `k` of `bytes`, if it is there.
    fn number(&self, bytes: &[u8], k: usize) -> Option<u64> {
        let raw = bytes.get(k * self.width..(k + 1) * self.width)?;
        let mut value = 0u64;
        for i in 0..self.width {
            let byte = if self.big_endian {
                raw[i]
            } else {
                raw[self.width - 1 - i]
            };
            value = (value << 8) | u64::from(byte);
        }
        Some(value)
    }
}

/// Refuses a compressed `.vtu` whose data arrays declare more than elasto
/// reads from a mesh file, or more blocks than their data holds; `Ok` for a
/// file without compression.
pub(crate) fn check_declared_sizes(path: &Path, bytes: &[u8]) -> Result<(), MeshImportError> {
    let Some(file_tag) = tag_at(bytes, b"<VTKFile") else {
        return Ok(());
    };
    if attribute(file_tag.1, "compressor").is_none_or(str::is_empty) {
        return Ok(());
    }
    let format = HeaderFormat {
        width: if attribute(file_tag.1, "header_type") == Some("UInt64") {
            8
        } else {
            4
        },
        big_endian: attribute(file_tag.1, "byte_order") == Some("BigEndian"),
    };
    let appended = appended_data(bytes);
    // The tags come before the appended data, whose raw bytes may hold anything.
    let tags = &bytes[..tag_at(bytes, b"<AppendedData").map_or(bytes.len(), |(at, _)| at)];
    let mut total: u64 = 0;
    let mut search = 0;
    while let Some((start, tag)) = tag_at(&tags[search..], b"<DataArray") {
        let start = search + start;
        search = start + tag.len();
        let name = attribute(tag, "Name").unwrap_or("(unnamed)");
        let data: Option<(&[u8], bool)> = match attribute(tag, "format") {
            Some("binary") => {
                let content = &tags[search..];
                let end = find(content, b"<").unwrap_or(content.len());
                Some((content[..end].trim_ascii(), true))
            }
            Some("appended") => {
                let offset = attribute(tag, "offset").and_then(|o| o.trim().parse::<usize>().ok());
                match (appended, offset) {
                    (Some((data, base64)), Some(offset)) => {
                        data.get(offset..).map(|rest| (rest, base64))
                    }
                    _ => None,
                }
            }
            _ => None,
        };
        let Some((data, base64)) = data else {
            continue;
        };
        let refuse = |reason: String| MeshImportError::Syntax {
            path: path.to_owned(),
            location: Location::Byte(start),
            reason: format!("the data array `{name}` {reason}; refused before decompressing"),
        };
        let declared = declared_bytes(data, base64, format).map_err(refuse)?;
        total = total.saturating_add(declared);
        if total > MAX_MESH_FILE_BYTES {
            return Err(refuse(format!(
                "declares {declared} bytes once decompressed, {total} with the arrays before \
                 it: more than the {} GiB elasto reads from a mesh file",
                MAX_MESH_FILE_BYTES >> 30
            )));
        }
    }
    Ok(())
}

/// The bytes a compressed array's header declares (`nu (nb − 1) + np`), or
/// why the header cannot be right. A header that cannot be decoded counts
/// as nothing: `vtkio` refuses it itself.
fn declared_bytes(data: &[u8], base64: bool, format: HeaderFormat) -> Result<u64, String> {
    let width = format.width;
    // The first three numbers, and how many header bytes the data can hold.
    let (head, capacity) = if base64 {
        let chars = 4 * (3 * width).div_ceil(3);
        let Some(encoded) = data.get(..chars.min(data.len())) else {
            return Ok(0);
        };
        let Ok(head) = BASE64.decode(encoded) else {
            return Ok(0);
        };
        (head, data.len() / 4 * 3)
    } else {
        (data[..(3 * width).min(data.len())].to_vec(), data.len())
    };
    let (Some(blocks), Some(block), Some(last)) = (
        format.number(&head, 0),
        format.number(&head, 1),
        format.number(&head, 2),
    ) else {
        return Ok(0);
    };
    let header_bytes = blocks
        .checked_add(3)
        .and_then(|n| n.checked_mul(width as u64));
    if header_bytes.is_none_or(|n| n > capacity as u64) {
        return Err(format!(
            "declares {blocks} compressed blocks, more than its {capacity} bytes of data can \
             list"
        ));
    }
    if blocks == 0 {
        return if block == 0 && last == 0 {
            Ok(0)
        } else {
            Err(format!(
                "declares no compressed blocks but blocks of {block} bytes (the last {last})"
            ))
        };
    }
    let declared = block
        .checked_mul(blocks - 1)
        .and_then(|n| n.checked_add(last))
        .unwrap_or(u64::MAX);
    let most = (capacity as u64).saturating_mul(MAX_COMPRESSION_RATIO);
    if declared > most {
        return Err(format!(
            "declares {declared} bytes once decompressed from at most {capacity} bytes of data: \
             more than the {MAX_COMPRESSION_RATIO} to 1 that zlib can inflate"
        ));
    }
    Ok(declared)
}

/// The data of `<AppendedData>` (after its `_`) and whether it is base64.
fn appended_data(bytes: &[u8]) -> Option<(&[u8], bool)> {
    let (start, tag) = tag_at(bytes, b"<AppendedData")?;
    let after = start + tag.len();
    let underscore = after + find(&bytes[after..], b"_")?;
    let end = rfind(bytes, b"</AppendedData>").filter(|&end| end > underscore)?;
    let base64 = attribute(tag, "encoding") != Some("raw");
    let data = &bytes[underscore + 1..end];
    Some((if base64 { data.trim_ascii() } else { data }, base64))
}

/// The first tag starting with `name` (`<DataArray`), from `<` to `>`
/// included, with its offset.
fn tag_at<'b>(bytes: &'b [u8], name: &[u8]) -> Option<(usize, &'b [u8])> {
    let mut from = 0;
    loop {
        let start = from + find(&bytes[from..], name)?;
        let after = bytes.get(start + name.len()).copied();
        // `<DataArrayX` is another tag.
        if after.is_some_and(|b| b.is_ascii_whitespace() || b == b'>' || b == b'/') {
            let end = start + find(&bytes[start..], b">")?;
            return Some((start, &bytes[start..=end]));
        }
        from = start + name.len();
    }
}

/// The value of attribute `name` in `tag` (`name="value"` or `name='value'`).
fn attribute<'b>(tag: &'b [u8], name: &str) -> Option<&'b str> {
    let mut from = 0;
    while let Some(at) = find(&tag[from..], name.as_bytes()) {
        let at = from + at;
        from = at + name.len();
        let before = at.checked_sub(1).map(|i| tag[i]);
        if !before.is_some_and(|b| b.is_ascii_whitespace()) {
            continue;
        }
        let rest = tag[from..].trim_ascii_start();
        let Some(rest) = rest.strip_prefix(b"=") else {
            continue;
        };
        let rest = rest.trim_ascii_start();
        let quote = *rest.first()?;
        if quote != b'"' && quote != b'\'' {
            return None;
        }
        let value = &rest[1..];
        let end = value.iter().position(|&b| b == quote)?;
        return std::str::from_utf8(&value[..end]).ok();
    }
    None
}

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

fn rfind(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).rposition(|w| w == needle)
}

#[cfg(test)]
mod tests {
    use super::*;

    const FORMAT: HeaderFormat = HeaderFormat {
        width: 4,
        big_endian: false,
    };

    fn header(numbers: &[u32]) -> String {
        let bytes: Vec<u8> = numbers.iter().flat_map(|n| n.to_le_bytes()).collect();
        BASE64.encode(bytes)
    }

    #[test]
    fn a_header_declares_its_blocks_times_their_size() {
        let data = header(&[3, 32768, 100, 10, 10, 10]) + &"A".repeat(200);
        assert_eq!(
            declared_bytes(data.as_bytes(), true, FORMAT),
            Ok(2 * 32768 + 100)
        );
        let raw: Vec<u8> = [1u32, 32768, 1080, 182]
            .iter()
            .flat_map(|n| n.to_le_bytes())
            .collect();
        assert_eq!(declared_bytes(&raw, false, FORMAT), Ok(1080));
    }

    #[test]
    fn more_blocks_than_the_data_can_list_are_refused() {
        let data = header(&[1 << 20, 1 << 31, 0]);
        let reason = declared_bytes(data.as_bytes(), true, FORMAT).unwrap_err();
        assert!(
            reason.contains("declares 1048576 compressed blocks"),
            "{reason}"
        );
        let reason = declared_bytes(header(&[0, 32768, 0]).as_bytes(), true, FORMAT).unwrap_err();
        assert!(reason.contains("no compressed blocks"), "{reason}");
    }

    #[test]
    fn more_than_zlib_can_inflate_is_refused() {
        // 16 header bytes and 4 of data: 20 bytes can become 20 640.
        let raw: Vec<u8> = [1u32, 20640, 20640, 4, 0]
            .iter()
            .flat_map(|n| n.to_le_bytes())
            .collect();
        assert_eq!(declared_bytes(&raw, false, FORMAT), Ok(20640));
        let raw: Vec<u8> = [1u32, 20641, 20641, 4, 0]
            .iter()
            .flat_map(|n| n.to_le_bytes())
            .collect();
        let reason = declared_bytes(&raw, false, FORMAT).unwrap_err();
        assert!(
            reason.contains("declares 20641 bytes once decompressed from at most 20 bytes"),
            "{reason}"
        );
    }

    #[test]
    fn attributes_are_found_by_whole_name() {
        let tag = br#"<DataArray type="Int64" Name="offsets" format='binary' offset="12">"#;
        assert_eq!(attribute(tag, "Name"), Some("offsets"));
        assert_eq!(attribute(tag, "format"), Some("binary"));
        assert_eq!(attribute(tag, "offset"), Some("12"));
        assert_eq!(attribute(tag, "type"), Some("Int64"));
        assert_eq!(attribute(tag, "set"), None);
    }
}
