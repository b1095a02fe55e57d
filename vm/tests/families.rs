//! Shifts and rotates, conversions, real functions and table searches checked over
//! grids of values against Rust's own operations (or a model written from
//! ManagerFun.xml's descriptions). These stay in Rust because Rust computes the
//! expected values; the single examples of these families (the catalog's shift and
//! SHRB examples, boxes without power, ATT/FIFO/LIFO, illegal tables, FND's next
//! match) are run-corpus data in tests/data/run.

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

/// SM1.0 .. SM1.6 as a string of 0/1, SM1.0 first.
fn sm1(vm: &Vm) -> String {
    (0..7)
        .map(|b| char::from(b'0' + read(vm, &format!("SM1.{b}")) as u8))
        .collect()
}

// ---- shifts and rotates ---------------------------------------------------------------

/// Expected (result, zero, bit out) of a shift or rotate, written from the catalog text.
fn shift_model(kind: &str, w: u32, v: u32, n: u32) -> (u32, bool, bool) {
    let m = if w == 32 { u32::MAX } else { (1 << w) - 1 };
    let v = v & m;
    let (r, out) = match kind {
        "SR" => (
            if n >= w { 0 } else { v >> n },
            (1..=w).contains(&n) && v >> (n - 1) & 1 == 1,
        ),
        "SL" => (
            if n >= w { 0 } else { (v << n) & m },
            (1..=w).contains(&n) && v >> (w - n) & 1 == 1,
        ),
        "RR" | "RL" => {
            let k = n % w;
            let r = match (w, kind) {
                (8, "RR") => (v as u8).rotate_right(k) as u32,
                (8, _) => (v as u8).rotate_left(k) as u32,
                (16, "RR") => (v as u16).rotate_right(k) as u32,
                (16, _) => (v as u16).rotate_left(k) as u32,
                (_, "RR") => v.rotate_right(k),
                _ => v.rotate_left(k),
            };
            let out = k != 0
                && if kind == "RR" {
                    r >> (w - 1) & 1 == 1
                } else {
                    r & 1 == 1
                };
            (r, out)
        }
        _ => unreachable!(),
    };
    (r, r == 0, out)
}

#[test]
fn shifts_and_rotates_match_a_model_over_a_grid() {
    let values: [u32; 10] = [
        0,
        1,
        0x80,
        0x8001,
        0x1234_5678,
        0xFFFF_FFFF,
        0x8000_0000,
        0xA5A5,
        0x7F,
        0xDEAD_BEEF,
    ];
    for (suffix, w, var) in [("B", 8, "MB0"), ("W", 16, "MW0"), ("D", 32, "MD0")] {
        for kind in ["SR", "SL", "RR", "RL"] {
            let mut vm = vm_for(&format!("{kind}{suffix} {var}, MB10"));
            for &v in &values {
                for n in (0..=40).chain([63, 64, 200, 255]) {
                    let v = if w == 32 { v } else { v & ((1 << w) - 1) };
                    set(&mut vm, var, v);
                    set(&mut vm, "MB10", n);
                    set(&mut vm, "SM1.2", 1);
                    scan(&mut vm);
                    let (r, z, out) = shift_model(kind, w, v, n);
                    let what = format!("{kind}{suffix} {v:#x}, {n}");
                    assert_eq!(read(&vm, var), r, "{what}");
                    assert_eq!(read(&vm, "SM1.0") == 1, z, "{what}: SM1.0");
                    assert_eq!(read(&vm, "SM1.1") == 1, out, "{what}: SM1.1");
                    assert_eq!(read(&vm, "SM1.2"), 1, "{what}: SM1.2 is not written");
                }
            }
        }
    }
}

// ---- conversions -------------------------------------------------------------------

#[test]
fn integer_conversions_over_a_grid() {
    let mut vm = vm_for("ITD MW0, MD4");
    for v in (-32768i32..=32767)
        .step_by(97)
        .chain([-1, 0, 1, 32767, -32768])
    {
        set(&mut vm, "MW0", v as u16 as u32);
        scan(&mut vm);
        assert_eq!(read(&vm, "MD4") as i32, v, "ITD {v}");
    }
    let mut vm = vm_for("DTI MD0, MW4");
    let grid = (-70000i64..=70000)
        .step_by(331)
        .chain([
            i32::MIN as i64,
            i32::MAX as i64,
            -32769,
            -32768,
            32767,
            32768,
            0,
        ])
        .map(|v| v as i32);
    for v in grid {
        set(&mut vm, "MW4", 0xABCD);
        set(&mut vm, "MD0", v as u32);
        scan(&mut vm);
        match i16::try_from(v) {
            Ok(s) => {
                assert_eq!(read(&vm, "MW4"), s as u16 as u32, "DTI {v}");
                assert_eq!(read(&vm, "SM1.1"), 0);
            }
            Err(_) => {
                assert_eq!(read(&vm, "MW4"), 0xABCD, "DTI {v} leaves OUT");
                assert_eq!(read(&vm, "SM1.1"), 1);
            }
        }
    }
    let mut vm = vm_for("BTI MB0, MW2\nITB MW4, MB6");
    for v in [0u32, 1, 127, 128, 255] {
        set(&mut vm, "MB0", v);
        scan(&mut vm);
        assert_eq!(read(&vm, "MW2"), v);
    }
    for (v, ok) in [
        (0i32, true),
        (255, true),
        (256, false),
        (-1, false),
        (100, true),
    ] {
        set(&mut vm, "MB6", 0x5A);
        set(&mut vm, "MW4", v as u16 as u32);
        scan(&mut vm);
        assert_eq!(
            read(&vm, "MB6"),
            if ok { v as u32 } else { 0x5A },
            "ITB {v}"
        );
        assert_eq!(read(&vm, "SM1.1") == 0, ok);
    }
}

#[test]
fn dtr_rounds_to_nearest_even() {
    let mut vm = vm_for("DTR MD0, MD4");
    for v in [
        0i32,
        1,
        -1,
        16_777_217,
        -16_777_219,
        i32::MAX,
        i32::MIN,
        123_456_789,
    ] {
        set(&mut vm, "MD0", v as u32);
        scan(&mut vm);
        assert_eq!(f32::from_bits(read(&vm, "MD4")), v as f32, "DTR {v}");
    }
    set(&mut vm, "MD0", 16_777_217);
    scan(&mut vm);
    assert_eq!(
        f32::from_bits(read(&vm, "MD4")),
        16_777_216.0,
        "tie to even"
    );
}

#[test]
fn round_and_trunc_over_a_grid() {
    let mut reals: Vec<f32> = (-400..=400).map(|i| i as f32 * 0.25).collect();
    reals.extend([
        0.49999997,
        -0.49999997,
        2.5,
        -2.5,
        2.7,
        -2.7,
        1e9,
        -1e9,
        2_147_483_520.0,  // largest f32 below 2^31
        2_147_483_648.0,  // 2^31: too large
        -2_147_483_648.0, // -2^31: fits
        -2_147_483_904.0, // below -2^31
        1e20,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        -0.0,
        f32::MIN_POSITIVE,
    ]);
    for (name, f) in [
        ("ROUND", f64::round as fn(f64) -> f64),
        ("TRUNC", f64::trunc),
    ] {
        let mut vm = vm_for(&format!("{name} MD0, MD4"));
        for &x in &reals {
            set(&mut vm, "MD4", 0x5555_5555);
            set(&mut vm, "MD0", x.to_bits());
            scan(&mut vm);
            let exact = f(f64::from(x));
            let fits = exact.is_finite() && exact >= i32::MIN as f64 && exact <= i32::MAX as f64;
            if fits {
                assert_eq!(read(&vm, "MD4") as i32, exact as i32, "{name} {x}");
            } else {
                assert_eq!(read(&vm, "MD4"), 0x5555_5555, "{name} {x} leaves OUT");
            }
            assert_eq!(read(&vm, "SM1.1") == 0, fits, "{name} {x}: SM1.1");
        }
    }
    let mut vm = vm_for("ROUND MD0, MD4\nTRUNC MD0, MD8");
    for (x, r, t) in [(2.5f32, 3, 2), (-2.5, -3, -2), (2.7, 3, 2), (-2.7, -3, -2)] {
        set(&mut vm, "MD0", x.to_bits());
        scan(&mut vm);
        assert_eq!(
            (read(&vm, "MD4") as i32, read(&vm, "MD8") as i32),
            (r, t),
            "{x}"
        );
    }
}

#[test]
fn bcd_over_all_words() {
    let mut vm =
        vm_for("MOVW MW0, MW2\nBCDI MW2\nMOVW MW0, MW4\nIBCD MW4\nNETWORK 2\nLD SM0.0\nBCDI MW6");
    for v in (0u32..=0xFFFF)
        .step_by(7)
        .chain([0x9999, 0x1234, 9999, 10000])
    {
        set(&mut vm, "MW0", v);
        set(&mut vm, "MW6", v);
        scan(&mut vm);
        // BCDI: the hex digits read as decimal.
        let text = format!("{v:04x}");
        match text.parse::<u32>() {
            Ok(d) if text.chars().all(|c| c.is_ascii_digit()) => {
                assert_eq!(read(&vm, "MW2"), d, "BCDI {v:#06x}");
                assert_eq!(read(&vm, "SM1.6"), 0, "BCDI {v:#06x}");
            }
            _ => {
                assert_eq!(read(&vm, "MW2"), v, "BCDI {v:#06x} leaves OUT");
                assert_eq!(read(&vm, "SM1.6"), 1, "BCDI {v:#06x}");
            }
        }
        // IBCD: the decimal digits read as hex.
        if v <= 9999 {
            let want = u32::from_str_radix(&v.to_string(), 16).unwrap();
            assert_eq!(read(&vm, "MW4"), want, "IBCD {v}");
        } else {
            assert_eq!(read(&vm, "MW4"), v, "IBCD {v} leaves OUT");
        }
    }
    let mut vm = vm_for("IBCD MW0");
    for (v, ok) in [(0i32, true), (9999, true), (10000, false), (-1, false)] {
        set(&mut vm, "MW0", v as u16 as u32);
        scan(&mut vm);
        assert_eq!(read(&vm, "SM1.6") == 0, ok, "IBCD {v}");
    }
}

#[test]
fn seg_deco_enco() {
    let table = [
        0x3F, 0x06, 0x5B, 0x4F, 0x66, 0x6D, 0x7D, 0x07, 0x7F, 0x6F, 0x77, 0x7C, 0x39, 0x5E, 0x79,
        0x71,
    ];
    let mut vm = vm_for("SEG MB0, MB1\nDECO MB0, MW2");
    for v in 0u32..=255 {
        set(&mut vm, "MB0", v);
        scan(&mut vm);
        assert_eq!(read(&vm, "MB1"), table[(v & 15) as usize], "SEG {v}");
        assert_eq!(read(&vm, "MW2"), 1 << (v & 15), "DECO {v}");
    }
    let mut vm = vm_for("ENCO MW0, MB2");
    for v in 1u32..=0xFFFF {
        set(&mut vm, "MW0", v);
        scan(&mut vm);
        assert_eq!(read(&vm, "MB2"), v.trailing_zeros(), "ENCO {v:#x}");
        assert_eq!(read(&vm, "SM1.1"), 0);
    }
    set(&mut vm, "MW0", 0);
    set(&mut vm, "MB2", 99);
    scan(&mut vm);
    assert_eq!(read(&vm, "MB2"), 99, "ENCO 0 leaves OUT");
    assert_eq!(read(&vm, "SM1.1"), 1);
}

/// Instruction, operand, check of the result, expected SM1.0..SM1.2 ("" = any).
type RealCase = (&'static str, f32, fn(f32) -> bool, &'static str);

#[test]
fn real_functions() {
    let cases: [RealCase; 14] = [
        ("SIN", 0.0, |r| r == 0.0, "100"),
        ("SIN", std::f32::consts::FRAC_PI_2, |r| r == 1.0, "000"),
        ("SIN", -1.0, |r| (r + 0.841_470_96).abs() < 1e-6, "001"),
        ("SIN", f32::INFINITY, f32::is_nan, "010"),
        ("COS", 0.0, |r| r == 1.0, "000"),
        ("COS", std::f32::consts::PI, |r| r == -1.0, "001"),
        (
            "TAN",
            std::f32::consts::FRAC_PI_2,
            |r| r.is_finite() && r.abs() > 1e6,
            "",
        ),
        ("TAN", f32::NEG_INFINITY, f32::is_nan, "010"),
        ("LN", 1.0, |r| r == 0.0, "100"),
        ("LN", 0.0, |r| r == f32::NEG_INFINITY, "011"),
        ("LN", -1.0, f32::is_nan, "010"),
        ("EXP", 1.0, |r| r == std::f32::consts::E, "000"),
        ("EXP", 100.0, |r| r == f32::INFINITY, "010"),
        ("EXP", f32::NAN, f32::is_nan, "010"),
    ];
    for (name, x, ok, flags) in cases {
        let mut vm = vm_for(&format!("{name} MD0, MD4"));
        set(&mut vm, "MD0", x.to_bits());
        set(&mut vm, "SM1.3", 1);
        scan(&mut vm);
        let r = f32::from_bits(read(&vm, "MD4"));
        assert!(ok(r), "{name} {x} gave {r}");
        if !flags.is_empty() {
            assert_eq!(&sm1(&vm)[..3], flags, "{name} {x}");
        }
        assert_eq!(
            read(&vm, "SM1.3"),
            1,
            "{name}: other flags keep their values"
        );
    }
}

// ---- tables ------------------------------------------------------------------------

type Rel = fn(i16, i16) -> bool;

#[test]
fn find_searches_from_indx() {
    let mut vm = vm_for("FND= MW100, MW50, MW60\nFND<> MW100, MW50, MW62\nFND< MW100, MW50, MW64\nFND> MW100, MW50, MW66");
    let entries: [i16; 6] = [5, -3, 500, 7, 500, -40];
    set(&mut vm, "MW100", 10);
    set(&mut vm, "MW102", entries.len() as u32);
    for (i, v) in entries.iter().enumerate() {
        set(&mut vm, &format!("MW{}", 104 + 2 * i), *v as u16 as u32);
    }
    set(&mut vm, "MW116", 500); // beyond the count: never found
    for ptn in [-40i16, -3, 0, 5, 7, 500, 1000] {
        for start in [-5i16, 0, 1, 2, 3, 4, 5, 6, 7] {
            for var in ["MW60", "MW62", "MW64", "MW66"] {
                set(&mut vm, var, start as u16 as u32);
            }
            set(&mut vm, "MW50", ptn as u16 as u32);
            scan(&mut vm);
            let rels: [(&str, Rel); 4] = [
                ("MW60", |a, b| a == b),
                ("MW62", |a, b| a != b),
                ("MW64", |a, b| a < b),
                ("MW66", |a, b| a > b),
            ];
            for (var, rel) in rels {
                let from = start.max(0) as usize;
                let want = (from..entries.len())
                    .find(|&i| rel(entries[i], ptn))
                    .unwrap_or(entries.len());
                assert_eq!(read(&vm, var), want as u32, "{var} ptn {ptn} from {start}");
            }
            assert_eq!(read(&vm, "SM1.1"), 0);
        }
    }
}
