//! Symbol tables: CSV with the header `Symbol,Address,Comment` (as STEP 7-Micro/WIN
//! SMART exports it: quoted fields with `""` escapes, CRLF; the BOM is dropped with the
//! file's decoding) and tab-separated rows (as Micro/WIN pastes them, header optional).
//! Rows become the same `SymbolDecl`s as a SYMBOLS block's, spanning the table's text in
//! the program's joined text; the checker applies the same rules to both. Reading only:
//! no name or address is judged here beyond the row's shape.

use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;
use crate::syntax::ast::SymbolDecl;

/// One field of a row: its content's span (inside the quotes, blanks trimmed).
#[derive(Debug, Clone, Copy)]
struct Field {
    span: Span,
    /// Quoted with `""` inside.
    escaped: bool,
}

/// One record: its span (without the line break) and fields.
#[derive(Debug, Clone)]
struct Row {
    span: Span,
    fields: Vec<Field>,
}

/// The declarations of the table in `text[start..end]`, and what is wrong with it.
pub fn parse_table(text: &str, start: usize, end: usize) -> (Vec<SymbolDecl>, Vec<Diagnostic>) {
    let end = end.min(text.len());
    let mut diags = Vec::new();
    let body = text.get(start..end).unwrap_or("");
    let tab_separated = body
        .lines()
        .find(|l| !l.trim().is_empty())
        .is_some_and(|l| l.contains('\t'));
    let separator = if tab_separated { b'\t' } else { b',' };
    let rows = records(text, start, end, separator, &mut diags);
    let cell = |f: &Field| text.get(f.span.range()).unwrap_or("");
    let mut rows = rows
        .into_iter()
        .filter(|r| r.fields.iter().any(|f| !f.span.is_empty()))
        .peekable();
    let header = rows.peek().is_some_and(|r| is_header(&r.fields, cell));
    if header {
        rows.next();
    } else if let (false, Some(first)) = (tab_separated, rows.peek()) {
        let at = first.span;
        diags.push(
            Diagnostic::new(
                Code::BadSymbolTable,
                at,
                "a CSV symbol table starts with the header `Symbol,Address,Comment`",
            )
            .label("expected the header row here")
            .help("export the table from Micro/WIN SMART, or add the header line"),
        );
        return (Vec::new(), diags);
    }
    let decls = rows
        .filter_map(|r| declaration(text, &r, &mut diags))
        .collect();
    (decls, diags)
}

/// Whether a row is the header: `Symbol`, `Address`, optionally `Comment`, any case.
fn is_header<'t>(fields: &[Field], cell: impl Fn(&Field) -> &'t str) -> bool {
    let words = ["symbol", "address", "comment"];
    let named: Vec<&str> = fields.iter().map(&cell).filter(|c| !c.is_empty()).collect();
    named.len() >= 2
        && named.len() <= 3
        && named
            .iter()
            .zip(words)
            .all(|(c, w)| c.eq_ignore_ascii_case(w))
}

/// A data row as a declaration, or `None` (reported) when its shape is wrong.
fn declaration(text: &str, row: &Row, diags: &mut Vec<Diagnostic>) -> Option<SymbolDecl> {
    let cell = |f: &Field| text.get(f.span.range()).unwrap_or("");
    let mut bad = |span: Span, message: String, label: &str| {
        diags.push(
            Diagnostic::new(Code::BadSymbolTableRow, span, message)
                .label(label)
                .help("a row is `Symbol,Address,Comment`, e.g. `Temp,MD8:REAL,tank temperature`"),
        );
        None
    };
    if let Some(extra) = row.fields.iter().skip(3).find(|f| !cell(f).is_empty()) {
        return bad(
            extra.span,
            "a symbol table row has three fields: Symbol, Address, Comment".into(),
            "one field too many",
        );
    }
    let name = row.fields[0];
    if cell(&name).is_empty() {
        return bad(row.span, "this row names no symbol".into(), "no name");
    }
    if !is_word(cell(&name)) {
        return bad(
            name.span,
            format!("symbol name `{}` is not one word", cell(&name)),
            "letters, digits and `_` only",
        );
    }
    let Some(address) = row.fields.get(1).filter(|f| !cell(f).is_empty()) else {
        return bad(
            row.span,
            format!("symbol `{}` has no address", cell(&name)),
            "no address",
        );
    };
    let (address, data_type) = match cell(address).find(':') {
        None => (address.span, None),
        Some(colon) => {
            let colon = address.span.start as usize + colon;
            let before = trim(text, Span::new(address.span.start as usize, colon));
            let after = trim(text, Span::new(colon + 1, address.span.end as usize));
            if before.is_empty() || after.is_empty() {
                return bad(
                    address.span,
                    format!("`{}` is not `ADDRESS` or `ADDRESS:TYPE`", cell(address)),
                    "expected an address such as MD8 or MD8:REAL",
                );
            }
            (before, Some(after))
        }
    };
    let comment = row.fields.get(2).filter(|f| !cell(f).is_empty());
    Some(SymbolDecl {
        name: name.span,
        address,
        data_type,
        comment: comment.map(|c| c.span),
        comment_escaped: comment.is_some_and(|c| c.escaped),
    })
}

/// A name as the language's words are: a letter or `_`, then letters, digits, `_`.
pub fn is_word(name: &str) -> bool {
    let mut chars = name.chars();
    chars.next().is_some_and(|c| c.is_alphabetic() || c == '_')
        && chars.all(|c| c.is_alphanumeric() || c == '_')
}

/// `span` without the blanks at either end.
fn trim(text: &str, span: Span) -> Span {
    let s = text.get(span.range()).unwrap_or("");
    let start = span.start as usize + (s.len() - s.trim_start().len());
    let end = (span.end as usize - (s.len() - s.trim_end().len())).max(start);
    Span::new(start, end)
}

/// The records of `text[start..end]`, fields split at `separator`; a field may be
/// quoted (`"a ""b"", c"`), and a quoted field may hold separators and line breaks.
fn records(
    text: &str,
    start: usize,
    end: usize,
    separator: u8,
    diags: &mut Vec<Diagnostic>,
) -> Vec<Row> {
    let bytes = text.as_bytes();
    let stops_field = |b: u8| b == separator || b == b'\r' || b == b'\n';
    let mut rows = Vec::new();
    let mut i = start;
    while i < end {
        let row_start = i;
        let mut fields = Vec::new();
        loop {
            let lead = i;
            while i < end && (bytes[i] == b' ' || (bytes[i] == b'\t' && separator != b'\t')) {
                i += 1;
            }
            if i < end && bytes[i] == b'"' {
                let (field, next) = quoted(text, i, end, separator, diags);
                fields.push(field);
                i = next;
            } else {
                i = lead;
                while i < end && !stops_field(bytes[i]) {
                    i += 1;
                }
                fields.push(Field {
                    span: trim(text, Span::new(lead, i)),
                    escaped: false,
                });
            }
            if i < end && bytes[i] == separator {
                i += 1;
                continue;
            }
            break;
        }
        let row_end = i;
        if i < end && bytes[i] == b'\r' {
            i += 1;
        }
        if i < end && bytes[i] == b'\n' {
            i += 1;
        }
        rows.push(Row {
            span: Span::new(row_start, row_end),
            fields,
        });
    }
    rows
}

/// The quoted field opening at `open`, and where its row goes on (the separator or line
/// break after it). Text between the closing quote and that point is reported.
fn quoted(
    text: &str,
    open: usize,
    end: usize,
    separator: u8,
    diags: &mut Vec<Diagnostic>,
) -> (Field, usize) {
    let bytes = text.as_bytes();
    let mut i = open + 1;
    let mut escaped = false;
    let content_end = loop {
        if i >= end {
            diags.push(
                Diagnostic::new(
                    Code::BadSymbolTableRow,
                    Span::new(open, open + 1),
                    "this quote is not closed",
                )
                .label("opened here")
                .help("close the field with `\"`; a quote inside a field is written `\"\"`"),
            );
            break end;
        }
        if bytes[i] == b'"' {
            if i + 1 < end && bytes[i + 1] == b'"' {
                escaped = true;
                i += 2;
                continue;
            }
            i += 1;
            break i - 1;
        }
        i += 1;
    };
    let after = i;
    while i < end && bytes[i] != separator && bytes[i] != b'\r' && bytes[i] != b'\n' {
        i += 1;
    }
    let junk = trim(text, Span::new(after.min(i), i));
    if !junk.is_empty() {
        diags.push(
            Diagnostic::new(
                Code::BadSymbolTableRow,
                junk,
                "text after the closing quote of a field",
            )
            .label("outside the quotes")
            .help("put the whole field in quotes; a quote inside a field is written `\"\"`"),
        );
    }
    (
        Field {
            span: Span::new(open + 1, content_end),
            escaped,
        },
        i,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A declaration as text: name, address, type, comment.
    type Row = (String, String, Option<String>, Option<String>);

    fn table(text: &str) -> (Vec<Row>, Vec<Code>) {
        let (decls, diags) = parse_table(text, 0, text.len());
        let slice = |s: Span| text[s.range()].to_string();
        let rows = decls
            .iter()
            .map(|d| {
                (
                    slice(d.name),
                    slice(d.address),
                    d.data_type.map(slice),
                    d.comment_text(text),
                )
            })
            .collect();
        (rows, diags.iter().map(|d| d.code).collect())
    }

    fn row(n: &str, a: &str, t: Option<&str>, c: Option<&str>) -> Row {
        (n.into(), a.into(), t.map(Into::into), c.map(Into::into))
    }

    #[test]
    fn csv_with_quotes_crlf_and_trailing_fields() {
        let text = "symbol,ADDRESS,Comment,,\r\nStart,I0.0,\"push \"\"green\"\", left\"\r\nTemp, MD8:REAL ,tank,,\r\n\r\nLamp,Q0.0\r\n";
        let (rows, codes) = table(text);
        assert_eq!(codes, []);
        assert_eq!(
            rows,
            [
                row("Start", "I0.0", None, Some("push \"green\", left")),
                row("Temp", "MD8", Some("REAL"), Some("tank")),
                row("Lamp", "Q0.0", None, None),
            ]
        );
    }

    #[test]
    fn a_quoted_field_may_span_lines() {
        let (rows, codes) = table("Symbol,Address,Comment\nA,M0.0,\"two\nlines\"\nB,M0.1,\n");
        assert_eq!(codes, []);
        assert_eq!(
            rows,
            [
                row("A", "M0.0", None, Some("two\nlines")),
                row("B", "M0.1", None, None)
            ]
        );
    }

    #[test]
    fn tab_separated_with_or_without_header() {
        let (rows, codes) = table("Start\tI0.0\tpush button\nLamp\tQ0.0\t\n");
        assert_eq!(codes, []);
        assert_eq!(
            rows,
            [
                row("Start", "I0.0", None, Some("push button")),
                row("Lamp", "Q0.0", None, None)
            ]
        );
        let (rows, codes) = table("Symbol\tAddress\tComment\r\nSpeed\tMW10:INT\t\r\n");
        assert_eq!(codes, []);
        assert_eq!(rows, [row("Speed", "MW10", Some("INT"), None)]);
    }

    #[test]
    fn malformed_tables_and_rows_are_reported() {
        assert_eq!(table("Start,I0.0,\n").1, [Code::BadSymbolTable]);
        let (rows, codes) = table(
            "Symbol,Address,Comment\nMotor 1,Q0.0,\n,Q0.1,x\nNoAddr,,x\nA,Q0.2,c,extra\nB,\"Q0.3\"x,\nC,MD8:,\nD,Q0.4,\"open\n",
        );
        // Rows with a misplaced or open quote are reported and still declared.
        let names: Vec<&str> = rows.iter().map(|r| r.0.as_str()).collect();
        assert_eq!(names, ["B", "D"]);
        assert_eq!(codes, [Code::BadSymbolTableRow; 7]);
        assert_eq!(table("").1, []);
    }
}
