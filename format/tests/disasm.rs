//! The disassembler against hand-built CPU-EC20 images: every operand USE, constants
//! of each type, locals, data and system pages, and corrupted pages (which must give
//! `// cannot decode` comments and errors, never a panic). The round trip through the
//! compiler is compiler/tests/roundtrip.rs.

use std::collections::BTreeMap;
use std::sync::Arc;

use gutta_catalog::{stdlib, Address, DataType, Target, Width};
use gutta_format::disasm::{
    disassemble, disassemble_as, disassemble_with_errors, DisasmError, Disassembly, Format,
};
use gutta_format::{
    encode_data, encode_instructions, ArgumentPage, DataItem, Image, LocalEntry, LocalSection,
    PackedOperand, PageId, PageKind, PortEntry, Record, SystemPage, Use,
};

fn target() -> Arc<Target> {
    stdlib::shared("CPU-EC20").expect("the stdlib default target loads")
}

fn address(text: &str) -> Address {
    target()
        .memory
        .parse_address(text)
        .unwrap_or_else(|e| panic!("{text}: {e}"))
}

/// `MW20`, `I0.4`, `T5` as a USE 0 operand.
fn var(text: &str) -> PackedOperand {
    let a = address(text);
    PackedOperand::memory(a, Use::Value, a.width)
}

/// `&MB24`.
fn address_of(text: &str) -> PackedOperand {
    PackedOperand::memory(address(text), Use::AddressOf, Width::Dword)
}

/// `*MD4` accessing `width`.
fn pointer(text: &str, width: Width) -> PackedOperand {
    PackedOperand::memory(address(text), Use::Pointer, width)
}

/// The constant at K offset `offset`, `width` wide.
fn k(offset: u32, width: Width) -> PackedOperand {
    let slot = target().memory.area("K").expect("CPU-EC20 has K").slot;
    let a = Address {
        slot,
        width,
        offset,
        bit: 0,
    };
    PackedOperand::memory(a, Use::Value, width)
}

fn label(n: u16) -> PackedOperand {
    PackedOperand::special(Use::Label, 0, n)
}

fn sbr(n: u16) -> PackedOperand {
    PackedOperand::special(Use::Unit, 1, n)
}

fn int(n: u16) -> PackedOperand {
    PackedOperand::special(Use::Unit, 0, n)
}

fn literal(n: u16) -> PackedOperand {
    PackedOperand::special(Use::Literal, 0, n)
}

fn ins(mnemonic: &str, operands: &[PackedOperand]) -> Record {
    let t = target();
    let id = t
        .instructions
        .lookup(mnemonic)
        .unwrap_or_else(|| panic!("no {mnemonic}"));
    Record::Instruction {
        opcode: t.instructions.get(id).opcode,
        operands: operands.to_vec(),
    }
}

fn local(text: &str, section: LocalSection, data_type: DataType) -> LocalEntry {
    LocalEntry {
        operand: var(text),
        section,
        data_type,
    }
}

fn arguments(subroutine: bool, unit_number: u8, locals: Vec<LocalEntry>) -> Vec<u8> {
    ArgumentPage {
        subroutine,
        unit_number,
        locals,
    }
    .encode()
}

/// An image builder: pages by id, const page empty unless set.
struct Build {
    pages: BTreeMap<PageId, Vec<u8>>,
}

impl Build {
    fn new() -> Build {
        let mut pages = BTreeMap::new();
        pages.insert(PageId::new(PageKind::Const, 0), Vec::new());
        Build { pages }
    }

    fn page(mut self, kind: PageKind, number: u8, bytes: Vec<u8>) -> Build {
        self.pages.insert(PageId::new(kind, number), bytes);
        self
    }

    fn consts(self, bytes: Vec<u8>) -> Build {
        self.page(PageKind::Const, 0, bytes)
    }

    /// A unit: argument page `args` and instruction page `records`.
    fn unit(self, number: u8, args: Vec<u8>, records: &[Record]) -> Build {
        self.page(PageKind::Argument, number, args).page(
            PageKind::Instruction,
            number,
            encode_instructions(records),
        )
    }

    /// MAIN with no locals.
    fn main(self, records: &[Record]) -> Build {
        self.unit(0, arguments(false, 0, vec![]), records)
    }

    fn image(self) -> Image {
        Image {
            plc_type: "CPU-EC20".into(),
            pages: self.pages,
        }
    }
}

fn dis(image: &Image) -> Disassembly {
    disassemble_with_errors(image, &target())
}

/// The text of a clean disassembly (no errors allowed).
fn clean(image: &Image) -> String {
    let d = dis(image);
    assert!(d.errors.is_empty(), "errors: {:?}\n{}", d.errors, d.text);
    d.text
}

/// Instruction lines without their step comments, trimmed.
fn code_lines(text: &str) -> Vec<String> {
    text.lines()
        .map(|l| match l.find("// step") {
            Some(at) => l[..at].trim_end().to_string(),
            None => l.trim_end().to_string(),
        })
        .collect()
}

fn has_line(text: &str, want: &str) -> bool {
    code_lines(text).iter().any(|l| l == want)
}

fn assert_lines(text: &str, want: &[&str]) {
    for w in want {
        assert!(has_line(text, w), "missing line `{w}` in\n{text}");
    }
}

fn error_at(d: &Disassembly, kind: PageKind, number: u8, offset: usize) -> &DisasmError {
    d.errors
        .iter()
        .find(|e| e.page == Some(PageId::new(kind, number)) && e.offset == offset)
        .unwrap_or_else(|| {
            panic!(
                "no error at {} byte {offset}: {:?}\n{}",
                PageId::new(kind, number).file_name(),
                d.errors,
                d.text
            )
        })
}

#[test]
fn operands_of_every_use_print_by_name() {
    let image = Build::new()
        .consts(vec![0x01, 0x0E, 0x05, 0x00])
        .main(&[
            Record::Network(1),
            ins("LD", &[var("I0.4")]),
            ins("=", &[var("Q0.0")]),
            ins("MOVD", &[address_of("MB24"), var("MD4")]),
            ins("MOVW", &[k(0, Width::Word), pointer("MD4", Width::Word)]),
            ins("LDW>=", &[var("T5"), var("MW20")]),
            ins("JMP", &[label(3)]),
            ins("CALL", &[sbr(0), k(2, Width::Word)]),
            ins("ATCH", &[int(1), literal(10)]),
            ins("LDS", &[literal(2)]),
            Record::Network(7),
            ins("LBL", &[label(3)]),
            ins("ENI", &[]),
        ])
        .unit(1, arguments(false, 1, vec![]), &[])
        .unit(
            8,
            arguments(
                true,
                0,
                vec![local("LW0", LocalSection::Input, DataType::Int)],
            ),
            &[Record::Network(1), ins("INCW", &[var("LW0")])],
        )
        .image();
    let text = clean(&image);
    let want = "\
// Disassembly of an image for CPU-EC20, produced by gutta-cc dis
PLC_TYPE CPU-EC20

ORGANIZATION_BLOCK MAIN:OB1
BEGIN
NETWORK 1
LD     I0.4                  // step 0
=      Q0.0                  // step 1
MOVD   &MB24, MD4            // step 2
MOVW   16#0E01, *MD4         // step 3
LDW>=  T5, MW20              // step 4
JMP    3                     // step 5
CALL   SBR0, 5               // step 6
ATCH   INT1, 10              // step 7
LDS    2                     // step 8
NETWORK 7
LBL    3                     // step 0
ENI                          // step 1
END_ORGANIZATION_BLOCK

INTERRUPT_BLOCK INT1:INT1
BEGIN
END_INTERRUPT_BLOCK

SUBROUTINE_BLOCK SBR0:SBR0
VAR_INPUT
  in0 : INT;         // LW0
END_VAR
BEGIN
NETWORK 1
INCW   #in0                  // step 0
END_SUBROUTINE_BLOCK
";
    assert_eq!(text, want);
    assert_eq!(disassemble(&image, &target()), Ok(text));
}

/// The STEP 7-Micro/WIN layout of the same kind of image: `MAIN:OB1`, `INT_n:INTn`
/// and `SBR_n:SBRn` headers (their names in CALL and ATCH), `TITLE=`, `Network n`,
/// Micro/WIN's VAR lines, no step comments, CRLF, data blocks after a note; a unit the
/// image does not hold keeps its number as its name.
#[test]
fn awl_layout_is_micro_win_s() {
    let image = Build::new()
        .main(&[
            Record::Network(0),
            ins("LD", &[var("I0.4")]),
            ins("CALL", &[sbr(0), var("MW2"), var("M4.0")]),
            ins("ATCH", &[int(1), literal(10)]),
            ins("ATCH", &[int(2), literal(11)]),
        ])
        .unit(1, arguments(false, 1, vec![]), &[])
        .unit(
            8,
            arguments(
                true,
                0,
                vec![
                    local("LW0", LocalSection::Input, DataType::Int),
                    local("L2.0", LocalSection::Output, DataType::Bool),
                ],
            ),
            &[Record::Network(1), ins("INCW", &[var("LW0")])],
        )
        .page(
            PageKind::Data,
            0,
            encode_data(&[DataItem {
                operand: var("MW22"),
                value: 6,
            }]),
        )
        .image();
    let d = disassemble_as(&image, &target(), Format::Awl);
    assert!(d.errors.is_empty(), "{:?}", d.errors);
    let want = "\
// Disassembly of an image for CPU-EC20, produced by gutta-cc dis --format awl (STEP 7-Micro/WIN layout)
// timer-boxes: gutta
PLC_TYPE CPU-EC20
ORGANIZATION_BLOCK MAIN:OB1
TITLE=
BEGIN
Network 0
LD     I0.4
CALL   SBR_0, MW2, M4.0
ATCH   INT_0, 10
ATCH   INT1, 11
END_ORGANIZATION_BLOCK
INTERRUPT_BLOCK INT_0:INT0
TITLE=
BEGIN
END_INTERRUPT_BLOCK
SUBROUTINE_BLOCK SBR_0:SBR0
TITLE=
VAR_INPUT
in0:INT;\t// LW0
END_VAR
VAR_OUTPUT
out0:BOOL;\t// L2.0
END_VAR
BEGIN
Network 1
INCW   #in0
END_SUBROUTINE_BLOCK

// Micro/WIN exports data blocks (and keeps the system block) apart from the
// program; gutta-cc reads them in the same file, in its own layout, below.

DATA_BLOCK DAT0:DAT0
  MW22     WORD   6
END_DATA_BLOCK
"
    .replace('\n', "\r\n");
    assert_eq!(d.text, want);
    assert_eq!(
        disassemble_with_errors(&image, &target()).text,
        dis(&image).text,
        "stl stays the default"
    );
}

/// MAIN with one instruction per constant, the const page holding their bytes.
fn constants_image(consts: Vec<u8>, records: &[Record]) -> Image {
    let mut all = vec![Record::Network(1)];
    all.extend_from_slice(records);
    Build::new().consts(consts).main(&all).image()
}

#[test]
fn constants_are_spelled_for_their_operand_types() {
    let mut c = Vec::new();
    c.extend(1.5f32.to_le_bytes()); // 0
    c.extend(1e20f32.to_le_bytes()); // 4
    c.extend((-0.0f32).to_le_bytes()); // 8
    c.extend(0.1f32.to_le_bytes()); // 12
    c.extend((-3i16).to_le_bytes()); // 16
    c.extend((-70000i32).to_le_bytes()); // 18
    c.extend(0x0E01u16.to_le_bytes()); // 22
    c.extend([7, 0xFF]); // 24, 25
    c.extend(u32::MAX.to_le_bytes()); // 26
    c.extend(100i16.to_le_bytes()); // 30
    let image = constants_image(
        c,
        &[
            ins("MOVR", &[k(0, Width::Dword), var("MD40")]),
            ins("MOVR", &[k(4, Width::Dword), var("MD40")]),
            ins("MOVR", &[k(8, Width::Dword), var("MD40")]),
            ins("MOVR", &[k(12, Width::Dword), var("MD40")]),
            ins("+I", &[k(16, Width::Word), var("MW0")]),
            ins("+D", &[k(18, Width::Dword), var("MD0")]),
            ins("MOVW", &[k(22, Width::Word), var("MW0")]),
            ins("MOVB", &[k(24, Width::Byte), var("MB0")]),
            ins("MOVB", &[k(25, Width::Byte), var("MB0")]),
            ins("MOVD", &[k(26, Width::Dword), var("MD0")]),
            ins("TON", &[var("T4"), k(30, Width::Word)]),
            // A word that is the signed -1 for +I and 16#FFFF for MOVW.
            ins("+I", &[k(26, Width::Word), var("MW0")]),
            ins("MOVW", &[k(26, Width::Word), var("MW0")]),
            // K where the operand takes no constant: the address itself.
            ins("TON", &[k(30, Width::Word), var("MW2")]),
        ],
    );
    let text = clean(&image);
    assert_lines(
        &text,
        &[
            "MOVR   1.5, MD40",
            "MOVR   1.0e20, MD40",
            "MOVR   -0.0, MD40",
            "MOVR   0.1, MD40",
            "+I     -3, MW0",
            "+D     -70000, MD0",
            "MOVW   16#0E01, MW0",
            "MOVB   7, MB0",
            "MOVB   16#FF, MB0",
            "MOVD   16#FFFFFFFF, MD0",
            "TON    T4, 100",
            "+I     -1, MW0",
            "MOVW   16#FFFF, MW0",
            "TON    KW30, MW2",
        ],
    );
}

/// Every REAL literal the disassembler prints reads back (f64 parse, rounded to f32,
/// as the compiler reads it) to the constant's bits, and has digits on both sides of
/// its point.
#[test]
fn real_literals_read_back_exactly() {
    let mut bits: Vec<u32> = vec![
        0x0000_0001, // smallest subnormal
        0x007F_FFFF, // largest subnormal
        0x0080_0000, // smallest normal
        0x7F7F_FFFF, // f32::MAX
        0xFF7F_FFFF, // f32::MIN
        0x3F80_0001,
        0x4B80_0000, // 2^24
        0x5F00_0000, // 2^63
    ];
    let mut seed = 0x2545_F491_u32;
    for _ in 0..3000 {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        bits.push(seed);
    }
    bits.retain(|b| f32::from_bits(*b).is_finite());
    for chunk in bits.chunks(30) {
        let consts: Vec<u8> = chunk.iter().flat_map(|b| b.to_le_bytes()).collect();
        let records: Vec<Record> = (0..chunk.len())
            .map(|i| ins("MOVR", &[k(4 * i as u32, Width::Dword), var("MD0")]))
            .collect();
        let text = clean(&constants_image(consts, &records));
        let literals: Vec<String> = code_lines(&text)
            .iter()
            .filter_map(|l| l.strip_prefix("MOVR   "))
            .map(|l| l.trim_end_matches(", MD0").to_string())
            .collect();
        assert_eq!(literals.len(), chunk.len());
        for (lit, b) in literals.iter().zip(chunk) {
            let back = lit.parse::<f64>().map(|v| (v as f32).to_bits());
            assert_eq!(back, Ok(*b), "{lit} for 0x{b:08X}");
            let mantissa = lit.split(['e', 'E']).next().unwrap_or("");
            let (int, frac) = mantissa.split_once('.').unwrap_or(("", ""));
            assert!(
                !int.trim_start_matches('-').is_empty() && !frac.is_empty(),
                "{lit} needs digits on both sides of the point"
            );
        }
    }
}

#[test]
fn non_finite_real_constants_cannot_be_spelled() {
    let image = constants_image(
        f32::NAN.to_le_bytes().to_vec(),
        &[ins("MOVR", &[k(0, Width::Dword), var("MD0")])],
    );
    let d = dis(&image);
    // Operand 1 of the record at byte 4: byte 4 + 3.
    let e = error_at(&d, PageKind::Instruction, 0, 7);
    assert!(e.reason.contains("no literal"), "{e}");
    assert!(
        d.text.contains("// cannot decode step 0 (MOVR)"),
        "{}",
        d.text
    );
    assert!(disassemble(&image, &target()).is_err());
}

#[test]
fn call_arguments_take_the_callee_parameter_types() {
    let mut c = Vec::new();
    c.extend(40000u16.to_le_bytes()); // 0: UINT
    c.extend([1, 2]); // 2: BOOL 1 (bit 0); 3: a byte whose bit 1 is set
    c.extend((-5i16).to_le_bytes()); // 4: INT
    let params = vec![
        local("LW0", LocalSection::Input, DataType::Uint),
        local("L2.0", LocalSection::Input, DataType::Bool),
        local("L2.1", LocalSection::Input, DataType::Bool),
        local("LW3", LocalSection::Input, DataType::Int),
        local("LD5", LocalSection::InOut, DataType::Dword),
        local("LW9", LocalSection::Output, DataType::Word),
        local("LW11", LocalSection::Temp, DataType::Word),
    ];
    let bit_of_k3 = {
        let slot = target().memory.area("K").expect("K").slot;
        let a = Address {
            slot,
            width: Width::Bit,
            offset: 3,
            bit: 1,
        };
        PackedOperand::memory(a, Use::Value, Width::Bit)
    };
    let image = Build::new()
        .consts(c)
        .main(&[
            Record::Network(1),
            ins(
                "CALL",
                &[
                    sbr(0),
                    k(0, Width::Word),
                    k(2, Width::Bit),
                    bit_of_k3,
                    k(4, Width::Word),
                    pointer("MD0", Width::Dword),
                    var("MW10"),
                ],
            ),
        ])
        .unit(8, arguments(true, 0, params), &[Record::Network(1)])
        .image();
    let d = dis(&image);
    assert!(
        has_line(&d.text, "CALL   SBR0, 40000, 1, K3.1, -5, *MD0, MW10"),
        "{}",
        d.text
    );
    // K3's byte 2 is only read as a bit: compiling the text would not reproduce it.
    let e = error_at(&d, PageKind::Const, 0, 3);
    assert!(
        e.reason
            .contains("1 byte of the const page, the first KB3, is no"),
        "{e}"
    );
    assert_eq!(d.errors.len(), 1, "{:?}", d.errors);
}

#[test]
fn locals_print_by_name_only_where_the_text_means_the_same() {
    let locals = vec![
        local("LW0", LocalSection::Input, DataType::Uint),
        local("LB2", LocalSection::InOut, DataType::Byte),
        local("L3.0", LocalSection::Output, DataType::Bool),
        local("L3.1", LocalSection::Output, DataType::Bool),
        local("LD4", LocalSection::Temp, DataType::Dword),
        local("LD8", LocalSection::Temp, DataType::Real),
    ];
    let image = Build::new()
        .unit(
            8,
            arguments(true, 0, locals),
            &[
                Record::Network(1),
                ins("LD", &[var("L3.0")]),
                ins("A", &[var("L3.1")]),
                ins("INCW", &[var("LW0")]),
                // +I takes INT: a UINT local does not stand there, its address does.
                ins("+I", &[var("LW0"), var("MW0")]),
                // Part of a local is its address.
                ins("MOVB", &[var("LB0"), var("LB2")]),
                ins("MOVW", &[var("MW0"), pointer("LD4", Width::Word)]),
                ins("MOVD", &[var("LD8"), var("MD0")]),
                ins("MOVR", &[var("LD8"), var("MD0")]),
                ins("MOVD", &[address_of("LB2"), var("LD4")]),
            ],
        )
        .image();
    let text = clean(&image);
    assert!(
        text.contains(
            "\
SUBROUTINE_BLOCK SBR0:SBR0
VAR_INPUT
  in0 : UINT;        // LW0
END_VAR
VAR_IN_OUT
  io0 : BYTE;        // LB2
END_VAR
VAR_OUTPUT
  out0 : BOOL;       // L3.0
  out1 : BOOL;       // L3.1
END_VAR
VAR
  tmp0 : DWORD;      // LD4
  tmp1 : REAL;       // LD8
END_VAR
BEGIN
"
        ),
        "{text}"
    );
    assert_lines(
        &text,
        &[
            "LD     #out0",
            "A      #out1",
            "INCW   #in0",
            "+I     LW0, MW0",
            "MOVB   LB0, #io0",
            "MOVW   MW0, *#tmp0",
            "MOVD   LD8, MD0",
            "MOVR   #tmp1, MD0",
            "MOVD   &LB2, #tmp0",
        ],
    );
}

#[test]
fn locals_the_language_would_place_elsewhere_are_errors() {
    // in0 : INT recorded at LW2; the language puts the first local at LW0.
    let image = Build::new()
        .unit(
            8,
            arguments(
                true,
                0,
                vec![
                    local("LW2", LocalSection::Input, DataType::Int),
                    local("LW0", LocalSection::Temp, DataType::Int),
                ],
            ),
            &[Record::Network(1), ins("INCW", &[var("LW2")])],
        )
        .image();
    let d = dis(&image);
    let e = error_at(&d, PageKind::Argument, 8, 4);
    assert!(e.reason.contains("LW2") && e.reason.contains("LW0"), "{e}");
    error_at(&d, PageKind::Argument, 8, 12);
    // Names follow the language's places: LW2 is where the text puts tmp0.
    assert!(has_line(&d.text, "INCW   #tmp0"), "{}", d.text);
}

#[test]
fn argument_page_headers_and_order_are_checked() {
    let image = Build::new()
        .main(&[Record::Network(1)])
        .unit(
            8,
            arguments(
                false,
                3,
                vec![
                    local("LW0", LocalSection::Output, DataType::Int),
                    local("LW2", LocalSection::Input, DataType::Int),
                ],
            ),
            &[Record::Network(1)],
        )
        .image();
    let d = dis(&image);
    assert!(error_at(&d, PageKind::Argument, 8, 0)
        .reason
        .contains("INT3"));
    assert!(error_at(&d, PageKind::Argument, 8, 12)
        .reason
        .contains("L order"));
}

#[test]
fn data_pages_print_rows_that_encode_the_same_values() {
    let items = vec![
        DataItem {
            operand: var("MW22"),
            value: 6,
        },
        DataItem {
            operand: var("MB30"),
            value: u32::MAX,
        },
        DataItem {
            operand: var("M40.0"),
            value: 1,
        },
        DataItem {
            operand: var("MD44"),
            value: (-70000i32) as u32,
        },
        DataItem {
            operand: var("T5"),
            value: 100,
        },
        DataItem {
            operand: var("MW50"),
            value: 0xFFFF_8000,
        },
    ];
    let image = Build::new()
        .main(&[Record::Network(1)])
        .page(PageKind::Data, 3, encode_data(&items))
        .image();
    let text = clean(&image);
    assert!(
        text.contains(
            "\
DATA_BLOCK DAT3:DAT3
  MW22     WORD   6
  MB30     BYTE   -1
  M40.0    BOOL   1
  MD44     DWORD  4294897296
  T5       WORD   100
  MW50     WORD   -32768
END_DATA_BLOCK
"
        ),
        "{text}"
    );
}

#[test]
fn data_items_no_row_reproduces_are_errors() {
    let items = vec![
        DataItem {
            operand: var("MW0"),
            value: 1,
        },
        // Upper bits neither zero nor a sign extension.
        DataItem {
            operand: var("MB1"),
            value: 0x100,
        },
        DataItem {
            operand: var("M2.0"),
            value: 2,
        },
        DataItem {
            operand: address_of("MB3"),
            value: 0,
        },
    ];
    let mut bytes = encode_data(&items);
    bytes.extend([1, 2, 3]);
    let image = Build::new()
        .main(&[Record::Network(1)])
        .page(PageKind::Data, 0, bytes)
        .image();
    let d = dis(&image);
    assert!(has_line(&d.text, "  MW0      WORD   1"), "{}", d.text);
    error_at(&d, PageKind::Data, 0, 12);
    error_at(&d, PageKind::Data, 0, 20);
    error_at(&d, PageKind::Data, 0, 24);
    error_at(&d, PageKind::Data, 0, 32);
    assert_eq!(d.errors.len(), 4, "{:?}", d.errors);
    assert_eq!(d.text.matches("// cannot decode").count(), 4, "{}", d.text);
    assert!(d.text.contains("END_DATA_BLOCK"));
}

fn port(parity: u8) -> PortEntry {
    PortEntry {
        protocol: 0,
        address: 20,
        baud: 38400,
        data_bits: 8,
        parity,
        stop_bits: 1,
        timeout: 10,
        frame_gap: 5,
    }
}

fn system_image(password: [u8; 16], parity: u8) -> Image {
    let page = SystemPage {
        ports: vec![port(parity)],
        password,
    };
    Build::new()
        .main(&[Record::Network(1)])
        .page(PageKind::System, 0, page.encode())
        .image()
}

fn password(text: &[u8]) -> [u8; 16] {
    let mut pw = [0u8; 16];
    pw[..text.len()].copy_from_slice(text);
    pw
}

#[test]
fn system_page_prints_every_key() {
    let text = clean(&system_image(password(b"1\"2\\3"), 1));
    assert!(
        text.ends_with(
            "\
SYSTEM_BLOCK
  PORT0.PROTOCOL  = MODBUS
  PORT0.ADDRESS   = 20
  PORT0.BAUD      = 38400
  PORT0.DATA_BITS = 8
  PORT0.PARITY    = EVEN
  PORT0.STOP_BITS = 1
  PORT0.TIMEOUT   = 10
  PORT0.FRAME_GAP = 5
  PASSWORD        = \"1\\\"2\\\\3\"
END_SYSTEM_BLOCK
"
        ),
        "{text}"
    );
    let factory = clean(&system_image([0xFF; 16], 2));
    assert!(!factory.contains("PASSWORD"), "{factory}");
    assert!(has_line(&factory, "  PORT0.PARITY    = ODD"), "{factory}");
    let full = clean(&system_image(*b"0123456789ABCDEF", 0));
    assert!(
        has_line(&full, "  PASSWORD        = \"0123456789ABCDEF\""),
        "{full}"
    );
    assert!(has_line(&full, "  PORT0.PARITY    = NONE"), "{full}");
}

#[test]
fn system_values_no_key_spells_are_errors() {
    let d = dis(&system_image(password(b"ab"), 3));
    error_at(&d, PageKind::System, 0, 6);
    let d = dis(&system_image(password(b"a\x01b"), 0));
    error_at(&d, PageKind::System, 0, 11);
    let d = dis(&system_image([0; 16], 0));
    assert!(error_at(&d, PageKind::System, 0, 10)
        .reason
        .contains("zero"));
    let mut bytes = SystemPage {
        ports: vec![port(0), port(0)],
        password: [0xFF; 16],
    }
    .encode();
    let d = dis(&Build::new()
        .main(&[Record::Network(1)])
        .page(PageKind::System, 0, bytes.clone())
        .image());
    assert!(error_at(&d, PageKind::System, 0, 1)
        .reason
        .contains("2 ports"));
    bytes.truncate(5);
    let d = dis(&Build::new()
        .main(&[Record::Network(1)])
        .page(PageKind::System, 0, bytes)
        .image());
    assert!(
        d.text.contains("// cannot decode the system block"),
        "{}",
        d.text
    );
    assert!(!d.text.contains("SYSTEM_BLOCK\n"), "{}", d.text);
}

#[test]
fn corrupted_instructions_become_comments_with_errors() {
    let mut bytes = encode_instructions(&[
        Record::Network(1),
        ins("LD", &[var("I0.0")]), // 4
        Record::Instruction {
            opcode: 0x7777,
            operands: vec![],
        }, // 11
        ins("LD", &[PackedOperand(0x0000_0007)]), // 14: USE 7
        ins("MOVW", &[var("MB0"), var("MW0")]), // 21: a byte where a word belongs
        ins("JMP", &[PackedOperand::special(Use::Label, 2, 1)]), // 32: label with a slot
        ins("LD", &[PackedOperand(0x000B_0250)]), // 39: T at an odd byte
        ins("LD", &[var("M0.0"), var("M0.1")]), // 46: one operand too many
        ins("CALL", &[sbr(5)]),    // 57: no SBR5
        ins("=", &[var("Q0.1")]),  // 64
    ]);
    bytes.extend([0x01, 0x01, 0x05]); // 71: cut off
    let image = Build::new()
        .page(PageKind::Argument, 0, arguments(false, 0, vec![]))
        .page(PageKind::Instruction, 0, bytes)
        .image();
    let d = dis(&image);
    for at in [11, 17, 24, 35, 42, 46, 60, 71] {
        error_at(&d, PageKind::Instruction, 0, at);
    }
    assert_eq!(d.errors.len(), 8, "{:?}", d.errors);
    assert_eq!(d.text.matches("// cannot decode").count(), 8, "{}", d.text);
    // Steps count on past the bad ones.
    assert!(
        d.text.contains("LD     I0.0                  // step 0"),
        "{}",
        d.text
    );
    assert!(
        d.text.contains("=      Q0.1                  // step 8"),
        "{}",
        d.text
    );
    assert!(d
        .text
        .contains("// cannot decode step 1 (instruction/00.bin at byte 11): opcode 0x7777"));
    assert!(d
        .text
        .contains("// cannot decode the rest of the page (instruction/00.bin at byte 71)"));
    assert!(d.text.contains("END_ORGANIZATION_BLOCK"));
    assert_eq!(disassemble(&image, &target()), Err(d.errors[0].clone()));
}

#[test]
fn missing_and_undecodable_pages_are_errors() {
    // An instruction page without its argument page, an argument page that is too
    // short, no const page, and a PLC type that is not the target's.
    let mut pages = BTreeMap::new();
    pages.insert(
        PageId::new(PageKind::Instruction, 0),
        encode_instructions(&[Record::Network(1)]),
    );
    pages.insert(PageId::new(PageKind::Argument, 8), vec![1, 0, 1]);
    let image = Image {
        // A PLC type from a manifest may hold any text: it stays on the comment's line.
        plc_type: "CPU-EC20\nM3".into(),
        pages,
    };
    let d = dis(&image);
    assert!(
        d.text.starts_with(
            "// Disassembly of an image for CPU-EC20?M3, produced by gutta-cc dis\nPLC_TYPE CPU-EC20\n"
        ),
        "{}",
        d.text
    );
    assert!(d
        .errors
        .iter()
        .any(|e| e.page.is_none() && e.reason.contains("`CPU-EC20?M3`")));
    error_at(&d, PageKind::Const, 0, 0);
    error_at(&d, PageKind::Argument, 0, 0);
    error_at(&d, PageKind::Argument, 8, 3);
    error_at(&d, PageKind::Instruction, 8, 0);
    assert!(
        d.text
            .contains("SUBROUTINE_BLOCK SBR0:SBR0\n// cannot decode the locals"),
        "{}",
        d.text
    );
}

#[test]
fn const_bytes_no_constant_uses_are_errors() {
    let image = constants_image(
        vec![5, 0, 9, 9],
        &[ins("MOVW", &[k(0, Width::Word), var("MW0")])],
    );
    let d = dis(&image);
    assert!(has_line(&d.text, "MOVW   5, MW0"), "{}", d.text);
    let e = error_at(&d, PageKind::Const, 0, 2);
    assert!(
        e.reason.contains("2 bytes of the const page") && e.reason.contains("KB2"),
        "{e}"
    );
}

#[test]
fn calls_need_the_callee_argument_count() {
    let image = Build::new()
        .main(&[Record::Network(1), ins("CALL", &[sbr(0), var("MW0")])])
        .unit(8, arguments(true, 0, vec![]), &[Record::Network(1)])
        .image();
    let d = dis(&image);
    let e = error_at(&d, PageKind::Instruction, 0, 4);
    assert!(e.reason.contains("takes 0 arguments"), "{e}");
}

/// Random pages of every kind, some with valid opcodes and operands: the disassembler
/// returns (no panic), and every `cannot decode` comment has its error.
#[test]
fn random_bytes_never_panic() {
    let t = target();
    let opcodes: Vec<u16> = t
        .instructions
        .instructions
        .iter()
        .map(|i| i.opcode)
        .collect();
    let mut seed = 0x9E37_79B9_u32;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        seed
    };
    for _ in 0..400 {
        let mut pages = BTreeMap::new();
        for kind in PageKind::ALL {
            for _ in 0..(next() % 3) {
                let number = (next() % 12) as u8;
                let len = (next() % 48) as usize;
                let mut bytes: Vec<u8> = (0..len).map(|_| next() as u8).collect();
                if kind == PageKind::Instruction && next() % 2 == 0 {
                    // A network, then a known opcode with random operands.
                    let op = opcodes[next() as usize % opcodes.len()];
                    let mut head = vec![0, 0, 1, 0];
                    head.extend(op.to_le_bytes());
                    head.push((next() % 4) as u8);
                    head.extend(bytes);
                    bytes = head;
                }
                if kind == PageKind::Argument && bytes.len() >= 4 {
                    bytes[2] = ((bytes.len() - 4) / 8) as u8;
                    bytes.truncate(4 + 8 * bytes[2] as usize);
                }
                let number = if kind == PageKind::Const { 0 } else { number };
                pages.insert(PageId::new(kind, number), bytes);
            }
        }
        let image = Image {
            plc_type: "CPU-EC20".into(),
            pages,
        };
        let d = dis(&image);
        assert!(d
            .text
            .starts_with("// Disassembly of an image for CPU-EC20,"));
        assert!(
            d.errors.len() >= d.text.matches("// cannot decode").count(),
            "{:?}\n{}",
            d.errors,
            d.text
        );
        assert_eq!(disassemble(&image, &t).is_ok(), d.errors.is_empty());
    }
}
