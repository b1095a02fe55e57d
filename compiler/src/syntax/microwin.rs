//! The STEP 7-Micro/WIN dialect (docs/microwin.md, "Micro/WIN exports as they are"):
//! which files are Micro/WIN exports, and the tree pass that places their S7-200
//! interrupt blocks on GUTTA's interrupt numbers (S7-200 INTn -> GUTTA INT(n+1), since
//! GUTTA's MAIN is INT0) and drops empty template blocks nothing attaches. The line
//! rules of the dialect (`NOP 0`, `MEND`, `NAME:SBRn` operands) are the block parser's;
//! system symbol names (`Always_On`) are data in the target (`SystemBit MicroWin=`),
//! resolved by the checker. Decoding code pages is `source::decode_source`'s.

use gutta_catalog::Target;

use crate::diagnostics::{Code, Diagnostic};
use crate::syntax::ast::{BlockKind, BlockPrefix, InterruptPlacement, Program, Unit};

/// The first line that makes a `.lad` file a Micro/WIN export (any case, blanks around).
pub const MARKER: &str = "// dialect: microwin";

/// Whether a file is a Micro/WIN export: its name ends in `.awl` (any case), or its
/// first line is [`MARKER`].
pub fn is_microwin(name: &str, text: &str) -> bool {
    let awl = name
        .rsplit_once('.')
        .is_some_and(|(_, ext)| ext.eq_ignore_ascii_case("awl"));
    awl || has_marker(text)
}

/// Whether the text's first line is [`MARKER`] (a BOM before it is allowed).
pub fn has_marker(text: &str) -> bool {
    let text = text.strip_prefix('\u{FEFF}').unwrap_or(text);
    text.lines()
        .next()
        .is_some_and(|l| l.trim().eq_ignore_ascii_case(MARKER))
}

/// The dialect's tree pass: mark the program, then place every `INTERRUPT_BLOCK` that
/// writes an S7-200 number `INTn` on GUTTA's INT(n+1), dropping it instead when it has
/// no instruction and no operand of the program names it (by name or `INTn`). An
/// `ORGANIZATION_BLOCK` stays MAIN (INT0); a program without one keeps no INT0, so the
/// checker reports the missing MAIN (E0408) instead of running INT_0 as the main program.
/// Micro/WIN's template subroutine (an empty `SUBROUTINE_BLOCK` nothing calls,
/// `is_template_subroutine`) is dropped too. A text `gutta-cc dis --format awl` wrote
/// (its [`GUTTA_BOXES`] line) has no templates: its empty blocks are the image's and
/// stay, so that it compiles back to the same image.
pub fn apply(program: &mut Program, text: &str) {
    program.microwin = true;
    let templates = !has_gutta_boxes(text);
    let slice = |s: crate::source::Span| text.get(s.range()).unwrap_or("");
    let named: Vec<String> = program
        .units
        .iter()
        .flat_map(|u| &u.networks)
        .flat_map(|n| &n.operands)
        .map(|o| slice(o.span).to_ascii_uppercase())
        .collect();
    let mut placements = Vec::new();
    let mut kept: Vec<Unit> = Vec::with_capacity(program.units.len());
    for mut unit in std::mem::take(&mut program.units) {
        if templates && is_template_subroutine(&unit, text, &named) {
            continue;
        }
        let Some(s7_number) = s7_interrupt(&unit, text) else {
            kept.push(unit);
            continue;
        };
        let name = slice(unit.header.name).to_string();
        let numbered = format!("INT{s7_number}");
        let attached = named
            .iter()
            .any(|n| n.eq_ignore_ascii_case(&name) || *n == numbered);
        let empty = unit.networks.iter().all(|n| n.instructions.is_empty());
        let gutta_number = if templates && empty && !attached {
            None
        } else {
            if let Some((number, _)) = unit.header.number.as_mut() {
                number.number = s7_number + 1;
            }
            kept.push(unit);
            Some(s7_number + 1)
        };
        placements.push(InterruptPlacement {
            name,
            s7_number,
            gutta_number,
        });
    }
    program.units = kept;
    program.interrupt_placements = placements;
}

/// The key (upper case) under which the checker looks up a block operand: in the
/// dialect an S7-200 numbered interrupt `INTn` (`ATCH INT0, 10`) means GUTTA's INT(n+1),
/// where [`apply`] placed it; any other text, or any text outside the dialect, as
/// written.
pub fn block_key(program: &Program, text: &str) -> String {
    let key = text.to_ascii_uppercase();
    if !program.microwin {
        return key;
    }
    match key.strip_prefix("INT").map(str::parse::<u32>) {
        Some(Ok(n)) => format!("INT{}", n + 1),
        _ => key,
    }
}

/// W0206 for every user symbol (SYMBOLS block or symbol table) named like one of the
/// target's Micro/WIN system symbols: the user's symbol wins, as in Micro/WIN.
pub fn shadowed_system_names(program: &Program, text: &str, target: &Target) -> Vec<Diagnostic> {
    program
        .symbols
        .iter()
        .filter_map(|s| {
            let name = text.get(s.name.range())?;
            let bit = target.memory.microwin_system_bit(name)?;
            Some(
                Diagnostic::new(
                    Code::SystemNameShadowed,
                    s.name,
                    format!(
                        "symbol `{name}` hides Micro/WIN's system symbol for {}",
                        bit.address
                    ),
                )
                .label("this symbol is used")
                .help(format!(
                    "rename it to use {} under this name, or keep it on purpose",
                    bit.address
                )),
            )
        })
        .collect()
}

/// Whether a unit is Micro/WIN's template subroutine: a `SUBROUTINE_BLOCK` with no
/// instruction that no operand of the program names (`named`, upper case), neither by
/// its name (`CALL SBR_0`) nor by its number (`CALL SBR0`). Micro/WIN exports an empty
/// `SBR_0:SBR0` in every project; [`apply`] drops it without a word (docs/microwin.md,
/// "Template subroutines").
fn is_template_subroutine(unit: &Unit, text: &str, named: &[String]) -> bool {
    if unit.kind != BlockKind::Subroutine
        || unit.networks.iter().any(|n| !n.instructions.is_empty())
    {
        return false;
    }
    let name = text.get(unit.header.name.range()).unwrap_or("");
    let numbered = match unit.header.number {
        Some((n, _)) if n.prefix == BlockPrefix::Sbr => Some(format!("SBR{}", n.number)),
        _ => None,
    };
    !named
        .iter()
        .any(|n| n.eq_ignore_ascii_case(name) || numbered.as_deref() == Some(n.as_str()))
}

/// S7-200's interrupt number of an `INTERRUPT_BLOCK NAME:INTn` (not of an
/// `ORGANIZATION_BLOCK`, which is MAIN).
fn s7_interrupt(unit: &Unit, text: &str) -> Option<u32> {
    if unit.kind != BlockKind::Interrupt {
        return None;
    }
    let keyword = text
        .get(unit.header.span.range())
        .and_then(|l| l.split_whitespace().next())?;
    if !keyword.eq_ignore_ascii_case("INTERRUPT_BLOCK") {
        return None;
    }
    match unit.header.number {
        Some((n, _)) if n.prefix == BlockPrefix::Int => Some(n.number),
        _ => None,
    }
}

/// The placement of the S7-200 interrupt blocks as one line for the compile summary and
/// the listing: `S7-200 interrupts: INT_0 (INT0) -> INT1; INT_1 (INT1) empty, not
/// attached: dropped`; None when the program has none.
pub fn interrupt_summary(program: &Program) -> Option<String> {
    if program.interrupt_placements.is_empty() {
        return None;
    }
    let parts: Vec<String> = program
        .interrupt_placements
        .iter()
        .map(|p| match p.gutta_number {
            Some(g) => format!("{} (INT{}) -> INT{g}", p.name, p.s7_number),
            None => format!(
                "{} (INT{}) empty, not attached: dropped",
                p.name, p.s7_number
            ),
        })
        .collect();
    Some(format!("S7-200 interrupts: {}", parts.join("; ")))
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

#[cfg(test)]
mod tests {
    use super::*;

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
    fn interrupts_move_up_one_and_empty_unattached_ones_go() {
        let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.1\nATCH INT_1, 10\nEND_ORGANIZATION_BLOCK\n\
INTERRUPT_BLOCK INT_0:INT0\nBEGIN\nNETWORK 1\nEND_INTERRUPT_BLOCK\n\
INTERRUPT_BLOCK INT_1:INT1\nBEGIN\nNETWORK 1\nEND_INTERRUPT_BLOCK\n\
INTERRUPT_BLOCK INT_2:INT2\nBEGIN\nNETWORK 1\nLD SM0.0\n= Q0.0\nEND_INTERRUPT_BLOCK\n";
        let mut program = crate::syntax::parse(text).program;
        apply(&mut program, text);
        assert_eq!(program.units.len(), 3);
        assert_eq!(
            interrupt_summary(&program).as_deref(),
            Some("S7-200 interrupts: INT_0 (INT0) empty, not attached: dropped; INT_1 (INT1) -> INT2; INT_2 (INT2) -> INT3")
        );
    }
}
