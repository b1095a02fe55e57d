//! The ASCII conversions checked against an exact model over a grid of values (RTA's
//! rounding), which needs Rust to compute the expected text. Every other special
//! instruction test (immediate I/O, BITIM/CITIM, CEVNT, the ATH/HTA/ITA/DTA/RTA
//! examples) is run-corpus data in tests/data/run.

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

/// Run `RTA MD0, MB40, MB4` with IN = `x`, FMT = `fmt`: the buffer's text (its size,
/// at least 1 character; the bytes around it start as `_`) and SM1.1.
fn rta(x: f32, fmt: u32) -> (String, u32) {
    let mut vm = vm_for("RTA MD0, MB40, MB4");
    set(&mut vm, "MD0", x.to_bits());
    set(&mut vm, "MB4", fmt);
    put(&mut vm, 40, &[b'_'; 16]);
    vm.scan().expect("scan");
    (text(&vm, 40, (fmt >> 4).max(1)), read(&vm, "SM1.1"))
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
