//! The STEP 7-Micro/WIN dialect as a stage of its own (docs/microwin.md): parse ->
//! [`desugar`] -> check. A program is in the dialect when one of its sources is an
//! export ([`is_export`]: a `.awl` name or the marker line, read by `source.rs`); the
//! parser applies the dialect's line rules (`NOP 0`, `MEND`, `NAME:SBRn` operands) and
//! this stage does the rest before the checker runs: it places S7-200 interrupt blocks
//! on GUTTA's numbers and drops template blocks (`interrupts.rs`), translates S7-200
//! event numbers (`events.rs`), hands Micro/WIN's system symbols and SMART's I/O names
//! over as predefined names (`names.rs`) and the advice for an export split one block
//! per file (`split.rs`); after the checker, its pass over the checked code gives the
//! timer and counter bit lines the checker left as placeholders their instructions
//! (`timer_bits/`). What the checker must apply it gets as plain data
//! ([`check::Conventions`](crate::check::Conventions)); it never asks whether a program
//! is an export. This module imports the syntax tree, diagnostics and the checker's
//! plain-data types; nothing but `lib.rs` imports it.

mod aeno;
mod events;
mod interrupts;
mod names;
mod scr;
mod split;
mod timer_bits;

use gutta_catalog::Target;

use crate::check::{CheckOutput, Conventions, LTemporaries, LTemporaryPlacement};
use crate::diagnostics::Diagnostic;
use crate::source::{PartKind, SourceFile, Span};
use crate::syntax::ast::Program;
use crate::CompileOptions;

pub use crate::source::{has_gutta_boxes, has_marker, is_microwin, GUTTA_BOXES, MARKER};
pub use aeno::l_temporaries_summary;
pub use events::{event_summary, EventTranslation};
pub use interrupts::{interrupt_summary, InterruptPlacement};
pub use scr::{s_area_summary, SAreaBase, SAreaPlacement};

/// What the stage found that later stages and tools need to know: its diagnostics,
/// what the checker applies, and what it did to the export.
#[derive(Debug, Clone, Default)]
pub struct Desugared {
    pub diagnostics: Vec<Diagnostic>,
    pub conventions: Conventions,
    /// Set by [`desugar`]: None for a program in GUTTA's own language.
    pub export: Option<Export>,
}

/// What the dialect's stage did to a Micro/WIN export, for the compile summary, hover and
/// the tools (`CheckedFile::microwin`): the program itself is an ordinary one.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Export {
    /// Where each S7-200 interrupt block went, in file order.
    pub interrupt_placements: Vec<InterruptPlacement>,
    /// Timer boxes keep GUTTA's stack meaning (a [`GUTTA_BOXES`] line): no `LPS`/`LPP`
    /// around them.
    pub gutta_boxes: bool,
    /// Every event operand that translated (`10` of `ATCH INT_0, 10`), in program order.
    pub events: Vec<EventTranslation>,
    /// S7-200 timer and counter bit operands (`T37` of `LD T37`) and what they compile
    /// to, one Markdown line each (for hover); set by [`Desugared::after_check`].
    pub bits: Vec<(Span, String)>,
    /// Where the S bits went, when the program uses the S area; set by
    /// [`Desugared::after_check`].
    pub s_area: Option<SAreaPlacement>,
    /// Every S operand (`S0.1` of `LD S0.1`) with the address it compiles to (for hover
    /// and the drawing).
    pub s_operands: Vec<(Span, String, gutta_catalog::Address)>,
    /// The blocks whose Micro/WIN LAD temporaries L60-L63 went into the target's L, and
    /// where; set by [`Desugared::after_check`].
    pub l_temporaries: Vec<LTemporaryPlacement>,
}

/// What a note of the dialect's stage is about: `--message-format json` writes each note
/// as an object with this as its `kind` (`code-page`, `interrupts`, ...).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NoteKind {
    /// A file read in another code page than UTF-8 (written by the tools that read files).
    CodePage,
    /// Where the S7-200 interrupt blocks went.
    Interrupts,
    /// S7-200 event numbers that compile to another GUTTA number.
    Events,
    /// Where the S area (sequence control relays) lives in the target's memory.
    SArea,
    /// Where Micro/WIN's LAD temporaries L60-L63 went in each block.
    LTemporaries,
}

impl NoteKind {
    /// The `kind` of the note's JSON object.
    pub fn as_str(self) -> &'static str {
        match self {
            NoteKind::CodePage => "code-page",
            NoteKind::Interrupts => "interrupts",
            NoteKind::Events => "events",
            NoteKind::SArea => "s-area",
            NoteKind::LTemporaries => "l-temporaries",
        }
    }
}

/// One thing the compiler did to an export that the user should know, as the summary
/// line's part (`S7-200 interrupts: INT_0 (INT0) -> INT1`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Note {
    pub kind: NoteKind,
    pub message: String,
}

impl Export {
    /// What the stage did that the user should know, in the summary's order: where the
    /// S7-200 interrupt blocks went, the S7-200 event numbers that compile to another
    /// GUTTA number, ...; empty when there is nothing to show.
    pub fn notes(&self, target: &Target) -> Vec<Note> {
        [
            (
                NoteKind::Interrupts,
                interrupt_summary(&self.interrupt_placements),
            ),
            (NoteKind::Events, event_summary(&self.events, target)),
            (
                NoteKind::SArea,
                s_area_summary(self.s_area.as_ref(), target),
            ),
            (
                NoteKind::LTemporaries,
                l_temporaries_summary(&self.l_temporaries),
            ),
        ]
        .into_iter()
        .filter_map(|(kind, message)| {
            Some(Note {
                kind,
                message: message?,
            })
        })
        .collect()
    }

    /// [`Export::notes`] as one line for the compile summary and the listing; None when
    /// there is nothing to show.
    pub fn summary(&self, target: &Target) -> Option<String> {
        let parts: Vec<String> = self.notes(target).into_iter().map(|n| n.message).collect();
        (!parts.is_empty()).then(|| parts.join("; "))
    }
}

/// Whether the program is in the Micro/WIN dialect: one of its sources is a Micro/WIN
/// export ([`is_microwin`]: `.awl`, or the marker line).
pub fn is_export(file: &SourceFile) -> bool {
    file.parts()
        .iter()
        .filter(|p| p.kind == PartKind::Source)
        .any(|p| is_microwin(&p.name, file.text.get(p.start..p.end).unwrap_or("")))
}

/// The dialect's stage on a parsed program (its line rules applied by the parser): the
/// program becomes an ordinary one, what the checker must apply comes back as
/// [`Conventions`] and what the stage did as an [`Export`].
pub fn desugar(
    program: &mut Program,
    file: &SourceFile,
    target: &Target,
    options: &CompileOptions,
) -> Desugared {
    let text = file.text.as_str();
    let interrupt_placements = interrupts::place(program, text);
    let mut diagnostics = names::shadowed_system_names(program, text, target);
    let mut events = Vec::new();
    let renumbered_literals =
        events::translate(program, text, target, &mut diagnostics, &mut events);
    let conventions = Conventions {
        predefined_names: names::system_names(target),
        interrupt_operand_offset: interrupts::INTERRUPT_OFFSET,
        renumbered_literals,
        missing_main_help: Some(
            split::missing_main_help(program, file).unwrap_or_else(|| MISSING_MAIN_HELP.into()),
        ),
        block_elsewhere_help: split::block_elsewhere_help(program, file, target),
        timer_bit_lines: Some(timer_bits::bit_lines(target)),
        sequence: Some(scr::convention(target, options.s_area.clone())),
        aeno: Some(aeno::meanings(target)),
        l_temporaries: LTemporaries::last_bytes_of_l(target),
    };
    Desugared {
        diagnostics,
        conventions,
        export: Some(Export {
            interrupt_placements,
            gutta_boxes: has_gutta_boxes(text),
            events,
            bits: Vec::new(),
            s_area: None,
            s_operands: Vec::new(),
            l_temporaries: Vec::new(),
        }),
    }
}

impl Desugared {
    /// The dialect's pass over the checked code (`timer_bits/`): the placeholders the
    /// checker left for timer and counter bits get their instructions, timer boxes keep
    /// the S7-200 logic stack, presets are scaled or warned about; its diagnostics come
    /// back. Outside the dialect nothing happens.
    pub fn after_check(
        &mut self,
        output: &mut CheckOutput,
        text: &str,
        target: &Target,
        options: CompileOptions,
    ) -> Vec<Diagnostic> {
        let Some(export) = self.export.as_mut() else {
            return Vec::new();
        };
        export.l_temporaries = output.l_temporaries.clone();
        let Some(program) = output.program.as_mut() else {
            return Vec::new();
        };
        let sequence = scr::rewrite(
            &mut program.units,
            &output.sequence,
            &mut output.bit_lines,
            target,
            options.s_area.is_some(),
        );
        export.s_area = sequence.placement;
        export.s_operands = output
            .sequence
            .s_operands
            .iter()
            .map(|s| (s.span, s.name.clone(), s.address))
            .collect();
        let mut diagnostics = sequence.diagnostics;
        let report = timer_bits::rewrite(
            &mut program.units,
            &output.bit_lines,
            text,
            target,
            options,
            !export.gutta_boxes,
        );
        export.bits = report.notes;
        diagnostics.extend(report.diagnostics);
        diagnostics
    }
}

/// E0408's help in an export: the S7-200's INT0 is no main program here.
const MISSING_MAIN_HELP: &str = "add `ORGANIZATION_BLOCK MAIN:OB1` ... `END_ORGANIZATION_BLOCK`; in a Micro/WIN export an S7-200 INTERRUPT_BLOCK INTn is interrupt routine INT(n+1), never the main program";

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::BitOp;

    /// The stage leaves an ordinary program and says what the checker must apply.
    #[test]
    fn an_export_becomes_a_program_and_conventions() {
        let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD Always_On\nATCH INT_0, 10\nLD T37\n= Q0.0\nEND_ORGANIZATION_BLOCK\n\
INTERRUPT_BLOCK INT_0:INT0\nBEGIN\nNETWORK 1\nLD SM0.0\n= Q0.1\nEND_INTERRUPT_BLOCK\n";
        let target = gutta_catalog::stdlib::shared(gutta_catalog::stdlib::DEFAULT).unwrap();
        let mut program = crate::syntax::parse_microwin_files(text, &[text.len()]).program;
        let out = desugar(
            &mut program,
            &SourceFile::new("main.awl", text),
            &target,
            &CompileOptions::default(),
        );
        let export = out.export.as_ref().unwrap();
        assert!(!export.gutta_boxes && export.events.len() == 1);
        assert_eq!(
            program.units[1].header.number.map(|(n, _)| n.number),
            Some(1)
        );
        let c = &out.conventions;
        assert_eq!(c.interrupt_operand_offset, 1);
        let always_on = c
            .predefined_names
            .iter()
            .find(|p| p.name == "Always_On")
            .and_then(|p| p.address);
        assert_eq!(always_on, target.memory.parse_address("SM0.0").ok());
        let ten = text.find("10").unwrap();
        let renumbered = c.renumbered_literals.get(&Span::new(ten, ten + 2));
        let event = target
            .memory
            .event_for_s7200(10)
            .map(|e| i64::from(e.number));
        assert_eq!(renumbered.copied(), Some(event));
        let ld = target.instructions.lookup("LD").unwrap();
        let lines = c.timer_bit_lines.as_ref().unwrap();
        assert!(matches!(
            lines.get(&ld),
            Some(BitOp::Read { negated: false, .. })
        ));
        assert_eq!(lines.len(), 8, "{lines:?}");
        // GUTTA's own language: nothing to apply.
        let gutta = Conventions::default();
        assert!(gutta.timer_bit_lines.is_none() && gutta.predefined_names.is_empty());
    }
}
