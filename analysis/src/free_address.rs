//! A free address for a new symbol, of the kind its use needs: the operand's width and
//! an area the operand accepts (M where it may, as the compiler's help lines say, else
//! the first the target lists), the first address there that no operand of the
//! program and no symbol (SYMBOLS blocks and symbol tables) or data block touches.
//! Used by the "declare symbol" quick fix. Plain data; no LSP types.

use std::collections::{HashMap, HashSet};

use gutta_catalog::rules::DataRules;
use gutta_catalog::{Address, Area, AreaKind, OperandKind as SpecKind, Width};
use gutta_compiler::source::Span;
use gutta_compiler::syntax::ast::OperandKind;
use gutta_compiler::CheckedFile;

/// The free address (as the target writes it: `M0.1`, `MW4`, `T2`) for a symbol used
/// at `span` (a plain name operand of an instruction), or None when the use does not
/// say what it needs (a CALL argument, a block operand) or its areas are full.
pub fn for_use(checked: &CheckedFile, span: Span) -> Option<String> {
    let (spec_index, id) = operand_at(checked, span)?;
    let spec = checked
        .target
        .instructions
        .get(id)
        .operands
        .get(spec_index)?;
    if matches!(spec.kind, SpecKind::Label | SpecKind::Block) {
        return None;
    }
    let rules = DataRules::from_spec(spec);
    let memory = &checked.target.memory;
    let fits = |a: &&Area| {
        !matches!(a.kind, AreaKind::Constant | AreaKind::Local)
            && a.allows(rules.width)
            && rules.accepts_area(a)
            && rules.may_write(a)
    };
    let area = memory
        .areas
        .iter()
        .filter(fits)
        .find(|a| a.kind == AreaKind::Memory)
        .or_else(|| memory.areas.iter().find(fits))?;
    let used = used_bits(checked);
    first_free(checked, area, rules.width, &used).map(|a| memory.format_address(&a))
}

/// The operand index of the plain name operand at `span`, and its instruction.
fn operand_at(checked: &CheckedFile, span: Span) -> Option<(usize, gutta_catalog::InstrId)> {
    let mnemonics: HashMap<Span, _> = checked.output.mnemonics.iter().copied().collect();
    for network in checked.ast.units.iter().flat_map(|u| &u.networks) {
        for ins in &network.instructions {
            let (a, b) = (ins.operands.0 as usize, ins.operands.1 as usize);
            let Some(ops) = network.operands.get(a..b) else {
                continue;
            };
            let found = ops.iter().position(|o| match o.kind {
                OperandKind::Name {
                    prefix: gutta_compiler::syntax::ast::Prefix::None,
                    local: false,
                    name,
                } => name == span,
                _ => false,
            });
            if let Some(i) = found {
                return Some((i, *mnemonics.get(&ins.mnemonic)?));
            }
        }
    }
    None
}

/// Every bit the program touches, as (slot, bit number from the area's start): direct
/// addresses in operands, symbols' addresses, data block rows.
fn used_bits(checked: &CheckedFile) -> HashSet<(u8, u32)> {
    let memory = &checked.target.memory;
    let text = &checked.file.text;
    let written = |s: Span| {
        text.get(s.range())
            .and_then(|t| memory.parse_address(t.trim()).ok())
    };
    let declared = checked
        .ast
        .symbols
        .iter()
        .filter_map(|d| written(d.address));
    let data = checked
        .ast
        .data_blocks
        .iter()
        .flat_map(|b| &b.rows)
        .filter_map(|r| written(r.address));
    let operands = checked.output.addresses.iter().map(|(_, a)| *a);
    let mut used = HashSet::new();
    for a in operands.chain(declared).chain(data) {
        used.extend(bits_of(&a));
    }
    used
}

/// The bits an address covers.
fn bits_of(a: &Address) -> impl Iterator<Item = (u8, u32)> {
    let first = a.offset * 8 + u32::from(a.bit);
    let slot = a.slot;
    (first..first + a.width.bits()).map(move |b| (slot, b))
}

/// The first address of `width` in `area` (aligned to its width) that touches no used
/// bit and exists on the target.
fn first_free(
    checked: &CheckedFile,
    area: &Area,
    width: Width,
    used: &HashSet<(u8, u32)>,
) -> Option<Address> {
    let memory = &checked.target.memory;
    let step = width.bytes().max(area.unit.bytes());
    let bits: &[u8] = if width == Width::Bit {
        &[0, 1, 2, 3, 4, 5, 6, 7]
    } else {
        &[0]
    };
    (0..area.size).step_by(step as usize).find_map(|offset| {
        bits.iter().find_map(|&bit| {
            let a = Address {
                slot: area.slot,
                width,
                offset,
                bit,
            };
            let free = bits_of(&a).all(|b| !used.contains(&b));
            let exists = memory.parse_address(&memory.format_address(&a)).ok() == Some(a);
            (free && exists).then_some(a)
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use gutta_compiler::source::SourceFile;

    fn free(text: &str, name: &str, nth: usize) -> Option<String> {
        let c = gutta_compiler::check_source(SourceFile::new("t.lad", text), None);
        let at = text.match_indices(name).nth(nth).expect("the name").0;
        for_use(&c, Span::new(at, at + name.len()))
    }

    const PROGRAM: &str = "SYMBOLS\n  Start : M0.0\n  Speed : MW2\nEND_SYMBOLS\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD Start\nA M0.1\nA Lamp\n= Pump\nMOVW Speed, Target\nMOVD MD8, Total\nMOVB 1, Small\nTON Delay, 10\nCALL SBR_X, Arg\nEND_ORGANIZATION_BLOCK\n";

    #[test]
    fn the_first_free_address_of_the_width_the_use_needs() {
        // M0.0 and M0.1 are taken, MW2 covers MB2..MB3, MD8 covers MB8..MB11.
        assert_eq!(free(PROGRAM, "Lamp", 0).as_deref(), Some("M0.2"));
        assert_eq!(free(PROGRAM, "Pump", 0).as_deref(), Some("M0.2"));
        // Words from MW0: MW0 holds M0.0, MW2 is Speed, MW4 is free.
        assert_eq!(free(PROGRAM, "Target", 0).as_deref(), Some("MW4"));
        assert_eq!(free(PROGRAM, "Total", 0).as_deref(), Some("MD4"));
        assert_eq!(free(PROGRAM, "Small", 0).as_deref(), Some("MB1"));
        // A timer operand takes only T.
        assert_eq!(free(PROGRAM, "Delay", 0).as_deref(), Some("T0"));
        // A CALL argument says nothing about what it needs without the subroutine.
        assert_eq!(free(PROGRAM, "Arg", 0), None);
    }
}
