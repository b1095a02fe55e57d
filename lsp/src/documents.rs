//! The documents the client has open: their text as the client sees it, full and
//! incremental changes, and the one place that converts LSP positions (line, UTF-16
//! code unit) to byte offsets and back. It knows nothing of programs or the compiler.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use lsp_types::{Position, Range, TextDocumentContentChangeEvent, Uri};

/// One open document.
#[derive(Debug, Clone)]
pub struct Document {
    pub text: String,
    pub version: i32,
    pub language_id: String,
}

/// Every open document by its URI.
#[derive(Debug, Default)]
pub struct Documents {
    open: HashMap<Uri, Document>,
}

impl Documents {
    pub fn open(&mut self, uri: Uri, document: Document) {
        self.open.insert(uri, document);
    }

    pub fn close(&mut self, uri: &Uri) -> Option<Document> {
        self.open.remove(uri)
    }

    pub fn get(&self, uri: &Uri) -> Option<&Document> {
        self.open.get(uri)
    }

    pub fn is_open(&self, uri: &Uri) -> bool {
        self.open.contains_key(uri)
    }

    pub fn uris(&self) -> impl Iterator<Item = &Uri> {
        self.open.keys()
    }

    /// Apply `didChange`'s changes in order: a change without a range replaces the
    /// whole text; a range out of the text is clamped to it. False when `uri` is not
    /// open (the change is dropped).
    pub fn change(
        &mut self,
        uri: &Uri,
        version: i32,
        changes: Vec<TextDocumentContentChangeEvent>,
    ) -> bool {
        let Some(doc) = self.open.get_mut(uri) else {
            return false;
        };
        for change in changes {
            match change.range {
                None => doc.text = change.text,
                Some(range) => {
                    let (start, end) = byte_range(&doc.text, range);
                    doc.text.replace_range(start..end, &change.text);
                }
            }
        }
        doc.version = version;
        true
    }
}

/// Byte offsets of an LSP range in `text` (start <= end, both on char boundaries).
pub fn byte_range(text: &str, range: Range) -> (usize, usize) {
    let a = Lines::new(text).offset(text, range.start);
    let b = Lines::new(text).offset(text, range.end);
    (a.min(b), a.max(b))
}

/// Where each line of a text starts, for position <-> offset conversion. Lines end at
/// `\n` (a `\r` before it belongs to the line ending, not the line).
#[derive(Debug, Clone, Default)]
pub struct Lines {
    starts: Vec<usize>,
}

impl Lines {
    pub fn new(text: &str) -> Lines {
        let mut starts = vec![0];
        starts.extend(
            text.bytes()
                .enumerate()
                .filter(|(_, b)| *b == b'\n')
                .map(|(i, _)| i + 1),
        );
        Lines { starts }
    }

    /// 0-based line holding byte `offset`.
    pub fn line_of(&self, offset: usize) -> usize {
        self.starts
            .partition_point(|s| *s <= offset)
            .saturating_sub(1)
    }

    /// The byte offset of `position` in `text` (which this index was built from). A
    /// line past the end is the text's end; a character past the line's end is the
    /// line's end; a character inside a surrogate pair is the start of that character.
    pub fn offset(&self, text: &str, position: Position) -> usize {
        let Some(&start) = self.starts.get(position.line as usize) else {
            return text.len();
        };
        let end = self
            .starts
            .get(position.line as usize + 1)
            .map(|next| next - 1)
            .unwrap_or(text.len());
        let line = text.get(start..end).unwrap_or("");
        let line = line.strip_suffix('\r').unwrap_or(line);
        let mut units = 0u32;
        for (i, c) in line.char_indices() {
            let next = units + c.len_utf16() as u32;
            if next > position.character {
                return start + i;
            }
            units = next;
        }
        start + line.len()
    }

    /// The LSP position of byte `offset` in `text` (clamped to the text and down to a
    /// char boundary).
    pub fn position(&self, text: &str, offset: usize) -> Position {
        let mut offset = offset.min(text.len());
        while !text.is_char_boundary(offset) {
            offset -= 1;
        }
        let line = self.line_of(offset);
        let start = self.starts[line];
        let character = text
            .get(start..offset)
            .map(|s| s.encode_utf16().count())
            .unwrap_or(0);
        Position::new(line as u32, character as u32)
    }
}

/// The file path of a `file:` URI (percent-decoded); `None` for other schemes.
pub fn uri_to_path(uri: &Uri) -> Option<PathBuf> {
    let rest = uri.as_str().strip_prefix("file://")?;
    // `file:///path` or `file://host/path`: the path starts at the first '/'.
    let path = &rest[rest.find('/')?..];
    let path = path.split(['?', '#']).next().unwrap_or(path);
    let bytes = percent_decode(path);
    let decoded = String::from_utf8(bytes).ok()?;
    // `file:///C:/x` on Windows.
    let trimmed = match decoded.as_bytes() {
        [b'/', d, b':', ..] if d.is_ascii_alphabetic() && cfg!(windows) => &decoded[1..],
        _ => decoded.as_str(),
    };
    Some(PathBuf::from(trimmed))
}

/// The `file:` URI of an absolute path, with every byte but unreserved ones and `/`
/// percent-encoded (`None` only if the result would not parse, which encoding rules out).
pub fn path_to_uri(path: &Path) -> Option<Uri> {
    let text = path.to_string_lossy().replace('\\', "/");
    let mut out = String::from("file://");
    if !text.starts_with('/') {
        out.push('/');
    }
    for b in text.bytes() {
        if b.is_ascii_alphanumeric() || b"-._~/:".contains(&b) {
            out.push(b as char);
        } else {
            out.push_str(&format!("%{b:02X}"));
        }
    }
    out.parse().ok()
}

fn percent_decode(s: &str) -> Vec<u8> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            let hex = std::str::from_utf8(&bytes[i + 1..i + 3]).ok();
            if let Some(v) = hex.and_then(|h| u8::from_str_radix(h, 16).ok()) {
                out.push(v);
                i += 3;
                continue;
            }
        }
        out.push(bytes[i]);
        i += 1;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pos(line: u32, character: u32) -> Position {
        Position::new(line, character)
    }

    #[test]
    fn utf16_columns_count_surrogate_pairs_and_cjk() {
        let text = "LD 启动 // 🚀x\r\n= Q0.0\n";
        let lines = Lines::new(text);
        // 启 and 动 are one UTF-16 unit each, 🚀 is two.
        let x = text.find('x').unwrap();
        assert_eq!(lines.position(text, x), pos(0, 11));
        assert_eq!(lines.offset(text, pos(0, 11)), x);
        // Inside the surrogate pair: the rocket's start.
        let rocket = text.find('🚀').unwrap();
        assert_eq!(lines.offset(text, pos(0, 10)), rocket);
        // Past the line's end: before the CRLF.
        assert_eq!(lines.offset(text, pos(0, 99)), text.find('\r').unwrap());
        let q = text.find('Q').unwrap();
        assert_eq!(lines.position(text, q), pos(1, 2));
        assert_eq!(lines.offset(text, pos(1, 2)), q);
        assert_eq!(lines.offset(text, pos(7, 0)), text.len());
        assert_eq!(lines.position(text, text.len()), pos(2, 0));
        // Inside a multi-byte char: its start.
        let qi = text.find('启').unwrap();
        assert_eq!(lines.position(text, qi + 1), pos(0, 3));
    }

    #[test]
    fn incremental_changes_apply_in_order() {
        let uri: Uri = "file:///a.lad".parse().unwrap();
        let mut docs = Documents::default();
        docs.open(
            uri.clone(),
            Document {
                text: "LD 启动\r\n= Q0.0\n".into(),
                version: 1,
                language_id: "gutta".into(),
            },
        );
        let change = |l0, c0, l1, c1, text: &str| TextDocumentContentChangeEvent {
            range: Some(Range::new(pos(l0, c0), pos(l1, c1))),
            range_length: None,
            text: text.into(),
        };
        assert!(docs.change(
            &uri,
            2,
            vec![
                change(0, 3, 0, 5, "🚀"),
                change(1, 2, 1, 6, "M1.0"),
                change(0, 5, 0, 5, "!")
            ]
        ));
        assert_eq!(docs.get(&uri).unwrap().text, "LD 🚀!\r\n= M1.0\n");
        // Reversed and out-of-range ranges are clamped and ordered.
        assert!(docs.change(&uri, 3, vec![change(9, 0, 1, 0, "")]));
        assert_eq!(docs.get(&uri).unwrap().text, "LD 🚀!\r\n");
        assert!(docs.change(
            &uri,
            4,
            vec![TextDocumentContentChangeEvent {
                range: None,
                range_length: None,
                text: "x".into()
            }]
        ));
        assert_eq!(docs.get(&uri).unwrap().text, "x");
        assert!(!docs.change(&"file:///b.lad".parse().unwrap(), 1, Vec::new()));
    }

    #[test]
    fn file_uris_round_trip_with_spaces_and_unicode() {
        let path = Path::new("/tmp/my project/启动.lad");
        let uri = path_to_uri(path).unwrap();
        assert_eq!(
            uri.as_str(),
            "file:///tmp/my%20project/%E5%90%AF%E5%8A%A8.lad"
        );
        assert_eq!(uri_to_path(&uri).as_deref(), Some(path));
        assert_eq!(uri_to_path(&"untitled:Untitled-1".parse().unwrap()), None);
    }
}
