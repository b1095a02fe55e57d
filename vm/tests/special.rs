//! Immediate byte I/O, the interval timer, CEVNT and the ASCII conversions: small
//! programs compiled by gutta-cc and run on the VM, checked against ManagerFun.xml's
//! descriptions.

mod common;

use common::{read, set};
use gutta_vm::{Vm, VmConfig};

/// A VM running `code` as the body of MAIN, every scan (under `LD SM0.0`).
fn vm_for(code: &str) -> Vm {
    let text = format!(
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\n{code}\nEND_ORGANIZATION_BLOCK\n"
    );
    common::load(&text, VmConfig::default())
}

fn scan(vm: &mut Vm) {
    vm.scan().expect("scan");
}

/// Put `bytes` into MB`start`...
fn put(vm: &mut Vm, start: u32, bytes: &[u8]) {
    for (k, b) in bytes.iter().enumerate() {
        set(vm, &format!("MB{}", start + k as u32), u32::from(*b));
    }
}

/// The `n` bytes from MB`start` as text.
fn text(vm: &Vm, start: u32, n: u32) -> String {
    (start..start + n)
        .map(|a| char::from(read(vm, &format!("MB{a}")) as u8))
        .collect()
}

// ---- immediate I/O ----------------------------------------------------------------------

#[test]
fn bir_reads_the_terminal_with_forces() {
    // Programs cannot write I, and the host sets terminals only between scans, so the
    // terminal and the image agree whenever BIR runs.
    let mut vm = vm_for("BIR IB0, MB10");
    set(&mut vm, "IB0", 0xA5);
    scan(&mut vm);
    assert_eq!(read(&vm, "MB10"), 0xA5, "the physical input");
    let at = |vm: &Vm, v: &str| vm.target().memory.parse_address(v).expect("address");
    let (i00, i06) = (at(&vm, "I0.0"), at(&vm, "I0.6"));
    vm.force(i00, 0).expect("force");
    vm.force(i06, 1).expect("force");
    scan(&mut vm);
    assert_eq!(
        read(&vm, "MB10"),
        0xE4,
        "forced bits read their force values"
    );
}

#[test]
fn biw_writes_the_output_at_once() {
    let mut vm = vm_for("BIW MB10, QB0\nMOVB QB0, MB11");
    set(&mut vm, "MB10", 0x5A);
    scan(&mut vm);
    assert_eq!((read(&vm, "QB0"), read(&vm, "MB11")), (0x5A, 0x5A));
}

#[test]
fn immediate_moves_do_nothing_without_power() {
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD I0.7\nBIR IB0, MB10\nBIW MB11, QB0\nEND_ORGANIZATION_BLOCK\n";
    let mut vm = common::load(text, VmConfig::default());
    set(&mut vm, "IB0", 0x12);
    set(&mut vm, "MB10", 0x33);
    set(&mut vm, "MB11", 0x44);
    scan(&mut vm);
    assert_eq!((read(&vm, "MB10"), read(&vm, "QB0")), (0x33, 0));
}

// ---- interval timer ---------------------------------------------------------------------

#[test]
fn bitim_and_citim_measure_virtual_milliseconds() {
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.1\nBITIM MD20\n\
                NETWORK 2\nLD SM0.0\nCITIM MD20, MD24\nBITIM MD28\n\
                NETWORK 3\nLD I0.0\nBITIM MD32\nEND_ORGANIZATION_BLOCK\n";
    let config = VmConfig {
        scan_ms: 7,
        ..VmConfig::default()
    };
    let mut vm = common::load(text, config);
    set(&mut vm, "MD32", 99);
    scan(&mut vm);
    assert_eq!((read(&vm, "MD20"), read(&vm, "MD24")), (0, 0));
    for _ in 0..4 {
        scan(&mut vm);
    }
    // The fifth scan starts at 4 * 7 ms.
    assert_eq!((read(&vm, "MD24"), read(&vm, "MD28")), (28, 28));
    assert_eq!(read(&vm, "MD32"), 99, "no power flow, no change");
    // Modulo 2^32: a start just before the wrap.
    set(&mut vm, "MD20", 0xFFFF_FFF0);
    scan(&mut vm);
    assert_eq!(read(&vm, "MD24"), 35 + 16);
    set(&mut vm, "I0.0", 1);
    scan(&mut vm);
    assert_eq!(read(&vm, "MD32"), 42);
}

// ---- CEVNT ------------------------------------------------------------------------------

/// Timed event 10 every 30 ms (scans of 10 ms) with interrupts off; I0.1 runs CEVNT 10,
/// I0.0 switches interrupts on.
fn cevnt_vm() -> Vm {
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.1\nMOVB 30, SMB10\nATCH TICK, 10\n\
                NETWORK 2\nLD I0.1\nCEVNT 10\nNETWORK 3\nLDN I0.0\nJMP 1\nNETWORK 4\nENI\n\
                NETWORK 5\nLBL 1\nLD SM0.0\nMOVB 1, MB99\nEND_ORGANIZATION_BLOCK\n\
                INTERRUPT_BLOCK TICK:INT1\nBEGIN\nNETWORK 1\nLD SM0.0\nINCW MW30\nEND_INTERRUPT_BLOCK\n";
    common::load(text, VmConfig::default())
}

#[test]
fn cevnt_discards_the_pending_occurrence_and_keeps_the_association() {
    for clear in [false, true] {
        let mut vm = cevnt_vm();
        for _ in 0..3 {
            scan(&mut vm);
        }
        // One occurrence is pending (30 ms, interrupts off).
        set(&mut vm, "I0.0", 1);
        set(&mut vm, "I0.1", u32::from(clear));
        scan(&mut vm);
        assert_eq!(read(&vm, "MW30"), u32::from(!clear), "clear = {clear}");
        set(&mut vm, "I0.1", 0);
        for _ in 0..3 {
            scan(&mut vm);
        }
        assert_eq!(
            read(&vm, "MW30"),
            u32::from(!clear) + 1,
            "still attached (clear = {clear})"
        );
    }
}

// ---- ASCII conversions ------------------------------------------------------------------

#[test]
fn ath_examples() {
    let mut vm = vm_for("ATH MB40, MB60, 4");
    put(&mut vm, 40, b"1A2f");
    scan(&mut vm);
    assert_eq!((read(&vm, "MB60"), read(&vm, "MB61")), (0x1A, 0x2F));
    assert_eq!(read(&vm, "SM1.1"), 0);

    let mut vm = vm_for("ATH MB40, MB60, 3");
    put(&mut vm, 40, b"ABC");
    put(&mut vm, 60, &[0x55, 0x55, 0x55]);
    scan(&mut vm);
    assert_eq!(
        (read(&vm, "MB60"), read(&vm, "MB61"), read(&vm, "MB62")),
        (0xAB, 0xC0, 0x55),
        "odd LEN: the low half of the last byte is 0"
    );

    // An illegal character stops the conversion there.
    let mut vm = vm_for("ATH MB40, MB60, 4");
    put(&mut vm, 40, b"12X4");
    put(&mut vm, 60, &[0x55, 0x55]);
    scan(&mut vm);
    assert_eq!((read(&vm, "MB60"), read(&vm, "MB61")), (0x12, 0x55));
    assert_eq!(read(&vm, "SM1.1"), 1);
    put(&mut vm, 40, b"1X");
    put(&mut vm, 60, &[0x55, 0x55]);
    scan(&mut vm);
    assert_eq!((read(&vm, "MB60"), read(&vm, "MB61")), (0x10, 0x55));
    assert_eq!(read(&vm, "SM1.1"), 1);
}

#[test]
fn ath_variable_len_and_area_end() {
    let mut vm = vm_for("ATH MB40, MB60, MB5");
    put(&mut vm, 40, b"12");
    set(&mut vm, "SM1.1", 1);
    scan(&mut vm);
    assert_eq!(read(&vm, "MB60"), 0, "LEN 0 converts nothing");
    assert_eq!(read(&vm, "SM1.1"), 0);

    // M has 128 bytes: MB126 + 4 runs past its end.
    let mut vm = vm_for("ATH MB126, MB60, 4");
    put(&mut vm, 126, b"12");
    put(&mut vm, 60, &[0x55]);
    scan(&mut vm);
    assert_eq!((read(&vm, "MB60"), read(&vm, "SM1.1")), (0x55, 1));
}

#[test]
fn hta_examples() {
    let mut vm = vm_for("HTA MB60, MB40, 4");
    put(&mut vm, 60, &[0x1A, 0x2F]);
    set(&mut vm, "SM1.1", 1);
    scan(&mut vm);
    assert_eq!(text(&vm, 40, 4), "1A2F");
    assert_eq!(read(&vm, "SM1.1"), 0);

    let mut vm = vm_for("HTA MB60, MB40, 3");
    put(&mut vm, 60, &[0xB7, 0x9E]);
    put(&mut vm, 40, b"____");
    scan(&mut vm);
    assert_eq!(text(&vm, 40, 4), "B79_");

    let mut vm = vm_for("HTA MB60, MB125, 4");
    put(&mut vm, 125, b"___");
    scan(&mut vm);
    assert_eq!((text(&vm, 125, 3).as_str(), read(&vm, "SM1.1")), ("___", 1));
}

/// Run `MNEMONIC MD/MW0, MB40, FMT` with IN = `v`; the text and SM1.1.
fn to_ascii(mnemonic: &str, v: u32, fmt: u32, n: u32) -> (String, u32) {
    let input = match mnemonic {
        "ITA" => "MW0",
        _ => "MD0",
    };
    let mut vm = vm_for(&format!("{mnemonic} {input}, MB40, MB4"));
    set(&mut vm, input, v);
    set(&mut vm, "MB4", fmt);
    put(&mut vm, 40, &[b'_'; 16]);
    scan(&mut vm);
    (text(&vm, 40, n), read(&vm, "SM1.1"))
}

fn ok(s: &str) -> (String, u32) {
    (s.to_string(), 0)
}

#[test]
fn ita_examples() {
    let ita = |v: i16, fmt: u32| to_ascii("ITA", v as u16 as u32, fmt, 8);
    assert_eq!(ita(12345, 0x0B), ok("  12,345"));
    assert_eq!(ita(5, 0x02), ok("    0.05"));
    assert_eq!(ita(-5, 0x02), ok("   -0.05"));
    assert_eq!(ita(-32768, 0x05), ok("-0.32768"));
    assert_eq!(ita(32767, 0x00), ok("   32767"));
    assert_eq!(ita(0, 0x00), ok("       0"));
    assert_eq!(ita(-7, 0x0C), ok(" -0,0007"));
    assert_eq!(ita(123, 0x06), ("________".into(), 1), "6 decimals");
    assert_eq!(ita(123, 0x12), ("________".into(), 1), "bits 7..4");
}

#[test]
fn dta_examples() {
    let dta = |v: i32, fmt: u32| to_ascii("DTA", v as u32, fmt, 12);
    assert_eq!(dta(-123_456, 0x02), ok("    -1234.56"));
    assert_eq!(dta(i32::MIN, 0x05), ok("-21474.83648"));
    assert_eq!(dta(i32::MAX, 0x00), ok("  2147483647"));
    assert_eq!(dta(1, 0x0D), ok("     0,00001"));
    assert_eq!(dta(1, 0x07), ("____________".into(), 1));
}

#[test]
fn ita_past_the_area_end_writes_nothing() {
    let mut vm = vm_for("ITA MW0, MB124, 0");
    put(&mut vm, 124, b"____");
    scan(&mut vm);
    assert_eq!(
        (text(&vm, 124, 4).as_str(), read(&vm, "SM1.1")),
        ("____", 1)
    );
}

fn rta(x: f32, fmt: u32) -> (String, u32) {
    to_ascii("RTA", x.to_bits(), fmt, (fmt >> 4).max(1))
}

#[test]
fn rta_examples() {
    assert_eq!(rta(1.23456, 0xA2), ok("      1.23"));
    assert_eq!(rta(2.5, 0x30), ok("  3"), "halves away from zero");
    assert_eq!(rta(-2.5, 0x30), ok(" -3"));
    assert_eq!(rta(0.125, 0x52), ok(" 0.13"), "0.125 is exact: a half");
    assert_eq!(rta(0.005, 0x52), ok(" 0.00"), "0.005 is a little below");
    assert_eq!(rta(-0.001, 0x52), ok(" 0.00"), "rounds to zero: no sign");
    assert_eq!(rta(-1.5, 0x69), ok("  -1,5"));
    assert_eq!(rta(1234.5, 0x41), ("****".into(), 1), "does not fit");
    assert_eq!(rta(-999.9, 0x51), ("*****".into(), 1), "-999.9 needs 6");
    assert_eq!(rta(f32::NAN, 0x31), ("***".into(), 1));
    assert_eq!(rta(f32::INFINITY, 0x31), ("***".into(), 1));
    assert_eq!(rta(1e20, 0xF0), ("*".repeat(15), 1));
    assert_eq!(rta(1.0, 0x20), ("__".into(), 1), "size 2");
    assert_eq!(
        rta(1.0, 0x32),
        ("___".into(), 1),
        "size not above decimals + 1"
    );
    assert_eq!(rta(1.0, 0x36), ("___".into(), 1), "6 decimals");
}

/// x * 10^d is exact in f64 for a REAL and d <= 5 (24 + 17 bits), so f64::round is
/// an exact model of halves away from zero.
#[test]
fn rta_rounds_like_an_exact_model_over_a_grid() {
    let mut values = vec![0.0f32, 0.5, 1.5, 0.045, 2.675, 1e-10, 123_456.8, 12_345.675];
    for k in 0..200 {
        values.push(k as f32 * 0.0125 - 1.3);
        values.push((k as f32).powi(3) / 7.0);
    }
    for x in values {
        for d in 0..=5u32 {
            let scaled = (f64::from(x) * 10f64.powi(d as i32)).round().abs() as u128;
            let digits = format!("{scaled:0w$}", w = d as usize + 1);
            let (int, frac) = digits.split_at(digits.len() - d as usize);
            let sign = if x < 0.0 && scaled != 0 { "-" } else { "" };
            let body = if d == 0 {
                format!("{sign}{int}")
            } else {
                format!("{sign}{int}.{frac}")
            };
            let want = if body.len() <= 15 {
                (format!("{body:>15}"), 0)
            } else {
                ("*".repeat(15), 1)
            };
            assert_eq!(rta(x, 0xF0 | d), want, "x = {x}, d = {d}");
        }
    }
}
