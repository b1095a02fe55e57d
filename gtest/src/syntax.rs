//! The `.gtest` format (docs/testing-programs.md): a test file's text into a
//! [`TestFile`] of header lines and tests, each statement with its byte span, plus
//! coded diagnostics (E0801-E0804, E0809, W0801, W0802). Line-oriented like the
//! language: every line is one statement, so recovery is exact (one diagnostic per bad
//! line) and parsing never fails. It knows no target and no program: names stay text
//! until `resolve.rs`.

use gutta_compiler::diagnostics::{Code, Diagnostic};
use gutta_compiler::source::Span;
use gutta_compiler::suggest::closest;
use gutta_compiler::syntax::numbers::{convert, Number};

/// The header keywords (before the first test).
pub const HEADER_KEYWORDS: [&str; 5] = ["PROGRAM", "SCAN_TIME", "PLC_TYPE", "OPTION", "WATCHDOG"];

/// The statement keywords inside a test.
pub const STATEMENT_KEYWORDS: [&str; 11] = [
    "SET", "SCAN", "ADVANCE", "EXPECT", "UNTIL", "FORCE", "UNFORCE", "RESET", "RUN", "STOP",
    "END_TEST",
];

/// What `OPTION` may name: a compile option (`gutta_compiler::CompileOptions`).
pub const OPTIONS: [&str; 2] = ["scale-timer-presets", "s-area"];

/// A parsed test file.
#[derive(Debug, Clone, Default)]
pub struct TestFile {
    pub header: Header,
    pub tests: Vec<TestCase>,
}

/// The header lines, each with the span of its value.
#[derive(Debug, Clone, Default)]
pub struct Header {
    /// `PROGRAM path`: the path as written.
    pub program: Option<(String, Span)>,
    /// `SCAN_TIME`: milliseconds per scan.
    pub scan_time_ms: Option<(u32, Span)>,
    pub plc_type: Option<(String, Span)>,
    pub options: Vec<(String, Span)>,
    /// `OPTION s-area MB100`: where a Micro/WIN export's S area goes, as written.
    pub s_area: Option<(String, Span)>,
    /// `WATCHDOG n`: instructions one scan may execute.
    pub watchdog: Option<(u64, Span)>,
}

/// `TEST name` ... `END_TEST`.
#[derive(Debug, Clone)]
pub struct TestCase {
    pub name: String,
    /// The name in `TEST name`.
    pub name_span: Span,
    /// The whole `TEST name` line.
    pub span: Span,
    pub statements: Vec<Statement>,
}

/// One statement line of a test.
#[derive(Debug, Clone)]
pub struct Statement {
    /// The line without its comment and surrounding blanks.
    pub span: Span,
    pub kind: StatementKind,
}

#[derive(Debug, Clone)]
pub enum StatementKind {
    /// `SET a = 1, b = 2`: write variables (an input's terminal holds its value).
    Set(Vec<Assignment>),
    /// `FORCE a = 1`.
    Force(Vec<Assignment>),
    /// `UNFORCE a, b`; empty for `UNFORCE ALL`.
    Unforce(Vec<VarRef>),
    /// `SCAN n` (1 without n).
    Scan(u32),
    /// `ADVANCE 2s`: scans until this many milliseconds of virtual time have passed.
    Advance(u32),
    /// `EXPECT a = 1, b <> 2`.
    Expect(Vec<Comparison>),
    /// `EXPECT FAULT code`: the last scan faulted with this code.
    ExpectFault(u8),
    /// `EXPECT RUN` (true) or `EXPECT STOP` (false).
    ExpectMode(bool),
    /// `UNTIL a = 1, b = 2 WITHIN n SCANS`: scan until all hold, at most n scans.
    Until {
        conditions: Vec<Comparison>,
        within: u32,
    },
    /// Power-on reset.
    Reset,
    Run,
    Stop,
}

/// A variable as written: a symbol or a direct address.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VarRef {
    pub name: String,
    pub span: Span,
}

/// A value as written.
#[derive(Debug, Clone, PartialEq)]
pub struct Literal {
    pub value: LiteralValue,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub enum LiteralValue {
    /// An integer; `based`: written `16#..`/`2#..`/`8#..` (raw bits for a REAL).
    Integer {
        value: i64,
        based: bool,
    },
    Real(f64),
    Bool(bool),
    /// `"text"`: consecutive bytes.
    Text(Vec<u8>),
}

/// `VAR = VALUE` of SET and FORCE.
#[derive(Debug, Clone)]
pub struct Assignment {
    pub var: VarRef,
    pub value: Literal,
}

/// A comparison operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CompareOp {
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
}

impl CompareOp {
    pub fn as_str(self) -> &'static str {
        match self {
            CompareOp::Eq => "=",
            CompareOp::Ne => "<>",
            CompareOp::Lt => "<",
            CompareOp::Le => "<=",
            CompareOp::Gt => ">",
            CompareOp::Ge => ">=",
        }
    }

    /// Whether `ordering` (actual compared with expected) satisfies the operator.
    pub fn holds(self, ordering: std::cmp::Ordering) -> bool {
        use std::cmp::Ordering::{Equal, Greater, Less};
        match self {
            CompareOp::Eq => ordering == Equal,
            CompareOp::Ne => ordering != Equal,
            CompareOp::Lt => ordering == Less,
            CompareOp::Le => ordering != Greater,
            CompareOp::Gt => ordering == Greater,
            CompareOp::Ge => ordering != Less,
        }
    }
}

/// `VAR OP VALUE` of EXPECT and UNTIL.
#[derive(Debug, Clone)]
pub struct Comparison {
    pub var: VarRef,
    pub op: CompareOp,
    pub value: Literal,
    pub span: Span,
}

// ---- tokens of one line ----------------------------------------------------------------

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    /// A run of characters up to a blank, `,`, an operator or `"`.
    Atom(String),
    Op(CompareOp),
    Comma,
    Text(Vec<u8>),
    /// A text without its closing `"`, or with characters outside printable ASCII.
    BadText(String),
}

#[derive(Debug, Clone)]
struct Token {
    tok: Tok,
    span: Span,
}

/// The tokens of `line` (starting at byte `base` of the file), up to a `//` comment.
fn tokenize(line: &str, base: usize) -> Vec<Token> {
    let bytes = line.as_bytes();
    let mut tokens = Vec::new();
    let mut i = 0;
    let span = |a: usize, b: usize| Span::new(base + a, base + b);
    while i < bytes.len() {
        let c = bytes[i];
        match c {
            b' ' | b'\t' | b'\r' => i += 1,
            b'/' if bytes.get(i + 1) == Some(&b'/') => break,
            b',' => {
                tokens.push(Token {
                    tok: Tok::Comma,
                    span: span(i, i + 1),
                });
                i += 1;
            }
            b'=' | b'<' | b'>' => {
                let next = bytes.get(i + 1).copied();
                let (op, len) = match (c, next) {
                    (b'<', Some(b'>')) => (CompareOp::Ne, 2),
                    (b'<', Some(b'=')) => (CompareOp::Le, 2),
                    (b'>', Some(b'=')) => (CompareOp::Ge, 2),
                    (b'<', _) => (CompareOp::Lt, 1),
                    (b'>', _) => (CompareOp::Gt, 1),
                    _ => (CompareOp::Eq, 1),
                };
                tokens.push(Token {
                    tok: Tok::Op(op),
                    span: span(i, i + len),
                });
                i += len;
            }
            b'"' => {
                let start = i;
                let close = line[i + 1..].find('"').map(|k| i + 1 + k);
                let end = close.map_or(line.len(), |k| k + 1);
                let inner = &line[i + 1..close.unwrap_or(line.len())];
                let printable =
                    !inner.is_empty() && inner.bytes().all(|b| (0x20..0x7F).contains(&b));
                let tok = if close.is_some() && printable {
                    Tok::Text(inner.as_bytes().to_vec())
                } else {
                    Tok::BadText(line[start..end].to_string())
                };
                tokens.push(Token {
                    tok,
                    span: span(start, end),
                });
                i = end;
            }
            _ => {
                let start = i;
                while i < bytes.len() {
                    let b = bytes[i];
                    let comment = b == b'/' && bytes.get(i + 1) == Some(&b'/');
                    if matches!(b, b' ' | b'\t' | b'\r' | b',' | b'=' | b'<' | b'>' | b'"')
                        || comment
                    {
                        break;
                    }
                    // Whole UTF-8 characters: a symbol may be Chinese.
                    i += utf8_len(b);
                }
                let end = i.min(line.len());
                tokens.push(Token {
                    tok: Tok::Atom(line[start..end].to_string()),
                    span: span(start, end),
                });
                i = end;
            }
        }
    }
    tokens
}

fn utf8_len(first: u8) -> usize {
    match first {
        0xF0..=0xFF => 4,
        0xE0..=0xEF => 3,
        0xC0..=0xDF => 2,
        _ => 1,
    }
}

/// A literal from an atom: a number as in the language, or TRUE/FALSE (ON/OFF).
fn literal(atom: &str) -> Result<LiteralValue, String> {
    match atom.to_ascii_uppercase().as_str() {
        "TRUE" | "ON" => return Ok(LiteralValue::Bool(true)),
        "FALSE" | "OFF" => return Ok(LiteralValue::Bool(false)),
        _ => {}
    }
    let (negative, body) = match atom.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, atom.strip_prefix('+').unwrap_or(atom)),
    };
    if !body.starts_with(|c: char| c.is_ascii_digit()) {
        return Err(format!(
            "`{atom}` is not a value: a number (5, -3, 16#FF, 1.5), TRUE/FALSE, or a text in quotes"
        ));
    }
    match convert(body, negative) {
        Ok(Number::Integer(value)) => Ok(LiteralValue::Integer {
            value,
            based: body.contains('#'),
        }),
        Ok(Number::Real(v)) => Ok(LiteralValue::Real(v)),
        Err(e) => Err(format!("`{atom}`: {e}")),
    }
}

/// A duration in whole milliseconds: `10ms`, `2s`, `1.5s`, `250 ms` (the unit may be a
/// separate atom, `unit`).
fn duration(number: &str, unit: Option<&str>) -> Result<u32, String> {
    let lower = number.to_ascii_lowercase();
    let (digits, unit) = match unit {
        Some(u) => (lower.as_str(), u.to_ascii_lowercase()),
        None => {
            let split = lower
                .find(|c: char| !(c.is_ascii_digit() || c == '.' || c == '_'))
                .unwrap_or(lower.len());
            (&lower[..split], lower[split..].to_string())
        }
    };
    let scale = match unit.as_str() {
        "ms" => 1.0,
        "s" => 1000.0,
        "" => return Err(format!("`{number}` needs a unit: ms or s (10ms, 2s)")),
        other => {
            return Err(format!(
                "`{other}` is not a unit of time: ms or s (10ms, 2s)"
            ))
        }
    };
    let clean: String = digits.chars().filter(|&c| c != '_').collect();
    let value: f64 = clean
        .parse()
        .map_err(|_| format!("`{number}` is not a duration (10ms, 2s, 1.5s)"))?;
    let ms = value * scale;
    if ms.fract() != 0.0 {
        return Err(format!("`{number}` is not a whole number of milliseconds"));
    }
    if !(0.0..=f64::from(u32::MAX)).contains(&ms) {
        return Err(format!("`{number}` is too long a time"));
    }
    Ok(ms as u32)
}

/// A positive count (`SCAN 5`, `WITHIN 100 SCANS`).
fn count(atom: &str) -> Result<u32, String> {
    let clean: String = atom.chars().filter(|&c| c != '_').collect();
    clean
        .parse::<u32>()
        .ok()
        .filter(|&n| n > 0)
        .ok_or_else(|| format!("`{atom}` is not a positive whole number"))
}

// ---- the parser ------------------------------------------------------------------------

/// Where the parser is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Place {
    Header,
    InTest,
    BetweenTests,
}

struct Parser {
    file: TestFile,
    diagnostics: Vec<Diagnostic>,
    place: Place,
    /// The open test (its index in `file.tests`).
    open: Option<usize>,
    /// Span of the first statement of each header keyword, for "given twice".
    header_seen: Vec<(&'static str, Span)>,
}

/// Parse a test file's text; never fails.
pub fn parse(text: &str) -> (TestFile, Vec<Diagnostic>) {
    let mut p = Parser {
        file: TestFile::default(),
        diagnostics: Vec::new(),
        place: Place::Header,
        open: None,
        header_seen: Vec::new(),
    };
    let mut offset = 0;
    for raw in text.split_inclusive('\n') {
        let line = raw.trim_end_matches(['\n', '\r']);
        p.line(line, offset);
        offset += raw.len();
    }
    if let Some(i) = p.open {
        let test = &p.file.tests[i];
        p.diagnostics.push(
            Diagnostic::new(
                Code::TestStructure,
                test.span,
                format!("test `{}` has no END_TEST", test.name),
            )
            .label("this test is not closed")
            .help("end it with a line `END_TEST`"),
        );
    }
    if p.file.tests.is_empty() && p.diagnostics.iter().all(|d| !d.is_error()) {
        p.diagnostics.push(
            Diagnostic::new(
                Code::NoTests,
                Span::new(0, 0),
                "this test file has no tests",
            )
            .help("add `TEST name` ... `END_TEST` (docs/testing-programs.md)"),
        );
    }
    let clean = p.diagnostics.iter().all(|d| !d.is_error());
    for test in p.file.tests.iter().filter(|_| clean) {
        let checks = test.statements.iter().any(|s| {
            matches!(
                s.kind,
                StatementKind::Expect(_)
                    | StatementKind::ExpectFault(_)
                    | StatementKind::ExpectMode(_)
                    | StatementKind::Until { .. }
            )
        });
        if !checks {
            p.diagnostics.push(
                Diagnostic::new(
                    Code::TestChecksNothing,
                    test.name_span,
                    format!(
                        "test `{}` has no EXPECT or UNTIL: it cannot fail",
                        test.name
                    ),
                )
                .help("add the EXPECT the test is about"),
            );
        }
    }
    (p.file, p.diagnostics)
}

impl Parser {
    fn error(&mut self, code: Code, span: Span, message: impl Into<String>) -> Option<()> {
        self.diagnostics.push(Diagnostic::new(code, span, message));
        None
    }

    fn line(&mut self, line: &str, base: usize) {
        let tokens = tokenize(line, base);
        let Some(first) = tokens.first() else {
            return;
        };
        let end = tokens.last().map_or(first.span, |t| t.span);
        let span = first.span.to(end);
        let Tok::Atom(word) = &first.tok else {
            self.error(
                Code::TestSyntax,
                first.span,
                "a statement starts with its keyword (SET, SCAN, EXPECT, ...)",
            );
            return;
        };
        let keyword = word.to_ascii_uppercase();
        let rest = &tokens[1..];
        if HEADER_KEYWORDS.contains(&keyword.as_str()) {
            self.header_line(&keyword, first.span, span, rest, line, base);
        } else if keyword == "TEST" {
            self.test_line(first.span, span, rest);
        } else if STATEMENT_KEYWORDS.contains(&keyword.as_str()) {
            self.statement_line(&keyword, first.span, span, rest);
        } else {
            let candidates: Vec<&str> = HEADER_KEYWORDS
                .iter()
                .chain(STATEMENT_KEYWORDS.iter())
                .chain(["TEST"].iter())
                .copied()
                .collect();
            let help = match closest(word, candidates.iter().copied()) {
                Some(k) => format!("did you mean `{k}`?"),
                None => "statements: SET, SCAN, ADVANCE, EXPECT, UNTIL, FORCE, UNFORCE, RESET, RUN, STOP; headers: PROGRAM, SCAN_TIME, PLC_TYPE, OPTION, WATCHDOG".into(),
            };
            self.diagnostics.push(
                Diagnostic::new(
                    Code::UnknownStatement,
                    first.span,
                    format!("`{word}` is not a test statement"),
                )
                .help(help),
            );
        }
    }

    fn header_line(
        &mut self,
        keyword: &str,
        key_span: Span,
        span: Span,
        rest: &[Token],
        line: &str,
        base: usize,
    ) {
        if self.place != Place::Header {
            let why = if self.place == Place::InTest {
                "inside a test"
            } else {
                "after the first test"
            };
            self.diagnostics.push(
                Diagnostic::new(
                    Code::TestStructure,
                    key_span,
                    format!("`{keyword}` is a header line, here {why}"),
                )
                .help("header lines come before the first TEST"),
            );
            return;
        }
        let keyword: &'static str = HEADER_KEYWORDS
            .iter()
            .find(|k| **k == keyword)
            .copied()
            .unwrap_or("PROGRAM");
        if keyword != "OPTION" {
            if let Some((_, first)) = self.header_seen.iter().find(|(k, _)| *k == keyword) {
                let first = *first;
                self.diagnostics.push(
                    Diagnostic::new(
                        Code::TestHeaderValue,
                        span,
                        format!("`{keyword}` is given twice"),
                    )
                    .with_secondary(first, "first given here"),
                );
                return;
            }
            self.header_seen.push((keyword, span));
        }
        let value_span = match (rest.first(), rest.last()) {
            (Some(a), Some(b)) => a.span.to(b.span),
            _ => {
                self.error(
                    Code::TestSyntax,
                    span,
                    format!("`{keyword}` needs its value"),
                );
                return;
            }
        };
        let atom = |k: usize| match rest.get(k).map(|t| &t.tok) {
            Some(Tok::Atom(a)) => Some(a.as_str()),
            _ => None,
        };
        match keyword {
            "PROGRAM" => {
                // The rest of the line is the path (blanks allowed), quotes optional.
                let start = value_span.start as usize - base;
                let end = value_span.end as usize - base;
                let raw = line[start..end].trim();
                let path = raw
                    .strip_prefix('"')
                    .and_then(|r| r.strip_suffix('"'))
                    .unwrap_or(raw);
                self.file.header.program = Some((path.to_string(), value_span));
            }
            "SCAN_TIME" => {
                let parsed = match (rest.len(), atom(0), atom(1)) {
                    (1, Some(n), None) => duration(n, None),
                    (2, Some(n), Some(u)) => duration(n, Some(u)),
                    _ => Err("SCAN_TIME takes one duration: 10ms, 1s".into()),
                };
                match parsed {
                    Ok(0) => {
                        self.error(
                            Code::TestHeaderValue,
                            value_span,
                            "a scan takes at least 1 ms",
                        );
                    }
                    Ok(ms) => self.file.header.scan_time_ms = Some((ms, value_span)),
                    Err(e) => {
                        self.error(Code::TestSyntax, value_span, e);
                    }
                }
            }
            "PLC_TYPE" => match (rest.len(), atom(0)) {
                (1, Some(name)) => {
                    self.file.header.plc_type = Some((name.to_string(), value_span));
                }
                _ => {
                    self.error(Code::TestSyntax, value_span, "PLC_TYPE takes one name");
                }
            },
            "OPTION" => match (rest.len(), atom(0)) {
                (2, Some(name)) if name.eq_ignore_ascii_case("s-area") => match atom(1) {
                    Some(value) if value.parse::<gutta_compiler::microwin::SAreaBase>().is_ok() => {
                        self.file.header.s_area = Some((value.to_string(), value_span));
                    }
                    _ => {
                        self.error(
                            Code::TestHeaderValue,
                            value_span,
                            "OPTION s-area takes a byte address such as MB96",
                        );
                    }
                },
                (1, Some(name)) if name.eq_ignore_ascii_case("s-area") => {
                    self.error(
                        Code::TestHeaderValue,
                        value_span,
                        "OPTION s-area takes a byte address such as MB96",
                    );
                }
                (1, Some(name)) if OPTIONS.contains(&name.to_ascii_lowercase().as_str()) => {
                    self.file
                        .header
                        .options
                        .push((name.to_ascii_lowercase(), value_span));
                }
                (1, Some(name)) => {
                    self.diagnostics.push(
                        Diagnostic::new(
                            Code::TestHeaderValue,
                            value_span,
                            format!("`{name}` is not a compile option"),
                        )
                        .help(format!("options: {}", OPTIONS.join(", "))),
                    );
                }
                _ => {
                    self.error(Code::TestSyntax, value_span, "OPTION takes one name");
                }
            },
            _ => match (rest.len(), atom(0)) {
                (1, Some(n)) => match count(n) {
                    Ok(n) => self.file.header.watchdog = Some((u64::from(n), value_span)),
                    Err(e) => {
                        self.error(Code::TestHeaderValue, value_span, e);
                    }
                },
                _ => {
                    self.error(
                        Code::TestSyntax,
                        value_span,
                        "WATCHDOG takes the instructions one scan may execute",
                    );
                }
            },
        }
    }

    fn test_line(&mut self, key_span: Span, span: Span, rest: &[Token]) {
        if let Some(open) = self.open {
            let name = self.file.tests[open].name.clone();
            let open_span = self.file.tests[open].span;
            self.diagnostics.push(
                Diagnostic::new(
                    Code::TestStructure,
                    key_span,
                    format!("a TEST inside test `{name}`"),
                )
                .with_secondary(open_span, "this test has no END_TEST before it")
                .help("end the test before with `END_TEST`"),
            );
            // Recover: close the open test and start the new one.
        }
        let name = match rest {
            [Token {
                tok: Tok::Atom(name),
                span,
            }] if is_test_name(name) => (name.clone(), *span),
            _ => {
                let at = rest
                    .first()
                    .map_or(span, |t| t.span.to(rest[rest.len() - 1].span));
                self.diagnostics.push(
                    Diagnostic::new(Code::TestSyntax, at, "TEST takes one name")
                        .help("a name is a letter or `_`, then letters, digits or `_`: `TEST lamp_latches`"),
                );
                (String::from("?"), span)
            }
        };
        if let Some(previous) = self
            .file
            .tests
            .iter()
            .find(|t| t.name.eq_ignore_ascii_case(&name.0) && name.0 != "?")
        {
            let previous = previous.name_span;
            self.diagnostics.push(
                Diagnostic::new(
                    Code::DuplicateTest,
                    name.1,
                    format!("test `{}` is defined twice", name.0),
                )
                .with_secondary(previous, "first defined here"),
            );
        }
        self.file.tests.push(TestCase {
            name: name.0,
            name_span: name.1,
            span,
            statements: Vec::new(),
        });
        self.open = Some(self.file.tests.len() - 1);
        self.place = Place::InTest;
    }

    fn statement_line(&mut self, keyword: &str, key_span: Span, span: Span, rest: &[Token]) {
        if keyword == "END_TEST" {
            if self.open.take().is_none() {
                self.error(Code::TestStructure, key_span, "END_TEST without its TEST");
            } else {
                self.place = Place::BetweenTests;
                if !rest.is_empty() {
                    self.error(Code::TestSyntax, span, "END_TEST stands alone on its line");
                }
            }
            return;
        }
        let Some(open) = self.open else {
            self.diagnostics.push(
                Diagnostic::new(
                    Code::TestStructure,
                    key_span,
                    format!("`{keyword}` outside a test"),
                )
                .help("statements belong between `TEST name` and `END_TEST`"),
            );
            return;
        };
        if let Some(kind) = self.statement(keyword, span, rest) {
            self.file.tests[open]
                .statements
                .push(Statement { span, kind });
        }
    }

    fn statement(&mut self, keyword: &str, span: Span, rest: &[Token]) -> Option<StatementKind> {
        let only = |k: StatementKind| -> Result<StatementKind, (Span, String)> {
            match rest.first() {
                None => Ok(k),
                Some(t) => Err((
                    t.span.to(rest[rest.len() - 1].span),
                    format!("`{keyword}` takes nothing"),
                )),
            }
        };
        let result = match keyword {
            "SET" => assignments(rest, span).map(StatementKind::Set),
            "FORCE" => assignments(rest, span).map(StatementKind::Force),
            "UNFORCE" => unforce(rest, span),
            "SCAN" => match rest {
                [] => Ok(StatementKind::Scan(1)),
                [Token {
                    tok: Tok::Atom(n),
                    span,
                }] => count(n).map(StatementKind::Scan).map_err(|e| (*span, e)),
                _ => Err((
                    span,
                    "SCAN takes a number of scans: `SCAN`, `SCAN 10`".into(),
                )),
            },
            "ADVANCE" => match rest {
                [Token {
                    tok: Tok::Atom(n),
                    span,
                }] => duration(n, None).map_err(|e| (*span, e)),
                [Token {
                    tok: Tok::Atom(n),
                    span: a,
                }, Token {
                    tok: Tok::Atom(u),
                    span: b,
                }] => duration(n, Some(u)).map_err(|e| (a.to(*b), e)),
                _ => Err((
                    span,
                    "ADVANCE takes a duration: `ADVANCE 2s`, `ADVANCE 500ms`".into(),
                )),
            }
            .and_then(|ms| {
                if ms == 0 {
                    Err((span, "ADVANCE needs a time above 0".into()))
                } else {
                    Ok(StatementKind::Advance(ms))
                }
            }),
            "EXPECT" => expect(rest, span),
            "UNTIL" => until(rest, span),
            "RESET" => only(StatementKind::Reset),
            "RUN" => only(StatementKind::Run),
            _ => only(StatementKind::Stop),
        };
        match result {
            Ok(kind) => Some(kind),
            Err((at, message)) => {
                self.error(Code::TestSyntax, at, message);
                None
            }
        }
    }
}

/// A test name: a letter or `_`, then letters, digits or `_` (JUnit and `--filter`
/// name tests by it).
fn is_test_name(name: &str) -> bool {
    let mut chars = name.chars();
    chars.next().is_some_and(|c| c.is_alphabetic() || c == '_')
        && chars.all(|c| c.is_alphanumeric() || c == '_')
}

type Parsed<T> = Result<T, (Span, String)>;

/// Split at commas into non-empty groups.
fn groups(rest: &[Token], span: Span, what: &str) -> Parsed<Vec<Vec<Token>>> {
    let mut groups = vec![Vec::new()];
    for t in rest {
        if t.tok == Tok::Comma {
            groups.push(Vec::new());
        } else if let Some(g) = groups.last_mut() {
            g.push(t.clone());
        }
    }
    if groups.iter().any(Vec::is_empty) {
        let at = rest
            .first()
            .map_or(span, |t| t.span.to(rest[rest.len() - 1].span));
        return Err((at, format!("expected {what}, separated by commas")));
    }
    Ok(groups)
}

fn var_ref(t: &Token) -> Parsed<VarRef> {
    match &t.tok {
        Tok::Atom(name)
            if !name.starts_with(|c: char| c.is_ascii_digit() || c == '-' || c == '+') =>
        {
            Ok(VarRef {
                name: name.clone(),
                span: t.span,
            })
        }
        _ => Err((
            t.span,
            "expected a variable (a symbol or an address such as MW20, Q0.0)".into(),
        )),
    }
}

fn value(t: &Token) -> Parsed<Literal> {
    let value =
        match &t.tok {
            Tok::Atom(a) => literal(a).map_err(|e| (t.span, e))?,
            Tok::Text(bytes) => LiteralValue::Text(bytes.clone()),
            Tok::BadText(_) => return Err((
                t.span,
                "a text is one or more printable ASCII characters in double quotes, on one line"
                    .into(),
            )),
            _ => return Err((t.span, "expected a value".into())),
        };
    Ok(Literal {
        value,
        span: t.span,
    })
}

/// `VAR OP VALUE` (`=` only for assignments).
fn comparison(group: &[Token], assignment: bool) -> Parsed<Comparison> {
    let span = group[0].span.to(group[group.len() - 1].span);
    let shape = if assignment {
        "VAR = VALUE"
    } else {
        "VAR OP VALUE (OP: = <> < <= > >=)"
    };
    match group {
        [var, Token {
            tok: Tok::Op(op),
            span: op_span,
        }, val] => {
            let var = var_ref(var)?;
            if assignment && *op != CompareOp::Eq {
                return Err((*op_span, format!("expected `=` in {shape}")));
            }
            Ok(Comparison {
                var,
                op: *op,
                value: value(val)?,
                span,
            })
        }
        _ => Err((span, format!("expected {shape}"))),
    }
}

fn assignments(rest: &[Token], span: Span) -> Parsed<Vec<Assignment>> {
    groups(rest, span, "VAR = VALUE")?
        .iter()
        .map(|g| {
            comparison(g, true).map(|c| Assignment {
                var: c.var,
                value: c.value,
            })
        })
        .collect()
}

fn comparisons(rest: &[Token], span: Span) -> Parsed<Vec<Comparison>> {
    groups(rest, span, "comparisons VAR OP VALUE")?
        .iter()
        .map(|g| comparison(g, false))
        .collect()
}

fn unforce(rest: &[Token], span: Span) -> Parsed<StatementKind> {
    if let [Token {
        tok: Tok::Atom(all),
        ..
    }] = rest
    {
        if all.eq_ignore_ascii_case("ALL") {
            return Ok(StatementKind::Unforce(Vec::new()));
        }
    }
    let vars = groups(rest, span, "variables")?
        .iter()
        .map(|g| match g.as_slice() {
            [t] => var_ref(t),
            _ => Err((
                g[0].span.to(g[g.len() - 1].span),
                "UNFORCE takes variables, or ALL".into(),
            )),
        })
        .collect::<Parsed<Vec<_>>>()?;
    Ok(StatementKind::Unforce(vars))
}

fn expect(rest: &[Token], span: Span) -> Parsed<StatementKind> {
    let word = |k: usize| match rest.get(k).map(|t| &t.tok) {
        Some(Tok::Atom(a)) => Some(a.to_ascii_uppercase()),
        _ => None,
    };
    match (rest.len(), word(0).as_deref()) {
        (1, Some("RUN")) => return Ok(StatementKind::ExpectMode(true)),
        (1, Some("STOP")) => return Ok(StatementKind::ExpectMode(false)),
        (2, Some("FAULT")) => {
            let code = word(1)
                .and_then(|c| c.parse::<u8>().ok())
                .ok_or((rest[1].span, "a fault code is a number 0..255".to_string()))?;
            return Ok(StatementKind::ExpectFault(code));
        }
        (_, Some("FAULT")) => {
            return Err((
                span,
                "EXPECT FAULT takes the fault code: `EXPECT FAULT 3`".into(),
            ))
        }
        _ => {}
    }
    comparisons(rest, span).map(StatementKind::Expect)
}

fn until(rest: &[Token], span: Span) -> Parsed<StatementKind> {
    let within = rest
        .iter()
        .rposition(|t| matches!(&t.tok, Tok::Atom(a) if a.eq_ignore_ascii_case("WITHIN")))
        .ok_or((
            span,
            "UNTIL needs its limit: `UNTIL Q0.1 = 1 WITHIN 100 SCANS`".to_string(),
        ))?;
    let tail = &rest[within + 1..];
    let limit = match tail {
        [Token {
            tok: Tok::Atom(n),
            span: n_span,
        }, Token {
            tok: Tok::Atom(unit),
            ..
        }] if unit.eq_ignore_ascii_case("SCANS") || unit.eq_ignore_ascii_case("SCAN") => {
            count(n).map_err(|e| (*n_span, e))?
        }
        _ => {
            let at = tail
                .first()
                .map_or(rest[within].span, |t| t.span.to(tail[tail.len() - 1].span));
            return Err((at, "expected `WITHIN n SCANS`".into()));
        }
    };
    if within == 0 {
        return Err((span, "UNTIL needs a condition before WITHIN".into()));
    }
    Ok(StatementKind::Until {
        conditions: comparisons(&rest[..within], span)?,
        within: limit,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn codes(text: &str) -> Vec<(&'static str, String)> {
        let (_, d) = parse(text);
        d.iter()
            .map(|d| (d.code.as_str(), text[d.primary.span.range()].to_string()))
            .collect()
    }

    #[test]
    fn the_example_of_the_issue_parses() {
        let text = "PROGRAM ../src/main.lad          // optional\nSCAN_TIME 10ms\n\n\
            TEST lamp_latches\n  SET    Start = 1\n  SCAN   1\n  EXPECT Lamp = 1\n  SET    Start = 0, Stop = 1\n  SCAN\n  EXPECT Lamp = 0, MW20 = -5\nEND_TEST\n\n\
            test timer_runs_out\n  SET    I0.0 = 1\n  ADVANCE 2s\n  EXPECT Q0.0 = 1\n  UNTIL  Q0.1 = 1 WITHIN 100 SCANS\n  FORCE  I0.2 = 1\n  unforce I0.2\nEND_TEST\n";
        let (file, diagnostics) = parse(text);
        assert!(diagnostics.is_empty(), "{diagnostics:?}");
        assert_eq!(
            file.header.program.as_ref().map(|p| p.0.as_str()),
            Some("../src/main.lad")
        );
        assert_eq!(file.header.scan_time_ms.map(|s| s.0), Some(10));
        assert_eq!(file.tests.len(), 2);
        assert_eq!(file.tests[0].statements.len(), 6);
        assert!(matches!(
            file.tests[1].statements[1].kind,
            StatementKind::Advance(2000)
        ));
        match &file.tests[1].statements[3].kind {
            StatementKind::Until { conditions, within } => {
                assert_eq!((conditions.len(), *within), (1, 100));
                assert_eq!(conditions[0].var.name, "Q0.1");
            }
            other => panic!("{other:?}"),
        }
        match &file.tests[0].statements[5].kind {
            StatementKind::Expect(c) => {
                assert_eq!(
                    c[1].value.value,
                    LiteralValue::Integer {
                        value: -5,
                        based: false
                    }
                );
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn values_are_as_in_the_language() {
        assert_eq!(
            literal("16#FF"),
            Ok(LiteralValue::Integer {
                value: 255,
                based: true
            })
        );
        assert_eq!(
            literal("-3"),
            Ok(LiteralValue::Integer {
                value: -3,
                based: false
            })
        );
        assert_eq!(literal("1.5"), Ok(LiteralValue::Real(1.5)));
        assert_eq!(literal("true"), Ok(LiteralValue::Bool(true)));
        assert!(literal("2#102").is_err());
        assert!(literal("Lamp").is_err());
        assert_eq!(duration("1.5s", None), Ok(1500));
        assert_eq!(duration("250", Some("MS")), Ok(250));
        assert!(duration("10", None).is_err());
        assert!(duration("1.5ms", None).is_err());
        assert!(duration("3min", None).is_err());
    }

    #[test]
    fn each_mistake_is_one_coded_diagnostic_at_its_place() {
        assert_eq!(
            codes("TEST a\n  SETT Q0.0 = 1\n  EXPECT Q0.0 = 1\nEND_TEST\n"),
            [("E0802", "SETT".to_string())]
        );
        assert_eq!(
            codes("TEST a\n  EXPECT Q0.0 == 1\nEND_TEST\n"),
            [("E0801", "Q0.0 == 1".to_string())]
        );
        assert_eq!(
            codes("SET Q0.0 = 1\nTEST a\nEXPECT Q0.0 = 1\nEND_TEST\n"),
            [("E0803", "SET".to_string())]
        );
        assert_eq!(
            codes("TEST a\nEXPECT Q0.0 = 1\nEND_TEST\nTEST A\nEXPECT Q0.0 = 1\nEND_TEST\n"),
            [("E0804", "A".to_string())]
        );
        assert_eq!(
            codes("TEST a\nEXPECT Q0.0 = 1\n"),
            [("E0803", "TEST a".to_string())]
        );
        assert_eq!(
            codes("TEST a\nSCAN_TIME 5ms\nEXPECT Q0.0 = 1\nEND_TEST\n"),
            [("E0803", "SCAN_TIME".to_string())]
        );
        assert_eq!(
            codes("SCAN_TIME 0ms\nTEST a\nEXPECT Q0.0 = 1\nEND_TEST\n"),
            [("E0809", "0ms".to_string())]
        );
        assert_eq!(
            codes("TEST a\nUNTIL Q0.0 = 1 WITHIN 0 SCANS\nEND_TEST\n"),
            [("E0801", "0".to_string())]
        );
        assert_eq!(
            codes("TEST a\nSCAN\nEND_TEST\n"),
            [("W0801", "a".to_string())]
        );
        assert_eq!(codes("// nothing\n"), [("W0802", String::new())]);
        assert_eq!(
            codes("TEST a\nSET MB40 = \"12\nEXPECT MB40 = \"12\"\nEND_TEST\n"),
            [("E0801", "\"12".to_string())]
        );
    }

    #[test]
    fn comments_texts_and_extensions_parse() {
        let text = "PLC_TYPE EC30-EK51\nOPTION scale-timer-presets\nWATCHDOG 1000\n\
            TEST t // a comment\nSET MB40 = \"1A//2f\" // text keeps its slashes\nSCAN 3\nEXPECT FAULT 3\nRESET\nRUN\nEXPECT RUN\nSTOP\nEXPECT STOP\nUNFORCE ALL\nEND_TEST\n";
        let (file, d) = parse(text);
        assert!(d.is_empty(), "{d:?}");
        assert_eq!(
            file.header.plc_type.as_ref().map(|p| p.0.as_str()),
            Some("EC30-EK51")
        );
        assert_eq!(file.header.watchdog.map(|w| w.0), Some(1000));
        let kinds = &file.tests[0].statements;
        match &kinds[0].kind {
            StatementKind::Set(a) => {
                assert_eq!(a[0].value.value, LiteralValue::Text(b"1A//2f".to_vec()))
            }
            other => panic!("{other:?}"),
        }
        assert!(matches!(kinds[2].kind, StatementKind::ExpectFault(3)));
        assert!(matches!(kinds[5].kind, StatementKind::ExpectMode(true)));
        assert!(matches!(kinds[7].kind, StatementKind::ExpectMode(false)));
        assert!(matches!(&kinds[8].kind, StatementKind::Unforce(v) if v.is_empty()));
    }
}
