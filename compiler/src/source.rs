//! Source text as the compiler sees it: decoded UTF-8 (BOM dropped), with a line
//! index that turns byte offsets into 1-based lines and character columns. A program of
//! several files is one text with a file table (each file appended, then one separator
//! newline), so spans stay plain byte offsets everywhere; this is the only place that
//! turns them into (file, line, column).

use std::ops::Range;

/// A byte range in one source file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct Span {
    pub start: u32,
    pub end: u32,
}

impl Span {
    pub fn new(start: usize, end: usize) -> Span {
        Span {
            start: start as u32,
            end: end as u32,
        }
    }

    pub fn range(self) -> Range<usize> {
        self.start as usize..self.end as usize
    }

    /// The smallest span covering both.
    pub fn to(self, other: Span) -> Span {
        Span {
            start: self.start.min(other.start),
            end: self.end.max(other.end),
        }
    }

    pub fn is_empty(self) -> bool {
        self.start >= self.end
    }

    pub fn contains(self, offset: usize) -> bool {
        (self.start as usize..=self.end as usize).contains(&offset)
    }
}

/// One source file (its name, for messages, and its text), or the joined text of a
/// program in several files ([`SourceFile::join`]): then `name` is the first source's
/// and `parts` says where each file lies in `text`.
#[derive(Debug, Clone)]
pub struct SourceFile {
    pub name: String,
    pub text: String,
    /// Empty for one file; else every file in order, starting at offset 0.
    parts: Vec<FilePart>,
}

/// What a file of a program holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PartKind {
    /// A .lad source.
    Source,
    /// A symbol table (CSV or tab-separated rows).
    SymbolTable,
    /// A Micro/WIN data block export ([`is_data_block_tab`]: its first line is
    /// `DATA_BLOCK_TAB name`), given among the sources under any name.
    DataBlockTab,
}

/// One file in a joined text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FilePart {
    pub name: String,
    pub kind: PartKind,
    /// Byte offset of the file's first byte in the joined text (a line start).
    pub start: usize,
    /// Byte offset of the separator newline after the file's text: where "the file
    /// ends" is reported.
    pub end: usize,
}

/// A position resolved to its file: 1-based line and character column in that file,
/// and the byte offset within that file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Location<'a> {
    pub file: &'a str,
    pub line: u32,
    pub column: u32,
    pub offset: usize,
}

/// Why source bytes are not a program text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EncodingError {
    /// Byte offset of the first invalid byte.
    pub offset: usize,
}

impl SourceFile {
    pub fn new(name: impl Into<String>, text: impl Into<String>) -> SourceFile {
        let mut text: String = text.into();
        if text.starts_with('\u{FEFF}') {
            text.drain(..3);
        }
        SourceFile {
            name: name.into(),
            text,
            parts: Vec::new(),
        }
    }

    /// One text of several files: the sources in order, then the data block exports
    /// among them ([`is_data_block_tab`], in their order), then the symbol tables, each
    /// followed by one separator newline. One source and no table stays as it is.
    pub fn join(sources: Vec<SourceFile>, tables: Vec<SourceFile>) -> SourceFile {
        if sources.len() == 1 && tables.is_empty() {
            if let Some(single) = sources.into_iter().next() {
                return single;
            }
            return SourceFile::new("", "");
        }
        let name = sources
            .first()
            .or(tables.first())
            .map(|f| f.name.clone())
            .unwrap_or_default();
        let total: usize = sources
            .iter()
            .chain(&tables)
            .map(|f| f.text.len() + 1)
            .sum();
        let mut text = String::with_capacity(total);
        let mut parts = Vec::with_capacity(sources.len() + tables.len());
        // The program's own sources first: the block parser reads them as one run.
        let (data_blocks, sources): (Vec<SourceFile>, Vec<SourceFile>) = sources
            .into_iter()
            .partition(|f| is_data_block_tab(&f.text));
        let kinds = sources
            .into_iter()
            .map(|f| (f, PartKind::Source))
            .chain(data_blocks.into_iter().map(|f| (f, PartKind::DataBlockTab)))
            .chain(tables.into_iter().map(|f| (f, PartKind::SymbolTable)));
        for (file, kind) in kinds {
            let start = text.len();
            text.push_str(&file.text);
            let end = text.len();
            text.push('\n');
            parts.push(FilePart {
                name: file.name,
                kind,
                start,
                end,
            });
        }
        SourceFile { name, text, parts }
    }

    /// Every file of the text (one part for a single file).
    pub fn parts(&self) -> Vec<FilePart> {
        if self.parts.is_empty() {
            let kind = if is_data_block_tab(&self.text) {
                PartKind::DataBlockTab
            } else {
                PartKind::Source
            };
            return vec![FilePart {
                name: self.name.clone(),
                kind,
                start: 0,
                end: self.text.len(),
            }];
        }
        self.parts.clone()
    }

    /// Whether the text joins several files.
    pub fn is_joined(&self) -> bool {
        !self.parts.is_empty()
    }

    /// Index into [`SourceFile::parts`] of the file holding `offset` (0 for one file).
    pub fn part_index(&self, offset: usize) -> usize {
        if self.parts.is_empty() {
            return 0;
        }
        self.parts
            .partition_point(|p| p.start <= offset)
            .saturating_sub(1)
    }

    /// The name of the file holding `offset`.
    pub fn file_name_at(&self, offset: usize) -> &str {
        match self.parts.get(self.part_index(offset)) {
            Some(p) => &p.name,
            None => &self.name,
        }
    }

    /// Byte range in `text` of the file holding `offset`, separator included (so a
    /// span at the file's end lies inside it).
    pub fn part_range(&self, offset: usize) -> Range<usize> {
        match self.parts.get(self.part_index(offset)) {
            Some(p) => p.start..(p.end + 1).min(self.text.len()),
            None => 0..self.text.len(),
        }
    }

    /// `offset` as file, line and column of the file it lies in.
    pub fn locate(&self, index: &LineIndex, offset: usize) -> Location<'_> {
        let at = index.line_col(&self.text, offset);
        let Some(part) = self.parts.get(self.part_index(offset)) else {
            return Location {
                file: &self.name,
                line: at.line,
                column: at.column,
                offset: offset.min(self.text.len()),
            };
        };
        let first_line = index.line_of(part.start) as u32;
        Location {
            file: &part.name,
            line: at.line - first_line,
            column: at.column,
            offset: offset.min(self.text.len()).saturating_sub(part.start),
        }
    }

    /// Decode file bytes: UTF-8, with or without BOM.
    pub fn from_bytes(
        name: impl Into<String>,
        bytes: Vec<u8>,
    ) -> Result<SourceFile, EncodingError> {
        match String::from_utf8(bytes) {
            Ok(text) => Ok(SourceFile::new(name, text)),
            Err(e) => Err(EncodingError {
                offset: e.utf8_error().valid_up_to(),
            }),
        }
    }

    /// Decode the bytes of a STEP 7-Micro/WIN export or a symbol table (docs/microwin.md):
    /// UTF-8 (BOM dropped) when they are UTF-8, else GBK when they are valid GBK, else
    /// Windows-1252 (which decodes every byte). Also says which it was.
    pub fn from_code_page_bytes(
        name: impl Into<String>,
        bytes: Vec<u8>,
    ) -> (SourceFile, SourceEncoding) {
        let (text, encoding) = decode_code_page(bytes);
        (SourceFile::new(name, text), encoding)
    }

    /// A program file's bytes as text, by the one rule every tool follows
    /// (docs/microwin.md): a symbol table (`table`), a Micro/WIN export (a `.awl` name,
    /// or the dialect marker on its first line) or a data block export (its first line
    /// `DATA_BLOCK_TAB`, any name) in its code page (UTF-8, else GBK, else
    /// Windows-1252); any other source strictly UTF-8.
    pub fn from_program_file_bytes(
        name: impl Into<String>,
        bytes: Vec<u8>,
        table: bool,
    ) -> Result<(SourceFile, SourceEncoding), EncodingError> {
        let name = name.into();
        let head = String::from_utf8_lossy(&bytes[..bytes.len().min(256)]).into_owned();
        // A data block export's header may follow any number of comment lines.
        if table || is_microwin(&name, &head) || is_data_block_tab(&String::from_utf8_lossy(&bytes))
        {
            return Ok(SourceFile::from_code_page_bytes(name, bytes));
        }
        SourceFile::from_bytes(name, bytes).map(|f| (f, SourceEncoding::Utf8))
    }

    pub fn slice(&self, span: Span) -> &str {
        self.text.get(span.range()).unwrap_or("")
    }
}

/// The first line that makes a `.lad` file a Micro/WIN export (any case, blanks around).
pub const MARKER: &str = "// dialect: microwin";

/// Whether a file is a Micro/WIN export (docs/microwin.md): its name ends in `.awl` (any
/// case), or its first line is [`MARKER`]. Which dialect a file is in is read here, with
/// its code page, before any stage runs; the dialect's stage is `crate::microwin`.
pub fn is_microwin(name: &str, text: &str) -> bool {
    let awl = name
        .rsplit_once('.')
        .is_some_and(|(_, ext)| ext.eq_ignore_ascii_case("awl"));
    awl || has_marker(text)
}

/// The keyword that opens a Micro/WIN data block export.
pub const DATA_BLOCK_TAB: &str = "DATA_BLOCK_TAB";

/// Whether a source file is a Micro/WIN data block export (docs/microwin.md, "Data
/// block exports"), whatever it is called: its first line that is neither blank nor a
/// `//` comment starts with the word `DATA_BLOCK_TAB` (any case; a BOM before it is
/// allowed). Read here with the file's code page, like [`is_microwin`].
pub fn is_data_block_tab(text: &str) -> bool {
    let text = text.strip_prefix('\u{FEFF}').unwrap_or(text);
    text.lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with("//"))
        .and_then(|l| l.split_whitespace().next())
        .is_some_and(|w| w.eq_ignore_ascii_case(DATA_BLOCK_TAB))
}

/// Whether the text's first line is [`MARKER`] (a BOM before it is allowed).
pub fn has_marker(text: &str) -> bool {
    let text = text.strip_prefix('\u{FEFF}').unwrap_or(text);
    text.lines()
        .next()
        .is_some_and(|l| l.trim().eq_ignore_ascii_case(MARKER))
}

/// The comment line that keeps GUTTA's meaning of timer and counter boxes in a
/// Micro/WIN export: a box leaves its done state on the logic stack, as on GUTTA, not
/// its input, as on an S7-200 (docs/microwin.md, "Timer and counter bits").
/// `gutta-cc dis --format awl` writes it, so that its text compiles back to the same
/// image.
pub const GUTTA_BOXES: &str = "// timer-boxes: gutta";

/// Whether a line of the text is [`GUTTA_BOXES`] (any case, blanks around).
pub fn has_gutta_boxes(text: &str) -> bool {
    text.lines()
        .any(|l| l.trim().eq_ignore_ascii_case(GUTTA_BOXES))
}

/// The text encoding a source file was read in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SourceEncoding {
    Utf8,
    Gbk,
    Windows1252,
}

impl SourceEncoding {
    pub fn as_str(self) -> &'static str {
        match self {
            SourceEncoding::Utf8 => "UTF-8",
            SourceEncoding::Gbk => "GBK",
            SourceEncoding::Windows1252 => "Windows-1252",
        }
    }
}

/// Bytes of a Micro/WIN export to text: UTF-8 when valid, else GBK when valid, else
/// Windows-1252. Pure (no I/O); [`SourceFile::from_code_page_bytes`] uses it.
pub fn decode_code_page(bytes: Vec<u8>) -> (String, SourceEncoding) {
    let bytes = match String::from_utf8(bytes) {
        Ok(text) => return (text, SourceEncoding::Utf8),
        Err(e) => e.into_bytes(),
    };
    if let Some(text) = encoding_rs::GBK.decode_without_bom_handling_and_without_replacement(&bytes)
    {
        return (text.into_owned(), SourceEncoding::Gbk);
    }
    let (text, _) = encoding_rs::WINDOWS_1252.decode_without_bom_handling(&bytes);
    (text.into_owned(), SourceEncoding::Windows1252)
}

/// Byte offset -> (line, column) lookups; lines and columns are 1-based, columns count
/// characters (Unicode scalar values).
#[derive(Debug, Clone)]
pub struct LineIndex {
    /// Byte offset of the start of every line.
    starts: Vec<u32>,
}

/// A 1-based line and character column.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LineCol {
    pub line: u32,
    pub column: u32,
}

impl LineIndex {
    pub fn new(text: &str) -> LineIndex {
        let mut starts = vec![0u32];
        starts.extend(
            text.bytes()
                .enumerate()
                .filter(|(_, b)| *b == b'\n')
                .map(|(i, _)| i as u32 + 1),
        );
        LineIndex { starts }
    }

    /// 0-based line containing `offset`.
    pub fn line_of(&self, offset: usize) -> usize {
        match self.starts.binary_search(&(offset as u32)) {
            Ok(i) => i,
            Err(i) => i - 1,
        }
    }

    pub fn line_start(&self, line: usize) -> usize {
        self.starts.get(line).copied().unwrap_or(0) as usize
    }

    pub fn line_count(&self) -> usize {
        self.starts.len()
    }

    pub fn line_col(&self, text: &str, offset: usize) -> LineCol {
        let offset = offset.min(text.len());
        let line = self.line_of(offset);
        let start = self.line_start(line);
        let column = text
            .get(start..offset)
            .map(|s| s.chars().count())
            .unwrap_or(offset - start);
        LineCol {
            line: line as u32 + 1,
            column: column as u32 + 1,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bom_is_dropped_and_columns_count_characters() {
        let f = SourceFile::new("a.lad", "\u{FEFF}LD 启动\r\n= Q0.0");
        assert_eq!(f.text, "LD 启动\r\n= Q0.0");
        let idx = LineIndex::new(&f.text);
        let q = f.text.find("Q0.0").unwrap();
        assert_eq!(idx.line_col(&f.text, q), LineCol { line: 2, column: 3 });
        let end = f.text.find('\r').unwrap();
        assert_eq!(idx.line_col(&f.text, end), LineCol { line: 1, column: 6 });
    }

    #[test]
    fn awl_names_and_the_marker_choose_the_dialect() {
        assert!(is_microwin("a/b/MAIN.AWL", "ORGANIZATION_BLOCK MAIN:OB1"));
        assert!(is_microwin("x.lad", "\u{FEFF}  // Dialect: MicroWIN \r\nX"));
        assert!(!is_microwin(
            "x.lad",
            "ORGANIZATION_BLOCK MAIN:OB1\n// dialect: microwin"
        ));
        assert!(!is_microwin("awl", ""));
    }

    #[test]
    fn data_block_exports_are_known_by_their_header_and_join_after_the_sources() {
        assert!(is_data_block_tab(
            "\u{FEFF}// x\r\n\r\n  data_block_tab DB1\r\nBEGIN"
        ));
        assert!(is_data_block_tab("DATA_BLOCK_TAB"));
        assert!(!is_data_block_tab("DATA_BLOCK DAT0\nDATA_BLOCK_TAB"));
        assert!(!is_data_block_tab("DATA_BLOCK_TABLE x"));
        let joined = SourceFile::join(
            vec![
                SourceFile::new("a.awl", "x"),
                SourceFile::new("db.txt", "DATA_BLOCK_TAB\nEND_DATA_BLOCK_TAB"),
                SourceFile::new("b.awl", "y"),
            ],
            vec![SourceFile::new("s.csv", "Symbol,Address\n")],
        );
        let kinds: Vec<(String, PartKind)> = joined
            .parts()
            .into_iter()
            .map(|p| (p.name, p.kind))
            .collect();
        assert_eq!(
            kinds,
            [
                ("a.awl".to_string(), PartKind::Source),
                ("b.awl".to_string(), PartKind::Source),
                ("db.txt".to_string(), PartKind::DataBlockTab),
                ("s.csv".to_string(), PartKind::SymbolTable),
            ]
        );
        let alone = SourceFile::new("DB1.txt", "DATA_BLOCK_TAB DB1");
        assert_eq!(alone.parts()[0].kind, PartKind::DataBlockTab);
        // GBK bytes around an ASCII header still make the file one.
        let gbk = b"// \xca\xfd\xbe\xdd\r\nDATA_BLOCK_TAB \xca\xfd\r\n".to_vec();
        let (file, encoding) = SourceFile::from_program_file_bytes("DB1.txt", gbk, false).unwrap();
        assert_eq!(encoding, SourceEncoding::Gbk);
        assert!(file.text.contains("数"));
    }

    #[test]
    fn joined_files_locate_in_their_own_file() {
        let joined = SourceFile::join(
            vec![
                SourceFile::new("a.lad", "x\ny"),
                SourceFile::new("b.lad", "\u{FEFF}z\n"),
            ],
            vec![SourceFile::new("s.csv", "Symbol,Address\n")],
        );
        assert_eq!(joined.text, "x\ny\nz\n\nSymbol,Address\n\n");
        let idx = LineIndex::new(&joined.text);
        let at = |offset| {
            let l = joined.locate(&idx, offset);
            (l.file, l.line, l.column, l.offset)
        };
        assert_eq!(at(2), ("a.lad", 2, 1, 2));
        // The end of a.lad (its separator) is still a.lad.
        assert_eq!(at(3), ("a.lad", 2, 2, 3));
        assert_eq!(at(4), ("b.lad", 1, 1, 0));
        assert_eq!(at(7), ("s.csv", 1, 1, 0));
        assert_eq!(joined.part_range(5), 4..7);
        let single = SourceFile::join(vec![SourceFile::new("m.lad", "a")], Vec::new());
        assert!(!single.is_joined());
        assert_eq!(single.parts().len(), 1);
    }
}
