//! The block parser: reads the file line by line, tracks which block and section it
//! is in (the state machine here), and hands each line to its block kind's module,
//! which runs the line's grammar (lines.rs). Structure errors (unterminated blocks,
//! misplaced sections, text outside blocks) and their recovery live here, reported once
//! each, and parsing always goes on: nothing the user wrote is dropped silently. No line
//! grammar and no block kind's content is parsed in this file.

use chumsky::prelude::*;

use crate::diagnostics::{Code, Diagnostic, Fix, Suggestion};
use crate::source::Span;
use crate::suggest::closest;
use crate::syntax::ast::{BlockKind, Program, VarSection};
use crate::syntax::lexer::{LineLexer, Spanned, Tok};
use crate::syntax::lines::span as sp;

/// Run a line grammar over a token slice; owned result or (message, span) of the first error.
macro_rules! run_grammar {
    ($toks:expr, $eoi:expr, $parser:expr) => {{
        let eoi: SimpleSpan = $eoi;
        let input = $toks.map(eoi, |(t, s)| (t, s));
        let (out, errs) = $parser.parse(input).into_output_errors();
        match (out, errs.first()) {
            (Some(o), None) => Ok(o),
            (_, Some(e)) => Err((
                $crate::syntax::lines::describe_error(e),
                $crate::syntax::lines::span(*e.span()),
            )),
            (None, None) => Err(("syntax error".to_string(), $crate::syntax::lines::span(eoi))),
        }
    }};
}

mod code;
mod data;
mod header;
mod keywords;
mod line;
mod plc_type;
mod symbols;
mod system;
mod units;

use keywords::{keyword, Kw};

pub use keywords::is_keyword;

/// A tree and what went wrong on the way.
#[derive(Debug, Clone, Default)]
pub struct ParseOutput {
    pub program: Program,
    pub diagnostics: Vec<Diagnostic>,
}

/// Parse a whole file. Never fails.
pub fn parse(text: &str) -> ParseOutput {
    parse_files(text, &[text.len()])
}

/// Parse the sources of a program joined into one text (`SourceFile::join`): `ends`
/// holds the offset where each file ends, in order (the last is where parsing stops).
/// A block open at a file's end is reported there, and `PLC_TYPE` may start each file.
pub fn parse_files(text: &str, ends: &[usize]) -> ParseOutput {
    parse_files_in(text, ends, false)
}

/// [`parse_files`] for a program in the Micro/WIN dialect with its line rules (`NOP 0`,
/// `MEND`, `NAME:SBRn` operands, `code.rs`). The tree it gives is the parser's; the
/// dialect's own stage (`crate::microwin::desugar`) runs on it before the checker.
pub fn parse_microwin_files(text: &str, ends: &[usize]) -> ParseOutput {
    parse_files_in(text, ends, true)
}

fn parse_files_in(text: &str, ends: &[usize], microwin: bool) -> ParseOutput {
    let stop = ends.last().copied().unwrap_or(0).min(text.len());
    let text = text.get(..stop).unwrap_or(text);
    let mut parser = BlockParser::new(text);
    parser.microwin = microwin;
    let mut lexer = LineLexer::new(text);
    let mut line = Vec::new();
    let mut file = 0;
    while lexer.next_line(&mut line) {
        if let Some(&(_, first)) = line.first() {
            while file + 1 < ends.len() && first.start as usize >= ends[file] {
                parser.end_file(ends[file]);
                file += 1;
            }
        }
        parser.line(&line);
    }
    parser.finish()
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
    /// Blocks and symbols parsed before the current file (PLC_TYPE must precede the
    /// file's own).
    blocks_before_file: usize,
    /// The current file's PLC_TYPE line, once seen.
    file_plc_type: Option<Span>,
    /// The program is in the Micro/WIN dialect: apply its line rules (`code.rs`).
    microwin: bool,
    /// In that dialect, the current unit's `MEND`, and whether E0115 was reported.
    mend: Option<(Span, bool)>,
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
            blocks_before_file: 0,
            file_plc_type: None,
            microwin: false,
            mend: None,
        }
    }

    /// How many blocks and symbols are parsed so far.
    fn blocks_so_far(&self) -> usize {
        self.program.units.len()
            + self.program.data_blocks.len()
            + self.program.system_blocks.len()
            + self.program.symbols.len()
    }

    /// A file of a joined program ends at `at`: what is open there is reported there;
    /// the next file starts at the top level.
    fn end_file(&mut self, at: usize) {
        self.close_open(Span::new(at, at), "the file ends here");
        self.junk_run = false;
        self.blocks_before_file = self.blocks_so_far();
        self.file_plc_type = None;
    }

    fn slice(&self, s: Span) -> &'t str {
        self.text.get(s.range()).unwrap_or("")
    }

    fn report(&mut self, d: Diagnostic) {
        self.diags.push(d);
    }

    fn finish(mut self) -> ParseOutput {
        let eof = Span::new(self.text.len(), self.text.len());
        self.close_open(eof, "the file ends here");
        ParseOutput {
            program: self.program,
            diagnostics: self.diags,
        }
    }

    /// One line's tokens: its lexical errors reported, then the line without error tokens
    /// to its handler.
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
            self.title(first_span);
            return;
        }
        if first == Tok::Word {
            if let Some(kw) = keyword(self.slice(first_span)) {
                self.junk_run = false;
                self.keyword_line(kw, first_span, line_span, toks, comment);
                return;
            }
            if let Some(kw) = self.misspelt_end(first_span) {
                self.junk_run = false;
                self.keyword_line(kw, first_span, line_span, toks, comment);
                return;
            }
        }
        self.content_line(toks, line_span, comment);
    }

    /// A line starting with a block keyword, to the block kind it belongs to.
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
            Kw::Symbols => self.symbols_header(line_span),
            Kw::Organization | Kw::Interrupt | Kw::Subroutine => {
                self.unit_header(kw, kw_span, line_span)
            }
            Kw::Data => self.data_header(kw_span, line_span),
            Kw::System => self.system_header(line_span),
            Kw::EndSymbols
            | Kw::EndOrganization
            | Kw::EndInterrupt
            | Kw::EndSubroutine
            | Kw::EndData
            | Kw::EndSystem => self.end_line(kw, line_span),
            Kw::Begin => self.begin_line(line_span),
            Kw::Network => self.network_keyword(line_span, comment),
            Kw::Var(section) => self.var_header(section, line_span),
            Kw::EndVar => self.end_var_line(line_span),
        }
    }

    /// A line that is no keyword: the content of the block it stands in.
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

    // ---- structure and recovery ----------------------------------------------------

    /// Close whatever block is open because `at` starts something else (or the file ends).
    fn close_open(&mut self, at: Span, why: &str) {
        if let State::Vars { .. } = self.state {
            self.close_vars(at, why);
            return self.close_open(at, why);
        }
        if let Some((header, kw, end)) = self.open_block_keywords() {
            self.report(
                Diagnostic::new(
                    Code::UnterminatedBlock,
                    header,
                    format!("{kw} is not closed"),
                )
                .label("opened here")
                .with_secondary(at, why)
                .help(format!("add `{end}` at the end of the block"))
                .fix(self.insert_end_line(at, end)),
            );
        }
        self.state = State::Top;
    }

    /// The fix of an unclosed block: `end` on its own line where the next thing starts
    /// (or the file ends).
    pub(super) fn insert_end_line(&self, at: Span, end: &str) -> Fix {
        let at_line_start = at.start == 0 || self.text[..at.start as usize].ends_with('\n');
        let text = if at_line_start {
            format!("{end}\n")
        } else {
            format!("\n{end}\n")
        };
        Fix {
            title: format!("Add `{end}`"),
            edits: vec![(Span::new(at.start as usize, at.start as usize), text)],
        }
    }

    /// The open block's header span, its opening keyword and its END_ keyword.
    fn open_block_keywords(&self) -> Option<(Span, &'static str, &'static str)> {
        match self.state {
            State::Top | State::Vars { .. } => None,
            State::Symbols { header } => Some((header, "SYMBOLS", "END_SYMBOLS")),
            State::UnitHead | State::Body => self.program.units.last().map(|u| {
                let (kw, end) = self.unit_keywords(u);
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
        }
    }

    /// A first word that is a misspelt `END_...` keyword (`END_ORGANISATION_BLOCK`):
    /// one E0116 with the keyword meant and the fix that writes it over the word, and
    /// the keyword, for the line to close what it would close. The keyword meant is the
    /// one the open section or block ends with when it is close enough, else the
    /// closest END_ keyword, else (a word starting `END_` in an open block) the open
    /// block's own. None outside blocks (the line is stray text there) and for other
    /// words (no mnemonic starts with `END_`; `END` is one).
    fn misspelt_end(&mut self, word_span: Span) -> Option<Kw> {
        let word = self.slice(word_span);
        let upper = word.to_ascii_uppercase();
        if self.state == State::Top || !upper.starts_with("END") || upper == "END" {
            return None;
        }
        let block_end = self.open_block_keywords().map(|(_, _, end)| end);
        let section_end = matches!(self.state, State::Vars { .. }).then_some("END_VAR");
        let expected = section_end.into_iter().chain(block_end);
        let meant = closest(word, expected)
            .or_else(|| closest(word, keywords::end_keywords()))
            .or_else(|| block_end.filter(|_| upper.starts_with("END_")))?;
        let kw = keyword(meant)?;
        self.report(
            Diagnostic::new(
                Code::MisspeltEnd,
                word_span,
                format!("`{word}` is not a keyword"),
            )
            .label("misspelt END_ keyword")
            .suggest(Suggestion::new(word_span, meant)),
        );
        Some(kw)
    }

    /// A block keyword opens a block: whatever is open is closed first (reported).
    fn open_block(&mut self, at: Span) {
        if self.state != State::Top {
            self.close_open(at, "a new block starts here");
        }
        self.reported_no_network = false;
        self.reported_no_begin = false;
    }

    /// An END_ keyword: closes the open block, reporting one that is not its kind
    /// (closed all the same) or no open block.
    fn end_line(&mut self, kw: Kw, line_span: Span) {
        let word = self.slice(sp(self.chum[0].1)).to_ascii_uppercase();
        if self.chum.len() > 1 {
            self.expect_nothing_after(line_span, &word);
        }
        if let State::Vars { .. } = self.state {
            if kw != Kw::EndSymbols {
                self.close_vars(line_span, "the section ends here without END_VAR");
            }
        }
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
        if !self.end_closes_open_block(kw) {
            self.report_mismatched_end(&word, line_span);
        }
        self.record_end(line_span);
        self.state = State::Top;
    }

    /// Whether `kw` is the END_ keyword of the open block.
    fn end_closes_open_block(&self, kw: Kw) -> bool {
        let open_unit = self.program.units.last().map(|u| u.kind);
        match (self.state, kw) {
            (State::Symbols { .. }, Kw::EndSymbols) => true,
            (State::Data, Kw::EndData) => true,
            (State::System, Kw::EndSystem) => true,
            (State::UnitHead | State::Body, Kw::EndSubroutine) => {
                open_unit == Some(BlockKind::Subroutine)
            }
            (State::UnitHead | State::Body, Kw::EndOrganization | Kw::EndInterrupt) => {
                open_unit == Some(BlockKind::Interrupt)
            }
            _ => false,
        }
    }

    fn report_mismatched_end(&mut self, word: &str, line_span: Span) {
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

    /// The open block's END_ line.
    fn record_end(&mut self, line_span: Span) {
        let end = match self.state {
            State::UnitHead | State::Body => self.program.units.last_mut().map(|u| &mut u.end),
            State::Data => self.program.data_blocks.last_mut().map(|d| &mut d.end),
            State::System => self.program.system_blocks.last_mut().map(|d| &mut d.end),
            _ => None,
        };
        if let Some(end) = end {
            *end = Some(line_span);
        }
    }

    /// A keyword where it does not belong: E0109 inside a block, stray text outside.
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

    /// Text outside any block: one E0107 per run of such lines.
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

    /// A keyword that stands alone on its line: anything after it is E0102.
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
}
