//! Micro/WIN data block exports (docs/microwin.md, "Data block exports"): a file that
//! starts with `DATA_BLOCK_TAB name` (`source::is_data_block_tab`), then an optional
//! `BEGIN`, rows `VB40 1, 2, 3 // comment` (an address and values separated by commas;
//! a line of values alone continues the row above) and `END_DATA_BLOCK_TAB`. Values are
//! whole numbers (`-5`, `16#FF`, `2#1010`), reals (`1.5`) and quoted characters (`'AB'`,
//! or `"AB"` for an S7-200 string with its length byte). Reading only: the addresses and
//! whether each value fits are the checker's (`check/data_block_tab.rs`); every line this
//! module cannot read is one E0227 at that line (E0104 for a malformed number).

use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;
use crate::syntax::ast::{DataBlockTab, TabRow, TabValue, TabValueKind};
use crate::syntax::numbers::{self, Number};

/// The keyword that opens a data block export (the file rule's: `source.rs`).
pub use crate::source::DATA_BLOCK_TAB as HEADER;
/// The keyword that closes it.
pub const END: &str = "END_DATA_BLOCK_TAB";

/// The longest S7-200 string: its length byte counts to 254.
const MAX_STRING: usize = 254;

/// Where the reader is in the file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Stage {
    /// Before the `DATA_BLOCK_TAB` line.
    Head,
    /// Right after it: `BEGIN` may come.
    Header,
    Rows,
    /// After `END_DATA_BLOCK_TAB`: only blanks and comments.
    Done,
}

/// The data block export in `text[start..end]`, and what is wrong with it. Never fails:
/// a line it cannot read is reported and left out (a continuation of it with it).
pub fn parse_data_block_tab(
    text: &str,
    start: usize,
    end: usize,
) -> (Option<DataBlockTab>, Vec<Diagnostic>) {
    let end = end.min(text.len());
    let mut diags = Vec::new();
    let mut block: Option<DataBlockTab> = None;
    let mut stage = Stage::Head;
    // Whether the last row line was read (its continuation lines belong to it), or was
    // not (they are dropped with it); None before the first row line.
    let mut row_open: Option<bool> = None;
    let mut offset = start;
    let body = text.get(start..end).unwrap_or("");
    for raw in body.split_inclusive('\n') {
        let line_start = offset;
        offset += raw.len();
        let Some((content, span)) = content_of(raw, line_start) else {
            continue;
        };
        let first_word = content.split_whitespace().next().unwrap_or("");
        match stage {
            Stage::Head => {
                if first_word.eq_ignore_ascii_case(HEADER) {
                    let rest = content[first_word.len()..].trim_start();
                    let name = (!rest.is_empty()).then(|| {
                        let at = span.end as usize - rest.len();
                        Span::new(at, span.end as usize)
                    });
                    block = Some(DataBlockTab {
                        header: span,
                        name,
                        rows: Vec::new(),
                        end: None,
                    });
                    stage = Stage::Header;
                } else {
                    diags.push(
                        Diagnostic::new(
                            Code::S7200DataBlock,
                            span,
                            "a data block export starts with `DATA_BLOCK_TAB name`",
                        )
                        .label("expected the header line here"),
                    );
                    return (None, diags);
                }
            }
            Stage::Done => diags.push(
                Diagnostic::new(
                    Code::S7200DataBlock,
                    span,
                    "text after END_DATA_BLOCK_TAB",
                )
                .help("a data block export ends with its END_DATA_BLOCK_TAB line; put further rows before it"),
            ),
            Stage::Header | Stage::Rows => {
                let Some(b) = block.as_mut() else { break };
                if content.eq_ignore_ascii_case("BEGIN") && stage == Stage::Header {
                    stage = Stage::Rows;
                } else if content.eq_ignore_ascii_case(END) {
                    b.end = Some(span);
                    stage = Stage::Done;
                } else {
                    stage = Stage::Rows;
                    row_open = Some(row_line(b, content, span, row_open, &mut diags));
                }
            }
        }
    }
    if let Some(b) = &block {
        if b.end.is_none() {
            diags.push(
                Diagnostic::new(
                    Code::UnterminatedBlock,
                    b.header,
                    "DATA_BLOCK_TAB is not closed by END_DATA_BLOCK_TAB",
                )
                .label("the file ends before END_DATA_BLOCK_TAB")
                .help("an export cut short would give a shorter data block; export it again or add the missing rows and END_DATA_BLOCK_TAB"),
            );
        }
    }
    (block, diags)
}

/// A line without its line end and `//` comment, trimmed, with its span; None for a
/// blank or comment-only line.
fn content_of(raw: &str, line_start: usize) -> Option<(&str, Span)> {
    let line = raw.trim_end_matches(['\n', '\r']);
    let cut = comment_start(line).unwrap_or(line.len());
    let before = &line[..cut];
    let content = before.trim();
    if content.is_empty() {
        return None;
    }
    let lead = before.len() - before.trim_start().len();
    let at = line_start + lead;
    Some((content, Span::new(at, at + content.len())))
}

/// Byte index of `//` outside quotes.
fn comment_start(line: &str) -> Option<usize> {
    let mut quote: Option<char> = None;
    let mut chars = line.char_indices().peekable();
    while let Some((i, c)) = chars.next() {
        match (quote, c) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), _) => {}
            (None, '\'' | '"') => quote = Some(c),
            (None, '/') if chars.peek().is_some_and(|&(_, n)| n == '/') => return Some(i),
            _ => {}
        }
    }
    None
}

/// A row line (an address and values) or a continuation (values alone) read into `b`;
/// returns whether it was read, so that its continuation lines follow it. `row_open`:
/// whether the row line above was read, None when there was none.
fn row_line(
    b: &mut DataBlockTab,
    content: &str,
    span: Span,
    row_open: Option<bool>,
    diags: &mut Vec<Diagnostic>,
) -> bool {
    let at = span.start as usize;
    let starts_value = content
        .chars()
        .next()
        .is_some_and(|c| c.is_ascii_digit() || matches!(c, '+' | '-' | '\'' | '"'));
    if starts_value {
        let Some(values) = values(content, at, diags) else {
            return false;
        };
        match row_open {
            Some(true) => {}
            // A continuation of a line that was not read is that line's mistake.
            Some(false) => return false,
            None => {
                diags.push(
                    Diagnostic::new(Code::S7200DataBlock, span, "values without an address")
                        .help("a row starts with the V address of its first value: `VB20 7`"),
                );
                return false;
            }
        }
        if let Some(row) = b.rows.last_mut() {
            row.values.extend(values);
        }
        return true;
    }
    let address_len = content
        .find(|c: char| c.is_whitespace() || c == ',')
        .unwrap_or(content.len());
    let address = &content[..address_len];
    let is_address = address
        .chars()
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic())
        && address
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '.');
    if !is_address {
        diags.push(
            Diagnostic::new(
                Code::S7200DataBlock,
                span,
                format!("`{content}` is no data block row"),
            )
            .help("a row is a V address and its values separated by commas (`VB40 1, 2, 3`); a line of values alone continues the row above"),
        );
        return false;
    }
    let rest = &content[address_len..];
    let rest_trimmed = rest.trim_start();
    if rest_trimmed.is_empty() {
        diags.push(
            Diagnostic::new(
                Code::S7200DataBlock,
                span,
                format!("`{address}` has no value"),
            )
            .label("a value must follow the address")
            .help("write the value after the address: `VB20 7`"),
        );
        return false;
    }
    let values_at = at + content.len() - rest_trimmed.len();
    let Some(values) = values(rest_trimmed, values_at, diags) else {
        return false;
    };
    b.rows.push(TabRow {
        span,
        address: Span::new(at, at + address_len),
        values,
    });
    true
}

/// The values of `text` (at byte `at`), separated by commas; a comma may end the line
/// (the next line continues). None when one is wrong (reported).
fn values(text: &str, at: usize, diags: &mut Vec<Diagnostic>) -> Option<Vec<TabValue>> {
    let mut out = Vec::new();
    let mut ok = true;
    let pieces = split_commas(text);
    let last = pieces.len().saturating_sub(1);
    for (k, (from, to)) in pieces.into_iter().enumerate() {
        let piece = &text[from..to];
        let value = piece.trim();
        let lead = piece.len() - piece.trim_start().len();
        let span = Span::new(at + from + lead, at + from + lead + value.len());
        if value.is_empty() {
            if k == last && k > 0 {
                break;
            }
            diags.push(
                Diagnostic::new(
                    Code::S7200DataBlock,
                    Span::new(at + to, at + to + 1),
                    "a value is missing between commas",
                )
                .label("no value before this comma"),
            );
            ok = false;
            continue;
        }
        match value_of(value) {
            Ok(kind) => out.push(TabValue { span, kind }),
            Err(refusal) => {
                diags.push(refusal.at(span));
                ok = false;
            }
        }
    }
    ok.then_some(out)
}

/// Byte ranges of the comma-separated pieces of `text`, commas inside quotes kept.
fn split_commas(text: &str) -> Vec<(usize, usize)> {
    let mut pieces = Vec::new();
    let mut quote: Option<char> = None;
    let mut from = 0;
    for (i, c) in text.char_indices() {
        match (quote, c) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), _) => {}
            (None, '\'' | '"') => quote = Some(c),
            (None, ',') => {
                pieces.push((from, i));
                from = i + 1;
            }
            _ => {}
        }
    }
    pieces.push((from, text.len()));
    pieces
}

/// Why a value cannot be read: its code, message and help, made a diagnostic at the
/// value by the caller.
struct Refusal {
    code: Code,
    message: String,
    help: Option<&'static str>,
}

impl Refusal {
    fn new(message: String) -> Refusal {
        Refusal {
            code: Code::S7200DataBlock,
            message,
            help: None,
        }
    }

    fn help(self, help: &'static str) -> Refusal {
        Refusal {
            help: Some(help),
            ..self
        }
    }

    fn at(self, span: Span) -> Diagnostic {
        let d = Diagnostic::new(self.code, span, self.message);
        match self.help {
            Some(h) => d.help(h),
            None => d,
        }
    }
}

/// One value: a number or quoted characters.
fn value_of(value: &str) -> Result<TabValueKind, Refusal> {
    let bad = Refusal::new;
    if let Some(q) = value.chars().next().filter(|c| matches!(c, '\'' | '"')) {
        let inner = value
            .strip_prefix(q)
            .and_then(|v| v.strip_suffix(q))
            .filter(|_| value.len() >= 2)
            .ok_or_else(|| {
                bad(format!("the quoted value {value} is not closed by {q}"))
                    .help("quote characters on one line: `'AB'`")
            })?;
        if inner.contains(q) {
            return Err(bad(format!("{value} is more than one quoted value"))
                .help("separate values with commas: `'A', 'B'`"));
        }
        if let Some(c) = inner
            .chars()
            .find(|c| !c.is_ascii() || c.is_ascii_control())
        {
            return Err(bad(format!(
                "`{c}` is no printable ASCII character: a quoted value sets one byte per character"
            ))
            .help("write the byte's code as a number instead (`16#E4`)"));
        }
        let bytes = inner.as_bytes().to_vec();
        if q == '\'' {
            if bytes.is_empty() {
                return Err(bad("empty characters `''` set no byte".into())
                    .help("write at least one character, or a number"));
            }
            return Ok(TabValueKind::Chars(bytes));
        }
        if bytes.len() > MAX_STRING {
            return Err(bad(format!(
                "a string holds at most {MAX_STRING} characters; this one has {}",
                bytes.len()
            )));
        }
        return Ok(TabValueKind::String(bytes));
    }
    if value.contains(char::is_whitespace) {
        return Err(bad(format!("`{value}` is more than one value"))
            .help("separate values with commas: `VB40 1, 2, 3`"));
    }
    let (negative, digits) = match value.as_bytes().first() {
        Some(b'-') => (true, &value[1..]),
        Some(b'+') => (false, &value[1..]),
        _ => (false, value),
    };
    if !digits.starts_with(|c: char| c.is_ascii_digit()) {
        return Err(bad(format!("`{value}` is not a number")).help(
            "a value is a number (`7`, `-5`, `16#FF`, `1.5`) or quoted characters (`'AB'`)",
        ));
    }
    match numbers::convert(digits, negative) {
        Ok(Number::Integer(v)) => Ok(TabValueKind::Integer(v)),
        Ok(Number::Real(v)) if v.is_finite() => Ok(TabValueKind::Real(v)),
        Ok(Number::Real(_)) => Err(bad(format!("`{value}` is no finite REAL"))),
        Err(e) => Err(Refusal {
            code: Code::MalformedNumber,
            message: e.to_string(),
            help: None,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> (Option<DataBlockTab>, Vec<(String, String)>) {
        let (b, d) = parse_data_block_tab(text, 0, text.len());
        let d = d
            .into_iter()
            .map(|d| {
                (
                    d.code.as_str().to_string(),
                    text[d.primary.span.range()].to_string(),
                )
            })
            .collect();
        (b, d)
    }

    #[test]
    fn rows_values_comments_and_continuations() {
        let text = "// exported\r\nDATA_BLOCK_TAB 数据块1\r\nBEGIN\r\nVB20    7   // seven\r\n\r\n// only a comment\r\nVB40 1, 2,\r\n     -3, 'A,B' // 'x'\r\nVW50 16#FF, 2#1010\r\nVD60 1.5\r\nVB70 \"Hi\"\r\nEND_DATA_BLOCK_TAB\r\n";
        let (b, d) = parse(text);
        assert!(d.is_empty(), "{d:?}");
        let b = b.unwrap();
        assert_eq!(&text[b.name.unwrap().range()], "数据块1");
        assert!(b.end.is_some());
        let kinds: Vec<Vec<TabValueKind>> = b
            .rows
            .iter()
            .map(|r| r.values.iter().map(|v| v.kind.clone()).collect())
            .collect();
        use TabValueKind::*;
        assert_eq!(
            kinds,
            [
                vec![Integer(7)],
                vec![Integer(1), Integer(2), Integer(-3), Chars(b"A,B".to_vec())],
                vec![Integer(255), Integer(10)],
                vec![Real(1.5)],
                vec![String(b"Hi".to_vec())],
            ]
        );
        let addresses: Vec<&str> = b.rows.iter().map(|r| &text[r.address.range()]).collect();
        assert_eq!(addresses, ["VB20", "VB40", "VW50", "VD60", "VB70"]);
        assert_eq!(&text[b.rows[1].values[3].span.range()], "'A,B'");
    }

    #[test]
    fn a_missing_name_begin_and_end() {
        let (b, d) = parse("DATA_BLOCK_TAB\nVB0 1\n");
        let b = b.unwrap();
        assert!(b.name.is_none() && b.end.is_none() && b.rows.len() == 1);
        assert_eq!(d, [("E0105".into(), "DATA_BLOCK_TAB".into())]);
    }

    #[test]
    fn malformed_lines_are_one_error_each() {
        let text = "DATA_BLOCK_TAB x\nBEGIN\n1, 2\nVB0\nVB1 1 2\nVB2 2#12\n  3\nVB4 1,,2\nVB5 'ab\nVB6 'ä'\n? 5\nEND_DATA_BLOCK_TAB\nVB9 1\n";
        let (b, d) = parse(text);
        let d: Vec<(&str, &str)> = d.iter().map(|(c, s)| (c.as_str(), s.as_str())).collect();
        assert_eq!(
            d,
            [
                ("E0227", "1, 2"),
                ("E0227", "VB0"),
                ("E0227", "1 2"),
                ("E0104", "2#12"),
                ("E0227", ","),
                ("E0227", "'ab"),
                ("E0227", "'ä'"),
                ("E0227", "? 5"),
                ("E0227", "VB9 1"),
            ]
        );
        // The continuation `3` of the bad `VB2` row is dropped with it.
        assert!(b.unwrap().rows.is_empty());
    }
}
