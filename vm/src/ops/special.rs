//! Immediate byte I/O (BIR, BIW), the interval timer (BITIM, CITIM), clearing a pending
//! event (CEVNT) and the ASCII conversions (ATH, HTA, ITA, DTA, RTA), as ManagerFun.xml
//! describes them.
//!
//! Immediate I/O: the VM's physical inputs are the input terminals the host sets
//! (`Vm::write` on I), so BIR reads the terminal byte with the force image laid over
//! it and leaves the input image (I memory) as it is. (Programs cannot write I and the
//! host sets terminals between scans, so today this equals reading IB.) The VM has no output terminals:
//! Q memory is both the output image and the physical outputs, so BIW writes Q memory
//! (a forced output bit gets its force value again at the end of the scan).
//!
//! The millisecond clock of BITIM/CITIM is the VM's virtual clock (ms since reset, low
//! 32 bits; it advances after each scan, so it reads the same during a whole scan).
//!
//! CEVNT drops the event's pending occurrence (the VM keeps at most one per event,
//! queued while interrupts are off); the ATCH association stays.
//!
//! ASCII buffers: every byte a conversion reads or writes must lie inside its area,
//! otherwise nothing is written and SM1.1 is set. SM1.1 is written on every execution,
//! the other flags keep their values. ATH: an illegal character stops the conversion;
//! the bytes completed before it are written, and when it stands in the low half of a
//! byte, that byte gets its high half and a low half of 0 (as for an odd LEN). A number
//! that rounds to zero is written without `-`.

use super::{Control, Exec, Handler};
use crate::fault::Fault;
use gutta_catalog::Address;
use gutta_catalog::Width;

fn bir(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let loc = e.locate(0)?;
    let at = loc.offset as usize;
    let v = match e.terminals.input_byte(loc.slot, at) {
        Some(byte) => byte,
        // Not an input area with terminals: its memory is all there is.
        None => e.read_at(loc)? as u8,
    };
    e.set(1, u32::from(v))?;
    Ok(Control::Next)
}

fn biw(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let v = e.get(0)? & 0xFF;
    e.set(1, v)?;
    Ok(Control::Next)
}

/// The free-running millisecond clock: the virtual clock modulo 2^32.
fn clock(e: &Exec<'_>) -> u32 {
    e.clock.ms as u32
}

fn bitim(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let now = clock(e);
    e.set(0, now)?;
    Ok(Control::Next)
}

fn citim(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let start = e.get(0)?;
    let now = clock(e);
    e.set(1, now.wrapping_sub(start))?;
    Ok(Control::Next)
}

fn cevnt(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let event = e.get(0)?;
    e.interrupts.pending.remove(&event);
    Ok(Control::Next)
}

// ---- ASCII buffers ----------------------------------------------------------------------

/// The `n` bytes starting at operand `i`'s location, if they lie inside its area.
fn buffer(e: &Exec<'_>, i: usize, n: usize) -> Result<Option<Address>, Fault> {
    let loc = e.locate(i)?;
    let len = e.machine.memory.area(loc.slot).map_or(0, <[u8]>::len);
    let fits = (loc.offset as usize)
        .checked_add(n)
        .is_some_and(|end| end <= len);
    Ok(fits.then_some(Address {
        width: Width::Byte,
        bit: 0,
        ..loc
    }))
}

fn read_bytes(e: &Exec<'_>, loc: Address, n: usize) -> Vec<u8> {
    let area = e.machine.memory.area(loc.slot).unwrap_or(&[]);
    area[loc.offset as usize..loc.offset as usize + n].to_vec()
}

fn write_bytes(e: &mut Exec<'_>, loc: Address, bytes: &[u8]) {
    if let Some(area) = e.machine.memory.area_mut(loc.slot) {
        let at = loc.offset as usize;
        area[at..at + bytes.len()].copy_from_slice(bytes);
    }
}

fn hex_value(c: u8) -> Option<u8> {
    (c as char).to_digit(16).map(|d| d as u8)
}

/// ATH IN, OUT, LEN: LEN hex characters into LEN/2 (rounded up) bytes.
fn ath(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let n = (e.get(2)? & 0xFF) as usize;
    let (Some(src), Some(dst)) = (buffer(e, 0, n)?, buffer(e, 1, n.div_ceil(2))?) else {
        e.flag(1, true);
        return Ok(Control::Next);
    };
    let chars = read_bytes(e, src, n);
    let digits: Vec<u8> = chars.iter().map_while(|c| hex_value(*c)).collect();
    let out: Vec<u8> = digits
        .chunks(2)
        .map(|p| (p[0] << 4) | p.get(1).copied().unwrap_or(0))
        .collect();
    write_bytes(e, dst, &out);
    e.flag(1, digits.len() < n);
    Ok(Control::Next)
}

/// HTA IN, OUT, LEN: LEN hex digits (high half first) into LEN characters.
fn hta(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let n = (e.get(2)? & 0xFF) as usize;
    let (Some(src), Some(dst)) = (buffer(e, 0, n.div_ceil(2))?, buffer(e, 1, n)?) else {
        e.flag(1, true);
        return Ok(Control::Next);
    };
    let bytes = read_bytes(e, src, n.div_ceil(2));
    let out: Vec<u8> = (0..n)
        .map(|k| {
            let b = bytes[k / 2];
            let d = if k % 2 == 0 { b >> 4 } else { b & 0xF };
            b"0123456789ABCDEF"[d as usize]
        })
        .collect();
    write_bytes(e, dst, &out);
    e.flag(1, false);
    Ok(Control::Next)
}

/// The text of `magnitude` / 10^`decimals` with its sign, e.g. `-1234.56`.
fn fixed_point(negative: bool, magnitude: u128, decimals: usize, sep: char) -> String {
    let digits = format!("{magnitude:0width$}", width = decimals + 1);
    let (int, frac) = digits.split_at(digits.len() - decimals);
    let sign = if negative && magnitude != 0 { "-" } else { "" };
    if decimals == 0 {
        format!("{sign}{int}")
    } else {
        format!("{sign}{int}{sep}{frac}")
    }
}

/// The separator and decimals of FMT bits 3..0, if the decimals are 0..5.
fn format_bits(fmt: u32) -> Option<(char, usize)> {
    let decimals = (fmt & 7) as usize;
    let sep = if fmt & 8 == 0 { '.' } else { ',' };
    (decimals <= 5).then_some((sep, decimals))
}

/// ITA/DTA: the integer IN as a fixed-point number right-aligned in `size` characters.
fn int_to_ascii(e: &mut Exec<'_>, size: usize) -> Result<Control, Fault> {
    let v = e.get_signed(0)?;
    let fmt = e.get(2)? & 0xFF;
    let format = format_bits(fmt).filter(|_| fmt & 0xF0 == 0);
    let (Some((sep, decimals)), Some(dst)) = (format, buffer(e, 1, size)?) else {
        e.flag(1, true);
        return Ok(Control::Next);
    };
    let text = fixed_point(v < 0, u128::from(v.unsigned_abs()), decimals, sep);
    // INT in 8 and DINT in 12 characters always fit (at most `-21474.83648`).
    let text = format!("{text:>size$}");
    write_bytes(e, dst, text.as_bytes());
    e.flag(1, false);
    Ok(Control::Next)
}

fn ita(e: &mut Exec<'_>) -> Result<Control, Fault> {
    int_to_ascii(e, 8)
}

fn dta(e: &mut Exec<'_>) -> Result<Control, Fault> {
    int_to_ascii(e, 12)
}

/// |x| * 10^decimals rounded to an integer, halves away from zero, computed exactly
/// from the REAL's binary value; None when |x| is 10^15 or more (it fits no buffer).
fn scaled_magnitude(x: f32, decimals: usize) -> Option<u128> {
    let a = x.abs();
    if !a.is_finite() || f64::from(a) >= 1e15 {
        return None;
    }
    if a == 0.0 {
        return Some(0);
    }
    // a = m * 2^exp exactly.
    let bits = a.to_bits();
    let biased = (bits >> 23) & 0xFF;
    let frac = u128::from(bits & 0x7F_FFFF);
    let (m, exp) = if biased == 0 {
        (frac, -149)
    } else {
        (frac | 1 << 23, biased as i32 - 150)
    };
    let q = m * 10u128.pow(decimals as u32);
    if exp >= 0 {
        // a < 2^50, so q << exp < 2^91.
        return Some(q << exp);
    }
    let shift = (-exp) as u32;
    if shift > 100 {
        // q < 2^41: far below one half.
        return Some(0);
    }
    let whole = q >> shift;
    let rest = q & ((1u128 << shift) - 1);
    Some(whole + u128::from(rest >= 1u128 << (shift - 1)))
}

/// RTA IN, OUT, FMT: the REAL right-aligned in FMT bits 7..4 characters.
fn rta(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let x = e.get_real(0)?;
    let fmt = e.get(2)? & 0xFF;
    let size = (fmt >> 4) as usize;
    let format = format_bits(fmt).filter(|(_, d)| (3..=15).contains(&size) && size > d + 1);
    let Some((sep, decimals)) = format else {
        e.flag(1, true);
        return Ok(Control::Next);
    };
    let Some(dst) = buffer(e, 1, size)? else {
        e.flag(1, true);
        return Ok(Control::Next);
    };
    let text = scaled_magnitude(x, decimals)
        .map(|m| fixed_point(x.is_sign_negative(), m, decimals, sep))
        .filter(|t| t.len() <= size);
    let ok = text.is_some();
    let text = match text {
        Some(t) => format!("{t:>size$}"),
        None => "*".repeat(size),
    };
    write_bytes(e, dst, text.as_bytes());
    e.flag(1, !ok);
    Ok(Control::Next)
}

pub fn lookup(m: &str) -> Option<Handler> {
    Some(match m {
        "BIR" => bir,
        "BIW" => biw,
        "BITIM" => bitim,
        "CITIM" => citim,
        "CEVNT" => cevnt,
        "ATH" => ath,
        "HTA" => hta,
        "ITA" => ita,
        "DTA" => dta,
        "RTA" => rta,
        _ => return None,
    })
}
