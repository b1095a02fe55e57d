//! What an instruction is, as data (docs/instruction-schema.md, "What an instruction
//! is"): the shipped set gives every timer and counter its kind and pins and every
//! instruction its ladder element, and the parser refuses values it does not know.

use gutta_catalog::{
    stdlib, CatalogErrorCode, CompareOp, DataType, Flow, InstructionSet, Join, LadderClass,
    LoopRole, TimerCounterKind,
};

const MANAGER_FUN: &str = include_str!("../../stdlib/ManagerFun.xml");

fn shipped() -> InstructionSet {
    InstructionSet::parse(MANAGER_FUN.as_bytes()).expect("stdlib/ManagerFun.xml loads")
}

/// The shipped file with one piece of text replaced (which must be there).
fn edited(from: &str, to: &str) -> Result<InstructionSet, gutta_catalog::CatalogError> {
    assert!(MANAGER_FUN.contains(from), "`{from}` is not in the file");
    InstructionSet::parse(MANAGER_FUN.replacen(from, to, 1).as_bytes())
}

#[test]
fn one_instruction_defines_labels_and_its_operand_is_a_label() {
    let set = shipped();
    let definers: Vec<&str> = set
        .instructions
        .iter()
        .filter(|i| i.defines_label)
        .map(|i| i.mnemonic.as_str())
        .collect();
    assert_eq!(definers, ["LBL"]);
    let lbl = set.get(set.label_definition().expect("a label definition"));
    assert!(
        matches!(lbl.operands.as_slice(), [o] if o.kind == gutta_catalog::OperandKind::Label),
        "{:?}",
        lbl.operands
    );
}

#[test]
fn every_timer_and_counter_has_its_kind_and_pins() {
    let set = shipped();
    // The decisions, as Micro/WIN draws the boxes: power inputs in STL load order,
    // then the number and the preset as operands.
    let expected = [
        (TimerCounterKind::OnDelay, "TON", &["IN"][..], "T", "PT"),
        (TimerCounterKind::OffDelay, "TOF", &["IN"], "T", "PT"),
        (
            TimerCounterKind::RetentiveOnDelay,
            "TONR",
            &["IN"],
            "T",
            "PT",
        ),
        (TimerCounterKind::CountUp, "CTU", &["CU", "R"], "C", "PV"),
        (TimerCounterKind::CountDown, "CTD", &["CD", "LD"], "C", "PV"),
        (
            TimerCounterKind::CountUpDown,
            "CTUD",
            &["CU", "CD", "R"],
            "C",
            "PV",
        ),
    ];
    assert_eq!(TimerCounterKind::all().count(), expected.len());
    for (kind, keyword, inputs, number, preset) in expected {
        assert_eq!(kind.keyword(), keyword);
        let id = set.by_kind(kind).unwrap_or_else(|| panic!("no {keyword}"));
        let ins = set.get(id);
        assert_eq!(
            ins.mnemonic, keyword,
            "the {keyword} box is the {keyword} instruction"
        );
        assert_eq!(ins.power_inputs, inputs, "{keyword}");
        assert_eq!(ins.power_output.as_deref(), Some("Q"), "{keyword}");
        assert_eq!(ins.ladder, LadderClass::Box, "{keyword}");
        let names: Vec<&str> = ins.operands.iter().map(|o| o.name.as_str()).collect();
        assert_eq!(names, [number, preset], "{keyword}");
        assert_eq!(kind.is_timer(), number == "T", "{keyword}");
    }
    // Every instruction that drives a timer or counter number has a kind, one per kind,
    // and reads one power input per logic stack level.
    let mut seen = Vec::new();
    for ins in &set.instructions {
        let drives = ins.operands.first().is_some_and(|o| {
            matches!(o.areas.as_deref(), Some([a]) if a == "T" || a == "C") && o.role.writes()
        });
        assert_eq!(drives, ins.kind.is_some(), "{}", ins.mnemonic);
        if let Some(kind) = ins.kind {
            assert!(!seen.contains(&kind), "{} repeats a kind", ins.mnemonic);
            seen.push(kind);
            assert_eq!(ins.power_inputs.len(), usize::from(ins.stack_needs));
        }
    }
}

#[test]
fn every_instruction_has_a_ladder_element_that_fits_its_flow() {
    let set = shipped();
    for ins in &set.instructions {
        let m = &ins.mnemonic;
        match ins.flow {
            Flow::Load | Flow::Combine => {
                assert!(ins.ladder.is_contact(), "{m}");
                assert!(ins.join().is_some(), "{m}");
            }
            Flow::Output => assert!(ins.ladder.is_coil(), "{m}"),
            Flow::Stack if ins.kind.is_none() => assert!(ins.ladder.is_stack(), "{m}"),
            _ => {
                assert_eq!(ins.ladder, LadderClass::Box, "{m}");
                assert_eq!(
                    ins.power_inputs.len(),
                    if ins.kind.is_some() {
                        ins.stack_needs.into()
                    } else {
                        1
                    },
                    "{m}"
                );
            }
        }
        assert_eq!(ins.compare.is_some(), ins.family == "Compare", "{m}");
        if ins.immediate {
            // The immediate forms reach only the physical I/O.
            let area = ins.operands[0].areas.clone().unwrap_or_default();
            assert!(area == ["I"] || area == ["Q"], "{m}");
        }
    }
    // The stack operations are one instruction each.
    for class in LadderClass::all().filter(|c| c.is_stack()) {
        let count = set
            .instructions
            .iter()
            .filter(|i| i.ladder == class)
            .count();
        assert_eq!(count, 1, "{}", class.keyword());
    }
    // Boxes that end the power path have no output.
    let ending: Vec<&str> = set
        .instructions
        .iter()
        .filter(|i| i.flow == Flow::Box && i.power_output.is_none())
        .map(|i| i.mnemonic.as_str())
        .collect();
    assert_eq!(ending, ["JMP", "CRET", "END", "STOP", "FOR", "CRETI"]);
}

#[test]
fn contacts_and_compares_are_found_by_what_they_are() {
    let set = shipped();
    let name = |id| set.get(id).mnemonic.as_str();
    let find = |join, op, ty| set.compare(join, op, ty).map(name);
    assert_eq!(
        find(Join::Load, CompareOp::Ge, DataType::Int),
        Some("LDW>=")
    );
    assert_eq!(find(Join::And, CompareOp::Lt, DataType::Int), Some("AW<"));
    assert_eq!(find(Join::Or, CompareOp::Ne, DataType::Real), Some("OR<>"));
    assert_eq!(find(Join::Or, CompareOp::Eq, DataType::Byte), Some("OB="));
    // 3 forms x 4 types x 6 relations, each found once.
    let mut count = 0;
    for join in [Join::Load, Join::And, Join::Or] {
        for ty in [
            DataType::Byte,
            DataType::Int,
            DataType::Dint,
            DataType::Real,
        ] {
            for op in CompareOp::all() {
                let id = set.compare(join, op, ty).expect("every compare exists");
                assert_eq!(set.get(id).compare, Some(op));
                count += 1;
            }
        }
    }
    assert_eq!(
        count,
        set.instructions
            .iter()
            .filter(|i| i.compare.is_some())
            .count()
    );
    let plain = |class, join| set.plain(class, join).map(name);
    assert_eq!(plain(LadderClass::Contact, Some(Join::Load)), Some("LD"));
    assert_eq!(
        plain(LadderClass::ClosedContact, Some(Join::Or)),
        Some("ON")
    );
    assert_eq!(plain(LadderClass::ResetCoil, None), Some("R"));
    assert_eq!(plain(LadderClass::Pop, None), Some("LPP"));
    // Every contact has its three STL forms, and they lead back to it.
    let forms = |m: &str| {
        let id = set.lookup(m).expect(m);
        [Join::Load, Join::And, Join::Or].map(|j| set.with_join(id, j).map(name))
    };
    assert_eq!(forms("LDNI"), [Some("LDNI"), Some("ANI"), Some("ONI")]);
    assert_eq!(forms("A"), [Some("LD"), Some("A"), Some("O")]);
    assert_eq!(forms("OW>="), [Some("LDW>="), Some("AW>="), Some("OW>=")]);
    assert_eq!(forms("MOVW"), [None, None, None]);
    for (i, ins) in set.instructions.iter().enumerate() {
        let id = gutta_catalog::InstrId(i as u16);
        if let Some(join) = ins.join() {
            for other in [Join::Load, Join::And, Join::Or] {
                let there = set.with_join(id, other).expect("every form exists");
                assert_eq!(set.with_join(there, join), Some(id), "{}", ins.mnemonic);
            }
        }
    }
    assert_eq!(set.by_loop_role(LoopRole::Start).map(name), Some("FOR"));
    assert_eq!(set.by_loop_role(LoopRole::End).map(name), Some("NEXT"));
}

#[test]
fn timer_resolutions_come_from_the_targets_timers() {
    let target = stdlib::default_target().expect("stdlib");
    // CPU-EC20: T0-T1 1 ms, T2-T3 10 ms, T4-T15 100 ms.
    let ton = TimerCounterKind::OnDelay;
    assert_eq!(target.timer_resolution(ton, 0), Some(1));
    assert_eq!(target.timer_resolution(ton, 3), Some(10));
    assert_eq!(
        target.timer_resolution(TimerCounterKind::RetentiveOnDelay, 4),
        Some(100)
    );
    assert_eq!(target.timer_resolution(TimerCounterKind::CountUp, 4), None);
    for n in 0..1000 {
        assert_eq!(
            target.timer_resolution(TimerCounterKind::OffDelay, n),
            target.memory.timer_resolution(n)
        );
    }
}

#[test]
fn an_unknown_kind_is_a_clear_catalog_error() {
    let e = edited(r#"Kind="TON""#, r#"Kind="TIMER""#).expect_err("TIMER is no kind");
    assert_eq!(e.code, CatalogErrorCode::Value);
    assert!(
        e.message.contains("unknown Kind `TIMER` of TON")
            && e.message.contains("TON, TOF, TONR, CTU, CTD, CTUD"),
        "{}",
        e.message
    );
}

#[test]
fn what_an_instruction_is_is_checked_at_load() {
    let cases = [
        // An unknown ladder element.
        (
            r#"Ladder="ClosedContact" Logic="Or" Immediate="true""#,
            r#"Ladder="Switch" Logic="Or" Immediate="true""#,
            CatalogErrorCode::Value,
            "unknown Ladder `Switch` of ONI",
        ),
        // A contact without its element.
        (
            r#"Flow="Load" Ladder="Contact""#,
            r#"Flow="Load""#,
            CatalogErrorCode::Syntax,
            "LD: Flow=\"Load\" needs a Ladder attribute",
        ),
        // A coil drawn as a contact.
        (
            r#"Flow="Output" Ladder="Coil""#,
            r#"Flow="Output" Ladder="Contact""#,
            CatalogErrorCode::Value,
            "Ladder=\"Contact\" of = does not fit Flow=\"Output\"",
        ),
        // A Combine that does not say how it joins.
        (
            r#"Ladder="Contact" Logic="And""#,
            r#"Ladder="Contact""#,
            CatalogErrorCode::Syntax,
            "A: Logic goes with Flow=\"Combine\"",
        ),
        // A counter whose pins do not match the levels it reads.
        (
            r#"PowerInputs="CU R""#,
            r#"PowerInputs="CU""#,
            CatalogErrorCode::Value,
            "CTU is a timer or counter",
        ),
        // A kind on an instruction that is not a Stack box.
        (
            r#"Flow="Box" PowerOutput="" Loop="Start""#,
            r#"Flow="Box" PowerOutput="" Loop="Start" Kind="TON""#,
            CatalogErrorCode::Syntax,
            "FOR: Kind goes with Flow=\"Stack\"",
        ),
        // A compare without its relation.
        (
            r#"Ladder="Compare" Compare="Eq""#,
            r#"Ladder="Compare""#,
            CatalogErrorCode::Syntax,
            "Compare goes with Ladder=\"Compare\"",
        ),
        (
            r#"Loop="End""#,
            r#"Loop="Finish""#,
            CatalogErrorCode::Value,
            "unknown Loop `Finish` of NEXT",
        ),
    ];
    for (from, to, code, message) in cases {
        let e = edited(from, to).expect_err(to);
        assert_eq!(e.code, code, "{to}: {}", e.message);
        assert!(e.message.contains(message), "{to}: {}", e.message);
    }
}
