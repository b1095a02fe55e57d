//! Invariants of the shipped instruction set (stdlib/ManagerFun.xml) and the check that
//! docs/instructions.md is the reference generated from it.

#![allow(
    clippy::disallowed_methods,
    reason = "the docs test reads the generated page and rewrites it on request"
)]

use std::path::PathBuf;

use gutta_catalog::docs::instruction_reference;
use gutta_catalog::{stdlib, DataType, Flow, Instruction, InstructionSet, OperandKind, Role};

const MANAGER_FUN: &[u8] = include_bytes!("../../stdlib/ManagerFun.xml");

fn shipped() -> InstructionSet {
    match InstructionSet::parse(MANAGER_FUN) {
        Ok(set) => set,
        Err(e) => panic!("stdlib/ManagerFun.xml does not load: {e}"),
    }
}

fn get<'a>(set: &'a InstructionSet, mnemonic: &str) -> &'a Instruction {
    match set.lookup(mnemonic) {
        Some(id) => set.get(id),
        None => panic!("{mnemonic} is missing from stdlib/ManagerFun.xml"),
    }
}

fn types(ins: &Instruction, operand: usize) -> Vec<DataType> {
    ins.operands[operand].types.clone()
}

#[test]
fn reference_doc_is_generated_from_the_xml() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../docs/instructions.md");
    let generated = instruction_reference(&shipped());
    if std::env::var_os("UPDATE_DOCS").is_some_and(|v| v == "1") {
        std::fs::write(&path, &generated).expect("write docs/instructions.md");
        return;
    }
    let on_disk = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        on_disk == generated,
        "docs/instructions.md is not the reference generated from stdlib/ManagerFun.xml; \
         regenerate it with `UPDATE_DOCS=1 cargo test -p gutta-catalog --test instruction_set` \
         and commit the result"
    );
}

#[test]
fn the_instruction_set_loads_with_the_default_target() {
    let target = stdlib::default_target().expect("default target loads");
    assert_eq!(target.instructions, shipped());
    let set = shipped();
    assert_eq!(
        (set.logic_stack_depth, set.call_depth, set.for_depth),
        (9, 8, 8)
    );
}

/// The mnemonics the brief requires, by family.
const REQUIRED: &[(&str, &[&str])] = &[
    (
        "bit logic",
        &[
            "LD", "LDN", "A", "AN", "O", "ON", "NOT", "EU", "ED", "=", "S", "R", "ALD", "OLD",
            "LPS", "LRD", "LPP", "LDS", "LDI", "LDNI", "AI", "ANI", "OI", "ONI", "=I", "SI", "RI",
            "NOP",
        ],
    ),
    (
        "timers and counters",
        &["TON", "TOF", "TONR", "CTU", "CTD", "CTUD"],
    ),
    (
        "integer and real math",
        &[
            "+I", "-I", "*I", "/I", "+D", "-D", "*D", "/D", "MUL", "DIV", "+R", "-R", "*R", "/R",
            "SQRT", "INCB", "INCW", "INCD", "DECB", "DECW", "DECD",
        ],
    ),
    (
        "logic",
        &[
            "ANDB", "ANDW", "ANDD", "ORB", "ORW", "ORD", "XORB", "XORW", "XORD", "INVB", "INVW",
            "INVD",
        ],
    ),
    (
        "moves",
        &[
            "MOVB", "MOVW", "MOVD", "MOVR", "BMB", "BMW", "BMD", "SWAP", "FILL",
        ],
    ),
    (
        "shifts and rotates",
        &[
            "SRB", "SRW", "SRD", "SLB", "SLW", "SLD", "RRB", "RRW", "RRD", "RLB", "RLW", "RLD",
            "SHRB",
        ],
    ),
    (
        "conversions",
        &[
            "BTI", "ITB", "ITD", "DTI", "DTR", "ROUND", "TRUNC", "BCDI", "IBCD", "SEG", "DECO",
            "ENCO",
        ],
    ),
    (
        "program control",
        &[
            "JMP", "LBL", "CALL", "CRET", "RET", "END", "STOP", "WDR", "FOR", "NEXT",
        ],
    ),
    (
        "interrupts",
        &["ENI", "DISI", "ATCH", "DTCH", "RETI", "CRETI"],
    ),
    (
        "tables",
        &["ATT", "FIFO", "LIFO", "FND=", "FND<>", "FND<", "FND>"],
    ),
    ("communication", &["EXCH"]),
];

#[test]
fn every_required_mnemonic_is_present() {
    let set = shipped();
    let missing: Vec<String> = REQUIRED
        .iter()
        .flat_map(|(family, names)| names.iter().map(move |m| (family, m)))
        .filter(|(_, m)| set.lookup(m).is_none())
        .map(|(family, m)| format!("{m} ({family})"))
        .collect();
    assert!(missing.is_empty(), "missing mnemonics: {missing:?}");
}

#[test]
fn the_compare_matrix_is_complete_and_follows_the_opcode_layout() {
    let set = shipped();
    let forms = [
        ("LD", Flow::Load),
        ("A", Flow::Combine),
        ("O", Flow::Combine),
    ];
    let kinds: [(&str, &[DataType]); 4] = [
        ("B", &[DataType::Byte, DataType::Usint]),
        ("W", &[DataType::Int, DataType::Word]),
        ("D", &[DataType::Dint, DataType::Dword]),
        ("R", &[DataType::Real]),
    ];
    let ops = ["=", "<>", "<", "<=", ">", ">="];
    let mut count = 0;
    for (form_code, (form, flow)) in forms.iter().enumerate() {
        for (type_code, (kind, allowed)) in kinds.iter().enumerate() {
            for (op_code, op) in ops.iter().enumerate() {
                let mnemonic = format!("{form}{kind}{op}");
                let ins = get(&set, &mnemonic);
                let opcode =
                    0x0200 | (form_code << 5) as u16 | (type_code << 3) as u16 | op_code as u16;
                assert_eq!(ins.opcode, opcode, "opcode of {mnemonic}");
                assert_eq!(ins.flow, *flow, "flow of {mnemonic}");
                assert_eq!(ins.family, "Compare", "family of {mnemonic}");
                assert_eq!(ins.operands.len(), 2, "operands of {mnemonic}");
                for (i, op) in ins.operands.iter().enumerate() {
                    assert_eq!(op.role, Role::In, "{mnemonic} operand {i}");
                    assert_eq!(
                        types(ins, i),
                        allowed.to_vec(),
                        "types of {mnemonic} operand {i}"
                    );
                    assert!(
                        op.constant && op.pointer,
                        "{mnemonic} operand {i} takes constants and pointers"
                    );
                }
                count += 1;
            }
        }
    }
    assert_eq!(count, 72);
    let compares = set
        .instructions
        .iter()
        .filter(|i| i.family == "Compare")
        .count();
    assert_eq!(compares, 72, "the Compare family holds exactly the matrix");
}

/// The family plan: the high byte of an opcode names the family.
const FAMILIES: &[(&str, u16)] = &[
    ("Bit logic", 0x01),
    ("Compare", 0x02),
    ("Timer and counter", 0x03),
    ("Integer math", 0x04),
    ("Real math", 0x05),
    ("Logic", 0x06),
    ("Move", 0x07),
    ("Shift and rotate", 0x08),
    ("Conversion", 0x09),
    ("Program control", 0x0A),
    ("Interrupt", 0x0B),
    ("Table", 0x0C),
    ("Communication", 0x0E),
];

#[test]
fn opcodes_follow_the_family_plan() {
    let set = shipped();
    for ins in &set.instructions {
        let high = FAMILIES
            .iter()
            .find(|(name, _)| *name == ins.family)
            .map(|(_, high)| *high)
            .unwrap_or_else(|| panic!("{} has unknown family `{}`", ins.mnemonic, ins.family));
        assert_eq!(
            ins.opcode >> 8,
            high,
            "{} (0x{:04X}) is not in family {} (0x{high:02X}xx)",
            ins.mnemonic,
            ins.opcode,
            ins.family
        );
        assert_ne!(
            ins.opcode & 0xFF,
            0xFF,
            "{}: low byte 0xFF is reserved",
            ins.mnemonic
        );
    }
    for (mnemonic, opcode) in [
        ("LD", 0x0101),
        ("LDI", 0x0109),
        ("LDW>=", 0x020D),
        ("OR=", 0x0258),
        ("TON", 0x0301),
        ("MOVB", 0x0701),
        ("EXCH", 0x0E01),
        ("FND>", 0x0C14),
    ] {
        assert_eq!(get(&set, mnemonic).opcode, opcode, "opcode of {mnemonic}");
    }
}

#[test]
fn every_data_and_literal_operand_has_types() {
    let set = shipped();
    for ins in &set.instructions {
        for op in &ins.operands {
            if matches!(op.kind, OperandKind::Data | OperandKind::Literal) {
                assert!(
                    !op.types.is_empty(),
                    "{} {} has no types",
                    ins.mnemonic,
                    op.name
                );
            }
        }
    }
}

#[test]
fn every_instruction_is_documented() {
    let set = shipped();
    for ins in &set.instructions {
        assert!(!ins.summary.is_empty(), "{} has no Summary", ins.mnemonic);
        assert!(
            !ins.description.is_empty(),
            "{} has no Description",
            ins.mnemonic
        );
        assert!(!ins.example.is_empty(), "{} has no Example", ins.mnemonic);
        assert!(
            ins.description.contains("Flags:"),
            "{}: the description must say which flags it sets",
            ins.mnemonic
        );
    }
}

#[test]
fn examples_use_only_known_mnemonics() {
    let set = shipped();
    for ins in &set.instructions {
        let mut uses_itself = false;
        for line in ins.example.lines() {
            let code = line.split("//").next().unwrap_or("").trim();
            let Some(word) = code.split_whitespace().next() else {
                continue;
            };
            assert!(
                set.lookup(word).is_some(),
                "example of {} uses unknown mnemonic `{word}`",
                ins.mnemonic
            );
            uses_itself |= word.eq_ignore_ascii_case(&ins.mnemonic);
        }
        assert!(
            uses_itself,
            "the example of {} does not use it",
            ins.mnemonic
        );
    }
}

const AREAS: &[&str] = &[
    "I", "Q", "AI", "AQ", "M", "V", "T", "C", "HC", "SM", "J", "K", "L",
];

#[test]
fn operand_areas_are_known_area_names() {
    let set = shipped();
    for ins in &set.instructions {
        for op in &ins.operands {
            for area in op.areas.iter().flatten() {
                assert!(
                    AREAS.contains(&area.as_str()),
                    "{} {} names unknown area `{area}`",
                    ins.mnemonic,
                    op.name
                );
            }
        }
    }
}

#[test]
fn immediate_instructions_are_limited_to_physical_io() {
    let set = shipped();
    for m in ["LDI", "LDNI", "AI", "ANI", "OI", "ONI"] {
        let op = &get(&set, m).operands[0];
        assert_eq!(op.areas, Some(vec!["I".to_string()]), "{m}");
        assert_eq!(op.role, Role::In, "{m}");
    }
    for m in ["=I", "SI", "RI"] {
        let op = &get(&set, m).operands[0];
        assert_eq!(op.areas, Some(vec!["Q".to_string()]), "{m}");
        assert_eq!(op.role, Role::Out, "{m}");
    }
}

#[test]
fn timers_and_counters_have_the_decided_stack_effects() {
    let set = shipped();
    for (m, needs, delta, area) in [
        ("TON", 1, 0, "T"),
        ("TOF", 1, 0, "T"),
        ("TONR", 1, 0, "T"),
        ("CTU", 2, -1, "C"),
        ("CTD", 2, -1, "C"),
        ("CTUD", 3, -2, "C"),
    ] {
        let ins = get(&set, m);
        assert_eq!((ins.stack_needs, ins.stack_delta), (needs, delta), "{m}");
        assert_eq!(ins.flow, Flow::Stack, "{m} runs on every execution");
        let op = &ins.operands[0];
        assert_eq!(op.types, vec![DataType::Int], "{m}");
        assert_eq!(op.areas, Some(vec![area.to_string()]), "{m}");
        assert_eq!(op.role, Role::InOut, "{m}");
        assert!(!op.pointer && !op.constant, "{m}");
    }
    for (m, needs, delta) in [
        ("ALD", 2, -1),
        ("OLD", 2, -1),
        ("LPS", 1, 1),
        ("LRD", 2, 0),
        ("LPP", 2, -1),
        ("LDS", 1, 1),
        ("NOT", 1, 0),
        ("EU", 1, 0),
        ("ED", 1, 0),
    ] {
        let ins = get(&set, m);
        assert_eq!(ins.flow, Flow::Stack, "{m}");
        assert_eq!((ins.stack_needs, ins.stack_delta), (needs, delta), "{m}");
    }
    let lds = &get(&set, "LDS").operands[0];
    assert_eq!(
        (lds.kind, lds.min, lds.max),
        (OperandKind::Literal, Some(0), Some(8))
    );
}

#[test]
fn flows_follow_the_decisions() {
    let set = shipped();
    for m in ["LBL", "NEXT", "RET", "RETI", "ENI", "DISI", "NOP"] {
        assert_eq!(get(&set, m).flow, Flow::Always, "{m}");
    }
    for m in [
        "MOVW", "+I", "JMP", "CALL", "CRET", "END", "STOP", "WDR", "FOR", "ATCH", "DTCH", "CRETI",
        "EXCH", "ATT", "FND=", "SHRB",
    ] {
        assert_eq!(get(&set, m).flow, Flow::Box, "{m}");
    }
    assert!(get(&set, "CALL").call_arguments);
    assert_eq!(
        set.instructions.iter().filter(|i| i.call_arguments).count(),
        1,
        "only CALL takes arguments"
    );
}

#[test]
fn operand_defaults_follow_the_decisions() {
    let set = shipped();
    for ins in &set.instructions {
        for op in &ins.operands {
            if op.address_of {
                assert_eq!(
                    (ins.mnemonic.as_str(), op.name.as_str()),
                    ("MOVD", "IN"),
                    "only MOVD IN takes an address"
                );
            }
            if op.types.first() == Some(&DataType::Bool) {
                assert!(!op.constant && !op.pointer, "{} {}", ins.mnemonic, op.name);
            }
            if op.role != Role::In {
                assert!(!op.constant, "{} {} is written", ins.mnemonic, op.name);
            }
        }
    }
    let exch = get(&set, "EXCH");
    let tbl = &exch.operands[0];
    assert_eq!(tbl.types, vec![DataType::Byte]);
    assert_eq!(tbl.areas, Some(vec!["M".to_string()]));
    assert!(!tbl.constant && !tbl.pointer);
    let port = &exch.operands[1];
    assert_eq!(
        (port.kind, port.min, port.max),
        (OperandKind::Literal, Some(0), Some(1))
    );
}

#[test]
fn operand_order_is_s7_200_stl() {
    let set = shipped();
    let names = |m: &str| -> Vec<String> {
        get(&set, m)
            .operands
            .iter()
            .map(|o| o.name.clone())
            .collect()
    };
    for (m, expected) in [
        ("+I", vec!["IN1", "OUT"]),
        ("INCW", vec!["OUT"]),
        ("SRW", vec!["OUT", "N"]),
        ("BCDI", vec!["OUT"]),
        ("MUL", vec!["IN1", "OUT"]),
        ("DIV", vec!["IN1", "OUT"]),
        ("BMW", vec!["IN", "OUT", "N"]),
        ("FILL", vec!["IN", "OUT", "N"]),
        ("SHRB", vec!["DATA", "S_BIT", "N"]),
        ("ATT", vec!["DATA", "TBL"]),
        ("FIFO", vec!["TBL", "DATA"]),
        ("FND=", vec!["TBL", "PTN", "INDX"]),
        ("FOR", vec!["INDX", "INIT", "FINAL"]),
        ("ATCH", vec!["INT", "EVNT"]),
        ("DTCH", vec!["EVNT"]),
        ("LDS", vec!["N"]),
        ("S", vec!["BIT", "N"]),
        ("TON", vec!["T", "PT"]),
        ("CTU", vec!["C", "PV"]),
        ("EXCH", vec!["TBL", "PORT"]),
    ] {
        assert_eq!(names(m), expected, "operands of {m}");
    }
    assert_eq!(get(&set, "+I").operands[1].role, Role::InOut);
    assert_eq!(types(get(&set, "MUL"), 1), vec![DataType::Dint]);
    assert_eq!(types(get(&set, "DIV"), 1), vec![DataType::Dint]);
}
