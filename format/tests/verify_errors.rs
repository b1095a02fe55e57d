//! One test per `VerifyError` variant: a hand-built image that breaks exactly that
//! rule (a valid program with one change) must fail with its code, at the right page
//! and byte where it has one. `every_code_has_a_test` keeps the list complete.

mod common;

use std::cell::Cell;

use common::*;
use gutta_catalog::{DataType, Target, Width};
use gutta_format::{
    encode_instructions, verify, DataItem, Image, LocalSection, Location, PackedOperand, PageId,
    PageKind, Record, Use, VerifyCode, VerifyError,
};

thread_local! {
    static CHECKED: Cell<usize> = const { Cell::new(0) };
}

/// Verify and expect `code`; the Display starts with the code and names the page.
fn expect(image: &Image, t: &Target, code: VerifyCode) -> VerifyError {
    CHECKED.with(|c| c.set(c.get() + 1));
    let err = match verify(image, t) {
        Ok(_) => panic!("expected {code}, the image verified"),
        Err(e) => e,
    };
    assert_eq!(err.code(), code, "{err}");
    let text = err.to_string();
    assert!(text.starts_with(code.as_str()), "{text}");
    if let Some(page) = err.page() {
        assert!(text.contains(&page.file_name()), "{text}");
    }
    if let Some(at) = err.location() {
        assert!(text.contains(&format!("at byte {}", at.offset)), "{text}");
    }
    err
}

/// Each case gets `$check` (verify and expect the case's code, returning the error)
/// and must call it at least once.
macro_rules! rejects {
    ($($name:ident => $code:ident |$check:ident| $body:block)*) => {
        $(
            #[test]
            fn $name() {
                let $check = |image: &Image, t: &Target| expect(image, t, VerifyCode::$code);
                CHECKED.with(|c| c.set(0));
                $body
                assert!(CHECKED.with(|c| c.get()) > 0, "the case verified nothing");
            }
        )*
        const TESTED: &[VerifyCode] = &[$(VerifyCode::$code),*];
    };
}

#[test]
fn every_code_has_a_test_and_codes_are_unique() {
    for code in VerifyCode::ALL {
        assert!(TESTED.contains(code), "no test for {code:?}");
    }
    let mut seen: Vec<&str> = VerifyCode::ALL.iter().map(|c| c.as_str()).collect();
    seen.sort_unstable();
    seen.dedup();
    assert_eq!(seen.len(), VerifyCode::ALL.len());
    for (i, code) in VerifyCode::ALL.iter().enumerate() {
        assert_eq!(
            code.as_str(),
            format!("V{:04}", i + 1),
            "codes are numbered in order"
        );
        assert!(!code.summary().is_empty());
    }
}

#[test]
fn every_code_is_documented() {
    let doc = include_str!("../../docs/image-format.md");
    let section = doc
        .split("## Verifying an image")
        .nth(1)
        .expect("docs/image-format.md has the section");
    let rows: Vec<&str> = section
        .lines()
        .filter_map(|l| l.strip_prefix("| V"))
        .map(|l| l.get(..4).unwrap_or(""))
        .collect();
    let codes: Vec<&str> = VerifyCode::ALL.iter().map(|c| &c.as_str()[1..]).collect();
    assert_eq!(rows, codes, "one table row per code, in order");
}

fn page(kind: PageKind, number: u8) -> PageId {
    PageId::new(kind, number)
}

fn at(kind: PageKind, number: u8, offset: usize) -> Option<Location> {
    Some(Location {
        page: page(kind, number),
        offset,
    })
}

/// MAIN with one network holding `records`, after `LD SM0.0`.
fn main_with(t: &Target, records: Vec<Record>) -> ImageSpec {
    let mut all = vec![Record::Network(1), ins(t, "LD", vec![val(t, "SM0.0")])];
    all.extend(records);
    ImageSpec::main(t, all)
}

/// Byte offset of operand `i` of the record at index `record` of MAIN (main_with).
fn operand_at(spec: &ImageSpec, record: usize, i: usize) -> usize {
    let records = &spec.units[&0].records;
    records[..record].iter().map(Record::len).sum::<usize>() + 3 + 4 * i
}

fn with_field(op: PackedOperand, mask: u32, value: u32) -> PackedOperand {
    PackedOperand((op.0 & !mask) | value)
}

rejects! {
    plc_type_mismatch => PlcTypeMismatch |check| {
        let t = target();
        let mut spec = full_program(&t);
        spec.plc_type = "CPU-EC20-M3".into();
        let e = check(&spec.build(), &t);
        assert_eq!(e.to_string(), "V0001 manifest.json: the image is for PLC type `CPU-EC20-M3`, the target is `CPU-EC20`");
    }

    page_not_on_target => PageNotOnTarget |check| {
        let t = target();
        let base = full_program(&t).build();
        // Program page 16 = IntSize 8 + SbrSize 8 is past the last unit.
        let mut image = base.clone();
        image.pages.insert(page(PageKind::Argument, 16), vec![1, 8, 0, 0]);
        image.pages.insert(page(PageKind::Instruction, 16), vec![]);
        assert_eq!(check(&image, &t).page(), Some(page(PageKind::Argument, 16)));
        let mut image = base.clone();
        image.pages.insert(page(PageKind::System, 1), vec![]);
        assert_eq!(check(&image, &t).page(), Some(page(PageKind::System, 1)));
        let mut image = base;
        image.pages.insert(page(PageKind::Const, 1), vec![]);
        check(&image, &t);
    }

    missing_const_page => MissingConstPage |check| {
        let t = target();
        let mut image = full_program(&t).build();
        image.pages.remove(&page(PageKind::Const, 0));
        assert_eq!(check(&image, &t), VerifyError::MissingConstPage);
    }

    missing_main => MissingMain |check| {
        let t = target();
        let mut image = full_program(&t).build();
        image.pages.remove(&page(PageKind::Argument, 0));
        image.pages.remove(&page(PageKind::Instruction, 0));
        check(&image, &t);
    }

    unpaired_page => UnpairedPage |check| {
        let t = target();
        let mut image = full_program(&t).build();
        image.pages.remove(&page(PageKind::Instruction, 8));
        let e = check(&image, &t);
        assert_eq!(e, VerifyError::UnpairedPage { page: page(PageKind::Argument, 8), missing: page(PageKind::Instruction, 8) });
        let mut image = full_program(&t).build();
        image.pages.remove(&page(PageKind::Argument, 0));
        check(&image, &t);
    }

    size_limit => SizeLimit |check| {
        let t = target();
        let limit = |e: VerifyError| match e {
            VerifyError::SizeLimit { limit, .. } => limit,
            other => panic!("{other}"),
        };
        // Const page one byte over ProgramBlockConstBinarySize (128 = K).
        let mut spec = full_program(&t);
        spec.consts = vec![0; 129];
        assert_eq!(limit(check(&spec.build(), &t)), "ProgramBlockConstBinarySize");
        // Instructions: 10752 bytes in all.
        let mut image = full_program(&t).build();
        let mut big = vec![0, 0, 1, 0];
        big.extend(std::iter::repeat_n([0x30, 0x01, 0], 3584).flatten()); // NOP x 3584
        image.pages.insert(page(PageKind::Instruction, 1), big);
        assert_eq!(limit(check(&image, &t)), "ProgramBlockInstructionBinarySize");
        // Locals: 32 per subroutine.
        let locals = (0..33).map(|_| local(&t, "LB0", LocalSection::Temp, DataType::Byte)).collect();
        let spec = full_program(&t).unit(&t, true, 3, locals, vec![]);
        assert_eq!(limit(check(&spec.build(), &t)), "ProgramBlockPageArgSbrSize");
        let locals = (0..33).map(|_| local(&t, "LB0", LocalSection::Temp, DataType::Byte)).collect();
        let spec = full_program(&t).unit(&t, false, 3, locals, vec![]);
        assert_eq!(limit(check(&spec.build(), &t)), "ProgramBlockPageArgIntSize");
        // Data items: 16 per page.
        let mut spec = full_program(&t);
        spec.data.insert(1, vec![DataItem { operand: val(&t, "MB0"), value: 0 }; 17]);
        assert_eq!(limit(check(&spec.build(), &t)), "DataBlockPageItemSize");
        // System page: 50 bytes.
        let mut image = full_program(&t).build();
        image.pages.insert(page(PageKind::System, 0), vec![1; 51]);
        assert_eq!(limit(check(&image, &t)), "SystemBlockBinarySize");
        // The const page also fits K when K is the smaller limit.
        let mut small_k = (*t).clone();
        small_k.memory.areas.iter_mut().filter(|a| a.name == "K").for_each(|a| a.size = 8);
        let spec = full_program(&small_k);
        let mut bigger = spec.clone();
        bigger.consts = vec![0; 9];
        assert_eq!(limit(check(&bigger.build(), &small_k)), "the size of K");
    }

    decode => Decode |check| {
        let t = target();
        let mut image = full_program(&t).build();
        image.pages.insert(page(PageKind::Instruction, 1), vec![0, 0, 1, 0, 0x01, 0x01]);
        assert_eq!(check(&image, &t).location(), at(PageKind::Instruction, 1, 4));
        let mut image = full_program(&t).build();
        image.pages.insert(page(PageKind::Data, 0), vec![0; 9]);
        check(&image, &t);
        let mut image = full_program(&t).build();
        image.pages.insert(page(PageKind::Argument, 1), vec![0, 1, 1, 0]);
        check(&image, &t);
    }

    unit_header => UnitHeader |check| {
        let t = target();
        let mut spec = full_program(&t);
        spec.units.get_mut(&8).expect("SBR0").arguments.unit_number = 1;
        assert_eq!(check(&spec.build(), &t).location(), at(PageKind::Argument, 8, 1));
        let mut spec = full_program(&t);
        spec.units.get_mut(&1).expect("INT1").arguments.subroutine = true;
        assert_eq!(check(&spec.build(), &t).location(), at(PageKind::Argument, 1, 0));
    }

    interrupt_parameter => InterruptParameter |check| {
        let t = target();
        let mut spec = full_program(&t);
        spec.units.get_mut(&1).expect("INT1").arguments.locals[0].section = LocalSection::Input;
        assert_eq!(check(&spec.build(), &t).location(), at(PageKind::Argument, 1, 8));
    }

    local_order => LocalOrder |check| {
        let t = target();
        let mut spec = full_program(&t);
        spec.units.get_mut(&8).expect("SBR0").arguments.locals.swap(0, 3);
        assert_eq!(check(&spec.build(), &t).location(), at(PageKind::Argument, 8, 16));
    }

    loop_depth => LoopDepth |check| {
        // ForDepth FORs may be open at once; one more is refused at that FOR.
        let t = target();
        let max = usize::from(t.instructions.for_depth);
        let for_ = || ins(&t, "FOR", vec![val(&t, "MW0"), val(&t, "MW2"), val(&t, "MW4")]);
        let nest = |depth: usize| {
            let mut records: Vec<Record> = (0..depth).map(|_| for_()).collect();
            records.extend((0..depth).map(|_| ins(&t, "NEXT", vec![])));
            main_with(&t, records).build()
        };
        assert!(verify(&nest(max), &t).is_ok(), "{max} nested loops are allowed");
        let e = check(&nest(max + 1), &t);
        // Each FOR record is 3 + 3 x 4 bytes; the first one is at byte 11.
        assert_eq!(e.location(), at(PageKind::Instruction, 0, 11 + 15 * max));
    }

    overlapping_locals => OverlappingLocals |check| {
        // SBR0's locals: LW0 in, LW2 in/out, LD4 out, L8.0 temp. Moving the output to
        // LD0 makes it share L with both parameters before it (the fuzzer's find: a
        // CALL then depended on the order its parameters were copied in).
        let t = target();
        let mut spec = full_program(&t);
        let sbr0 = &mut spec.units.get_mut(&8).expect("SBR0").arguments.locals;
        sbr0[2].operand = val(&t, "LD0");
        let e = check(&spec.build(), &t);
        assert_eq!(e.location(), at(PageKind::Argument, 8, 4 + 8 * 2));
        assert!(matches!(e, VerifyError::OverlappingLocals { local: 2, other: 0, .. }), "{e}");
        // A BOOL on a bit of a byte local overlaps it; one on its own byte does not.
        let mut spec = full_program(&t);
        spec.units.get_mut(&8).expect("SBR0").arguments.locals[3].operand = val(&t, "L5.1");
        let e = check(&spec.build(), &t);
        assert!(matches!(e, VerifyError::OverlappingLocals { local: 3, other: 2, .. }), "{e}");
        // A long local holding a later, shorter one that is not its neighbour in order.
        let mut spec = full_program(&t);
        let locals = &mut spec.units.get_mut(&8).expect("SBR0").arguments.locals;
        locals[0].operand = val(&t, "LW10");
        locals[1].operand = val(&t, "LW12");
        locals[2].operand = val(&t, "LD8");
        locals[3].operand = val(&t, "L20.0");
        let e = check(&spec.build(), &t);
        assert!(matches!(e, VerifyError::OverlappingLocals { local: 2, other: 0, .. }), "{e}");
    }

    unknown_opcode => UnknownOpcode |check| {
        let t = target();
        let spec = main_with(&t, vec![Record::Instruction { opcode: 0xFFFF, operands: vec![] }]);
        assert_eq!(check(&spec.build(), &t).location(), at(PageKind::Instruction, 0, 11));
    }

    not_in_unit => NotInUnit |check| {
        let t = target();
        check(&main_with(&t, vec![ins(&t, "RET", vec![])]).build(), &t);
        let spec = full_program(&t).unit(&t, true, 1, vec![], vec![Record::Network(1), ins(&t, "END", vec![])]);
        check(&spec.build(), &t);
        let spec = full_program(&t).unit(&t, false, 2, vec![], vec![Record::Network(1), ins(&t, "RET", vec![])]);
        check(&spec.build(), &t);
    }

    operand_count => OperandCount |check| {
        let t = target();
        check(&main_with(&t, vec![ins(&t, "MOVW", vec![val(&t, "MW0")])]).build(), &t);
        check(&main_with(&t, vec![ins(&t, "ENI", vec![lit(0)])]).build(), &t);
        // CALL SBR0 takes 1 + 3 operands.
        let mut spec = full_program(&t);
        let main = &mut spec.units.get_mut(&0).expect("MAIN").records;
        let call = main.iter_mut().find(|r| matches!(r, Record::Instruction { operands, .. } if operands.len() == 4)).expect("the CALL");
        if let Record::Instruction { operands, .. } = call {
            operands.pop();
        }
        let e = check(&spec.build(), &t);
        assert!(matches!(e, VerifyError::OperandCount { expected: 4, found: 3, .. }), "{e}");
    }

    use_not_allowed => UseNotAllowed |check| {
        let t = target();
        // BOOL operands take no pointer.
        check(&main_with(&t, vec![ins(&t, "=", vec![ptr(&t, "MD4", Width::Bit)])]).build(), &t);
        // &MB24 is accepted by MOVD's IN only, not by MOVW.
        check(&main_with(&t, vec![ins(&t, "MOVD", vec![val(&t, "MD0"), addr_of(&t, "MB24")])]).build(), &t);
        // USE 6 does not exist; USE 3 (label) where a variable belongs.
        check(&main_with(&t, vec![ins(&t, "LD", vec![PackedOperand(6)])]).build(), &t);
        check(&main_with(&t, vec![ins(&t, "LD", vec![label(1)])]).build(), &t);
        check(&main_with(&t, vec![ins(&t, "JMP", vec![lit(1)])]).build(), &t);
        check(&main_with(&t, vec![ins(&t, "CALL", vec![lit(0)])]).build(), &t);
        // A data item is a value (USE 0).
        let mut spec = full_program(&t);
        spec.data.insert(1, vec![DataItem { operand: addr_of(&t, "MB0"), value: 0 }]);
        assert_eq!(check(&spec.build(), &t).location(), at(PageKind::Data, 1, 0));
    }

    malformed_operand => MalformedOperand |check| {
        let t = target();
        let spec = main_with(&t, vec![ins(&t, "JMP", vec![with_field(label(3), 0xF0, 0x10)]), ins(&t, "LBL", vec![label(3)])]);
        assert_eq!(check(&spec.build(), &t).location(), at(PageKind::Instruction, 0, operand_at(&spec, 2, 0)));
        check(&main_with(&t, vec![ins(&t, "LDS", vec![with_field(lit(1), 0xF00, 0x100)])]).build(), &t);
        // A unit operand's SLOT is 0 or 1.
        check(&main_with(&t, vec![ins(&t, "CALL", vec![PackedOperand::special(Use::Unit, 2, 0)])]).build(), &t);
        // A data item's WIDTH is 0..3.
        let mut spec = full_program(&t);
        spec.data.insert(1, vec![DataItem { operand: with_field(val(&t, "MB0"), 0xF00, 0x400), value: 0 }]);
        check(&spec.build(), &t);
    }

    value_out_of_range => ValueOutOfRange |check| {
        let t = target();
        check(&main_with(&t, vec![ins(&t, "LDS", vec![lit(9)])]).build(), &t);
        check(&main_with(&t, vec![ins(&t, "LBL", vec![label(256)])]).build(), &t);
        // EXCH's PORT is narrowed to the target's ports: CPU-EC20 has PORT0 only.
        let e = check(&main_with(&t, vec![ins(&t, "EXCH", vec![val(&t, "MB0"), lit(1)])]).build(), &t);
        assert!(matches!(e, VerifyError::ValueOutOfRange { value: 1, min: 0, max: 0, .. }), "{e}");
        let t2 = target_named("CPU-EC20-M3");
        verify(&main_with(&t2, vec![ins(&t2, "EXCH", vec![val(&t2, "MB0"), lit(1)])]).build(), &t2).expect("two ports");
        // Operand names compare case-insensitively (gutta_catalog::rules), as in the
        // checker: a ManagerFun.xml that spells `port` narrows it the same.
        let lower = target_with_manager_fun(|text| text.replace(r#"Name="PORT""#, r#"Name="port""#));
        let e = check(&main_with(&lower, vec![ins(&lower, "EXCH", vec![val(&lower, "MB0"), lit(1)])]).build(), &lower);
        assert!(matches!(e, VerifyError::ValueOutOfRange { value: 1, min: 0, max: 0, .. }), "{e}");
    }

    no_such_area => NoSuchArea |check| {
        let t = target();
        let op = with_field(val(&t, "MW0"), 0xF0, 0xF0);
        let spec = main_with(&t, vec![ins(&t, "MOVW", vec![op, val(&t, "MW2")])]);
        assert_eq!(check(&spec.build(), &t).location(), at(PageKind::Instruction, 0, operand_at(&spec, 2, 0)));
    }

    width_mismatch => WidthMismatch |check| {
        let t = target();
        check(&main_with(&t, vec![ins(&t, "MOVW", vec![val(&t, "MB0"), val(&t, "MW2")])]).build(), &t);
        // *MD4 accessed as a byte where MOVW needs a word.
        check(&main_with(&t, vec![ins(&t, "MOVW", vec![ptr(&t, "MD4", Width::Byte), val(&t, "MW2")])]).build(), &t);
        // &MB24 is a DWORD.
        let bad = with_field(addr_of(&t, "MB24"), 0xF00, 0x100);
        check(&main_with(&t, vec![ins(&t, "MOVD", vec![bad, val(&t, "MD4")])]).build(), &t);
        // A local's WIDTH is its type's.
        let mut spec = full_program(&t);
        spec.units.get_mut(&8).expect("SBR0").arguments.locals[0].data_type = DataType::Dint;
        assert_eq!(check(&spec.build(), &t).location(), at(PageKind::Argument, 8, 4));
    }

    width_not_allowed => WidthNotAllowed |check| {
        let t = target();
        // AI has no bits: a bit operand in slot 2.
        let ai_bit = PackedOperand(0x0000_0020);
        check(&main_with(&t, vec![ins(&t, "LD", vec![ai_bit])]).build(), &t);
        // A data item with a width J lacks (J is BYTE only).
        let mut spec = full_program(&t);
        let jw = PackedOperand(0x0000_0280);
        spec.data.insert(1, vec![DataItem { operand: jw, value: 0 }]);
        check(&spec.build(), &t);
    }

    bit_offset => BitOffset |check| {
        let t = target();
        let m08 = with_field(val(&t, "M0.0"), 0xF000, 0x8000);
        check(&main_with(&t, vec![ins(&t, "LD", vec![m08])]).build(), &t);
        let mb0_bit3 = with_field(val(&t, "MB0"), 0xF000, 0x3000);
        let e = check(&main_with(&t, vec![ins(&t, "MOVB", vec![mb0_bit3, val(&t, "MB1")])]).build(), &t);
        assert!(matches!(e, VerifyError::BitOffset { bit: 3, width: Width::Byte, .. }), "{e}");
        // A pointer access has BIT_OFFSET 0 whatever it reads.
        let md4_bit3 = with_field(ptr(&t, "MD4", Width::Word), 0xF000, 0x3000);
        let e = check(&main_with(&t, vec![ins(&t, "MOVW", vec![md4_bit3, val(&t, "MW8")])]).build(), &t);
        assert!(matches!(e, VerifyError::BitOffset { bit: 3, .. }), "{e}");
    }

    out_of_area => OutOfArea |check| {
        let t = target();
        let mw127 = PackedOperand::memory(gutta_catalog::Address { slot: 4, width: Width::Word, offset: 127, bit: 0 }, Use::Value, Width::Word);
        let e = check(&main_with(&t, vec![ins(&t, "MOVW", vec![val(&t, "MW0"), mw127])]).build(), &t);
        assert!(matches!(e, VerifyError::OutOfArea { offset: 127, bytes: 2, size: 128, .. }), "{e}");
        // The pointer DWORD itself must lie in the area: *MD126.
        let md126 = PackedOperand::memory(gutta_catalog::Address { slot: 4, width: Width::Dword, offset: 126, bit: 0 }, Use::Pointer, Width::Word);
        check(&main_with(&t, vec![ins(&t, "MOVW", vec![val(&t, "MW0"), md126])]).build(), &t);
        // A local outside L (32 bytes).
        let mut spec = full_program(&t);
        spec.units.get_mut(&1).expect("INT1").arguments.locals[0].operand = PackedOperand(0x0020_01A0);
        check(&spec.build(), &t);
    }

    misaligned => Misaligned |check| {
        let t = target();
        // Timers count in words: byte offset 11 is no timer.
        let t_odd = PackedOperand::memory(gutta_catalog::Address { slot: 5, width: Width::Word, offset: 11, bit: 0 }, Use::Value, Width::Word);
        check(&main_with(&t, vec![ins(&t, "TON", vec![t_odd, val(&t, "KW0")])]).build(), &t);
    }

    area_not_allowed => AreaNotAllowed |check| {
        let t = target();
        // =I writes Q only.
        check(&main_with(&t, vec![ins(&t, "=I", vec![val(&t, "M0.0")])]).build(), &t);
        // TON's T is a timer, not a word of M; constants are no timers either.
        check(&main_with(&t, vec![ins(&t, "TON", vec![val(&t, "MW0"), val(&t, "KW0")])]).build(), &t);
        check(&main_with(&t, vec![ins(&t, "TON", vec![val(&t, "KW0"), val(&t, "KW0")])]).build(), &t);
        // Locals live in L.
        let mut spec = full_program(&t);
        spec.units.get_mut(&1).expect("INT1").arguments.locals[0].operand = val(&t, "MB0");
        check(&spec.build(), &t);
        // Data blocks initialise M, Q, AQ, T, C only.
        for bad in ["SMB2", "LB0", "KB0", "IB0"] {
            let mut spec = full_program(&t);
            spec.data.insert(1, vec![DataItem { operand: val(&t, bad), value: 0 }]);
            check(&spec.build(), &t);
        }
    }

    not_pointer_area => NotPointerArea |check| {
        let t = target();
        check(&main_with(&t, vec![ins(&t, "MOVW", vec![val(&t, "MW0"), ptr(&t, "SMD0", Width::Word)])]).build(), &t);
    }

    not_address_of_area => NotAddressOfArea |check| {
        let t = target();
        check(&main_with(&t, vec![ins(&t, "MOVD", vec![addr_of(&t, "QB0"), val(&t, "MD4")])]).build(), &t);
    }

    write_to_read_only => WriteToReadOnly |check| {
        let t = target();
        check(&main_with(&t, vec![ins(&t, "MOVB", vec![val(&t, "MB0"), val(&t, "IB0")])]).build(), &t);
        check(&main_with(&t, vec![ins(&t, "MOVW", vec![val(&t, "MW0"), val(&t, "KW0")])]).build(), &t);
        // A VAR_OUTPUT argument is written back: not into K.
        let mut spec = full_program(&t);
        let main = &mut spec.units.get_mut(&0).expect("MAIN").records;
        for r in main.iter_mut() {
            if let Record::Instruction { operands, .. } = r {
                if operands.len() == 4 {
                    operands[3] = val(&t, "KD4");
                }
            }
        }
        check(&spec.build(), &t);
    }

    block_kind_mismatch => BlockKindMismatch |check| {
        let t = target();
        let full = full_program(&t);
        let with_main = |records: Vec<Record>| {
            let mut spec = full.clone();
            spec.units.get_mut(&0).expect("MAIN").records = [vec![Record::Network(1), ins(&t, "LD", vec![val(&t, "SM0.0")])], records].concat();
            spec.build()
        };
        check(&with_main(vec![ins(&t, "CALL", vec![int(1)])]), &t);
        check(&with_main(vec![ins(&t, "ATCH", vec![sbr(0), lit(10)])]), &t);
        // MAIN is attached to no event.
        check(&with_main(vec![ins(&t, "ATCH", vec![int(0), lit(10)])]), &t);
    }

    no_such_unit => NoSuchUnit |check| {
        let t = target();
        check(&main_with(&t, vec![ins(&t, "CALL", vec![sbr(1)])]).build(), &t);
        check(&main_with(&t, vec![ins(&t, "CALL", vec![sbr(8)])]).build(), &t);
        check(&main_with(&t, vec![ins(&t, "ATCH", vec![int(2), lit(10)])]).build(), &t);
        check(&main_with(&t, vec![ins(&t, "ATCH", vec![int(300), lit(10)])]).build(), &t);
    }

    jump_without_label => JumpWithoutLabel |check| {
        let t = target();
        let spec = main_with(&t, vec![ins(&t, "JMP", vec![label(4)])]);
        assert_eq!(check(&spec.build(), &t).location(), at(PageKind::Instruction, 0, 11));
        // A label of another unit does not count.
        let spec = main_with(&t, vec![ins(&t, "JMP", vec![label(4)])])
            .unit(&t, false, 1, vec![], vec![Record::Network(1), ins(&t, "LBL", vec![label(4)])]);
        check(&spec.build(), &t);
    }

    duplicate_label => DuplicateLabel |check| {
        let t = target();
        let spec = main_with(&t, vec![ins(&t, "LBL", vec![label(4)]), ins(&t, "LBL", vec![label(4)])]);
        let e = check(&spec.build(), &t);
        assert!(matches!(e, VerifyError::DuplicateLabel { label: 4, first: 11, .. }), "{e}");
    }

    unmatched_loop => UnmatchedLoop |check| {
        let t = target();
        let for_ = || ins(&t, "FOR", vec![val(&t, "MW0"), val(&t, "MW2"), val(&t, "MW4")]);
        let next = || ins(&t, "NEXT", vec![]);
        // A FOR never closed: the error is at the FOR (record 2 of MAIN, byte 11).
        let e = check(&main_with(&t, vec![for_()]).build(), &t);
        assert_eq!(e.location(), at(PageKind::Instruction, 0, 11));
        assert!(matches!(&e, VerifyError::UnmatchedLoop { mnemonic, .. } if mnemonic == "FOR"), "{e}");
        // A NEXT with no open FOR.
        let e = check(&main_with(&t, vec![next()]).build(), &t);
        assert!(matches!(&e, VerifyError::UnmatchedLoop { mnemonic, .. } if mnemonic == "NEXT"), "{e}");
        // Nested: the inner NEXT closes the inner FOR, so the outer one stays open.
        let e = check(&main_with(&t, vec![for_(), for_(), next()]).build(), &t);
        assert_eq!(e.location(), at(PageKind::Instruction, 0, 11));
        // A FOR of another unit does not close this page's NEXT.
        let spec = main_with(&t, vec![next()])
            .unit(&t, false, 1, vec![], vec![Record::Network(1), ins(&t, "LD", vec![val(&t, "SM0.0")]), for_()]);
        check(&spec.build(), &t);
    }

    call_cycle => CallCycle |check| {
        let t = target();
        let call = |n| vec![Record::Network(1), ins(&t, "LD", vec![val(&t, "SM0.0")]), ins(&t, "CALL", vec![sbr(n)])];
        let spec = main_with(&t, vec![ins(&t, "CALL", vec![sbr(0)])])
            .unit(&t, true, 0, vec![], call(1))
            .unit(&t, true, 1, vec![], call(0));
        check(&spec.build(), &t);
        let spec = main_with(&t, vec![]).unit(&t, true, 2, vec![], call(2));
        let e = check(&spec.build(), &t);
        assert!(matches!(e, VerifyError::CallCycle { callee: 10, .. }), "{e}");
    }

    call_depth => CallDepth |check| {
        // CPU-EC20-M3 has 64 subroutines; CallDepth is 8. MAIN -> SBR0 -> ... -> SBRn.
        let t = target_named("CPU-EC20-M3");
        let chain = |deepest: u8| {
            let call = |n| vec![Record::Network(1), ins(&t, "LD", vec![val(&t, "SM0.0")]), ins(&t, "CALL", vec![sbr(n)])];
            let mut spec = main_with(&t, vec![ins(&t, "CALL", vec![sbr(0)])]);
            for n in 0..deepest {
                spec = spec.unit(&t, true, n, vec![], call(u16::from(n) + 1));
            }
            spec.unit(&t, true, deepest, vec![], vec![])
        };
        verify(&chain(7).build(), &t).expect("8 nested calls are allowed");
        let e = check(&chain(8).build(), &t);
        assert!(matches!(e, VerifyError::CallDepth { depth: 9, max: 8, .. }), "{e}");
        assert_eq!(e.page(), Some(page(PageKind::Instruction, 0)));
    }

    data_value => DataValue |check| {
        let t = target();
        for (addr, value) in [("MB30", 0x100), ("M40.0", 2), ("MW22", 0x0001_8000), ("MB0", 0xFFFF_FF7F)] {
            let mut spec = full_program(&t);
            spec.data.insert(1, vec![DataItem { operand: val(&t, addr), value }]);
            assert_eq!(check(&spec.build(), &t).location(), at(PageKind::Data, 1, 4));
        }
    }

    system_version => SystemVersion |check| {
        let t = target();
        let mut image = full_program(&t).build();
        image.pages.get_mut(&page(PageKind::System, 0)).expect("system page")[0] = 2;
        assert_eq!(check(&image, &t).location(), at(PageKind::System, 0, 0));
    }

    system_port_count => SystemPortCount |check| {
        let t = target();
        let mut spec = full_program(&t);
        spec.system.as_mut().expect("system").ports.push(port());
        assert_eq!(check(&spec.build(), &t).location(), at(PageKind::System, 0, 1));
    }

    system_value => SystemValue |check| {
        let t = target();
        // (byte, bad value) for each checked setting of port 0.
        for (offset, value) in [(2, 1), (4, 5), (5, 7), (6, 3), (7, 0), (7, 3), (8, 0), (9, 0)] {
            let mut image = full_program(&t).build();
            image.pages.get_mut(&page(PageKind::System, 0)).expect("system page")[offset] = value;
            assert_eq!(check(&image, &t).location(), at(PageKind::System, 0, offset));
        }
    }

    system_password => SystemPassword |check| {
        let t = target();
        for password in [*b"12\x003\0\0\0\0\0\0\0\0\0\0\0\0", [0; 16], [0xFE; 16], *b"\xFF\xFF\xFF\xFF\xFF\xFF\xFF\xFF\xFF\xFF\xFF\xFF\xFF\xFF\xFF\x00"] {
            let mut spec = full_program(&t);
            spec.system.as_mut().expect("system").password = password;
            assert_eq!(check(&spec.build(), &t).location(), at(PageKind::System, 0, 10));
        }
    }

    unknown_event => UnknownEvent |check| {
        let t = target();
        let mut spec = full_program(&t);
        for r in &mut spec.units.get_mut(&0).expect("MAIN").records {
            if let Record::Instruction { operands, .. } = r {
                if operands.first() == Some(&int(1)) {
                    operands[1] = lit(9);
                }
            }
        }
        check(&spec.build(), &t);
        // `evnt` in lower case is an event number all the same.
        let lower = target_with_manager_fun(|text| text.replace(r#"Name="EVNT""#, r#"Name="evnt""#));
        let mut spec = full_program(&lower);
        for r in &mut spec.units.get_mut(&0).expect("MAIN").records {
            if let Record::Instruction { operands, .. } = r {
                if operands.first() == Some(&int(1)) {
                    operands[1] = lit(9);
                }
            }
        }
        let e = check(&spec.build(), &lower);
        assert!(matches!(e, VerifyError::UnknownEvent { event: 9, .. }), "{e}");
    }

    reserved_not_zero => ReservedNotZero |check| {
        let t = target();
        for offset in [3, 10, 19] {
            let mut image = full_program(&t).build();
            image.pages.get_mut(&page(PageKind::Argument, 8)).expect("SBR0")[offset] = 1;
            assert_eq!(check(&image, &t).location(), at(PageKind::Argument, 8, offset));
        }
    }
}

#[test]
fn instruction_record_offsets_are_exact() {
    // A sanity check of the helper the cases above rely on.
    let t = target();
    let spec = main_with(
        &t,
        vec![ins(&t, "MOVW", vec![val(&t, "MW0"), val(&t, "MW2")])],
    );
    let bytes = encode_instructions(&spec.units[&0].records);
    let at = operand_at(&spec, 2, 1);
    assert_eq!(&bytes[at..at + 4], &val(&t, "MW2").to_le_bytes());
}
