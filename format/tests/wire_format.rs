//! Pins the byte layout of docs/image-format.md: its examples (packed operands, pointer
//! values, file names, unit page numbers, manifest layout) and every page layout, byte
//! by byte. A change here is a change of the format and needs a new format version.

mod common;

use common::*;
use gutta_catalog::{DataType, Width};
use gutta_format::{
    crc16, decode_instructions, encode_data, encode_instructions, verify, Address, ArgumentPage,
    DataItem, Image, LocalSection, Manifest, ManifestPage, PageId, PageKind, Pointer, Record,
    SystemPage, FORMAT_VERSION, MANIFEST_FILE,
};

#[test]
fn documented_operand_examples() {
    let t = target();
    // "Examples on CPU-EC20 (M is slot 4, K slot 9)".
    assert_eq!(t.memory.area("M").map(|a| a.slot), Some(4));
    assert_eq!(t.memory.area("K").map(|a| a.slot), Some(9));
    assert_eq!(val(&t, "MW20").0, 0x0014_0240);
    assert_eq!(val(&t, "MW20").to_le_bytes(), [0x40, 0x02, 0x14, 0x00]);
    assert_eq!(val(&t, "M0.3").0, 0x0000_3040);
    assert_eq!(ptr(&t, "MD4", Width::Word).0, 0x0004_0242);
    assert_eq!(addr_of(&t, "MB24").0, 0x0018_0341);
    // "T5 = 10": the offset counts bytes.
    assert_eq!(val(&t, "T5").offset(), 10);
    // Labels, units, literals.
    assert_eq!(label(3).0, 0x0003_0003);
    assert_eq!(sbr(2).0, 0x0002_0014);
    assert_eq!(int(1).0, 0x0001_0004);
    assert_eq!(lit(2).0, 0x0002_0005);
    // "MOVD &MB24, MD4 stores 0x0400_0018; +D 2 makes it 0x0400_001A".
    let m_byte = |offset| Address {
        slot: 4,
        width: Width::Byte,
        offset,
        bit: 0,
    };
    assert_eq!(Pointer::to(m_byte(24)).0, 0x0400_0018);
    assert_eq!(Pointer::to(m_byte(24)).0 + 2, Pointer::to(m_byte(26)).0);
    assert_eq!(
        Pointer(0x0400_001A).target(Width::Word),
        Address {
            width: Width::Word,
            ..m_byte(26)
        }
    );
}

#[test]
fn file_names_and_unit_pages() {
    let name = |k, n| PageId::new(k, n).file_name();
    assert_eq!(name(PageKind::Const, 0), "const.bin");
    assert_eq!(name(PageKind::Argument, 8), "argument/08.bin");
    assert_eq!(name(PageKind::Instruction, 0x0F), "instruction/0F.bin");
    assert_eq!(name(PageKind::Data, 0), "data/0.bin");
    assert_eq!(name(PageKind::Data, 15), "data/F.bin");
    assert_eq!(name(PageKind::System, 0), "system/0.bin");
    assert_eq!(MANIFEST_FILE, "manifest.json");
    // "On CPU-EC20 MAIN is page 00, INT1 page 01, SBR0 page 08, SBR7 page 0F."
    let t = target();
    let spec = ImageSpec::main(&t, vec![])
        .unit(&t, false, 1, vec![], vec![])
        .unit(&t, true, 0, vec![], vec![])
        .unit(&t, true, 7, vec![], vec![]);
    let image = spec.build();
    let programs: Vec<u8> = image
        .pages
        .keys()
        .filter(|id| id.kind == PageKind::Argument)
        .map(|id| id.number)
        .collect();
    assert_eq!(programs, vec![0x00, 0x01, 0x08, 0x0F]);
    verify(&image, &t).expect("the documented numbering verifies");
}

#[test]
fn manifest_layout() {
    let manifest = Manifest {
        format: FORMAT_VERSION,
        plc_type: "CPU-EC20".into(),
        pages: vec![
            ManifestPage {
                kind: PageKind::Const,
                number: 0,
                file: "const.bin".into(),
                length: 18,
                crc: 0x1F2E,
            },
            ManifestPage {
                kind: PageKind::Argument,
                number: 0,
                file: "argument/00.bin".into(),
                length: 4,
                crc: 0x40BF,
            },
        ],
    };
    // The example of docs/image-format.md, byte for byte (with its final newline).
    let expected = r#"{
  "format": 1,
  "plc_type": "CPU-EC20",
  "pages": [
    { "kind": "const", "number": 0, "file": "const.bin", "length": 18, "crc": "0x1F2E" },
    { "kind": "argument", "number": 0, "file": "argument/00.bin", "length": 4, "crc": "0x40BF" }
  ]
}
"#;
    assert_eq!(manifest.to_json(), expected);
    let doc = include_str!("../../docs/image-format.md");
    let in_doc = expected.trim_end();
    assert!(
        doc.contains(in_doc),
        "the manifest example of the doc differs"
    );
}

#[test]
fn manifest_lists_pages_in_page_order_with_crc() {
    let t = target();
    let image = full_program(&t).build();
    let m = image.manifest();
    let order: Vec<(PageKind, u8)> = m.pages.iter().map(|p| (p.kind, p.number)).collect();
    assert_eq!(
        order,
        vec![
            (PageKind::Const, 0),
            (PageKind::Argument, 0),
            (PageKind::Argument, 1),
            (PageKind::Argument, 8),
            (PageKind::Instruction, 0),
            (PageKind::Instruction, 1),
            (PageKind::Instruction, 8),
            (PageKind::Data, 0),
            (PageKind::System, 0),
        ]
    );
    for p in &m.pages {
        let bytes = image.page(p.kind, p.number).expect("listed page");
        assert_eq!(p.length as usize, bytes.len());
        assert_eq!(p.crc, crc16(bytes));
    }
    // CRC-16/MODBUS: initial 0xFFFF, reflected polynomial 0xA001 (check value of "123456789").
    assert_eq!(crc16(b"123456789"), 0x4B37);
}

#[test]
fn instruction_records() {
    let t = target();
    let records = vec![
        Record::Network(7),
        ins(&t, "MOVW", vec![val(&t, "MW20"), val(&t, "MW22")]),
        ins(&t, "ENI", vec![]),
    ];
    let bytes = encode_instructions(&records);
    assert_eq!(
        bytes,
        [
            0x00, 0x00, 0x07, 0x00, // network 7
            0x02, 0x07, 0x02, // MOVW (0x0702), 2 operands
            0x40, 0x02, 0x14, 0x00, // MW20
            0x40, 0x02, 0x16, 0x00, // MW22
            0x01, 0x0B, 0x00, // ENI (0x0B01), no operands
        ]
    );
    let offsets: Vec<usize> = decode_instructions(&bytes)
        .expect("decodes")
        .into_iter()
        .map(|(at, _)| at)
        .collect();
    assert_eq!(offsets, vec![0, 4, 15]);
    // Every instruction record follows a network record.
    assert!(decode_instructions(&bytes[4..]).is_err());
}

#[test]
fn argument_page() {
    let t = target();
    let page = ArgumentPage {
        subroutine: true,
        unit_number: 2,
        locals: vec![
            local(&t, "LW0", LocalSection::Input, DataType::Int),
            local(&t, "L2.1", LocalSection::Temp, DataType::Bool),
        ],
    };
    let bytes = page.encode();
    assert_eq!(
        bytes,
        [
            1, 2, 2, 0, // subroutine 2, 2 locals, reserved
            0xA0, 0x02, 0x00, 0x00, 0, 5, 0, 0, // LW0, VAR_INPUT, INT
            0xA0, 0x10, 0x02, 0x00, 3, 0, 0, 0, // L2.1, VAR, BOOL
        ]
    );
    assert_eq!(ArgumentPage::decode(&bytes), Ok(page));
    // Data type codes in the documented order.
    let codes: Vec<u8> = DataType::ALL
        .iter()
        .map(|t| gutta_format::data_type_code(*t))
        .collect();
    assert_eq!(codes, (0..=10).collect::<Vec<u8>>());
}

#[test]
fn data_page() {
    let t = target();
    let items = vec![
        DataItem {
            operand: val(&t, "MB30"),
            value: 1,
        },
        DataItem {
            operand: val(&t, "MD44"),
            value: (-70000i32) as u32,
        },
    ];
    assert_eq!(
        encode_data(&items),
        [
            0x40, 0x01, 0x1E, 0x00, 1, 0, 0, 0, // MB30 := 1
            0x40, 0x03, 0x2C, 0x00, 0x90, 0xEE, 0xFE, 0xFF, // MD44 := -70000
        ]
    );
}

#[test]
fn system_page() {
    let t = target();
    let sys = system(&t);
    let bytes = sys.encode();
    // "Length 18 + 8P <= SystemBlockBinarySize (CPU-EC20: 26 of 50)".
    assert_eq!(bytes.len(), 26);
    assert_eq!(t.plc.system_block_binary_size, 50);
    assert_eq!(
        bytes,
        [
            1, 1, // layout 1, one port
            0, 20, 2, 8, 1, 1, 10,
            10, // Modbus RTU, station 20, 38400, 8, even, 1, 1 s, 10 ms
            b'1', b'2', b'3', b'4', 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
        ]
    );
    assert_eq!(SystemPage::decode(&bytes), Ok(sys));
}

#[test]
fn image_files_are_manifest_then_pages() {
    let t = target();
    let image: Image = full_program(&t).build();
    let files = image.files();
    assert_eq!(files[0].0, "manifest.json");
    assert_eq!(files[0].1, image.manifest().to_json().into_bytes());
    let names: Vec<&str> = files[1..].iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "const.bin",
            "argument/00.bin",
            "argument/01.bin",
            "argument/08.bin",
            "instruction/00.bin",
            "instruction/01.bin",
            "instruction/08.bin",
            "data/0.bin",
            "system/0.bin",
        ]
    );
}
