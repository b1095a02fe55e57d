//! The formatter: one .lad text in, the same program in the Micro/WIN export layout out
//! (docs/language.md, "Layout"). It changes only blanks and blank lines between tokens,
//! never a token, so it cannot change what the program means; a text with syntax errors
//! is refused, not half formatted. The line classifier here (`classify`) is also the
//! folding ranges' view of the text. No I/O, no LSP types.

use gutta_compiler::source::Span;
use gutta_compiler::syntax::lexer::{lex, Spanned, Tok};

/// Instruction lines: the mnemonic padded to this many characters, operands after it.
pub const MNEMONIC_COLUMN: usize = 7;
/// Data rows: the address and type columns are at least this wide.
pub const DATA_COLUMN: usize = 7;
/// Blanks between the widest commented line of a group and its `//` comments.
pub const COMMENT_GAP: usize = 2;
/// Indentation of declarations, data rows and system entries.
pub const INDENT: &str = "  ";

/// Why a text is not formatted: its first syntax error.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FormatRefusal {
    pub span: Span,
    pub message: String,
}

/// What a line is, as far as layout goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum LineKind {
    Blank,
    /// A line that is only a comment.
    Comment,
    /// `PLC_TYPE ...`.
    PlcType,
    /// A line that opens a block or section: a block header, `SYMBOLS`, `VAR...`.
    Open(Section),
    /// `END_...` of a block or section.
    Close(Section),
    /// `BEGIN`.
    Begin,
    /// `TITLE=...`.
    Title,
    /// `NETWORK n // title`.
    Network,
    /// A line inside a section: a declaration, instruction, data row or system entry.
    Item(Section),
}

/// The block or section a line belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Section {
    Symbols,
    /// A program block (header to END).
    Unit,
    Vars,
    /// A program block's code (instruction lines).
    Code,
    Data,
    System,
}

/// One line of the text: where it is and what it is.
#[derive(Debug, Clone)]
pub(crate) struct LineInfo {
    /// The line without its line end, in bytes of the whole text.
    pub span: Span,
    pub kind: LineKind,
    /// Its tokens (text offsets) without a trailing comment.
    pub tokens: Vec<Spanned>,
    pub comment: Option<Span>,
}

/// The lines of `text` classified by a small block state machine. Never fails: a line
/// it cannot place is an item of the section it is in.
pub(crate) fn classify(text: &str) -> Vec<LineInfo> {
    let mut out = Vec::new();
    let mut state = State::Top;
    let mut start = 0;
    for raw in text.split_inclusive('\n') {
        let body = raw.trim_end_matches('\n').trim_end_matches('\r');
        let span = Span::new(start, start + body.len());
        let mut tokens: Vec<Spanned> = lex(body)
            .into_iter()
            .map(|(t, s)| {
                (
                    t,
                    Span::new(start + s.start as usize, start + s.end as usize),
                )
            })
            .collect();
        start += raw.len();
        let comment = match tokens.last() {
            Some((Tok::Comment, c)) => Some(*c),
            _ => None,
        };
        if comment.is_some() {
            tokens.pop();
        }
        let first = tokens
            .first()
            .filter(|(t, _)| *t == Tok::Word)
            .map(|(_, s)| text[s.range()].to_ascii_uppercase());
        let kind = match (&first, tokens.first()) {
            (_, None) if comment.is_some() => LineKind::Comment,
            (_, None) => LineKind::Blank,
            (_, Some((Tok::Title, _))) => LineKind::Title,
            (Some(word), _) => state.word_line(word),
            (None, _) => state.item(),
        };
        out.push(LineInfo {
            span,
            kind,
            tokens,
            comment,
        });
    }
    out
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum State {
    Top,
    Symbols,
    UnitHead,
    Vars { in_code: bool },
    Code,
    Data,
    System,
}

impl State {
    /// The kind of a line that starts with `word` (upper case); moves the state.
    fn word_line(&mut self, word: &str) -> LineKind {
        let opened = match word {
            "PLC_TYPE" => return LineKind::PlcType,
            "SYMBOLS" => Some((State::Symbols, Section::Symbols)),
            "ORGANIZATION_BLOCK" | "SUBROUTINE_BLOCK" | "INTERRUPT_BLOCK" => {
                Some((State::UnitHead, Section::Unit))
            }
            "DATA_BLOCK" => Some((State::Data, Section::Data)),
            "SYSTEM_BLOCK" => Some((State::System, Section::System)),
            "VAR_INPUT" | "VAR_IN_OUT" | "VAR_OUTPUT" | "VAR" | "VAR_TEMP" => Some((
                State::Vars {
                    in_code: *self == State::Code,
                },
                Section::Vars,
            )),
            _ => None,
        };
        if let Some((state, section)) = opened {
            *self = state;
            return LineKind::Open(section);
        }
        let closed = match word {
            "END_SYMBOLS" => Some((State::Top, Section::Symbols)),
            "END_ORGANIZATION_BLOCK" | "END_SUBROUTINE_BLOCK" | "END_INTERRUPT_BLOCK" => {
                Some((State::Top, Section::Unit))
            }
            "END_DATA_BLOCK" => Some((State::Top, Section::Data)),
            "END_SYSTEM_BLOCK" => Some((State::Top, Section::System)),
            "END_VAR" => Some((
                match *self {
                    State::Vars { in_code: true } => State::Code,
                    _ => State::UnitHead,
                },
                Section::Vars,
            )),
            _ => None,
        };
        if let Some((state, section)) = closed {
            *self = state;
            return LineKind::Close(section);
        }
        match word {
            "BEGIN" => {
                *self = State::Code;
                LineKind::Begin
            }
            "NETWORK" if *self == State::Code => LineKind::Network,
            _ => self.item(),
        }
    }

    fn item(&self) -> LineKind {
        LineKind::Item(match self {
            State::Top | State::UnitHead => Section::Unit,
            State::Symbols => Section::Symbols,
            State::Vars { .. } => Section::Vars,
            State::Code => Section::Code,
            State::Data => Section::Data,
            State::System => Section::System,
        })
    }
}

/// `text` in the layout of docs/language.md ("Layout"), or the first syntax error. A
/// byte order mark stays; line ends follow the first line end (CRLF stays CRLF).
pub fn format(text: &str) -> Result<String, FormatRefusal> {
    let (bom, body) = match text.strip_prefix('\u{FEFF}') {
        Some(rest) => ("\u{FEFF}", rest),
        None => ("", text),
    };
    let parsed = gutta_compiler::syntax::parse(body);
    if let Some(d) = parsed.diagnostics.first() {
        return Err(FormatRefusal {
            span: d.primary.span,
            message: d.message.clone(),
        });
    }
    let newline = match body.find('\n') {
        Some(i) if i > 0 && body.as_bytes()[i - 1] == b'\r' => "\r\n",
        _ => "\n",
    };
    let lines = classify(body);
    let rendered = Renderer::new(body).render(&lines);
    let mut out = String::with_capacity(text.len() + 64);
    out.push_str(bom);
    for (i, line) in rendered.iter().enumerate() {
        if i > 0 {
            out.push_str(newline);
        }
        out.push_str(line);
    }
    if !rendered.is_empty() && body.ends_with('\n') {
        out.push_str(newline);
    }
    Ok(out)
}

/// A replacement of `span` (bytes of the original text) by `text`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Edit {
    pub span: Span,
    pub text: String,
}

/// [`format()`] as small edits, one per line that changes: each covers the line and the
/// blank lines before it (the blank lines at the end of the file are one more edit).
/// The formatter keeps every non-blank line, in order, so line n of the text is the
/// n-th non-blank line of the result. For range formatting: apply those that touch it.
pub fn format_edits(text: &str) -> Result<Vec<Edit>, FormatRefusal> {
    let formatted = format(text)?;
    let old = regions(text);
    let new = regions(&formatted);
    Ok(old
        .iter()
        .zip(&new)
        .filter(|(o, n)| text[o.range()] != formatted[n.range()])
        .map(|(o, n)| Edit {
            span: *o,
            text: formatted[n.range()].to_string(),
        })
        .collect())
}

/// Each non-blank line with the blank lines before it (from the end of the previous
/// non-blank line's line end to the end of its own text), then the rest of the text.
fn regions(text: &str) -> Vec<Span> {
    let mut regions = Vec::new();
    let (mut from, mut at) = (0, 0);
    for line in text.split_inclusive('\n') {
        let body = line.trim_end_matches(['\n', '\r']);
        if !body.trim().is_empty() {
            regions.push(Span::new(from, at + body.len()));
            from = at + line.len();
        }
        at += line.len();
    }
    regions.push(Span::new(from, text.len()));
    regions
}

/// A line's code, in cells that a group aligns.
#[derive(Debug, Clone)]
enum Cells {
    /// Written as it is (blanks between tokens made single).
    Plain(String),
    /// `MNEMONIC operands`.
    Instruction(String, String),
    /// `name : rest` (SYMBOLS, VAR) or `key = value` (system block), with the separator.
    Pair(String, &'static str, String),
    /// `ADDRESS TYPE VALUE`.
    DataRow(String, Option<String>, String),
}

#[derive(Debug, Clone)]
struct OutLine {
    indent: &'static str,
    cells: Cells,
    comment: Option<String>,
    /// Lines of one group align their cells and comments.
    group: Option<usize>,
    kind: LineKind,
}

struct Renderer<'t> {
    text: &'t str,
}

impl<'t> Renderer<'t> {
    fn new(text: &'t str) -> Self {
        Renderer { text }
    }

    fn render(&self, lines: &[LineInfo]) -> Vec<String> {
        let out = self.lay_out(lines);
        let out = blank_lines(out);
        let mut widths = std::collections::HashMap::new();
        for line in &out {
            if let Some(g) = line.group {
                let w: &mut Widths = widths.entry(g).or_default();
                w.add(&line.cells);
            }
        }
        let codes: Vec<String> = out
            .iter()
            .map(|l| {
                let w = l.group.and_then(|g| widths.get(&g)).copied();
                format!(
                    "{}{}",
                    l.indent,
                    cells_text(&l.cells, w.unwrap_or_default())
                )
            })
            .collect();
        let mut comment_column = std::collections::HashMap::new();
        for (line, code) in out.iter().zip(&codes) {
            if let (Some(g), Some(_)) = (line.group, &line.comment) {
                let c = comment_column.entry(g).or_insert(0);
                *c = (*c).max(width(code) + COMMENT_GAP);
            }
        }
        out.iter()
            .zip(codes)
            .map(|(line, code)| match &line.comment {
                None => code.trim_end().to_string(),
                Some(c) if code.trim().is_empty() => format!("{}{c}", line.indent),
                Some(c) => {
                    let column = line
                        .group
                        .and_then(|g| comment_column.get(&g))
                        .copied()
                        .unwrap_or(width(&code) + 1);
                    let pad = column.saturating_sub(width(&code)).max(1);
                    format!("{code}{}{c}", " ".repeat(pad))
                }
            })
            .collect()
    }

    /// Each line's cells, indentation and alignment group.
    fn lay_out(&self, lines: &[LineInfo]) -> Vec<OutLine> {
        let mut group = 0;
        let mut comment_indent = "";
        let mut out = Vec::with_capacity(lines.len());
        for line in lines {
            let comment = line
                .comment
                .map(|c| self.text[c.range()].trim_end().to_string());
            let toks = &line.tokens[..];
            let (indent, cells, in_group) = match line.kind {
                LineKind::Blank | LineKind::Comment => {
                    (comment_indent, Cells::Plain(String::new()), false)
                }
                LineKind::Open(section) | LineKind::Close(section) => {
                    group += 1;
                    comment_indent = match (line.kind, section) {
                        (LineKind::Open(_), Section::Unit | Section::Code) => "",
                        (LineKind::Open(_), _) => INDENT,
                        _ => "",
                    };
                    ("", Cells::Plain(self.joined(toks)), false)
                }
                LineKind::Network => {
                    group += 1;
                    ("", Cells::Plain(self.joined(toks)), false)
                }
                LineKind::Item(Section::Code) => ("", self.instruction(toks), true),
                LineKind::Item(Section::Symbols | Section::Vars) => {
                    (INDENT, self.pair(toks, Tok::Colon, " : "), true)
                }
                LineKind::Item(Section::System) => (INDENT, self.pair(toks, Tok::Eq, " = "), true),
                LineKind::Item(Section::Data) => (INDENT, self.data_row(toks), true),
                _ => ("", Cells::Plain(self.joined(toks)), false),
            };
            out.push(OutLine {
                indent,
                cells,
                comment,
                group: in_group.then_some(group),
                kind: line.kind,
            });
        }
        out
    }

    /// Tokens as written, blanks between them made one space; no blank before a comma
    /// and one after it. Adjacent tokens stay adjacent.
    fn joined(&self, toks: &[Spanned]) -> String {
        let mut s = String::new();
        for (i, (tok, span)) in toks.iter().enumerate() {
            if i > 0 {
                let prev = toks[i - 1];
                let gap = span.start > prev.1.end;
                if *tok != Tok::Comma && (prev.0 == Tok::Comma || gap) {
                    s.push(' ');
                }
            }
            s.push_str(&self.text[span.range()]);
        }
        s
    }

    /// The mnemonic is the run of adjacent tokens the line starts with.
    fn instruction(&self, toks: &[Spanned]) -> Cells {
        let mut n = 1;
        while n < toks.len() && toks[n].1.start == toks[n - 1].1.end {
            n += 1;
        }
        Cells::Instruction(self.joined(&toks[..n]), self.joined(&toks[n..]))
    }

    fn pair(&self, toks: &[Spanned], sep: Tok, shown: &'static str) -> Cells {
        match toks.iter().position(|(t, _)| *t == sep) {
            Some(i) => Cells::Pair(self.joined(&toks[..i]), shown, self.joined(&toks[i + 1..])),
            None => Cells::Plain(self.joined(toks)),
        }
    }

    fn data_row(&self, toks: &[Spanned]) -> Cells {
        let typed = toks.len() > 2 && toks[1].0 == Tok::Word;
        match toks.split_first() {
            Some((address, rest)) if !rest.is_empty() => {
                let address = self.joined(std::slice::from_ref(address));
                if typed {
                    Cells::DataRow(
                        address,
                        Some(self.joined(&rest[..1])),
                        self.joined(&rest[1..]),
                    )
                } else {
                    Cells::DataRow(address, None, self.joined(rest))
                }
            }
            _ => Cells::Plain(self.joined(toks)),
        }
    }
}

/// Blank lines: none at the start or end of the file, none right after a line that
/// opens a block or section nor right before its end, at most one elsewhere, exactly
/// one after a top-level block's end and after `PLC_TYPE`.
fn blank_lines(lines: Vec<OutLine>) -> Vec<OutLine> {
    let mut out: Vec<OutLine> = Vec::with_capacity(lines.len());
    let mut pending = false;
    for line in lines {
        if line.kind == LineKind::Blank {
            pending = true;
            continue;
        }
        let after = out.last().map(|l| l.kind);
        let forced = matches!(
            after,
            Some(
                LineKind::PlcType
                    | LineKind::Close(
                        Section::Symbols | Section::Unit | Section::Data | Section::System
                    )
            )
        );
        let suppressed = matches!(after, None | Some(LineKind::Open(_) | LineKind::Begin))
            || matches!(line.kind, LineKind::Close(_));
        if forced || (pending && !suppressed) {
            out.push(OutLine {
                indent: "",
                cells: Cells::Plain(String::new()),
                comment: None,
                group: None,
                kind: LineKind::Blank,
            });
        }
        pending = false;
        out.push(line);
    }
    out
}

/// Column widths of a group.
#[derive(Debug, Clone, Copy, Default)]
struct Widths {
    pair_left: usize,
    data_address: usize,
    data_type: usize,
}

impl Widths {
    fn add(&mut self, cells: &Cells) {
        match cells {
            Cells::Pair(left, _, _) => self.pair_left = self.pair_left.max(width(left)),
            Cells::DataRow(a, t, _) => {
                self.data_address = self.data_address.max(width(a) + 1).max(DATA_COLUMN);
                if let Some(t) = t {
                    self.data_type = self.data_type.max(width(t) + 1).max(DATA_COLUMN);
                }
            }
            Cells::Plain(_) | Cells::Instruction(..) => {}
        }
    }
}

fn cells_text(cells: &Cells, w: Widths) -> String {
    match cells {
        Cells::Plain(s) => s.clone(),
        Cells::Instruction(m, ops) if ops.is_empty() => m.clone(),
        Cells::Instruction(m, ops) => {
            let pad = MNEMONIC_COLUMN.saturating_sub(width(m)).max(1);
            format!("{m}{}{ops}", " ".repeat(pad))
        }
        Cells::Pair(left, sep, right) => {
            let pad = w.pair_left.saturating_sub(width(left));
            format!("{left}{}{sep}{right}", " ".repeat(pad))
        }
        Cells::DataRow(a, t, v) => {
            let t = t.as_deref().unwrap_or("");
            let ta = " ".repeat(w.data_address.saturating_sub(width(a)));
            let tt = " ".repeat(w.data_type.saturating_sub(width(t)));
            format!("{a}{ta}{t}{tt}{v}")
        }
    }
}

/// Width of a text in characters (what editors show in a fixed-width font, for the
/// scripts programs use outside comments).
fn width(s: &str) -> usize {
    s.chars().count()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fmt(text: &str) -> String {
        match format(text) {
            Ok(s) => s,
            Err(e) => panic!("refused: {e:?}"),
        }
    }

    #[test]
    fn code_in_the_export_layout() {
        let text = "PLC_TYPE CPU-EC20\nSYMBOLS\n Start:I0.0 // push\n  LongName   :  Q0.0\nEND_SYMBOLS\n\n\n\nORGANIZATION_BLOCK MAIN:OB1\n\nBEGIN\nNETWORK   1   //   latch\nLD Start // first\nO M0.0\n=  M0.0   // a longer comment\nMOVW  16#0E01 ,MW20\nLDW>= MW20,   5\nEND_ORGANIZATION_BLOCK   \nDATA_BLOCK D:DAT0\n MW22 UINT 6 // six\n  MB30 USINT 1\nEND_DATA_BLOCK\n";
        let expected = "PLC_TYPE CPU-EC20\n\nSYMBOLS\n  Start    : I0.0  // push\n  LongName : Q0.0\nEND_SYMBOLS\n\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1 //   latch\nLD     Start  // first\nO      M0.0\n=      M0.0   // a longer comment\nMOVW   16#0E01, MW20\nLDW>=  MW20, 5\nEND_ORGANIZATION_BLOCK\n\nDATA_BLOCK D:DAT0\n  MW22   UINT   6  // six\n  MB30   USINT  1\nEND_DATA_BLOCK\n";
        assert_eq!(fmt(text), expected);
        assert_eq!(fmt(expected), expected);
    }

    #[test]
    fn vars_system_block_and_comment_lines() {
        let text = "ORGANIZATION_BLOCK MAIN\nVAR\n// temps\nx:INT;\nlonger , y : BOOL; // two\nEND_VAR\nBEGIN\nNETWORK 1\n// a note\nLD SM0.0\nEND_ORGANIZATION_BLOCK\nSYSTEM_BLOCK\nPORT0.BAUD=38400\n  PORT0.PROTOCOL = MODBUS // slave\nEND_SYSTEM_BLOCK";
        let expected = "ORGANIZATION_BLOCK MAIN\nVAR\n  // temps\n  x         : INT;\n  longer, y : BOOL;  // two\nEND_VAR\nBEGIN\nNETWORK 1\n// a note\nLD     SM0.0\nEND_ORGANIZATION_BLOCK\n\nSYSTEM_BLOCK\n  PORT0.BAUD     = 38400\n  PORT0.PROTOCOL = MODBUS  // slave\nEND_SYSTEM_BLOCK";
        assert_eq!(fmt(text), expected);
    }

    #[test]
    fn line_ends_and_bom_are_kept() {
        let text = "\u{FEFF}ORGANIZATION_BLOCK MAIN\r\nBEGIN\r\nNETWORK 1  \r\nLD   SM0.0\r\n\r\n\r\nEND_ORGANIZATION_BLOCK\r\n";
        let expected = "\u{FEFF}ORGANIZATION_BLOCK MAIN\r\nBEGIN\r\nNETWORK 1\r\nLD     SM0.0\r\nEND_ORGANIZATION_BLOCK\r\n";
        assert_eq!(fmt(text), expected);
    }

    #[test]
    fn edits_cover_the_lines_that_change() {
        let text = "ORGANIZATION_BLOCK MAIN\n\n\nBEGIN\nNETWORK 1\nLD     SM0.0\n=  Q0.0\nEND_ORGANIZATION_BLOCK\n\n";
        let edits = format_edits(text).map(|e| {
            e.iter()
                .map(|e| (text[e.span.range()].to_string(), e.text.clone()))
                .collect::<Vec<_>>()
        });
        let expected = vec![
            ("\n\nBEGIN".to_string(), "BEGIN".to_string()),
            ("=  Q0.0".to_string(), "=      Q0.0".to_string()),
            ("\n".to_string(), String::new()),
        ];
        assert_eq!(edits, Ok(expected));
    }

    #[test]
    fn syntax_errors_are_refused() {
        let refusal =
            format("ORGANIZATION_BLOCK MAIN\nBEGIN\nNETWORK 1\nLD ?\nEND_ORGANIZATION_BLOCK\n");
        assert_eq!(refusal.map_err(|e| e.span), Err(Span::new(43, 44)));
    }

    #[test]
    fn classify_follows_the_blocks() {
        let kinds: Vec<LineKind> = classify("SYMBOLS\nA : I0.0\nEND_SYMBOLS\n// x\n")
            .into_iter()
            .map(|l| l.kind)
            .collect();
        assert_eq!(
            kinds,
            [
                LineKind::Open(Section::Symbols),
                LineKind::Item(Section::Symbols),
                LineKind::Close(Section::Symbols),
                LineKind::Comment,
            ]
        );
    }
}
