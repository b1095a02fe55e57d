//! The Modbus view of every stdlib target: round trips between addresses and Modbus
//! objects, the edges of the served ranges, and the load-time checks of mappings.

use gutta_catalog::{stdlib, Address, CatalogErrorCode, MemoryMap, ModbusCell, ModbusTable, Width};

fn maps() -> Vec<(&'static str, MemoryMap)> {
    stdlib::TARGETS
        .iter()
        .map(|(name, _, var)| {
            let map = MemoryMap::parse(var).unwrap_or_else(|e| panic!("{name}: {e}"));
            (*name, map)
        })
        .collect()
}

fn ec20() -> MemoryMap {
    maps().swap_remove(0).1
}

#[test]
fn constants_and_locals_have_no_modbus_address() {
    for (name, map) in maps() {
        for text in ["KB0", "LW0", "LD28", "L0.0", "K0.0"] {
            let address = map.parse_address(text).expect("address parses");
            assert_eq!(map.modbus_location(&address), None, "{name} {text}");
        }
    }
    let map = ec20();
    let past_m = Address {
        slot: map.area("M").expect("M").slot,
        width: Width::Word,
        offset: 127,
        bit: 0,
    };
    assert_eq!(map.modbus_location(&past_m), None);
    let no_slot = Address {
        slot: 15,
        width: Width::Byte,
        offset: 0,
        bit: 0,
    };
    assert_eq!(map.modbus_location(&no_slot), None);
}

#[test]
fn wire_addresses_reach_memory_and_stop_past_the_areas() {
    let map = ec20();
    let m = map.area("M").expect("M").slot;
    assert_eq!(
        map.modbus_cell(ModbusTable::HoldingRegister, 23),
        Some(ModbusCell {
            slot: m,
            offset: 30,
            bit: None
        })
    );
    let cell = map.modbus_cell(ModbusTable::Coil, 24).expect("served");
    assert_eq!(map.format_address(&cell.address()), "Q3.0");
    let cell = map
        .modbus_cell(ModbusTable::DiscreteInput, 4)
        .expect("served");
    assert_eq!(map.format_address(&cell.address()), "I0.4");
    let cell = map
        .modbus_cell(ModbusTable::HoldingRegister, 18)
        .expect("served");
    assert_eq!(map.format_address(&cell.address()), "MW20");
    assert_eq!(map.modbus_cell(ModbusTable::Coil, 64), None);
    assert_eq!(map.modbus_cell(ModbusTable::DiscreteInput, 64), None);
    assert_eq!(map.modbus_cell(ModbusTable::InputRegister, 8), None);
    assert_eq!(map.modbus_cell(ModbusTable::HoldingRegister, 112), None);
    assert_eq!(
        map.modbus_cell(ModbusTable::HoldingRegister, u16::MAX),
        None
    );
    let j15 = map
        .modbus_cell(ModbusTable::HoldingRegister, 111)
        .expect("last J register");
    assert_eq!(j15.slot, map.area("J").expect("J").slot);
    assert_eq!(j15.offset, 14);
}

#[test]
fn ranges_merge_adjacent_areas() {
    let map = ec20();
    assert_eq!(map.modbus_ranges(ModbusTable::HoldingRegister), [0..=111]);
    assert_eq!(map.modbus_ranges(ModbusTable::Coil), [0..=63]);
    assert_eq!(map.modbus_ranges(ModbusTable::DiscreteInput), [0..=63]);
    assert_eq!(map.modbus_ranges(ModbusTable::InputRegister), [0..=7]);
    // The capture of AN2002: read inputs 100005..100008, holding 400009..400012.
    assert!(map.modbus_serves(ModbusTable::DiscreteInput, 4, 4));
    assert!(map.modbus_serves(ModbusTable::HoldingRegister, 8, 4));
    assert!(map.modbus_serves(ModbusTable::HoldingRegister, 0, 112));
    assert!(!map.modbus_serves(ModbusTable::HoldingRegister, 0, 113));
    assert!(!map.modbus_serves(ModbusTable::HoldingRegister, 100, 13));
    assert!(!map.modbus_serves(ModbusTable::HoldingRegister, 0, 0));
    assert!(!map.modbus_serves(ModbusTable::Coil, u16::MAX, u16::MAX));
    // Every target's holding registers are one run from 400001 to the end of J.
    for (name, map) in maps() {
        let ranges = map.modbus_ranges(ModbusTable::HoldingRegister);
        let j = map
            .modbus_spans()
            .into_iter()
            .find(|s| Some(s.slot) == map.area("J").map(|a| a.slot))
            .expect("J span");
        assert_eq!(ranges, [0..=j.last_wire], "{name}");
    }
}

#[test]
fn every_object_round_trips() {
    for (name, map) in maps() {
        for span in map.modbus_spans() {
            for wire in span.first_wire..=span.last_wire {
                let cell = map.modbus_cell(span.table, wire).expect("served");
                assert_eq!(cell.slot, span.slot, "{name}");
                let loc = map
                    .modbus_location(&cell.address())
                    .expect("cell is mapped");
                assert_eq!(loc.table, span.table);
                assert_eq!(loc.pieces.len(), 1, "{name} {}", loc.variable);
                assert_eq!(loc.pieces[0].wire, wire);
                assert!(loc.pieces[0].is_whole(span.table));
            }
            let past = span.last_wire.checked_add(1);
            if let Some(past) = past {
                let next = map.modbus_cell(span.table, past);
                assert!(next.is_none_or(|c| c.slot != span.slot), "{name}");
            }
        }
    }
}

#[test]
fn every_byte_and_bit_round_trips() {
    for (name, map) in maps() {
        for area in map.areas.iter().filter(|a| a.modbus.is_some()) {
            for offset in 0..area.size {
                let byte = Address {
                    slot: area.slot,
                    width: Width::Byte,
                    offset,
                    bit: 0,
                };
                let loc = map.modbus_location(&byte).expect("mapped");
                let bits: u32 = loc.pieces.iter().map(|p| p.bit_count()).sum();
                assert_eq!(bits, 8, "{name} {}", loc.variable);
                for p in &loc.pieces {
                    let cell = map.modbus_cell(loc.table, p.wire).expect("served");
                    assert_eq!(cell.slot, area.slot);
                    match cell.bit {
                        Some(bit) => assert_eq!((cell.offset, bit), (offset, p.value_bit)),
                        None => {
                            assert_eq!(cell.offset, offset & !1);
                            assert_eq!(p.first_bit, (offset % 2) as u8 * 8);
                        }
                    }
                }
                for bit in 0..8 {
                    let address = Address {
                        width: Width::Bit,
                        bit,
                        ..byte
                    };
                    let loc = map.modbus_location(&address).expect("mapped");
                    assert_eq!(loc.pieces.len(), 1);
                    let p = loc.pieces[0];
                    let cell = map.modbus_cell(loc.table, p.wire).expect("served");
                    match cell.bit {
                        Some(b) => assert_eq!((cell.offset, b), (offset, bit)),
                        None => assert_eq!(p.first_bit, (offset % 2) as u8 * 8 + bit),
                    }
                }
            }
        }
    }
}

#[test]
fn dwords_take_two_registers_low_word_first() {
    let map = ec20();
    let md2 = map.parse_address("MD2").expect("MD2");
    let loc = map.modbus_location(&md2).expect("mapped");
    let got: Vec<(u32, u8, u8, u8)> = loc
        .pieces
        .iter()
        .map(|p| (p.reference, p.first_bit, p.last_bit, p.value_bit))
        .collect();
    assert_eq!(got, [(400010, 0, 15, 0), (400011, 0, 15, 16)]);
    let md1 = map.parse_address("MD1").expect("MD1");
    let loc = map.modbus_location(&md1).expect("mapped");
    assert_eq!(
        loc.to_string(),
        "MD1: holding registers 400009 bits 8..15, 400010, 400011 bits 0..7 (wire addresses 8..10)"
    );
    let id0 = map.parse_address("ID0").expect("ID0");
    assert_eq!(
        map.modbus_location(&id0).expect("mapped").to_string(),
        "ID0: discrete inputs 100001..100032 (wire addresses 0..31)"
    );
}

fn custom(m_start: &str, m_size: &str) -> String {
    format!(
        r#"<ManagerVar>
  <Area Name="AQ" Slot="3" Kind="AnalogOutput" Size="16" Unit="BYTE" Access="BYTE WORD" Modbus="HoldingRegister" ModbusStart="400001"/>
  <Area Name="M" Slot="4" Kind="Memory" Size="{m_size}" Unit="BYTE" Access="BYTE" Modbus="HoldingRegister" ModbusStart="{m_start}"/>
  <Area Name="T" Slot="5" Kind="Timer" Size="4" Unit="WORD" Access="WORD"/>
  <Area Name="C" Slot="6" Kind="Counter" Size="4" Unit="WORD" Access="WORD"/>
  <Area Name="K" Slot="9" Kind="Constant" Size="4" Unit="BYTE" Access="BYTE"/>
  <Area Name="L" Slot="10" Kind="Local" Size="4" Unit="BYTE" Access="BYTE"/>
  <Timers><Resolution First="0" Last="1" Milliseconds="100"/></Timers>
</ManagerVar>"#
    )
}

#[test]
fn overlapping_odd_and_oversized_mappings_are_rejected() {
    let parse = |start: &str, size: &str| MemoryMap::parse(custom(start, size).as_bytes());
    let gap = parse("400020", "16").expect("a gap between areas is fine");
    assert_eq!(
        gap.modbus_ranges(ModbusTable::HoldingRegister),
        [0..=7, 19..=26]
    );
    assert!(!gap.modbus_serves(ModbusTable::HoldingRegister, 0, 9));
    let code = |start: &str, size: &str| parse(start, size).map(|_| ()).map_err(|e| e.code);
    assert_eq!(code("400009", "16"), Ok(()));
    assert_eq!(code("400008", "16"), Err(CatalogErrorCode::Duplicate));
    assert_eq!(code("400009", "15"), Err(CatalogErrorCode::Value));
    assert_eq!(code("465530", "16"), Err(CatalogErrorCode::Value));
    assert_eq!(code("465529", "16"), Ok(()));
}
