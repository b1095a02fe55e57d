//! Program blocks (`ORGANIZATION_BLOCK`, `INTERRUPT_BLOCK`, `SUBROUTINE_BLOCK`): the
//! header and `TITLE=`, the VAR sections before `BEGIN`, `BEGIN`, and `NETWORK` lines.
//! The instructions inside a network are code.rs's; the end of a block is mod.rs's.

use chumsky::prelude::*;

use super::keywords::Kw;
use super::{BlockParser, State};
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;
use crate::syntax::ast::{BlockKind, Network, Unit, VarDecl, VarSection};
use crate::syntax::lines;

/// Why a VAR section closes when another line comes before its END_VAR.
const NO_END_VAR: &str = "the section ends here without END_VAR";

impl BlockParser<'_> {
    /// `ORGANIZATION_BLOCK`, `INTERRUPT_BLOCK` or `SUBROUTINE_BLOCK` with its header.
    pub(super) fn unit_header(&mut self, kw: Kw, kw_span: Span, line_span: Span) {
        self.open_block(line_span);
        self.mend = None;
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

    /// The keyword that opened the current program block and the one that closes it.
    pub(super) fn unit_keywords(&self, unit: &Unit) -> (&'static str, &'static str) {
        match (
            unit.kind,
            self.slice(unit.header.span).split_whitespace().next(),
        ) {
            (BlockKind::Subroutine, _) => ("SUBROUTINE_BLOCK", "END_SUBROUTINE_BLOCK"),
            (BlockKind::Interrupt, Some(k)) if k.eq_ignore_ascii_case("ORGANIZATION_BLOCK") => {
                ("ORGANIZATION_BLOCK", "END_ORGANIZATION_BLOCK")
            }
            _ => ("INTERRUPT_BLOCK", "END_INTERRUPT_BLOCK"),
        }
    }

    /// `TITLE=`: the unit's title right after its header; anywhere else E0109.
    pub(super) fn title(&mut self, tok: Span) {
        let text = self.slice(tok);
        let eq = text.find('=').unwrap_or(0) + 1;
        let rest = &text[eq..];
        let lead = rest.len() - rest.trim_start().len();
        let value = Span::new(
            tok.start as usize + eq + lead,
            tok.start as usize + eq + lead + rest.trim().len(),
        );
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

    /// `VAR_INPUT`, `VAR_IN_OUT`, `VAR_OUTPUT`, `VAR`/`VAR_TEMP`: a section opens (after
    /// BEGIN too, reported, so its declarations are still read).
    pub(super) fn var_header(&mut self, section: VarSection, line_span: Span) {
        match self.state {
            State::UnitHead => {
                self.state = State::Vars {
                    section,
                    header: line_span,
                    in_body: false,
                }
            }
            State::Vars { in_body, .. } => {
                self.close_vars(line_span, NO_END_VAR);
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
        }
    }

    /// `name, name : TYPE;` inside a VAR section.
    pub(super) fn var_line(&mut self, section: VarSection, line_span: Span, comment: Option<Span>) {
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

    /// `END_VAR`: back to where the section was opened.
    pub(super) fn end_var_line(&mut self, line_span: Span) {
        match self.state {
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
        }
    }

    /// An open VAR section is not closed (E0105) because `at` comes first.
    pub(super) fn close_vars(&mut self, at: Span, why: &str) {
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
                .help("add `END_VAR` at the end of the section")
                .fix(self.insert_end_line(at, "END_VAR")),
            );
            self.state = if in_body {
                State::Body
            } else {
                State::UnitHead
            };
        }
    }

    /// `BEGIN`: the code starts.
    pub(super) fn begin_line(&mut self, line_span: Span) {
        match self.state {
            State::UnitHead => self.state = State::Body,
            State::Vars { in_body: false, .. } => {
                self.close_vars(line_span, NO_END_VAR);
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
        }
    }

    /// Code without a BEGIN before it: reported once per block, then the code is read.
    pub(super) fn missing_begin(&mut self, at: Span) {
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

    /// `NETWORK [n] [// title]`: a new network of the current unit (a missing BEGIN is
    /// reported and assumed).
    pub(super) fn network_keyword(&mut self, line_span: Span, comment: Option<Span>) {
        match self.state {
            State::Body => {}
            State::UnitHead | State::Vars { .. } => {
                if let State::Vars { .. } = self.state {
                    self.close_vars(line_span, NO_END_VAR);
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
        self.network_line(line_span, comment);
    }

    fn network_line(&mut self, line_span: Span, comment: Option<Span>) {
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
}
