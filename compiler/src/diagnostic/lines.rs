//! Byte offsets to human and LSP positions.

/// Line starts of a source text, for converting byte offsets.
#[derive(Clone, Debug)]
pub struct LineIndex<'a> {
    source: &'a str,
    starts: Vec<usize>,
}

impl<'a> LineIndex<'a> {
    pub fn new(source: &'a str) -> Self {
        // A line ends at LF, CRLF or a lone CR (old Mac files).
        let mut starts = vec![0];
        let b = source.as_bytes();
        for (i, &c) in b.iter().enumerate() {
            if c == b'\n' || (c == b'\r' && b.get(i + 1) != Some(&b'\n')) {
                starts.push(i + 1);
            }
        }
        LineIndex { source, starts }
    }

    /// Clamps an offset into the text and back onto a character boundary, so that spans from a
    /// stale or foreign source never panic.
    fn clamp(&self, offset: usize) -> usize {
        let mut o = offset.min(self.source.len());
        while !self.source.is_char_boundary(o) {
            o -= 1;
        }
        o
    }

    /// 0-based line and the byte offset of its start.
    fn line_of(&self, offset: usize) -> (usize, usize) {
        let line = self.starts.partition_point(|&s| s <= offset) - 1;
        (line, self.starts[line])
    }

    /// 1-based line and 1-based column counted in characters (what editors show).
    pub fn line_col(&self, offset: usize) -> (usize, usize) {
        let o = self.clamp(offset);
        let (line, start) = self.line_of(o);
        (line + 1, self.source[start..o].chars().count() + 1)
    }

    /// 0-based line and 0-based UTF-16 code unit column (the LSP's default position encoding).
    pub fn utf16(&self, offset: usize) -> (u32, u32) {
        let o = self.clamp(offset);
        let (line, start) = self.line_of(o);
        let col: usize = self.source[start..o].chars().map(char::len_utf16).sum();
        (line as u32, col as u32)
    }

    /// The inverse of [`LineIndex::utf16`]; positions past a line's end clamp to the end.
    pub fn offset_of_utf16(&self, line: u32, character: u32) -> usize {
        let Some(&start) = self.starts.get(line as usize) else {
            return self.source.len();
        };
        let end = self
            .starts
            .get(line as usize + 1)
            .map_or(self.source.len(), |&e| e);
        let mut units = 0u32;
        for (i, c) in self.source[start..end].char_indices() {
            if units >= character || c == '\n' || c == '\r' {
                return start + i;
            }
            units += c.len_utf16() as u32;
        }
        end
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_count_characters_and_utf16_units() {
        let src = "ab\n// é😀x\nz";
        let idx = LineIndex::new(src);
        assert_eq!(idx.line_col(0), (1, 1));
        assert_eq!(idx.line_col(3), (2, 1));
        let x = src.find('x').unwrap();
        assert_eq!(idx.line_col(x), (2, 6));
        assert_eq!(idx.utf16(x), (1, 6));
        assert_eq!(idx.offset_of_utf16(1, 6), x);
        assert_eq!(idx.utf16(src.len()), (2, 1));
        // Inside a multi-byte character and past the end: clamped, no panic.
        assert_eq!(idx.utf16(src.find('é').unwrap() + 1), (1, 3));
        assert_eq!(idx.line_col(10_000), (3, 2));
        assert_eq!(idx.offset_of_utf16(99, 0), src.len());
    }
}
