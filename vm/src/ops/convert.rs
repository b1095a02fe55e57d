//! Conversions (BTI, ITB, ITD, DTI, DTR, ROUND, TRUNC, BCDI, IBCD, SEG, DECO, ENCO) and
//! real functions (SIN, COS, TAN, LN, EXP), as ManagerFun.xml describes them. IN is
//! operand 0 and OUT operand 1 (BCDI/IBCD: OUT is operand 0). A conversion that cannot
//! be done sets SM1.1 (SM1.6 for BCD) and leaves OUT unchanged; the flags an
//! instruction names are written on every execution, the others keep their values.

use super::{Control, Exec, Handler};
use crate::fault::Fault;

/// BTI: the unsigned byte to an INT.
fn bti(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let v = e.get(0)? & 0xFF;
    e.set(1, v)?;
    Ok(Control::Next)
}

/// ITB: the INT when 0..255, else SM1.1 and OUT unchanged.
fn itb(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let v = e.get(0)? as u16 as i16;
    let ok = (0..=255).contains(&v);
    if ok {
        e.set(1, v as u32)?;
    }
    e.flag(1, !ok);
    Ok(Control::Next)
}

/// ITD: sign-extend the INT to a DINT.
fn itd(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let v = e.get(0)? as u16 as i16 as i32;
    e.set(1, v as u32)?;
    Ok(Control::Next)
}

/// DTI: the DINT when it fits an INT, else SM1.1 and OUT unchanged.
fn dti(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let v = e.get(0)? as i32;
    let ok = i16::try_from(v).is_ok();
    if ok {
        e.set(1, v as u16 as u32)?;
    }
    e.flag(1, !ok);
    Ok(Control::Next)
}

/// DTR: the DINT to the nearest REAL (ties to even, as Rust's `as` does).
fn dtr(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let v = e.get(0)? as i32;
    e.set(1, (v as f32).to_bits())?;
    Ok(Control::Next)
}

/// A REAL already rounded to an integer into a DINT, or SM1.1 when it does not fit.
fn real_to_dint(e: &mut Exec<'_>, r: f32) -> Result<Control, Fault> {
    // -2^31 and 2^31 are exact in f32; a finite integral r in [-2^31, 2^31) fits.
    let ok = r.is_finite() && (-2_147_483_648.0..2_147_483_648.0).contains(&r);
    if ok {
        e.set(1, (r as i32) as u32)?;
    }
    e.flag(1, !ok);
    Ok(Control::Next)
}

/// ROUND: nearest integer, halves away from zero (`f32::round`).
fn round(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let r = e.get_real(0)?.round();
    real_to_dint(e, r)
}

/// TRUNC: toward zero.
fn trunc(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let r = e.get_real(0)?.trunc();
    real_to_dint(e, r)
}

/// BCDI: four BCD digits to their value; a digit above 9 sets SM1.6.
fn bcdi(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let v = e.get(0)? & 0xFFFF;
    let digits = [(v >> 12) & 0xF, (v >> 8) & 0xF, (v >> 4) & 0xF, v & 0xF];
    let ok = digits.iter().all(|d| *d <= 9);
    if ok {
        let n = digits.iter().fold(0, |acc, d| acc * 10 + d);
        e.set(0, n)?;
    }
    e.flag(6, !ok);
    Ok(Control::Next)
}

/// IBCD: an INT 0..9999 to four BCD digits; other values set SM1.6.
fn ibcd(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let v = e.get(0)? as u16 as i16;
    let ok = (0..=9999).contains(&v);
    if ok {
        let v = v as u32;
        let bcd = ((v / 1000) << 12) | ((v / 100 % 10) << 8) | ((v / 10 % 10) << 4) | (v % 10);
        e.set(0, bcd)?;
    }
    e.flag(6, !ok);
    Ok(Control::Next)
}

/// Seven-segment patterns of 0..F (bit 0 = segment a, ..., bit 6 = segment g).
const SEGMENTS: [u32; 16] = [
    0x3F, 0x06, 0x5B, 0x4F, 0x66, 0x6D, 0x7D, 0x07, 0x7F, 0x6F, 0x77, 0x7C, 0x39, 0x5E, 0x79, 0x71,
];

fn seg(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let v = e.get(0)? & 0xF;
    e.set(1, SEGMENTS[v as usize])?;
    Ok(Control::Next)
}

/// DECO: OUT := 1 << (IN & 16#0F).
fn deco(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let v = e.get(0)? & 0xF;
    e.set(1, 1 << v)?;
    Ok(Control::Next)
}

/// ENCO: the number of the lowest set bit of the word; IN = 0 sets SM1.1.
fn enco(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let v = e.get(0)? & 0xFFFF;
    if v != 0 {
        e.set(1, v.trailing_zeros())?;
    }
    e.flag(1, v == 0);
    Ok(Control::Next)
}

/// A real function: computed in f64 from the REAL operand and rounded to f32 (more
/// precise than the f32 routines), stored even when not finite. SM1.0 zero, SM1.1
/// not finite, SM1.2 negative (both 0 for NaN).
fn real_fn(e: &mut Exec<'_>, f: fn(f64) -> f64) -> Result<Control, Fault> {
    let x = e.get_real(0)?;
    let r = f(f64::from(x)) as f32;
    e.set(1, r.to_bits())?;
    e.flags(r == 0.0, !r.is_finite(), r < 0.0);
    Ok(Control::Next)
}
fn sin(e: &mut Exec<'_>) -> Result<Control, Fault> {
    real_fn(e, f64::sin)
}
fn cos(e: &mut Exec<'_>) -> Result<Control, Fault> {
    real_fn(e, f64::cos)
}
fn tan(e: &mut Exec<'_>) -> Result<Control, Fault> {
    real_fn(e, f64::tan)
}
fn ln(e: &mut Exec<'_>) -> Result<Control, Fault> {
    real_fn(e, f64::ln)
}
fn exp(e: &mut Exec<'_>) -> Result<Control, Fault> {
    real_fn(e, f64::exp)
}

pub fn lookup(m: &str) -> Option<Handler> {
    Some(match m {
        "BTI" => bti,
        "ITB" => itb,
        "ITD" => itd,
        "DTI" => dti,
        "DTR" => dtr,
        "ROUND" => round,
        "TRUNC" => trunc,
        "BCDI" => bcdi,
        "IBCD" => ibcd,
        "SEG" => seg,
        "DECO" => deco,
        "ENCO" => enco,
        "SIN" => sin,
        "COS" => cos,
        "TAN" => tan,
        "LN" => ln,
        "EXP" => exp,
        _ => return None,
    })
}
