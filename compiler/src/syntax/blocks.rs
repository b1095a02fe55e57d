//! The block parser: reads the file line by line, tracks which block and section it
//! is in, and hands each line's tokens to its grammar (lines.rs). Structure errors
//! (unterminated blocks, misplaced sections, text outside blocks) are reported here,
//! once each, and parsing always goes on: nothing the user wrote is dropped silently.

use chumsky::prelude::*;

use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;
use crate::syntax::ast::*;
use crate::syntax::lexer::{LineLexer, Spanned, Tok};
use crate::syntax::lines::{self, describe_error, span as sp, RawOperand, RawValue};

/// Run a line grammar over a token slice; owned result or (message, span) of the first error.
macro_rules! run_grammar {
    ($toks:expr, $eoi:expr, $parser:expr) => {{
        let eoi: SimpleSpan = $eoi;
        let input = $toks.map(eoi, |(t, s)| (t, s));
        let (out, errs) = $parser.parse(input).into_output_errors();
        match (out, errs.first()) {
            (Some(o), None) => Ok(o),
            (_, Some(e)) => Err((describe_error(e), sp(*e.span()))),
            (None, None) => Err(("syntax error".to_string(), sp(eoi))),
        }
    }};
}
use crate::syntax::numbers::{self, Number};

/// A tree and what went wrong on the way.
#[derive(Debug, Clone, Default)]
pub struct ParseOutput {
    pub program: Program,
    pub diagnostics: Vec<Diagnostic>,
}

/// Parse a whole file. Never fails.
pub fn parse(text: &str) -> ParseOutput {
    let mut parser = BlockParser::new(text);
    let mut lexer = LineLexer::new(text);
    let mut line = Vec::new();
    while lexer.next_line(&mut line) {
        parser.line(&line);
    }
    parser.finish()
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kw {
    PlcType,
    Symbols,
    EndSymbols,
    Organization,
    EndOrganization,
    Subroutine,
    EndSubroutine,
    Interrupt,
    EndInterrupt,
    Data,
    EndData,
    System,
    EndSystem,
    Begin,
    Network,
    Var(VarSection),
    EndVar,
}

const KEYWORDS: &[(&str, Kw)] = &[
    ("PLC_TYPE", Kw::PlcType),
    ("SYMBOLS", Kw::Symbols),
    ("END_SYMBOLS", Kw::EndSymbols),
    ("ORGANIZATION_BLOCK", Kw::Organization),
    ("END_ORGANIZATION_BLOCK", Kw::EndOrganization),
    ("SUBROUTINE_BLOCK", Kw::Subroutine),
    ("END_SUBROUTINE_BLOCK", Kw::EndSubroutine),
    ("INTERRUPT_BLOCK", Kw::Interrupt),
    ("END_INTERRUPT_BLOCK", Kw::EndInterrupt),
    ("DATA_BLOCK", Kw::Data),
    ("END_DATA_BLOCK", Kw::EndData),
    ("SYSTEM_BLOCK", Kw::System),
    ("END_SYSTEM_BLOCK", Kw::EndSystem),
    ("BEGIN", Kw::Begin),
    ("NETWORK", Kw::Network),
    ("VAR_INPUT", Kw::Var(VarSection::Input)),
    ("VAR_IN_OUT", Kw::Var(VarSection::InOut)),
    ("VAR_OUTPUT", Kw::Var(VarSection::Output)),
    ("VAR", Kw::Var(VarSection::Temp)),
    ("VAR_TEMP", Kw::Var(VarSection::Temp)),
    ("END_VAR", Kw::EndVar),
];

/// Whether a word is a reserved keyword of the block structure.
pub fn is_keyword(word: &str) -> bool {
    keyword(word).is_some()
}

fn keyword(word: &str) -> Option<Kw> {
    if word.len() < 3 || word.len() > 22 {
        return None;
    }
    KEYWORDS
        .iter()
        .find(|(k, _)| k.eq_ignore_ascii_case(word))
        .map(|(_, kw)| *kw)
}

/// What the parser is inside of.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum State {
    Top,
    Symbols {
        header: Span,
    },
    /// After a program block header, before BEGIN.
    UnitHead,
    Vars {
        section: VarSection,
        header: Span,
        in_body: bool,
    },
    Body,
    Data,
    System,
}

struct BlockParser<'t> {
    text: &'t str,
    program: Program,
    diags: Vec<Diagnostic>,
    state: State,
    /// The previous non-blank top-level line was already reported as stray text.
    junk_run: bool,
    /// Whether the current unit already got E0108 / missing-BEGIN reports.
    reported_no_network: bool,
    reported_no_begin: bool,
    /// Tokens of the current line in chumsky's span type.
    chum: Vec<(Tok, SimpleSpan)>,
    /// The current line already has a lexical error: do not report its grammar too.
    line_reported: bool,
    /// Tokens of the current line without error tokens (reused buffer).
    filtered: Vec<Spanned>,
}

fn is_op(t: Tok) -> bool {
    matches!(
        t,
        Tok::Plus
            | Tok::Minus
            | Tok::Star
            | Tok::Slash
            | Tok::Eq
            | Tok::Ne
            | Tok::Lt
            | Tok::Le
            | Tok::Gt
            | Tok::Ge
    )
}

fn is_compare(t: Tok) -> bool {
    matches!(t, Tok::Eq | Tok::Ne | Tok::Lt | Tok::Le | Tok::Gt | Tok::Ge)
}

impl<'t> BlockParser<'t> {
    fn new(text: &'t str) -> Self {
        BlockParser {
            text,
            program: Program::default(),
            diags: Vec::new(),
            state: State::Top,
            junk_run: false,
            reported_no_network: false,
            reported_no_begin: false,
            chum: Vec::new(),
            line_reported: false,
            filtered: Vec::new(),
        }
    }

    fn slice(&self, s: Span) -> &'t str {
        self.text.get(s.range()).unwrap_or("")
    }

    fn report(&mut self, d: Diagnostic) {
        self.diags.push(d);
    }

    fn line(&mut self, toks: &[Spanned]) {
        let (toks, comment) = match toks.split_last() {
            Some(((Tok::Comment, c), rest)) => (rest, Some(*c)),
            _ => (toks, None),
        };
        if toks.is_empty() {
            return;
        }
        self.line_reported = false;
        self.report_lexical_errors(toks);
        // Grammars see the line without error tokens; the line is reported already.
        self.chum.clear();
        self.chum.extend(
            toks.iter()
                .filter(|(t, _)| !matches!(t, Tok::Error | Tok::UnterminatedStr))
                .map(|(t, s)| (*t, SimpleSpan::from(s.range()))),
        );
        let mut filtered = std::mem::take(&mut self.filtered);
        filtered.clear();
        filtered.extend(
            toks.iter()
                .copied()
                .filter(|(t, _)| !matches!(t, Tok::Error | Tok::UnterminatedStr)),
        );
        self.line_filtered(&filtered, comment);
        self.filtered = filtered;
    }

    fn line_filtered(&mut self, toks: &[Spanned], comment: Option<Span>) {
        let Some(&(first, first_span)) = toks.first() else {
            return;
        };
        let line_span = first_span.to(toks[toks.len() - 1].1);

        if first == Tok::Title {
            self.title(first_span, toks);
            return;
        }
        if first == Tok::Word {
            if let Some(kw) = keyword(self.slice(first_span)) {
                self.junk_run = false;
                self.keyword_line(kw, first_span, line_span, toks, comment);
                return;
            }
        }
        self.content_line(toks, line_span, comment);
    }

    fn report_lexical_errors(&mut self, toks: &[Spanned]) {
        let mut i = 0;
        while i < toks.len() {
            match toks[i].0 {
                Tok::Error => {
                    let start = toks[i].1;
                    let mut end = start;
                    while i + 1 < toks.len()
                        && toks[i + 1].0 == Tok::Error
                        && toks[i + 1].1.start == end.end
                    {
                        i += 1;
                        end = toks[i].1;
                    }
                    let s = start.to(end);
                    let text = self.slice(s).to_string();
                    self.report(
                        Diagnostic::new(
                            Code::InvalidCharacter,
                            s,
                            format!("invalid character `{text}`"),
                        )
                        .label("not part of the language")
                        .help("comments start with `//`"),
                    );
                    self.line_reported = true;
                }
                Tok::UnterminatedStr => {
                    self.report(
                        Diagnostic::new(Code::UnterminatedString, toks[i].1, "unterminated string")
                            .label("no closing `\"` on this line"),
                    );
                    self.line_reported = true;
                }
                _ => {}
            }
            i += 1;
        }
    }

    fn finish(mut self) -> ParseOutput {
        let eof = Span::new(self.text.len(), self.text.len());
        self.close_open(eof, "the file ends here");
        ParseOutput {
            program: self.program,
            diagnostics: self.diags,
        }
    }

    fn eoi(&self, line_span: Span) -> SimpleSpan {
        SimpleSpan::from(line_span.end as usize..line_span.end as usize)
    }

    /// Report a grammar failure, unless the line already has a lexical error.
    fn syntax_error(&mut self, (message, at): (String, Span), context: &str) {
        if self.line_reported {
            return;
        }
        self.line_reported = true;
        self.report(Diagnostic::new(
            Code::Syntax,
            at,
            format!("{message} in {context}"),
        ));
    }

    fn convert_number(&mut self, raw: RawOperand) -> Operand {
        match raw {
            RawOperand::Name {
                prefix,
                local,
                name,
                span,
            } => Operand {
                span,
                kind: OperandKind::Name {
                    prefix,
                    local,
                    name,
                },
            },
            RawOperand::Number {
                negative,
                digits,
                span,
            } => match numbers::convert(self.slice(digits), negative) {
                Ok(Number::Integer(v)) => Operand {
                    span,
                    kind: OperandKind::Integer(v),
                },
                Ok(Number::Real(v)) => Operand {
                    span,
                    kind: OperandKind::Real(v),
                },
                Err(e) => {
                    self.report(Diagnostic::new(
                        Code::MalformedNumber,
                        digits,
                        format!("malformed number: {e}"),
                    ));
                    Operand {
                        span,
                        kind: OperandKind::Error,
                    }
                }
            },
        }
    }

    // ---- structure ---------------------------------------------------------------

    /// Close whatever block is open because `at` starts something else (or the file ends).
    fn close_open(&mut self, at: Span, why: &str) {
        let open = match self.state {
            State::Top => None,
            State::Symbols { header } => Some((header, "SYMBOLS", "END_SYMBOLS")),
            State::Vars { .. } => {
                self.close_vars(at, why);
                return self.close_open(at, why);
            }
            State::UnitHead | State::Body => self.program.units.last().map(|u| {
                let (kw, end) = match (u.kind, self.slice(u.header.span).split_whitespace().next())
                {
                    (BlockKind::Subroutine, _) => ("SUBROUTINE_BLOCK", "END_SUBROUTINE_BLOCK"),
                    (BlockKind::Interrupt, Some(k))
                        if k.eq_ignore_ascii_case("ORGANIZATION_BLOCK") =>
                    {
                        ("ORGANIZATION_BLOCK", "END_ORGANIZATION_BLOCK")
                    }
                    _ => ("INTERRUPT_BLOCK", "END_INTERRUPT_BLOCK"),
                };
                (u.header.span, kw, end)
            }),
            State::Data => self
                .program
                .data_blocks
                .last()
                .map(|d| (d.header.span, "DATA_BLOCK", "END_DATA_BLOCK")),
            State::System => self
                .program
                .system_blocks
                .last()
                .map(|d| (d.span, "SYSTEM_BLOCK", "END_SYSTEM_BLOCK")),
        };
        if let Some((header, kw, end)) = open {
            self.report(
                Diagnostic::new(
                    Code::UnterminatedBlock,
                    header,
                    format!("{kw} is not closed"),
                )
                .label("opened here")
                .with_secondary(at, why)
                .help(format!("add `{end}` at the end of the block")),
            );
        }
        self.state = State::Top;
    }

    fn open_block(&mut self, at: Span) {
        if self.state != State::Top {
            self.close_open(at, "a new block starts here");
        }
        self.reported_no_network = false;
        self.reported_no_begin = false;
    }

    fn keyword_line(
        &mut self,
        kw: Kw,
        kw_span: Span,
        line_span: Span,
        toks: &[Spanned],
        comment: Option<Span>,
    ) {
        if matches!(kw, Kw::Begin | Kw::Var(_) | Kw::EndVar) {
            let word = self.slice(kw_span).to_ascii_uppercase();
            self.expect_nothing_after(line_span, &word);
        }
        match kw {
            Kw::PlcType => self.plc_type_line(kw_span, line_span, toks),
            Kw::Symbols => {
                self.open_block(line_span);
                self.expect_nothing_after(line_span, "SYMBOLS");
                self.state = State::Symbols { header: line_span };
            }
            Kw::Organization | Kw::Interrupt | Kw::Subroutine => {
                self.open_block(line_span);
                let kind = if kw == Kw::Subroutine {
                    BlockKind::Subroutine
                } else {
                    BlockKind::Interrupt
                };
                let header = self.block_header(kw_span, line_span);
                self.program.units.push(Unit {
                    kind,
                    header,
                    title: None,
                    vars: Vec::new(),
                    networks: Vec::new(),
                    end: None,
                });
                self.state = State::UnitHead;
            }
            Kw::Data => {
                self.open_block(line_span);
                let header = self.block_header(kw_span, line_span);
                self.program.data_blocks.push(DataBlock {
                    header,
                    rows: Vec::new(),
                    end: None,
                });
                self.state = State::Data;
            }
            Kw::System => {
                self.open_block(line_span);
                self.expect_nothing_after(line_span, "SYSTEM_BLOCK");
                self.program.system_blocks.push(SystemBlock {
                    span: line_span,
                    entries: Vec::new(),
                    end: None,
                });
                self.state = State::System;
            }
            Kw::EndSymbols
            | Kw::EndOrganization
            | Kw::EndInterrupt
            | Kw::EndSubroutine
            | Kw::EndData
            | Kw::EndSystem => self.end_line(kw, line_span),
            Kw::Begin => match self.state {
                State::UnitHead => self.state = State::Body,
                State::Vars { in_body: false, .. } => {
                    self.close_vars(line_span, "the section ends here without END_VAR");
                    self.state = State::Body;
                }
                State::Body | State::Vars { in_body: true, .. } => self.report(
                    Diagnostic::new(
                        Code::MisplacedSection,
                        line_span,
                        "second BEGIN in this block",
                    )
                    .label("code has already begun"),
                ),
                _ => self.misplaced(
                    line_span,
                    "BEGIN belongs to a program block, after its VAR sections",
                ),
            },
            Kw::Network => {
                match self.state {
                    State::Body => {}
                    State::UnitHead | State::Vars { .. } => {
                        if let State::Vars { .. } = self.state {
                            self.close_vars(line_span, "the section ends here without END_VAR");
                        }
                        self.missing_begin(line_span);
                    }
                    _ => {
                        self.misplaced(
                            line_span,
                            "NETWORK belongs between BEGIN and the end of a program block",
                        );
                        return;
                    }
                }
                self.network_line(kw_span, line_span, comment);
            }
            Kw::Var(section) => match self.state {
                State::UnitHead => {
                    self.state = State::Vars {
                        section,
                        header: line_span,
                        in_body: false,
                    }
                }
                State::Vars { in_body, .. } => {
                    self.close_vars(line_span, "the section ends here without END_VAR");
                    self.state = State::Vars {
                        section,
                        header: line_span,
                        in_body,
                    };
                }
                State::Body => {
                    self.report(
                        Diagnostic::new(
                            Code::MisplacedSection,
                            line_span,
                            format!("{} section after BEGIN", section.keyword()),
                        )
                        .label("declarations must come before BEGIN")
                        .help("move this section above BEGIN"),
                    );
                    self.state = State::Vars {
                        section,
                        header: line_span,
                        in_body: true,
                    };
                }
                _ => self.misplaced(line_span, "VAR sections belong to program blocks"),
            },
            Kw::EndVar => match self.state {
                State::Vars { in_body, .. } => {
                    self.state = if in_body {
                        State::Body
                    } else {
                        State::UnitHead
                    }
                }
                _ => self.report(
                    Diagnostic::new(
                        Code::MismatchedEnd,
                        line_span,
                        "END_VAR without a VAR section",
                    )
                    .label("no VAR section is open"),
                ),
            },
        }
    }

    fn close_vars(&mut self, at: Span, why: &str) {
        if let State::Vars {
            section,
            header,
            in_body,
        } = self.state
        {
            self.report(
                Diagnostic::new(
                    Code::UnterminatedBlock,
                    header,
                    format!("{} section is not closed", section.keyword()),
                )
                .label("opened here")
                .with_secondary(at, why)
                .help("add `END_VAR` at the end of the section"),
            );
            self.state = if in_body {
                State::Body
            } else {
                State::UnitHead
            };
        }
    }

    fn missing_begin(&mut self, at: Span) {
        if !self.reported_no_begin {
            self.reported_no_begin = true;
            self.report(
                Diagnostic::new(
                    Code::MisplacedSection,
                    at,
                    "missing BEGIN before the code of this block",
                )
                .label("code starts here")
                .help("add a line `BEGIN` after the block's declarations"),
            );
        }
        self.state = State::Body;
    }

    fn misplaced(&mut self, at: Span, why: &str) {
        if self.state == State::Top {
            self.stray(at);
        } else {
            self.report(
                Diagnostic::new(Code::MisplacedSection, at, why.to_string())
                    .label("not allowed here"),
            );
        }
    }

    fn stray(&mut self, at: Span) {
        if !self.junk_run {
            self.report(
                Diagnostic::new(Code::OutsideBlock, at, "text outside any block")
                    .label("not inside a block")
                    .help("instructions belong inside `ORGANIZATION_BLOCK ... BEGIN ... END_ORGANIZATION_BLOCK`, after a `NETWORK` line"),
            );
        }
        self.junk_run = true;
    }

    fn expect_nothing_after(&mut self, line_span: Span, kw: &str) {
        if self.chum.len() > 1 {
            let at = Span {
                start: sp(self.chum[1].1).start,
                end: line_span.end,
            };
            self.report(
                Diagnostic::new(Code::Syntax, at, format!("unexpected text after {kw}"))
                    .label("remove this"),
            );
        }
    }

    fn end_line(&mut self, kw: Kw, line_span: Span) {
        if self.chum.len() > 1 {
            self.expect_nothing_after(
                line_span,
                self.slice(sp(self.chum[0].1)).to_ascii_uppercase().as_str(),
            );
        }
        if let State::Vars { .. } = self.state {
            if kw != Kw::EndSymbols {
                self.close_vars(line_span, "the section ends here without END_VAR");
            }
        }
        let matches = match (self.state, kw) {
            (State::Symbols { .. }, Kw::EndSymbols) => true,
            (State::Data, Kw::EndData) => true,
            (State::System, Kw::EndSystem) => true,
            (State::UnitHead | State::Body, Kw::EndSubroutine) => self
                .program
                .units
                .last()
                .is_some_and(|u| u.kind == BlockKind::Subroutine),
            (State::UnitHead | State::Body, Kw::EndOrganization | Kw::EndInterrupt) => self
                .program
                .units
                .last()
                .is_some_and(|u| u.kind == BlockKind::Interrupt),
            _ => false,
        };
        let word = self.slice(sp(self.chum[0].1)).to_ascii_uppercase();
        if self.state == State::Top {
            self.report(
                Diagnostic::new(
                    Code::MismatchedEnd,
                    line_span,
                    format!("{word} without an open block"),
                )
                .label("nothing to close"),
            );
            return;
        }
        if !matches {
            let open = match self.state {
                State::Symbols { .. } => "SYMBOLS",
                State::Data => "DATA_BLOCK",
                State::System => "SYSTEM_BLOCK",
                _ => match self.program.units.last().map(|u| u.kind) {
                    Some(BlockKind::Subroutine) => "SUBROUTINE_BLOCK",
                    _ => "an interrupt or organization block",
                },
            };
            self.report(
                Diagnostic::new(
                    Code::MismatchedEnd,
                    line_span,
                    format!("{word} does not close {open}"),
                )
                .label("mismatched END")
                .help("each block ends with the END_ keyword of its own kind"),
            );
        }
        match self.state {
            State::UnitHead | State::Body => {
                if let Some(u) = self.program.units.last_mut() {
                    u.end = Some(line_span);
                }
            }
            State::Data => {
                if let Some(d) = self.program.data_blocks.last_mut() {
                    d.end = Some(line_span);
                }
            }
            State::System => {
                if let Some(d) = self.program.system_blocks.last_mut() {
                    d.end = Some(line_span);
                }
            }
            _ => {}
        }
        self.state = State::Top;
    }

    fn plc_type_line(&mut self, kw_span: Span, line_span: Span, toks: &[Spanned]) {
        if self.state != State::Top {
            self.report(
                Diagnostic::new(Code::BadPlcType, line_span, "PLC_TYPE inside a block")
                    .label("must stand before all blocks"),
            );
            return;
        }
        let name_span = Span {
            start: toks.get(1).map(|t| t.1.start).unwrap_or(kw_span.end),
            end: line_span.end,
        };
        let name = self.slice(name_span).trim().to_string();
        if name.is_empty() || name.contains(char::is_whitespace) {
            self.report(
                Diagnostic::new(
                    Code::BadPlcType,
                    if name.is_empty() { kw_span } else { name_span },
                    "PLC_TYPE needs one PLC type name",
                )
                .help("for example `PLC_TYPE CPU-EC20`"),
            );
            return;
        }
        if let Some((_, first)) = &self.program.plc_type {
            let first = *first;
            self.report(
                Diagnostic::new(Code::BadPlcType, line_span, "PLC_TYPE given twice")
                    .with_secondary(first, "first given here"),
            );
            return;
        }
        let blocks = self.program.units.len()
            + self.program.data_blocks.len()
            + self.program.system_blocks.len()
            + self.program.symbols.len();
        if blocks > 0 {
            self.report(
                Diagnostic::new(
                    Code::BadPlcType,
                    line_span,
                    "PLC_TYPE after the first block",
                )
                .label("move it to the top of the file"),
            );
        }
        self.program.plc_type = Some((name, name_span));
    }

    fn block_header(&mut self, kw_span: Span, line_span: Span) -> BlockHeader {
        let eoi = self.eoi(line_span);
        let result = run_grammar!(self.chum[1..], eoi, lines::block_header());
        let (name, numbered) = match result {
            Ok(Some((name, numbered))) => (Some(name), numbered),
            Ok(None) => (None, None),
            Err(e) => {
                self.syntax_error(e, "block header");
                (None, None)
            }
        };
        let parse_numbered = |text: &str| -> Option<BlockNumber> {
            let split = text.find(|c: char| c.is_ascii_digit())?;
            let (prefix, digits) = text.split_at(split);
            let prefix = match prefix.to_ascii_uppercase().as_str() {
                "OB" => BlockPrefix::Ob,
                "INT" => BlockPrefix::Int,
                "SBR" => BlockPrefix::Sbr,
                "DAT" => BlockPrefix::Dat,
                _ => return None,
            };
            Some(BlockNumber {
                prefix,
                number: digits.parse().ok()?,
            })
        };
        let number = match (name, numbered) {
            (_, Some(n)) => match parse_numbered(self.slice(n)) {
                Some(b) => Some((b, n)),
                None => {
                    let text = self.slice(n).to_string();
                    self.report(
                        Diagnostic::new(
                            Code::BadBlockHeader,
                            n,
                            format!("`{text}` is not a numbered block name"),
                        )
                        .help("numbered names are OB1, INTn, SBRn or DATn"),
                    );
                    None
                }
            },
            (Some(n), None) => parse_numbered(self.slice(n)).map(|b| (b, n)),
            (None, None) => None,
        };
        BlockHeader {
            span: line_span,
            name: name.unwrap_or(Span {
                start: kw_span.end,
                end: kw_span.end,
            }),
            number,
        }
    }

    fn network_line(&mut self, kw_span: Span, line_span: Span, comment: Option<Span>) {
        let eoi = self.eoi(line_span);
        let number = match run_grammar!(self.chum[1..], eoi, lines::network_header()) {
            Ok(Some(n)) => match self.slice(n).replace('_', "").parse::<u32>() {
                Ok(v) if v <= u16::MAX as u32 => Some(v),
                _ => {
                    self.report(Diagnostic::new(
                        Code::MalformedNumber,
                        n,
                        "network number must be 0..65535",
                    ));
                    None
                }
            },
            Ok(None) => None,
            Err(e) => {
                self.syntax_error(e, "NETWORK line");
                None
            }
        };
        let title = comment
            .map(|c| self.comment_text(c))
            .filter(|s| !s.is_empty());
        let _ = kw_span;
        if let Some(u) = self.program.units.last_mut() {
            u.networks.push(Network {
                number,
                header: Some(line_span),
                span: line_span,
                title,
                instructions: Vec::new(),
                operands: Vec::new(),
            });
        }
    }

    /// Span of a comment's text without `//` and surrounding blanks.
    fn comment_text(&self, c: Span) -> Span {
        let text = self.slice(c);
        let body = text.trim_start_matches('/');
        let lead = text.len() - body.len() + (body.len() - body.trim_start().len());
        let trimmed = body.trim();
        Span::new(
            c.start as usize + lead,
            c.start as usize + lead + trimmed.len(),
        )
    }

    fn title(&mut self, tok: Span, toks: &[Spanned]) {
        let text = self.slice(tok);
        let eq = text.find('=').unwrap_or(0) + 1;
        let rest = &text[eq..];
        let lead = rest.len() - rest.trim_start().len();
        let value = Span::new(
            tok.start as usize + eq + lead,
            tok.start as usize + eq + lead + rest.trim().len(),
        );
        let _ = toks;
        match self.state {
            State::UnitHead => {
                if let Some(u) = self.program.units.last_mut() {
                    u.title = Some(value);
                }
            }
            State::Top => self.stray(tok),
            _ => self.report(
                Diagnostic::new(
                    Code::MisplacedSection,
                    tok,
                    "TITLE= belongs right after the block header",
                )
                .label("not allowed here")
                .help("network titles are written as a comment: `NETWORK 2 // title`"),
            ),
        }
    }

    // ---- content lines -----------------------------------------------------------

    fn content_line(&mut self, toks: &[Spanned], line_span: Span, comment: Option<Span>) {
        match self.state {
            State::Top => self.stray(line_span),
            State::Symbols { .. } => self.symbol_line(line_span, comment),
            State::Vars { section, .. } => self.var_line(section, line_span, comment),
            State::UnitHead => {
                self.missing_begin(line_span);
                self.instruction_line(toks, line_span);
            }
            State::Body => self.instruction_line(toks, line_span),
            State::Data => self.data_line(line_span),
            State::System => self.system_line(line_span),
        }
    }

    fn symbol_line(&mut self, line_span: Span, comment: Option<Span>) {
        let eoi = self.eoi(line_span);
        match run_grammar!(self.chum[..], eoi, lines::symbol_decl()) {
            Ok((name, address)) => {
                let comment = comment.map(|c| self.comment_text(c));
                self.program.symbols.push(SymbolDecl {
                    name,
                    address,
                    comment,
                });
            }
            Err(e) => self.syntax_error(e, "symbol declaration (`Name : ADDRESS`)"),
        }
    }

    fn var_line(&mut self, section: VarSection, line_span: Span, comment: Option<Span>) {
        let eoi = self.eoi(line_span);
        match run_grammar!(self.chum[..], eoi, lines::var_decl()) {
            Ok((names, ty)) => {
                let comment = comment.map(|c| self.comment_text(c));
                if let Some(u) = self.program.units.last_mut() {
                    for name in names {
                        u.vars.push(VarDecl {
                            section,
                            name,
                            ty,
                            comment,
                        });
                    }
                }
            }
            Err(e) => self.syntax_error(e, "local declaration (`name : TYPE;`)"),
        }
    }

    fn data_line(&mut self, line_span: Span) {
        let eoi = self.eoi(line_span);
        match run_grammar!(self.chum[..], eoi, lines::data_row()) {
            Ok((address, ty, value)) => {
                let value = self.convert_number(value);
                if let Some(d) = self.program.data_blocks.last_mut() {
                    d.rows.push(DataRow {
                        span: line_span,
                        address,
                        ty,
                        value,
                    });
                }
            }
            Err(e) => self.syntax_error(e, "data row (`ADDRESS TYPE VALUE`)"),
        }
    }

    fn system_line(&mut self, line_span: Span) {
        let eoi = self.eoi(line_span);
        match run_grammar!(self.chum[..], eoi, lines::system_entry()) {
            Ok((key, value)) => {
                let value = match value {
                    RawValue::Word(w) => SystemValue::Word(w),
                    RawValue::Str(s) => {
                        let inner = self.slice(s);
                        let inner = &inner[1..inner.len().saturating_sub(1).max(1)];
                        SystemValue::Str(unescape(inner), s)
                    }
                    RawValue::Number(n) => match self.convert_number(n) {
                        Operand {
                            kind: OperandKind::Integer(v),
                            span,
                        } => SystemValue::Integer(v, span),
                        Operand {
                            kind: OperandKind::Real(_),
                            span,
                        } => {
                            self.report(Diagnostic::new(
                                Code::SystemValue,
                                span,
                                "system block values are whole numbers",
                            ));
                            SystemValue::Error
                        }
                        _ => SystemValue::Error,
                    },
                };
                if let Some(b) = self.program.system_blocks.last_mut() {
                    b.entries.push(SystemEntry {
                        span: line_span,
                        key,
                        value,
                    });
                }
            }
            Err(e) => self.syntax_error(e, "system block entry (`KEY = VALUE`)"),
        }
    }

    fn instruction_line(&mut self, toks: &[Spanned], line_span: Span) {
        // The mnemonic: adjacent tokens `[op] [word] [compare]`, e.g. `=`, `+I`, `LDW>=`, `=I`.
        let mut i = 0;
        if is_op(toks[0].0) {
            i = 1;
        }
        if i < toks.len()
            && toks[i].0 == Tok::Word
            && (i == 0 || toks[i].1.start == toks[i - 1].1.end)
        {
            i += 1;
            if i < toks.len() && is_compare(toks[i].0) && toks[i].1.start == toks[i - 1].1.end {
                i += 1;
            }
        }
        if i == 0 {
            let found = toks[0].0.describe();
            self.syntax_error(
                (format!("expected an instruction, found {found}"), toks[0].1),
                "program code",
            );
            return;
        }
        let mnemonic = toks[0].1.to(toks[i - 1].1);
        let eoi = self.eoi(line_span);
        // Token index in the filtered chumsky buffer equals i (same filtering).
        let raw = match lines::simple_operand_list(&self.chum[i..]) {
            Some(ops) => Some(ops),
            None => match run_grammar!(self.chum[i..], eoi, lines::operand_list()) {
                Ok(ops) => Some(ops),
                Err(e) => {
                    // `LDW >= T4, 2`: a compare mnemonic written with a space.
                    let spaced_compare = i == 1
                        && toks[0].0 == Tok::Word
                        && toks
                            .get(1)
                            .is_some_and(|t| is_compare(t.0) && t.1.start > toks[0].1.end);
                    if spaced_compare {
                        let word = self.slice(toks[0].1).to_ascii_uppercase();
                        let op = self.slice(toks[1].1);
                        let at = toks[0].1.to(toks[1].1);
                        if !self.line_reported {
                            self.line_reported = true;
                            self.report(
                                Diagnostic::new(
                                    Code::Syntax,
                                    at,
                                    format!("compare instructions are one word: `{word}{op}`"),
                                )
                                .label("space inside the mnemonic")
                                .help(format!("write `{word}{op}` without the space")),
                            );
                        }
                    } else {
                        self.syntax_error(e, "operands");
                    }
                    None
                }
            },
        };
        let raw_failed = raw.is_none();
        let operands: Vec<Operand> = match raw {
            Some(ops) => ops.into_iter().map(|o| self.convert_number(o)).collect(),
            None => vec![Operand {
                span: Span {
                    start: mnemonic.end,
                    end: line_span.end,
                },
                kind: OperandKind::Error,
            }],
        };
        let Some(unit) = self.program.units.last_mut() else {
            return;
        };
        if unit.networks.is_empty() {
            unit.networks.push(Network {
                number: None,
                header: None,
                span: line_span,
                title: None,
                instructions: Vec::new(),
                operands: Vec::new(),
            });
            if !self.reported_no_network {
                self.reported_no_network = true;
                self.diags.push(
                    Diagnostic::new(
                        Code::NoNetwork,
                        line_span,
                        "instruction before the first NETWORK",
                    )
                    .label("not inside a network")
                    .help("add a line `NETWORK 1` before the code"),
                );
            }
        }
        let Some(net) = self
            .program
            .units
            .last_mut()
            .and_then(|u| u.networks.last_mut())
        else {
            return;
        };
        let start = net.operands.len() as u32;
        net.operands.extend(operands);
        let end = net.operands.len() as u32;
        net.instructions.push(Instruction {
            mnemonic,
            operands: (start, end),
            span: line_span,
            syntax_error: raw_failed,
        });
    }
}

/// Unescape `\"` and `\\` in a string literal's contents.
fn unescape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut chars = s.chars();
    while let Some(c) = chars.next() {
        if c == '\\' {
            if let Some(n) = chars.next() {
                out.push(n);
            }
        } else {
            out.push(c);
        }
    }
    out
}
