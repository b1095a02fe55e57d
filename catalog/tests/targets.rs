//! The six stdlib targets against a table transcribed by hand from GUTTA.md section 2
//! (IN1001): slots, names, sizes, permissions and Modbus ranges; plus encodings,
//! target-specific addresses and the decided timer and SM layout; and the check that
//! docs/targets.md is the page generated from the targets.

#![allow(
    clippy::disallowed_methods,
    clippy::disallowed_types,
    reason = "tests read and write their data files"
)]

use std::path::PathBuf;

use gutta_catalog::docs::target_reference;
use gutta_catalog::{
    stdlib, AddressError, AreaKind, MemoryMap, ModbusTable, Target, TargetSources, Width,
};

/// One area of one PLC type: name, slot, size in bytes, Modbus first and last
/// reference (None: K and L, not on Modbus).
struct AreaRow(&'static str, u8, u32, Option<(u32, u32)>);

struct TypeRow {
    name: &'static str,
    information: &'static str,
    /// Last timer, counter and high-speed counter number (`T0-15` gives 15).
    last_timer: u32,
    last_counter: u32,
    last_hc: Option<u32>,
    serial_ports: u8,
    areas: &'static [AreaRow],
}

const TYPES: &[TypeRow] = &[
    TypeRow {
        name: "CPU-EC20",
        information: "CPU-EC20 (8051, Compile)",
        last_timer: 15,
        last_counter: 7,
        last_hc: None,
        serial_ports: 1,
        areas: &[
            AreaRow("I", 0, 8, Some((100001, 100064))),
            AreaRow("Q", 1, 8, Some((1, 64))),
            AreaRow("AI", 2, 16, Some((300001, 300008))),
            AreaRow("AQ", 3, 16, Some((400001, 400008))),
            AreaRow("M", 4, 128, Some((400009, 400072))),
            AreaRow("T", 5, 32, Some((400073, 400088))),
            AreaRow("C", 6, 16, Some((400089, 400096))),
            AreaRow("SM", 7, 16, Some((400097, 400104))),
            AreaRow("J", 8, 16, Some((400105, 400112))),
            AreaRow("K", 9, 128, None),
            AreaRow("L", 10, 32, None),
        ],
    },
    TypeRow {
        name: "CPU-EC20-AVR",
        information: "CPU-EC20 (AVR, Compile)",
        last_timer: 31,
        last_counter: 15,
        last_hc: None,
        serial_ports: 2,
        areas: &[
            AreaRow("I", 0, 16, Some((100001, 100128))),
            AreaRow("Q", 1, 16, Some((1, 128))),
            AreaRow("AI", 2, 16, Some((300001, 300008))),
            AreaRow("AQ", 3, 16, Some((400001, 400008))),
            AreaRow("M", 4, 512, Some((400009, 400264))),
            AreaRow("T", 5, 64, Some((400265, 400296))),
            AreaRow("C", 6, 32, Some((400297, 400312))),
            AreaRow("SM", 7, 32, Some((400313, 400328))),
            AreaRow("J", 8, 16, Some((400329, 400336))),
            AreaRow("K", 9, 256, None),
            AreaRow("L", 10, 32, None),
        ],
    },
    TypeRow {
        name: "CPU-EC20-M3",
        information: "CPU-EC20 (Cortex-M3, Compile)",
        last_timer: 63,
        last_counter: 31,
        last_hc: None,
        serial_ports: 2,
        areas: &[
            AreaRow("I", 0, 16, Some((100001, 100128))),
            AreaRow("Q", 1, 16, Some((1, 128))),
            AreaRow("AI", 2, 16, Some((300001, 300008))),
            AreaRow("AQ", 3, 16, Some((400001, 400008))),
            AreaRow("M", 4, 3072, Some((400009, 401544))),
            AreaRow("T", 5, 128, Some((401545, 401608))),
            AreaRow("C", 6, 64, Some((401609, 401640))),
            AreaRow("SM", 7, 256, Some((401641, 401768))),
            AreaRow("J", 8, 32, Some((401769, 401784))),
            AreaRow("K", 9, 256, None),
            AreaRow("L", 10, 32, None),
        ],
    },
    TypeRow {
        name: "EC30-EK51",
        information: "EC30-EK51",
        last_timer: 31,
        last_counter: 7,
        last_hc: None,
        serial_ports: 2,
        areas: &[
            AreaRow("I", 0, 8, Some((100001, 100064))),
            AreaRow("Q", 1, 8, Some((1, 64))),
            AreaRow("AI", 2, 24, Some((300001, 300012))),
            AreaRow("AQ", 3, 24, Some((400001, 400012))),
            AreaRow("M", 4, 256, Some((400013, 400140))),
            AreaRow("T", 5, 64, Some((400141, 400172))),
            AreaRow("C", 6, 16, Some((400173, 400180))),
            AreaRow("SM", 7, 16, Some((400181, 400188))),
            AreaRow("J", 8, 16, Some((400189, 400196))),
            AreaRow("K", 9, 256, None),
            AreaRow("L", 10, 32, None),
        ],
    },
    TypeRow {
        name: "EC30-EKSTM32",
        information: "EC30-EKSTM32",
        last_timer: 127,
        last_counter: 63,
        last_hc: Some(3),
        serial_ports: 2,
        areas: &[
            AreaRow("I", 0, 32, Some((100001, 100256))),
            AreaRow("Q", 1, 32, Some((1, 256))),
            AreaRow("AI", 2, 256, Some((300001, 300128))),
            AreaRow("AQ", 3, 256, Some((400001, 400128))),
            AreaRow("M", 4, 3072, Some((400129, 401664))),
            AreaRow("T", 5, 256, Some((401665, 401792))),
            AreaRow("C", 6, 128, Some((401793, 401856))),
            AreaRow("HC", 7, 16, Some((401857, 401864))),
            AreaRow("SM", 8, 256, Some((401865, 401992))),
            AreaRow("J", 9, 16, Some((401993, 402000))),
            AreaRow("K", 10, 512, None),
            AreaRow("L", 11, 32, None),
        ],
    },
    TypeRow {
        name: "EC30-EKSTM32-XC",
        information: "EC30-EKSTM32-XC",
        last_timer: 127,
        last_counter: 63,
        last_hc: Some(3),
        serial_ports: 2,
        areas: &[
            AreaRow("I", 0, 32, Some((100001, 100256))),
            AreaRow("Q", 1, 32, Some((1, 256))),
            AreaRow("AI", 2, 256, Some((300001, 300128))),
            AreaRow("AQ", 3, 256, Some((400001, 400128))),
            AreaRow("M", 4, 3072, Some((400129, 401664))),
            AreaRow("V", 5, 8192, Some((401665, 405760))),
            AreaRow("T", 6, 256, Some((405761, 405888))),
            AreaRow("C", 7, 128, Some((405889, 405952))),
            AreaRow("HC", 8, 16, Some((405953, 405960))),
            AreaRow("SM", 9, 256, Some((405961, 406088))),
            AreaRow("J", 10, 16, Some((406089, 406096))),
            AreaRow("K", 11, 512, None),
            AreaRow("L", 12, 32, None),
        ],
    },
];

/// What every area of a name is, on every type (the slot tables of IN1001): kind,
/// offset unit, widths (bit/byte/word/dword columns), & column, * column, writable
/// by programs, Modbus table.
struct AreaProps {
    name: &'static str,
    kind: AreaKind,
    unit: Width,
    widths: &'static [Width],
    address_of: bool,
    pointer: bool,
    writable: bool,
    table: Option<ModbusTable>,
}

const ALL: &[Width] = &[Width::Bit, Width::Byte, Width::Word, Width::Dword];
const NO_BIT: &[Width] = &[Width::Byte, Width::Word, Width::Dword];

#[rustfmt::skip]
const PROPS: &[AreaProps] = &[
    AreaProps { name: "I",  kind: AreaKind::DigitalInput,     unit: Width::Byte,  widths: ALL,             address_of: false, pointer: false, writable: false, table: Some(ModbusTable::DiscreteInput) },
    AreaProps { name: "Q",  kind: AreaKind::DigitalOutput,    unit: Width::Byte,  widths: ALL,             address_of: false, pointer: false, writable: true,  table: Some(ModbusTable::Coil) },
    AreaProps { name: "AI", kind: AreaKind::AnalogInput,      unit: Width::Byte,  widths: NO_BIT,          address_of: false, pointer: false, writable: false, table: Some(ModbusTable::InputRegister) },
    AreaProps { name: "AQ", kind: AreaKind::AnalogOutput,     unit: Width::Byte,  widths: NO_BIT,          address_of: false, pointer: false, writable: true,  table: Some(ModbusTable::HoldingRegister) },
    AreaProps { name: "M",  kind: AreaKind::Memory,           unit: Width::Byte,  widths: ALL,             address_of: true,  pointer: true,  writable: true,  table: Some(ModbusTable::HoldingRegister) },
    AreaProps { name: "V",  kind: AreaKind::Memory,           unit: Width::Byte,  widths: ALL,             address_of: true,  pointer: true,  writable: true,  table: Some(ModbusTable::HoldingRegister) },
    AreaProps { name: "T",  kind: AreaKind::Timer,            unit: Width::Word,  widths: &[Width::Word],  address_of: false, pointer: false, writable: true,  table: Some(ModbusTable::HoldingRegister) },
    AreaProps { name: "C",  kind: AreaKind::Counter,          unit: Width::Word,  widths: &[Width::Word],  address_of: false, pointer: false, writable: true,  table: Some(ModbusTable::HoldingRegister) },
    AreaProps { name: "HC", kind: AreaKind::HighSpeedCounter, unit: Width::Dword, widths: &[Width::Dword], address_of: false, pointer: false, writable: true,  table: Some(ModbusTable::HoldingRegister) },
    AreaProps { name: "SM", kind: AreaKind::System,           unit: Width::Byte,  widths: ALL,             address_of: true,  pointer: false, writable: true,  table: Some(ModbusTable::HoldingRegister) },
    AreaProps { name: "J",  kind: AreaKind::Flow,             unit: Width::Byte,  widths: &[Width::Byte],  address_of: false, pointer: false, writable: true,  table: Some(ModbusTable::HoldingRegister) },
    AreaProps { name: "K",  kind: AreaKind::Constant,         unit: Width::Byte,  widths: ALL,             address_of: false, pointer: false, writable: false, table: None },
    AreaProps { name: "L",  kind: AreaKind::Local,            unit: Width::Byte,  widths: ALL,             address_of: true,  pointer: true,  writable: true,  table: None },
];

fn load_all() -> Vec<Target> {
    stdlib::names()
        .map(|n| stdlib::load(n).unwrap_or_else(|e| panic!("{n}: {e}")))
        .collect()
}

fn memory(name: &str) -> MemoryMap {
    stdlib::load(name)
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .memory
}

#[test]
fn targets_doc_is_generated_from_the_stdlib_targets() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../docs/targets.md");
    let generated = target_reference(&load_all());
    if std::env::var_os("UPDATE_DOCS").is_some_and(|v| v == "1") {
        std::fs::write(&path, &generated).expect("write docs/targets.md");
        return;
    }
    let on_disk = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        on_disk == generated,
        "docs/targets.md is not the page generated from stdlib/targets/; \
         regenerate it with `UPDATE_DOCS=1 cargo test -p gutta-catalog --test targets` \
         and commit the result"
    );
}

#[test]
fn stdlib_lists_the_six_types_default_first() {
    let names: Vec<&str> = stdlib::names().collect();
    let expected: Vec<&str> = TYPES.iter().map(|t| t.name).collect();
    assert_eq!(names, expected);
    assert_eq!(names[0], stdlib::DEFAULT);
}

#[test]
fn every_target_matches_the_in1001_table() {
    for (target, row) in load_all().iter().zip(TYPES) {
        let t = row.name;
        assert_eq!(target.name(), t);
        assert_eq!(target.plc.information, row.information, "{t}");
        let m = &target.memory;
        assert_eq!(m.plc_type.as_deref(), Some(t));
        let got: Vec<(&str, u8)> = m.areas.iter().map(|a| (a.name.as_str(), a.slot)).collect();
        let want: Vec<(&str, u8)> = row.areas.iter().map(|a| (a.0, a.1)).collect();
        assert_eq!(got, want, "{t}: names and slots");
        let spans = m.modbus_spans();
        for AreaRow(name, slot, size, modbus) in row.areas {
            let area = m.area(name).unwrap_or_else(|| panic!("{t}: no {name}"));
            assert_eq!(area.size, *size, "{t} {name} size");
            let props = PROPS.iter().find(|p| p.name == *name).expect("props");
            assert_eq!(area.kind, props.kind, "{t} {name} kind");
            assert_eq!(area.unit, props.unit, "{t} {name} unit");
            let widths: Vec<Width> = area.widths.iter().copied().collect();
            assert_eq!(widths, props.widths, "{t} {name} widths");
            assert_eq!(area.address_of, props.address_of, "{t} {name} &");
            assert_eq!(area.holds_pointer, props.pointer, "{t} {name} *");
            assert_eq!(area.writable, props.writable, "{t} {name} writable");
            assert_eq!(
                area.modbus.map(|mb| mb.table),
                props.table,
                "{t} {name} table"
            );
            let span = spans.iter().find(|s| s.slot == *slot);
            let got = span.map(|s| (s.first_reference(), s.last_reference()));
            assert_eq!(got, *modbus, "{t} {name} Modbus range");
            assert_eq!(
                area.modbus.map(|mb| mb.start),
                modbus.map(|r| r.0),
                "{t} {name} ModbusStart"
            );
        }
        let count = |kind| m.area_of_kind(kind).map(|a| a.unit_count());
        assert_eq!(count(AreaKind::Timer), Some(row.last_timer + 1), "{t} T");
        assert_eq!(
            count(AreaKind::Counter),
            Some(row.last_counter + 1),
            "{t} C"
        );
        assert_eq!(
            count(AreaKind::HighSpeedCounter),
            row.last_hc.map(|n| n + 1),
            "{t} HC"
        );
        assert_eq!(m.serial_ports, row.serial_ports, "{t} serial ports");
        assert_eq!(m.counter_max, 32767, "{t}");
        let forced: Vec<&str> = m
            .forcing
            .iter()
            .filter_map(|s| m.area_by_slot(*s))
            .map(|a| a.name.as_str())
            .collect();
        assert_eq!(forced, ["I", "Q"], "{t} forcing");
    }
}

#[test]
fn plc_limits_fit_the_memory() {
    let ec20 = &load_all()[0].plc;
    assert_eq!(
        (
            ec20.system_block_binary_size,
            ec20.data_block_page_size,
            ec20.data_block_page_item_size,
            ec20.program_block_page_int_size,
            ec20.program_block_page_sbr_size,
            ec20.program_block_page_arg_int_size,
            ec20.program_block_page_arg_sbr_size,
            ec20.program_block_const_binary_size,
            ec20.program_block_instruction_binary_size,
            ec20.exch_pack_size,
        ),
        (50, 16, 16, 8, 8, 32, 32, 128, 10752, 64)
    );
    assert!(ec20.exch_support.supports(0x0A10));
    for target in load_all() {
        let (p, m) = (&target.plc, &target.memory);
        let k = m.area_of_kind(AreaKind::Constant).expect("K").size;
        let l = m.area_of_kind(AreaKind::Local).expect("L").size;
        assert_eq!(p.program_block_const_binary_size, k, "{}", p.name);
        assert!(p.program_block_page_arg_sbr_size <= l, "{}", p.name);
        assert!(p.program_block_page_arg_int_size <= l, "{}", p.name);
        assert!(
            p.program_block_instruction_binary_size >= 10752,
            "{}",
            p.name
        );
        assert!((64..1024).contains(&p.exch_pack_size), "{}", p.name);
        assert!(p.name.chars().count() <= 16);
        assert_eq!(p.exch_support.rules, [(0, 0)], "{}", p.name);
    }
}

fn utf16(text: &[u8], big_endian: bool) -> Vec<u8> {
    let text = std::str::from_utf8(text).expect("stdlib files are UTF-8");
    let mut out = if big_endian {
        vec![0xFE, 0xFF]
    } else {
        vec![0xFF, 0xFE]
    };
    for unit in text.encode_utf16() {
        out.extend(if big_endian {
            unit.to_be_bytes()
        } else {
            unit.to_le_bytes()
        });
    }
    out
}

#[test]
fn utf16_files_give_the_same_target() {
    for (name, plc, var) in stdlib::TARGETS {
        let utf8 = stdlib::load(name).expect("loads");
        for big_endian in [false, true] {
            let (plc, var, fun) = (
                utf16(plc, big_endian),
                utf16(var, big_endian),
                utf16(stdlib::MANAGER_FUN, big_endian),
            );
            let t = Target::load(TargetSources {
                plc_type: &plc,
                manager_var: &var,
                manager_fun: &fun,
            })
            .unwrap_or_else(|e| panic!("{name} UTF-16 (big endian: {big_endian}): {e}"));
            assert_eq!(t.plc, utf8.plc, "{name}");
            assert_eq!(t.memory, utf8.memory, "{name}");
            assert_eq!(t.instructions, utf8.instructions, "{name}");
        }
    }
}

#[test]
fn area_specific_addresses_parse_only_where_the_area_exists() {
    for row in TYPES {
        let m = memory(row.name);
        let vb100 = m.parse_address("VB100");
        if row.name == "EC30-EKSTM32-XC" {
            assert_eq!(m.format_address(&vb100.expect("VB100")), "VB100");
        } else {
            assert!(
                matches!(&vb100, Err(AddressError::UnknownArea { prefix }) if prefix == "V"),
                "{}: {vb100:?}",
                row.name
            );
        }
        let hc = m.parse_address("HC1");
        if row.name.starts_with("EC30-EKSTM32") {
            let hc = hc.expect("HC1");
            assert_eq!(
                (hc.width, hc.offset),
                (Width::Dword, 4),
                "HC1 is bytes 4..7"
            );
            assert!(m.parse_address("HC0").is_ok());
            assert!(m.parse_address("HC4").is_err());
            assert!(m.parse_address("HCD0").is_err());
        } else {
            assert!(hc.is_err(), "{}", row.name);
            assert!(m.parse_address("HC0").is_err(), "{}", row.name);
        }
    }
    assert!(matches!(
        memory("CPU-EC20").parse_address("MB200"),
        Err(AddressError::OutOfRange { .. })
    ));
    assert!(memory("CPU-EC20-AVR").parse_address("MB200").is_ok());
}

#[test]
fn timers_have_the_decided_resolutions() {
    for target in load_all() {
        let m = &target.memory;
        let n = m.area_of_kind(AreaKind::Timer).expect("T").unit_count();
        assert_eq!(m.timer_resolution(0), Some(1), "{}", target.name());
        assert_eq!(m.timer_resolution(1), Some(1));
        assert_eq!(m.timer_resolution(2), Some(10));
        assert_eq!(m.timer_resolution(3), Some(10));
        assert_eq!(m.timer_resolution(4), Some(100), "{}", target.name());
        assert_eq!(m.timer_resolution(n - 1), Some(100));
        assert_eq!(m.timer_resolution(n), None);
    }
}

#[test]
fn system_memory_and_events_follow_the_decided_layout() {
    let bits = [
        ("SM0.0", "ALWAYS_ON"),
        ("SM0.1", "FIRST_SCAN"),
        ("SM0.2", "RETENTIVE_LOST"),
        ("SM0.3", "POWER_UP"),
        ("SM0.4", "CLOCK_60S"),
        ("SM0.5", "CLOCK_1S"),
        ("SM0.6", "SCAN_CLOCK"),
        ("SM1.0", "ZERO"),
        ("SM1.1", "OVERFLOW"),
        ("SM1.2", "NEGATIVE"),
        ("SM1.3", "DIV_ZERO"),
        ("SM1.4", "TABLE_FULL"),
        ("SM1.5", "TABLE_EMPTY"),
        ("SM1.6", "BCD_ERROR"),
        ("SMB2", "ERROR_CODE"),
        ("SMW4", "SCAN_TIME"),
        ("SMW6", "SCAN_TIME_MIN"),
        ("SMW8", "SCAN_TIME_MAX"),
        ("SMB10", "TIMED0_PERIOD"),
        ("SMB11", "TIMED1_PERIOD"),
    ];
    for target in load_all() {
        let m = &target.memory;
        let t = target.name();
        let sm = m.area_of_kind(AreaKind::System).expect("SM");
        assert!(sm.size >= 16, "{t}");
        for (address, name) in bits {
            let bit = m.system_bits.iter().find(|b| b.name == name);
            assert_eq!(bit.map(|b| b.address.as_str()), Some(address), "{t} {name}");
        }
        let mut names = std::collections::BTreeSet::new();
        for bit in &m.system_bits {
            let a = m.parse_address(&bit.address).expect("system bit parses");
            assert_eq!(a.slot, sm.slot, "{t} {}", bit.address);
            assert!(a.offset < 16, "{t} {}", bit.address);
            assert!(names.insert(bit.name.as_str()), "{t}: {} twice", bit.name);
        }
        let events: Vec<(u32, &str, Option<&str>)> = m
            .events
            .iter()
            .map(|e| (e.number, e.kind.as_str(), e.period.as_deref()))
            .collect();
        let mut want = Vec::new();
        for n in 0..4 {
            want.push((2 * n, "RisingEdge", None));
            want.push((2 * n + 1, "FallingEdge", None));
        }
        want.push((10, "Timed", Some("SMB10")));
        want.push((11, "Timed", Some("SMB11")));
        assert_eq!(events, want, "{t}");
    }
}

#[test]
fn modbus_worked_checks_hold_on_the_default_target() {
    let m = memory("CPU-EC20");
    let show = |text: &str| {
        let a = m.parse_address(text).expect("parses");
        m.modbus_location(&a).map(|l| l.to_string())
    };
    assert_eq!(
        show("MB31").as_deref(),
        Some("MB31: holding register 400024 bits 8..15 (wire address 23)")
    );
    assert_eq!(
        show("MW20").as_deref(),
        Some("MW20: holding register 400019 (wire address 18)")
    );
    assert_eq!(
        show("Q3.0").as_deref(),
        Some("Q3.0: coil 000025 (wire address 24)")
    );
    assert_eq!(
        show("I0.4").as_deref(),
        Some("I0.4: discrete input 100005 (wire address 4)")
    );
    assert_eq!(show("KB0"), None);
    // HC1 on EC30-EKSTM32 is bytes 4..7 of HC: registers 401859..401860.
    let m = memory("EC30-EKSTM32");
    let hc1 = m.parse_address("HC1").expect("HC1");
    let refs: Vec<u32> = m
        .modbus_location(&hc1)
        .expect("HC is on Modbus")
        .pieces
        .iter()
        .map(|p| p.reference)
        .collect();
    assert_eq!(refs, [401859, 401860]);
}
