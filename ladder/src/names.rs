//! Names as a drawing shows them (docs/ladder.md, "Names"): the label of a box and of a
//! compare contact in Micro/WIN's LAD names (`ADD_I`, `MOV_W`, `>=I`) or in the STL
//! mnemonics the source writes (`+I`, `MOVW`, `>=W`), and the pins a box draws for its
//! operands, from the catalog's operand roles. The LAD names are plain data (public
//! facts: the S7-200 system manual's LAD boxes); a test keeps a label for every box
//! instruction of every stdlib target. GUTTA's `W` is the S7-200's INT/WORD (`_I`, `_W`
//! in LAD) and its `D` the DINT/DWORD (`_DI`, `_DW`), as docs/microwin.md maps them.

use gutta_catalog::{Instruction, OperandKind, Role};

use crate::svg::Names;

/// STL mnemonic -> Micro/WIN's LAD box name, for every box instruction of the GUTTA
/// instruction set (stdlib/ManagerFun.xml). Boxes Micro/WIN names like the STL keep
/// their name here too, so the table says every box was looked at.
pub const LAD_NAMES: &[(&str, &str)] = &[
    ("NOP", "NOP"),
    // Timers and counters: the box is named by its kind.
    ("TON", "TON"),
    ("TOF", "TOF"),
    ("TONR", "TONR"),
    ("CTU", "CTU"),
    ("CTD", "CTD"),
    ("CTUD", "CTUD"),
    ("BITIM", "BGN_ITIME"),
    ("CITIM", "CAL_ITIME"),
    // Integer math: W is INT (`_I`), D is DINT (`_DI`).
    ("+I", "ADD_I"),
    ("-I", "SUB_I"),
    ("*I", "MUL_I"),
    ("/I", "DIV_I"),
    ("+D", "ADD_DI"),
    ("-D", "SUB_DI"),
    ("*D", "MUL_DI"),
    ("/D", "DIV_DI"),
    ("MUL", "MUL"),
    ("DIV", "DIV"),
    ("INCB", "INC_B"),
    ("INCW", "INC_W"),
    ("INCD", "INC_DW"),
    ("DECB", "DEC_B"),
    ("DECW", "DEC_W"),
    ("DECD", "DEC_DW"),
    // Real math.
    ("+R", "ADD_R"),
    ("-R", "SUB_R"),
    ("*R", "MUL_R"),
    ("/R", "DIV_R"),
    ("SQRT", "SQRT"),
    ("SIN", "SIN"),
    ("COS", "COS"),
    ("TAN", "TAN"),
    ("LN", "LN"),
    ("EXP", "EXP"),
    // Logic: W is WORD (`_W`), D is DWORD (`_DW`).
    ("ANDB", "WAND_B"),
    ("ANDW", "WAND_W"),
    ("ANDD", "WAND_DW"),
    ("ORB", "WOR_B"),
    ("ORW", "WOR_W"),
    ("ORD", "WOR_DW"),
    ("XORB", "WXOR_B"),
    ("XORW", "WXOR_W"),
    ("XORD", "WXOR_DW"),
    ("INVB", "INV_B"),
    ("INVW", "INV_W"),
    ("INVD", "INV_DW"),
    // Move.
    ("MOVB", "MOV_B"),
    ("MOVW", "MOV_W"),
    ("MOVD", "MOV_DW"),
    ("MOVR", "MOV_R"),
    ("BMB", "BLKMOV_B"),
    ("BMW", "BLKMOV_W"),
    ("BMD", "BLKMOV_D"),
    ("SWAP", "SWAP"),
    ("FILL", "FILL_N"),
    ("BIR", "MOV_BIR"),
    ("BIW", "MOV_BIW"),
    // Shift and rotate.
    ("SRB", "SHR_B"),
    ("SRW", "SHR_W"),
    ("SRD", "SHR_DW"),
    ("SLB", "SHL_B"),
    ("SLW", "SHL_W"),
    ("SLD", "SHL_DW"),
    ("RRB", "ROR_B"),
    ("RRW", "ROR_W"),
    ("RRD", "ROR_DW"),
    ("RLB", "ROL_B"),
    ("RLW", "ROL_W"),
    ("RLD", "ROL_DW"),
    ("SHRB", "SHRB"),
    // Conversion.
    ("BTI", "B_I"),
    ("ITB", "I_B"),
    ("ITD", "I_DI"),
    ("DTI", "DI_I"),
    ("DTR", "DI_R"),
    ("ROUND", "ROUND"),
    ("TRUNC", "TRUNC"),
    ("BCDI", "BCD_I"),
    ("IBCD", "I_BCD"),
    ("SEG", "SEG"),
    ("DECO", "DECO"),
    ("ENCO", "ENCO"),
    ("ATH", "ATH"),
    ("HTA", "HTA"),
    ("ITA", "I_A"),
    ("DTA", "DI_A"),
    ("RTA", "R_A"),
    // Program control.
    ("JMP", "JMP"),
    ("LBL", "LBL"),
    ("CALL", "CALL"),
    ("CRET", "RET"),
    ("RET", "RET"),
    ("END", "END"),
    ("STOP", "STOP"),
    ("WDR", "WDR"),
    ("FOR", "FOR"),
    ("NEXT", "NEXT"),
    // Interrupts.
    ("ENI", "ENI"),
    ("DISI", "DISI"),
    ("ATCH", "ATCH"),
    ("DTCH", "DTCH"),
    ("CEVNT", "CLR_EVNT"),
    ("RETI", "RETI"),
    ("CRETI", "RETI"),
    // Tables.
    ("ATT", "AD_T_TBL"),
    ("FIFO", "FIFO"),
    ("LIFO", "LIFO"),
    ("FND=", "TBL_FIND"),
    ("FND<>", "TBL_FIND"),
    ("FND<", "TBL_FIND"),
    ("FND>", "TBL_FIND"),
    // Communication: GUTTA's own (Modbus master), no Micro/WIN box.
    ("EXCH", "EXCH"),
];

/// Micro/WIN's LAD name of a box instruction, by its STL mnemonic (case folded).
pub fn lad_name(mnemonic: &str) -> Option<&'static str> {
    LAD_NAMES
        .iter()
        .find(|(stl, _)| stl.eq_ignore_ascii_case(mnemonic))
        .map(|(_, lad)| *lad)
}

/// The label of a box of `mnemonic`: its LAD name (the mnemonic when the table has
/// none), or the mnemonic itself with [`Names::Stl`].
pub fn box_label(mnemonic: &str, names: Names) -> &str {
    match names {
        Names::Lad => lad_name(mnemonic).unwrap_or(mnemonic),
        Names::Stl => mnemonic,
    }
}

/// The label inside a compare contact, from its relation as the model keeps it (the
/// STL form: relation then type letter, `>=W`, `=B`, `<>D`, `<R`): with [`Names::Lad`]
/// Micro/WIN's (`>=I`, `==B`, `<>D`, `<R`: `==` for equality, `I` for GUTTA's word
/// compare, which compares INTs).
pub fn compare_label(relation: &str, names: Names) -> String {
    if names == Names::Stl {
        return relation.to_string();
    }
    let Some(letter) = relation.chars().last().filter(|c| c.is_ascii_uppercase()) else {
        return relation.to_string();
    };
    let op = &relation[..relation.len() - 1];
    let op = match gutta_catalog::CompareOp::from_symbol(op) {
        Some(gutta_catalog::CompareOp::Eq) => "==",
        _ => op,
    };
    let letter = if letter == 'W' { 'I' } else { letter };
    format!("{op}{letter}")
}

/// How a box draws one operand (docs/ladder.md, "Elements"): its pin's name, whether
/// it is on the right (an output), and the name of the input pin it also has when the
/// operand is read and written (an in/out operand named `OUT`: `+I`'s OUT is also
/// ADD_I's `IN1`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PinSide {
    pub name: String,
    pub output: bool,
    pub input: Option<String>,
}

/// The pins of `spec`'s operands, in the catalog's order, from the operand roles: an
/// `Out` operand is an output pin; an `InOut` operand the catalog names `OUT` is the
/// result of a two-operand STL form (`+I IN1, OUT` is `OUT := OUT + IN1`), drawn on both
/// sides as Micro/WIN's three-operand box draws it: an input pin first (`IN1`, the
/// other inputs numbered after it, or `IN` when there is no numbered input) and the
/// output; any other `InOut` (FOR's INDX, a table's TBL) is updated in place and drawn
/// on the input side, as Micro/WIN draws it; `In` operands are input pins.
pub fn pin_sides(spec: &Instruction) -> Vec<PinSide> {
    let result = |o: &gutta_catalog::OperandSpec| {
        o.role == Role::InOut && o.name == "OUT" && o.kind == OperandKind::Data
    };
    let has_result = spec.operands.iter().any(result);
    let numbered = spec
        .operands
        .iter()
        .any(|o| o.role == Role::In && numbered_input(&o.name).is_some());
    spec.operands
        .iter()
        .map(|o| {
            if result(o) {
                let input = if numbered { "IN1" } else { "IN" };
                PinSide {
                    name: o.name.clone(),
                    output: true,
                    input: Some(input.to_string()),
                }
            } else {
                let name = match numbered_input(&o.name) {
                    Some(n) if has_result && o.role == Role::In => format!("IN{}", n + 1),
                    _ => o.name.clone(),
                };
                PinSide {
                    name,
                    output: o.role == Role::Out,
                    input: None,
                }
            }
        })
        .collect()
}

/// `IN1` -> 1.
fn numbered_input(name: &str) -> Option<u32> {
    name.strip_prefix("IN")?.parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use gutta_catalog::{Flow, LadderClass};

    #[test]
    fn every_box_of_every_stdlib_target_has_a_lad_name_and_every_name_an_instruction() {
        let mut mnemonics = std::collections::BTreeSet::new();
        for name in gutta_catalog::stdlib::names() {
            let target = gutta_catalog::stdlib::load(name).expect("stdlib target");
            for spec in &target.instructions.instructions {
                let boxed = spec.ladder == LadderClass::Box || spec.flow == Flow::Always;
                if boxed {
                    assert!(
                        lad_name(&spec.mnemonic).is_some(),
                        "{name}: `{}` has no LAD name in LAD_NAMES",
                        spec.mnemonic
                    );
                }
                mnemonics.insert(spec.mnemonic.clone());
            }
        }
        for (stl, lad) in LAD_NAMES {
            assert!(
                mnemonics.contains(*stl),
                "LAD_NAMES names `{stl}` ({lad}), no instruction"
            );
        }
    }

    #[test]
    fn box_and_compare_labels_follow_the_names_option() {
        assert_eq!(box_label("+I", Names::Lad), "ADD_I");
        assert_eq!(box_label("+I", Names::Stl), "+I");
        assert_eq!(box_label("MOVD", Names::Lad), "MOV_DW");
        assert_eq!(box_label("-D", Names::Lad), "SUB_DI");
        assert_eq!(box_label("MADE_UP", Names::Lad), "MADE_UP");
        assert_eq!(compare_label(">=W", Names::Lad), ">=I");
        assert_eq!(compare_label("=B", Names::Lad), "==B");
        assert_eq!(compare_label("<>D", Names::Lad), "<>D");
        assert_eq!(compare_label("<R", Names::Lad), "<R");
        assert_eq!(compare_label(">=W", Names::Stl), ">=W");
    }

    #[test]
    fn in_out_results_are_drawn_on_both_sides_and_updated_operands_as_inputs() {
        let set = gutta_catalog::stdlib::default_target()
            .expect("stdlib")
            .instructions;
        let sides = |m: &str| {
            pin_sides(set.get(set.lookup(m).expect(m)))
                .into_iter()
                .map(|p| (p.name, p.output, p.input))
                .collect::<Vec<_>>()
        };
        let s = |t: &str| t.to_string();
        assert_eq!(
            sides("+I"),
            vec![(s("IN2"), false, None), (s("OUT"), true, Some(s("IN1")))]
        );
        assert_eq!(sides("INCW"), vec![(s("OUT"), true, Some(s("IN")))]);
        assert_eq!(
            sides("SRW"),
            vec![(s("OUT"), true, Some(s("IN"))), (s("N"), false, None)]
        );
        assert_eq!(
            sides("FOR"),
            vec![
                (s("INDX"), false, None),
                (s("INIT"), false, None),
                (s("FINAL"), false, None)
            ]
        );
        assert_eq!(
            sides("MOVW"),
            vec![(s("IN"), false, None), (s("OUT"), true, None)]
        );
    }
}
