//! S7-200 interrupt blocks and Micro/WIN's template blocks (docs/microwin.md): the tree
//! edit that places every `INTERRUPT_BLOCK NAME:INTn` on GUTTA's INT(n+1) (GUTTA's MAIN
//! is INT0) and drops the empty blocks nothing calls or attaches, and the summary line
//! that says where each went. It edits block headers only; code is never touched.

use crate::source::{has_gutta_boxes, Span};
use crate::syntax::ast::{BlockKind, BlockPrefix, Program, Unit};

/// An S7-200 `INTERRUPT_BLOCK NAME:INTn` of a Micro/WIN export and its GUTTA page.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InterruptPlacement {
    /// The block's name as written (`INT_0`, `中断程序_0`).
    pub name: String,
    /// S7-200's number (`INT0` -> 0).
    pub s7_number: u32,
    /// GUTTA's interrupt number (S7-200's plus one), or None: the block was empty and
    /// nothing attaches it, so it was dropped.
    pub gutta_number: Option<u32>,
}

/// How far S7-200's interrupt numbers are from GUTTA's: `INTn` is GUTTA's INT(n+1).
pub(super) const INTERRUPT_OFFSET: u32 = 1;

/// Place every `INTERRUPT_BLOCK` that writes an S7-200 number `INTn` on GUTTA's
/// INT(n+1), dropping it instead when it has no instruction and no operand of the
/// program names it (by name or `INTn`). An `ORGANIZATION_BLOCK` stays MAIN (INT0); a
/// program without one keeps no INT0, so the checker reports the missing MAIN (E0408)
/// instead of running INT_0 as the main program. Micro/WIN's template subroutine (an
/// empty `SUBROUTINE_BLOCK` nothing calls, `is_template_subroutine`) is dropped too. A
/// text `gutta-cc dis --format awl` wrote (its `GUTTA_BOXES` line) has no templates:
/// its empty blocks are the image's and stay, so that it compiles back to the same
/// image.
pub(super) fn place(program: &mut Program, text: &str) -> Vec<InterruptPlacement> {
    let templates = !has_gutta_boxes(text);
    let slice = |s: Span| text.get(s.range()).unwrap_or("");
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
                number.number = s7_number + INTERRUPT_OFFSET;
            }
            kept.push(unit);
            Some(s7_number + INTERRUPT_OFFSET)
        };
        placements.push(InterruptPlacement {
            name,
            s7_number,
            gutta_number,
        });
    }
    program.units = kept;
    placements
}

/// Whether a unit is Micro/WIN's template subroutine: a `SUBROUTINE_BLOCK` with no
/// instruction that no operand of the program names (`named`, upper case), neither by
/// its name (`CALL SBR_0`) nor by its number (`CALL SBR0`). Micro/WIN exports an empty
/// `SBR_0:SBR0` in every project; [`place`] drops it without a word (docs/microwin.md,
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
pub fn interrupt_summary(placements: &[InterruptPlacement]) -> Option<String> {
    if placements.is_empty() {
        return None;
    }
    let parts: Vec<String> = placements
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interrupts_move_up_one_and_empty_unattached_ones_go() {
        let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.1\nATCH INT_1, 10\nEND_ORGANIZATION_BLOCK\n\
INTERRUPT_BLOCK INT_0:INT0\nBEGIN\nNETWORK 1\nEND_INTERRUPT_BLOCK\n\
INTERRUPT_BLOCK INT_1:INT1\nBEGIN\nNETWORK 1\nEND_INTERRUPT_BLOCK\n\
INTERRUPT_BLOCK INT_2:INT2\nBEGIN\nNETWORK 1\nLD SM0.0\n= Q0.0\nEND_INTERRUPT_BLOCK\n";
        let mut program = crate::syntax::parse(text).program;
        let placements = place(&mut program, text);
        assert_eq!(program.units.len(), 3);
        assert_eq!(
            interrupt_summary(&placements).as_deref(),
            Some("S7-200 interrupts: INT_0 (INT0) empty, not attached: dropped; INT_1 (INT1) -> INT2; INT_2 (INT2) -> INT3")
        );
    }
}
