//! Integer and real math and word logic. S7-200 order: `+I IN1, OUT` is OUT := OUT +
//! IN1. Integer results wrap and set SM1.1 on overflow; SM1.0 zero, SM1.2 negative;
//! add, subtract and multiply write SM1.0..SM1.2 only. Divisions write SM1.0..SM1.3: by
//! zero, SM1.3 set, the others cleared and OUT unchanged; the one integer overflow,
//! MIN divided by -1, sets SM1.1 and leaves OUT unchanged (ManagerFun.xml).

use super::{Control, Exec, Handler};
use crate::fault::Fault;

/// Store a signed result in OUT (operand `out`) of `bits` width, with flags.
fn store_int(e: &mut Exec<'_>, out: usize, exact: i64, bits: u32) -> Result<Control, Fault> {
    let (lo, hi) = (-(1i64 << (bits - 1)), (1i64 << (bits - 1)) - 1);
    let wrapped = ((exact as i128).rem_euclid(1i128 << bits)) as i64;
    let signed = if wrapped > hi {
        wrapped - (1i64 << bits)
    } else {
        wrapped
    };
    e.set(out, wrapped as u32)?;
    e.flags(signed == 0, !(lo..=hi).contains(&exact), signed < 0);
    Ok(Control::Next)
}

/// + - *: OUT := OUT op IN1, wrapped, flags SM1.0..SM1.2.
fn arith(e: &mut Exec<'_>, bits: u32, f: fn(i64, i64) -> i64) -> Result<Control, Fault> {
    let (a, b) = (e.get_signed(1)?, e.get_signed(0)?);
    store_int(e, 1, f(a, b), bits)
}

/// /I /D: OUT := OUT / IN1 truncated; SM1.3 written.
fn divide(e: &mut Exec<'_>, bits: u32) -> Result<Control, Fault> {
    let (a, b) = (e.get_signed(1)?, e.get_signed(0)?);
    if b == 0 {
        e.divide_by_zero();
        return Ok(Control::Next);
    }
    e.clear_divide();
    let q = a / b;
    if q > (1i64 << (bits - 1)) - 1 {
        // MIN / -1: OUT unchanged.
        e.flags(false, true, false);
        return Ok(Control::Next);
    }
    store_int(e, 1, q, bits)
}

fn add_i(e: &mut Exec<'_>) -> Result<Control, Fault> {
    arith(e, 16, |a, b| a + b)
}
fn sub_i(e: &mut Exec<'_>) -> Result<Control, Fault> {
    arith(e, 16, |a, b| a - b)
}
fn mul_i(e: &mut Exec<'_>) -> Result<Control, Fault> {
    arith(e, 16, |a, b| a * b)
}
fn div_i(e: &mut Exec<'_>) -> Result<Control, Fault> {
    divide(e, 16)
}
fn add_d(e: &mut Exec<'_>) -> Result<Control, Fault> {
    arith(e, 32, |a, b| a + b)
}
fn sub_d(e: &mut Exec<'_>) -> Result<Control, Fault> {
    arith(e, 32, |a, b| a - b)
}
fn mul_d(e: &mut Exec<'_>) -> Result<Control, Fault> {
    arith(e, 32, |a, b| a * b)
}
fn div_d(e: &mut Exec<'_>) -> Result<Control, Fault> {
    divide(e, 32)
}

/// MUL IN1, OUT: OUT (DINT) := IN1 (INT) x low word of OUT (INT).
fn mul(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let a = e.get_signed(0)?;
    let b = e.get(1)? as u16 as i16 as i64;
    store_int(e, 1, a * b, 32)
}

/// DIV IN1, OUT: low word of OUT / IN1; quotient to the low word, remainder high.
fn div(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let d = e.get_signed(0)?;
    let n = e.get(1)? as u16 as i16 as i64;
    if d == 0 {
        e.divide_by_zero();
        return Ok(Control::Next);
    }
    e.clear_divide();
    if n == -32768 && d == -1 {
        // The one overflow: OUT unchanged.
        e.flags(false, true, false);
        return Ok(Control::Next);
    }
    let (q, r) = (n.wrapping_div(d), n.wrapping_rem(d));
    let v = ((r as u16 as u32) << 16) | (q as u16 as u32);
    e.set(1, v)?;
    e.flags(q == 0, !(-32768..=32767).contains(&q), q < 0);
    Ok(Control::Next)
}

fn step(e: &mut Exec<'_>, delta: i64) -> Result<Control, Fault> {
    let w = e.width(0)?.bits();
    if w == 8 {
        // INCB/DECB work on unsigned bytes.
        let v = e.get(0)? as i64 + delta;
        let r = v.rem_euclid(256);
        e.set(0, r as u32)?;
        e.flags(r == 0, !(0..=255).contains(&v), false);
        return Ok(Control::Next);
    }
    let v = e.get_signed(0)? + delta;
    store_int(e, 0, v, w)
}
fn inc(e: &mut Exec<'_>) -> Result<Control, Fault> {
    step(e, 1)
}
fn dec(e: &mut Exec<'_>) -> Result<Control, Fault> {
    step(e, -1)
}

fn real(e: &mut Exec<'_>, f: fn(f32, f32) -> f32) -> Result<Control, Fault> {
    let (a, b) = (e.get_real(1)?, e.get_real(0)?);
    let r = f(a, b);
    e.set(1, r.to_bits())?;
    e.flags(r == 0.0, !r.is_finite(), r < 0.0);
    Ok(Control::Next)
}
fn add_r(e: &mut Exec<'_>) -> Result<Control, Fault> {
    real(e, |a, b| a + b)
}
fn sub_r(e: &mut Exec<'_>) -> Result<Control, Fault> {
    real(e, |a, b| a - b)
}
fn mul_r(e: &mut Exec<'_>) -> Result<Control, Fault> {
    real(e, |a, b| a * b)
}
fn div_r(e: &mut Exec<'_>) -> Result<Control, Fault> {
    if e.get_real(0)? == 0.0 {
        e.divide_by_zero();
        return Ok(Control::Next);
    }
    e.clear_divide();
    real(e, |a, b| a / b)
}
fn sqrt(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let r = e.get_real(0)?.sqrt();
    e.set(1, r.to_bits())?;
    e.flags(r == 0.0, !r.is_finite(), false);
    Ok(Control::Next)
}

fn logic(e: &mut Exec<'_>, f: fn(u32, u32) -> u32) -> Result<Control, Fault> {
    let w = e.width(1)?.bits();
    let mask = if w >= 32 { u32::MAX } else { (1u32 << w) - 1 };
    let r = f(e.get(1)?, e.get(0)?) & mask;
    e.set(1, r)?;
    e.flags(r == 0, false, false);
    Ok(Control::Next)
}
fn and(e: &mut Exec<'_>) -> Result<Control, Fault> {
    logic(e, |a, b| a & b)
}
fn or(e: &mut Exec<'_>) -> Result<Control, Fault> {
    logic(e, |a, b| a | b)
}
fn xor(e: &mut Exec<'_>) -> Result<Control, Fault> {
    logic(e, |a, b| a ^ b)
}
fn inv(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let w = e.width(0)?.bits();
    let mask = if w >= 32 { u32::MAX } else { (1u32 << w) - 1 };
    let r = !e.get(0)? & mask;
    e.set(0, r)?;
    e.flags(r == 0, false, false);
    Ok(Control::Next)
}

pub fn lookup(m: &str) -> Option<Handler> {
    Some(match m {
        "+I" => add_i,
        "-I" => sub_i,
        "*I" => mul_i,
        "/I" => div_i,
        "+D" => add_d,
        "-D" => sub_d,
        "*D" => mul_d,
        "/D" => div_d,
        "MUL" => mul,
        "DIV" => div,
        "INCB" | "INCW" | "INCD" => inc,
        "DECB" | "DECW" | "DECD" => dec,
        "+R" => add_r,
        "-R" => sub_r,
        "*R" => mul_r,
        "/R" => div_r,
        "SQRT" => sqrt,
        "ANDB" | "ANDW" | "ANDD" => and,
        "ORB" | "ORW" | "ORD" => or,
        "XORB" | "XORW" | "XORD" => xor,
        "INVB" | "INVW" | "INVD" => inv,
        _ => return None,
    })
}
