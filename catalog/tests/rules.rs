//! The shared rules (`gutta_catalog::rules`) on the stdlib targets: each rule the
//! checker and the verifier both apply, tested once here, at its home.

use gutta_catalog::rules::{
    self, address_of_target, check_literal, label_range, literal_range, placement_allowed,
    pointer_holder, unit_exists, unit_operand_accepts, AreaRule, DataRules, IndirectRefusal,
    LiteralRefusal,
};
use gutta_catalog::{stdlib, BlockKind, DataType, OperandSpec, Role, Target, Width};

fn target(name: &str) -> Target {
    stdlib::load(name).expect("stdlib target")
}

fn operand<'a>(t: &'a Target, mnemonic: &str, index: usize) -> &'a OperandSpec {
    let id = t.instructions.lookup(mnemonic).expect("mnemonic");
    &t.instructions.get(id).operands[index]
}

fn renamed(spec: &OperandSpec, name: &str) -> OperandSpec {
    OperandSpec {
        name: name.to_string(),
        ..spec.clone()
    }
}

#[test]
fn port_is_narrowed_to_the_serial_ports_of_the_target() {
    let one = target("CPU-EC20");
    let two = target("CPU-EC20-M3");
    let port = operand(&one, "EXCH", 1);
    assert_eq!(literal_range(port, &one.memory), 0..=0);
    assert_eq!(literal_range(port, &two.memory), 0..=1);
    assert_eq!(
        check_literal(port, &one.memory, 1),
        Err(LiteralRefusal::OutOfRange { min: 0, max: 0 })
    );
    assert_eq!(check_literal(port, &two.memory, 1), Ok(()));
}

#[test]
fn literal_names_compare_case_insensitively() {
    let t = target("CPU-EC20");
    let port = renamed(operand(&t, "EXCH", 1), "port");
    assert_eq!(literal_range(&port, &t.memory), 0..=0);
    let evnt = renamed(operand(&t, "ATCH", 1), "Evnt");
    assert_eq!(
        check_literal(&evnt, &t.memory, 9),
        Err(LiteralRefusal::NoSuchEvent)
    );
}

#[test]
fn evnt_is_one_of_the_events_of_the_target() {
    let t = target("CPU-EC20");
    let evnt = operand(&t, "ATCH", 1);
    for event in &t.memory.events {
        assert_eq!(
            check_literal(evnt, &t.memory, i64::from(event.number)),
            Ok(())
        );
    }
    // 9 is inside EVNT's Min..Max but no event; 300 is outside both: events first.
    assert_eq!(
        check_literal(evnt, &t.memory, 9),
        Err(LiteralRefusal::NoSuchEvent)
    );
    assert_eq!(
        check_literal(evnt, &t.memory, 300),
        Err(LiteralRefusal::NoSuchEvent)
    );
}

#[test]
fn other_literals_take_their_min_max() {
    let t = target("CPU-EC20");
    let n = operand(&t, "LDS", 0);
    assert_eq!(literal_range(n, &t.memory), 0..=8);
    assert_eq!(
        check_literal(n, &t.memory, 9),
        Err(LiteralRefusal::OutOfRange { min: 0, max: 8 })
    );
    assert!(check_literal(n, &t.memory, -1).is_err());
}

#[test]
fn labels_are_0_to_255_whatever_the_spec_says() {
    let t = target("CPU-EC20");
    assert_eq!(label_range(operand(&t, "LBL", 0)), 0..=255);
    let wide = OperandSpec {
        min: Some(-5),
        max: Some(1000),
        ..operand(&t, "JMP", 0).clone()
    };
    assert_eq!(label_range(&wide), 0..=255);
}

#[test]
fn unit_numbers_follow_the_plc_type_limits() {
    for name in stdlib::names() {
        let t = target(name);
        let (ints, attr) = rules::unit_limit(&t.plc, BlockKind::Interrupt);
        assert_eq!(
            (ints, attr),
            (t.plc.program_block_page_int_size, "ProgramBlockPageIntSize")
        );
        let (sbrs, _) = rules::unit_limit(&t.plc, BlockKind::Subroutine);
        assert!(unit_exists(&t.plc, BlockKind::Interrupt, 0), "{name}: MAIN");
        assert!(unit_exists(&t.plc, BlockKind::Interrupt, ints - 1));
        assert!(!unit_exists(&t.plc, BlockKind::Interrupt, ints));
        assert!(unit_exists(&t.plc, BlockKind::Subroutine, sbrs - 1));
        assert!(!unit_exists(&t.plc, BlockKind::Subroutine, sbrs));
    }
}

#[test]
fn unit_operands_name_their_kind_and_never_main() {
    let t = target("CPU-EC20");
    let call = operand(&t, "CALL", 0);
    let atch = operand(&t, "ATCH", 0);
    assert!(unit_operand_accepts(call, BlockKind::Subroutine, 0));
    assert!(!unit_operand_accepts(call, BlockKind::Interrupt, 1));
    assert!(unit_operand_accepts(atch, BlockKind::Interrupt, 1));
    assert!(!unit_operand_accepts(atch, BlockKind::Interrupt, 0));
    assert!(!unit_operand_accepts(atch, BlockKind::Subroutine, 1));
}

#[test]
fn placement_follows_units_of_manager_fun() {
    let t = target("CPU-EC20");
    let scope = |m: &str| {
        let id = t.instructions.lookup(m).expect("mnemonic");
        t.instructions.get(id).units
    };
    let (main, int1, sbr0) = (
        (BlockKind::Interrupt, 0),
        (BlockKind::Interrupt, 1),
        (BlockKind::Subroutine, 0),
    );
    let allowed =
        |m: &str, (kind, number): (BlockKind, u32)| placement_allowed(scope(m), kind, number);
    assert!(allowed("END", main) && !allowed("END", int1) && !allowed("END", sbr0));
    assert!(!allowed("RETI", main) && allowed("RETI", int1) && !allowed("RETI", sbr0));
    assert!(!allowed("RET", main) && !allowed("RET", int1) && allowed("RET", sbr0));
    assert!(allowed("LD", main) && allowed("LD", int1) && allowed("LD", sbr0));
}

#[test]
fn locals_and_parameters() {
    let t = target("CPU-EC20");
    assert_eq!(
        rules::locals_limit(&t.plc, BlockKind::Subroutine),
        (
            t.plc.program_block_page_arg_sbr_size,
            "ProgramBlockPageArgSbrSize"
        )
    );
    assert!(rules::takes_parameters(BlockKind::Subroutine));
    assert!(!rules::takes_parameters(BlockKind::Interrupt));
    let input = rules::parameter_spec("p".into(), Role::In, DataType::Dword);
    assert!(input.constant && input.pointer && input.address_of);
    assert!(DataRules::from_spec(&input).takes_address_of());
    // An output cannot be `&x`: a pointer value is only read.
    let output = rules::parameter_spec("q".into(), Role::Out, DataType::Udint);
    assert!(!output.constant);
    assert!(!DataRules::from_spec(&output).takes_address_of());
    let flag = rules::parameter_spec("b".into(), Role::InOut, DataType::Bool);
    assert!(!flag.pointer && !flag.address_of);
    assert_eq!(rules::access_width(&flag), Width::Bit);
}

#[test]
fn areas_writable_listed_and_constants() {
    let t = target("CPU-EC20");
    let area = |n: &str| t.memory.area(n).expect("area");
    // TON's timer operand lists T only.
    let ton = DataRules::from_spec(operand(&t, "TON", 0));
    assert!(matches!(ton.areas, AreaRule::Listed(_)));
    assert!(ton.accepts_area(area("T")) && !ton.accepts_area(area("M")));
    // A constant may stand where constants are taken, whatever the list: K.
    let constant = DataRules {
        constant: true,
        ..ton
    };
    assert!(constant.accepts_area(area("K")));
    // Written operands need a writable area.
    let movw_out = DataRules::from_spec(operand(&t, "MOVW", 1));
    assert!(movw_out.may_write(area("M")));
    assert!(!movw_out.may_write(area("I")) && !movw_out.may_write(area("K")));
    assert!(DataRules::from_spec(operand(&t, "MOVW", 0)).may_write(area("I")));
    // Data blocks initialise M, Q, AQ, T, C; locals live in L.
    let item = DataRules::data_item(Width::Word);
    assert!(["M", "Q", "AQ", "T", "C"]
        .iter()
        .all(|a| item.accepts_area(area(a))));
    assert!(["I", "AI", "K", "L", "SM"]
        .iter()
        .all(|a| !item.accepts_area(area(a))));
    let local = DataRules::local(Width::Byte);
    assert!(local.accepts_area(area("L")) && !local.accepts_area(area("M")));
}

#[test]
fn address_of_and_pointers_follow_the_area_permissions() {
    let t = target("CPU-EC20");
    let area = |n: &str| t.memory.area(n).expect("area");
    assert_eq!(address_of_target(area("M"), Width::Byte), Ok(()));
    assert_eq!(
        address_of_target(area("M"), Width::Word),
        Err(IndirectRefusal::Width)
    );
    assert_eq!(
        address_of_target(area("Q"), Width::Byte),
        Err(IndirectRefusal::Area)
    );
    assert_eq!(pointer_holder(area("M"), Width::Dword), Ok(()));
    assert_eq!(
        pointer_holder(area("L"), Width::Word),
        Err(IndirectRefusal::Width)
    );
    assert_eq!(
        pointer_holder(area("SM"), Width::Dword),
        Err(IndirectRefusal::Area)
    );
    // MOVD's IN takes `&`; MOVW's and MOVD's OUT do not.
    assert!(DataRules::from_spec(operand(&t, "MOVD", 0)).takes_address_of());
    assert!(!DataRules::from_spec(operand(&t, "MOVD", 1)).takes_address_of());
    assert!(!DataRules::from_spec(operand(&t, "MOVW", 0)).takes_address_of());
}

#[test]
fn locals_pack_bools_and_start_other_types_at_the_next_byte() {
    let mut layout = rules::LocalLayout::new();
    let places: Vec<(u32, u8)> = [
        Width::Bit,
        Width::Bit,
        Width::Word,
        Width::Byte,
        Width::Bit,
        Width::Dword,
    ]
    .into_iter()
    .map(|w| layout.place(w))
    .collect();
    assert_eq!(places, [(0, 0), (0, 1), (1, 0), (3, 0), (4, 0), (5, 0)]);
    // Nine BOOLs fill a byte and start the next.
    let mut layout = rules::LocalLayout::new();
    let last = (0..9).map(|_| layout.place(Width::Bit)).last();
    assert_eq!(last, Some((1, 0)));
    assert_eq!(layout.place(Width::Word), (2, 0));
}

#[test]
fn port_settings_and_passwords() {
    assert!(rules::port::STOP_BITS.contains(&2) && !rules::port::STOP_BITS.contains(&0));
    assert!(!rules::port::TIMEOUT.contains(&0) && rules::port::FRAME_GAP.contains(&255));
    assert_eq!(rules::port::DATA_BITS, 8);
    assert!(rules::password_allowed(b"1234"));
    assert!(rules::password_allowed(b"0123456789ABCDEF"));
    assert!(!rules::password_allowed(b""));
    assert!(!rules::password_allowed(b"0123456789ABCDEFG"));
    assert!(!rules::password_allowed(b"12\x003"));
    assert!(!rules::password_allowed("pässword".as_bytes()));
}

#[test]
fn for_loops_nest_at_most_for_depth_deep() {
    let t = gutta_catalog::stdlib::default_target().expect("the default target loads");
    let max = usize::from(t.instructions.for_depth);
    assert_eq!(max, 8, "ManagerFun.xml's ForDepth");
    assert!(gutta_catalog::rules::for_depth_allowed(
        &t.instructions,
        max
    ));
    assert!(!gutta_catalog::rules::for_depth_allowed(
        &t.instructions,
        max + 1
    ));
}
