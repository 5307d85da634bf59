//! A cursor over a mesh file's bytes: whitespace-separated tokens with line
//! numbers for the text formats, raw little- or big-endian numbers for binary
//! blocks, and errors that name the file and the place.

use super::{Location, MeshImportError};
use std::path::Path;
use std::str::FromStr;

/// Reads tokens and binary numbers from a file held in memory.
pub(crate) struct Cursor<'a> {
    bytes: &'a [u8],
    pos: usize,
    line: usize,
    path: &'a Path,
    comment: Option<u8>,
    binary: bool,
}

impl<'a> Cursor<'a> {
    /// A cursor at the start of `bytes`; `comment` starts a comment that runs
    /// to the end of its line (`#` in MEDIT and TetGen files).
    pub fn new(bytes: &'a [u8], path: &'a Path, comment: Option<u8>) -> Self {
        Self {
            bytes,
            pos: 0,
            line: 1,
            path,
            comment,
            binary: false,
        }
    }

    /// From now on, report places as byte offsets: line numbers mean nothing
    /// once binary data has been read.
    pub fn set_binary(&mut self) {
        self.binary = true;
    }

    /// The current place, for messages.
    pub fn location(&self) -> Location {
        if self.binary {
            Location::Byte(self.pos)
        } else {
            Location::Line(self.line)
        }
    }

    /// A "file ends early" error at the current place.
    pub fn truncated(&self, expected: impl Into<String>) -> MeshImportError {
        MeshImportError::Truncated {
            path: self.path.to_owned(),
            location: self.location(),
            expected: expected.into(),
        }
    }

    /// A syntax error at the current place.
    pub fn syntax(&self, reason: impl Into<String>) -> MeshImportError {
        MeshImportError::Syntax {
            path: self.path.to_owned(),
            location: self.location(),
            reason: reason.into(),
        }
    }

    /// Refuses a declared `count` of items, each taking at least
    /// `bytes_each` bytes, that the rest of the file cannot hold: a header
    /// that declares 10^12 nodes in a 100-byte file is an error before any
    /// allocation. `what` names the items ("nodes").
    pub fn declared_count(
        &self,
        count: u64,
        bytes_each: u64,
        what: impl FnOnce() -> String,
    ) -> Result<(), MeshImportError> {
        let bytes_left = self.bytes.len() - self.pos;
        // The last item needs no separator after it.
        if count.saturating_mul(bytes_each) > bytes_left as u64 + 1 {
            return Err(MeshImportError::CountBeyondFile {
                path: self.path.to_owned(),
                location: self.location(),
                count,
                what: what(),
                bytes_left,
            });
        }
        Ok(())
    }

    /// Skips whitespace and comments, counting lines.
    fn skip_space(&mut self) {
        while let Some(&b) = self.bytes.get(self.pos) {
            if b == b'\n' {
                self.line += 1;
            } else if Some(b) == self.comment {
                while self.bytes.get(self.pos).is_some_and(|&c| c != b'\n') {
                    self.pos += 1;
                }
                continue;
            } else if !b.is_ascii_whitespace() {
                break;
            }
            self.pos += 1;
        }
    }

    /// The next token, or `None` at the end of the file. A token that is not
    /// UTF-8 (binary data where text was expected) comes back as `"<binary>"`.
    pub fn token(&mut self) -> Option<&'a str> {
        self.skip_space();
        let start = self.pos;
        while self
            .bytes
            .get(self.pos)
            .is_some_and(|&b| !b.is_ascii_whitespace() && Some(b) != self.comment)
        {
            self.pos += 1;
        }
        if start == self.pos {
            return None;
        }
        Some(std::str::from_utf8(&self.bytes[start..self.pos]).unwrap_or("<binary>"))
    }

    /// The next token without consuming it.
    pub fn peek(&mut self) -> Option<&'a str> {
        let (pos, line) = (self.pos, self.line);
        let token = self.token();
        self.pos = pos;
        self.line = line;
        token
    }

    /// The next token; the end of the file is a truncation error naming `what`.
    pub fn expect_token(
        &mut self,
        what: impl FnOnce() -> String,
    ) -> Result<&'a str, MeshImportError> {
        match self.token() {
            Some(token) => Ok(token),
            None => Err(self.truncated(what())),
        }
    }

    /// The next token parsed as a number; `what` names it in messages.
    pub fn number<T: FromStr>(&mut self, what: impl Fn() -> String) -> Result<T, MeshImportError> {
        let token = self.expect_token(&what)?;
        token.parse().map_err(|_| {
            if self.at_end() {
                // A number cut in half by the end of the file.
                self.truncated(what())
            } else {
                self.syntax(format!("expected {}, found `{token}`", what()))
            }
        })
    }

    /// True when the last token ran into the end of the file.
    fn at_end(&self) -> bool {
        self.pos == self.bytes.len()
    }

    /// Requires the next token to be `keyword`.
    pub fn keyword(&mut self, keyword: &str) -> Result<(), MeshImportError> {
        let token = self.expect_token(|| format!("`{keyword}`"))?;
        if token == keyword {
            Ok(())
        } else if self.at_end() && keyword.starts_with(token) {
            Err(self.truncated(format!("`{keyword}`")))
        } else {
            Err(self.syntax(format!("expected `{keyword}`, found `{token}`")))
        }
    }

    /// Moves to just after the next line break (the end of a text line that
    /// precedes binary data).
    pub fn skip_line_end(&mut self) {
        while let Some(&b) = self.bytes.get(self.pos) {
            self.pos += 1;
            if b == b'\n' {
                self.line += 1;
                return;
            }
        }
    }

    /// Moves past the next occurrence of `marker`; false (at the end) when
    /// there is none.
    pub fn skip_past(&mut self, marker: &[u8]) -> bool {
        let rest = &self.bytes[self.pos..];
        match rest.windows(marker.len()).position(|w| w == marker) {
            Some(offset) => {
                self.line += rest[..offset + marker.len()]
                    .iter()
                    .filter(|&&b| b == b'\n')
                    .count();
                self.pos += offset + marker.len();
                true
            }
            None => {
                self.pos = self.bytes.len();
                false
            }
        }
    }

    /// The next `n` raw bytes; too few left is a truncation error naming `what`.
    pub fn bytes(
        &mut self,
        n: usize,
        what: impl FnOnce() -> String,
    ) -> Result<&'a [u8], MeshImportError> {
        match self
            .pos
            .checked_add(n)
            .filter(|&end| end <= self.bytes.len())
        {
            Some(end) => {
                let bytes = &self.bytes[self.pos..end];
                self.pos = end;
                Ok(bytes)
            }
            None => Err(self.truncated(what())),
        }
    }
}

/// The fewest bytes `numbers` numbers take as text: a digit and a separator
/// each (saturating: a header's own counts may be absurd).
pub(crate) fn text_bytes(numbers: u64) -> u64 {
    numbers.saturating_mul(2)
}

/// Byte order of binary data.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Endian {
    Little,
    Big,
}

impl Endian {
    /// An unsigned integer of `bytes.len()` (1, 2, 4 or 8) bytes.
    pub fn unsigned(self, bytes: &[u8]) -> u64 {
        let fold = |acc: u64, &b: &u8| (acc << 8) | u64::from(b);
        match self {
            Endian::Big => bytes.iter().fold(0, fold),
            Endian::Little => bytes.iter().rev().fold(0, fold),
        }
    }

    /// A signed integer of `bytes.len()` (1, 2, 4 or 8) bytes.
    pub fn signed(self, bytes: &[u8]) -> i64 {
        let bits = 8 * bytes.len() as u32;
        let raw = self.unsigned(bytes);
        if bits >= 64 {
            raw as i64
        } else {
            // Sign-extend from `bits` bits.
            let shift = 64 - bits;
            ((raw << shift) as i64) >> shift
        }
    }

    /// An IEEE double from 8 bytes.
    pub fn f64(self, bytes: &[u8]) -> f64 {
        f64::from_bits(self.unsigned(bytes))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_skip_comments_and_count_lines() {
        let text = b"# header\n  12 3.5 # trailing\n\nEnd";
        let path = Path::new("t.node");
        let mut c = Cursor::new(text, path, Some(b'#'));
        assert_eq!(c.number::<usize>(|| "count".into()).unwrap(), 12);
        assert_eq!(c.location(), Location::Line(2));
        assert_eq!(c.number::<f64>(|| "x".into()).unwrap(), 3.5);
        assert_eq!(c.peek(), Some("End"));
        assert_eq!(c.token(), Some("End"));
        assert_eq!(c.location(), Location::Line(4));
        let err = c.number::<f64>(|| "y".into()).unwrap_err();
        assert_eq!(
            err.to_string(),
            "t.node:4: the file is truncated: it ends where y should be"
        );
    }

    #[test]
    fn a_word_where_a_number_belongs_is_named_with_its_line() {
        let path = Path::new("m.mesh");
        let mut c = Cursor::new(b"1\n2 x 3\n", path, None);
        c.token();
        c.token();
        let err = c
            .number::<i64>(|| "vertex 1 of element 2".into())
            .unwrap_err();
        assert_eq!(
            err.to_string(),
            "m.mesh:2: expected vertex 1 of element 2, found `x`"
        );
    }

    #[test]
    fn binary_numbers_in_both_byte_orders() {
        assert_eq!(Endian::Little.unsigned(&[1, 0, 0, 0]), 1);
        assert_eq!(Endian::Big.unsigned(&[0, 0, 0, 1]), 1);
        assert_eq!(Endian::Little.signed(&[0xff, 0xff, 0xff, 0xff]), -1);
        assert_eq!(Endian::Little.f64(&2.5f64.to_le_bytes()), 2.5);
        assert_eq!(Endian::Big.f64(&(-0.75f64).to_be_bytes()), -0.75);
    }
}
