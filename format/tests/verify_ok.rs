//! Hand-built images that verify, and what `VerifiedImage` hands the VM.

mod common;

use common::*;
use gutta_catalog::{stdlib, BlockKind};
use gutta_format::{verify, LocalSection, PageKind, Record, UnitRecord};

#[test]
fn full_program_verifies_with_decoded_units() {
    let t = target();
    let spec = full_program(&t);
    let image = spec.build();
    let v = verify(&image, &t).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(v.image(), &image);
    assert_eq!(v.target_name(), "CPU-EC20");
    assert_eq!(v.units().keys().copied().collect::<Vec<_>>(), vec![0, 1, 8]);

    let main = v.main().expect("MAIN");
    assert_eq!(
        (main.kind, main.number, main.page),
        (BlockKind::Interrupt, 0, 0)
    );
    assert!(main.locals.is_empty());
    let records = &spec.units[&0].records;
    assert_eq!(main.records.len(), records.len());
    // Offsets are the encoded byte positions; instruction ids map back to opcodes.
    let mut offset = 0;
    for (got, want) in main.records.iter().zip(records) {
        match (got, want) {
            (UnitRecord::Network { offset: o, number }, Record::Network(n)) => {
                assert_eq!((*o, *number), (offset, *n));
            }
            (
                UnitRecord::Instruction {
                    offset: o,
                    id,
                    operands,
                },
                Record::Instruction {
                    opcode,
                    operands: want_ops,
                },
            ) => {
                assert_eq!(*o, offset);
                assert_eq!(t.instructions.get(*id).opcode, *opcode);
                assert_eq!(operands, want_ops);
            }
            other => panic!("record kinds differ: {other:?}"),
        }
        offset += want.len();
    }
    // LBL 3 is the last record of MAIN.
    assert_eq!(main.labels.get(&3), Some(&(main.records.len() - 1)));

    let sbr0 = v.unit(8).expect("SBR0");
    assert_eq!((sbr0.kind, sbr0.number), (BlockKind::Subroutine, 0));
    assert_eq!(sbr0.locals.len(), 4);
    assert_eq!(sbr0.parameters().count(), 3);
    assert_eq!(sbr0.locals[3].section, LocalSection::Temp);

    let int1 = v.unit(1).expect("INT1");
    assert_eq!((int1.kind, int1.number), (BlockKind::Interrupt, 1));

    assert_eq!(v.constants(), spec.consts.as_slice());
    assert_eq!(v.data().get(&0), spec.data.get(&0));
    assert_eq!(v.system(), spec.system.as_ref());
    assert_eq!(v.clone().into_image(), image);

    // Taking the units drops the pages they came from; the rest stays readable.
    let mut taken = v.clone();
    assert_eq!(taken.take_units(), *v.units());
    assert!(taken.units().is_empty());
    let kinds: Vec<PageKind> = taken.image().pages.keys().map(|id| id.kind).collect();
    assert!(!kinds.contains(&PageKind::Instruction), "{kinds:?}");
    assert!(!kinds.contains(&PageKind::Argument), "{kinds:?}");
    assert!(image.pages.keys().any(|id| id.kind == PageKind::Argument));
    assert_eq!(taken.constants(), spec.consts.as_slice());
    assert_eq!(taken.data(), v.data());
    assert_eq!(taken.system(), v.system());
}

#[test]
fn minimal_image_verifies_on_every_stdlib_target() {
    for name in stdlib::names() {
        let t = target_named(name);
        let spec = ImageSpec::main(
            &t,
            vec![
                Record::Network(1),
                ins(&t, "LD", vec![val(&t, "SM0.0")]),
                ins(&t, "=", vec![val(&t, "Q0.0")]),
            ],
        );
        let mut spec = spec;
        spec.system = Some(system(&t));
        verify(&spec.build(), &t).unwrap_or_else(|e| panic!("{name}: {e}"));
    }
}

#[test]
fn full_program_verifies_on_every_stdlib_target() {
    for name in stdlib::names() {
        let t = target_named(name);
        verify(&full_program(&t).build(), &t).unwrap_or_else(|e| panic!("{name}: {e}"));
    }
}

#[test]
fn empty_main_and_empty_const_page_verify() {
    let t = target();
    let image = ImageSpec::main(&t, Vec::new()).build();
    assert_eq!(image.page(PageKind::Const, 0), Some(&[][..]));
    let v = verify(&image, &t).unwrap_or_else(|e| panic!("{e}"));
    assert!(v.main().is_some_and(|m| m.records.is_empty()));
    assert!(v.data().is_empty());
    assert!(v.system().is_none());
}

#[test]
fn factory_password_and_limits_at_their_edges_verify() {
    let t = target();
    let mut spec = ImageSpec::main(&t, Vec::new());
    let mut sys = system(&t);
    sys.password = [0xFF; 16];
    spec.system = Some(sys);
    // The const page exactly as large as allowed, data pages up to the last number.
    spec.consts = vec![0; t.plc.program_block_const_binary_size as usize];
    let last = t.plc.data_block_page_size as u8 - 1;
    spec.data.insert(last, Vec::new());
    // The last subroutine page number, and the most locals a subroutine may have.
    let sbr_last = t.plc.program_block_page_sbr_size as u8 - 1;
    let locals = (0..t.plc.program_block_page_arg_sbr_size)
        .map(|i| {
            local(
                &t,
                &format!("LB{i}"),
                LocalSection::Temp,
                gutta_catalog::DataType::Byte,
            )
        })
        .collect();
    let spec = spec.unit(&t, true, sbr_last, locals, Vec::new());
    verify(&spec.build(), &t).unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn for_next_pairs_are_handed_to_the_vm() {
    // MAIN: Network, LD, FOR(2), FOR(3), NEXT(4), NEXT(5), FOR(6), NEXT(7): each NEXT
    // closes the innermost open FOR.
    let t = target();
    let for_ = || {
        ins(
            &t,
            "FOR",
            vec![val(&t, "MW0"), val(&t, "MW2"), val(&t, "MW4")],
        )
    };
    let next = || ins(&t, "NEXT", vec![]);
    let records = vec![
        Record::Network(1),
        ins(&t, "LD", vec![val(&t, "SM0.0")]),
        for_(),
        for_(),
        next(),
        next(),
        for_(),
        next(),
    ];
    let image = common::ImageSpec::main(&t, records).build();
    let v = verify(&image, &t).unwrap_or_else(|e| panic!("{e}"));
    let main = v.main().expect("MAIN");
    let pairs: Vec<(usize, usize)> = main.loops.iter().map(|(f, n)| (*f, *n)).collect();
    assert_eq!(pairs, vec![(2, 5), (3, 4), (6, 7)]);
}
