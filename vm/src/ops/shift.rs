//! Shifts and rotates (SRx, SLx, RRx, RLx, SHRB), as ManagerFun.xml describes them.
//! `SRW OUT, N`: OUT is operand 0 (its width is the access width), N operand 1.
//! Shifts and rotates write SM1.0 (result zero) and SM1.1 (the last bit moved out);
//! SHRB writes SM1.1 only. The other SM1 flags keep their values.

use gutta_catalog::Width;

use super::{Control, Exec, Handler};
use crate::fault::Fault;
use gutta_catalog::Address;

/// Width in bits of operand `i` (a DWORD when unknown).
fn bits_of(e: &Exec<'_>, i: usize) -> Result<u32, Fault> {
    Ok(e.width(i)?.bits())
}

fn mask(w: u32) -> u32 {
    if w >= 32 {
        u32::MAX
    } else {
        (1u32 << w) - 1
    }
}

/// Store OUT (operand 0) and write SM1.0 / SM1.1.
fn finish(e: &mut Exec<'_>, result: u32, out_bit: bool) -> Result<Control, Fault> {
    e.set(0, result)?;
    e.flag(0, result == 0);
    e.flag(1, out_bit);
    Ok(Control::Next)
}

/// SRB/SRW/SRD: logical shift right; SM1.1 = bit N-1 of the old value (1 <= N <= w).
fn shift_right(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let w = bits_of(e, 0)?;
    let v = e.get(0)? & mask(w);
    let n = e.get(1)? & 0xFF;
    let r = if n >= w { 0 } else { v >> n };
    let out = (1..=w).contains(&n) && (v >> (n - 1)) & 1 == 1;
    finish(e, r, out)
}

/// SLB/SLW/SLD: shift left; SM1.1 = bit w-N of the old value (1 <= N <= w).
fn shift_left(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let w = bits_of(e, 0)?;
    let v = e.get(0)? & mask(w);
    let n = e.get(1)? & 0xFF;
    let r = if n >= w { 0 } else { (v << n) & mask(w) };
    let out = (1..=w).contains(&n) && (v >> (w - n)) & 1 == 1;
    finish(e, r, out)
}

/// RRB/RRW/RRD: rotate right by N mod w; SM1.1 = the top bit of the result.
fn rotate_right(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let w = bits_of(e, 0)?;
    let v = e.get(0)? & mask(w);
    let n = (e.get(1)? & 0xFF) % w;
    if n == 0 {
        return finish(e, v, false);
    }
    let r = ((v >> n) | (v << (w - n))) & mask(w);
    finish(e, r, (r >> (w - 1)) & 1 == 1)
}

/// RLB/RLW/RLD: rotate left by N mod w; SM1.1 = bit 0 of the result.
fn rotate_left(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let w = bits_of(e, 0)?;
    let v = e.get(0)? & mask(w);
    let n = (e.get(1)? & 0xFF) % w;
    if n == 0 {
        return finish(e, v, false);
    }
    let r = ((v << n) | (v >> (w - n))) & mask(w);
    finish(e, r, r & 1 == 1)
}

/// SHRB DATA, S_BIT, N: shift the |N|-bit register starting at S_BIT by one bit.
/// N > 0 shifts up (DATA enters at S_BIT), N < 0 shifts down (DATA enters at the
/// highest bit). N = 0, |N| > 64 or a register running past its area: nothing is
/// shifted and SM1.1 is set.
fn shrb(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let data = e.get(0)? & 1;
    let start = e.locate(1)?;
    let n = e.get(2)? as u8 as i8 as i32;
    let len = n.unsigned_abs();
    let area_bytes = e.machine.memory.area(start.slot).map_or(0, <[u8]>::len) as u64;
    let first = start.offset as u64 * 8 + u64::from(start.bit & 7);
    if n == 0 || len > 64 || (first + u64::from(len) - 1) / 8 >= area_bytes {
        e.flag(1, true);
        return Ok(Control::Next);
    }
    let at = |i: u32| {
        let b = first + u64::from(i);
        Address {
            slot: start.slot,
            offset: (b / 8) as u32,
            width: Width::Bit,
            bit: (b % 8) as u8,
        }
    };
    let mut reg = Vec::with_capacity(len as usize);
    for i in 0..len {
        reg.push(e.read_at(at(i))?);
    }
    let out = if n > 0 {
        let out = reg[len as usize - 1];
        reg.rotate_right(1);
        reg[0] = data;
        out
    } else {
        let out = reg[0];
        reg.rotate_left(1);
        reg[len as usize - 1] = data;
        out
    };
    for (i, b) in reg.into_iter().enumerate() {
        e.write_at(at(i as u32), b)?;
    }
    e.flag(1, out == 1);
    Ok(Control::Next)
}

pub fn lookup(m: &str) -> Option<Handler> {
    Some(match m {
        "SRB" | "SRW" | "SRD" => shift_right,
        "SLB" | "SLW" | "SLD" => shift_left,
        "RRB" | "RRW" | "RRD" => rotate_right,
        "RLB" | "RLW" | "RLD" => rotate_left,
        "SHRB" => shrb,
        _ => return None,
    })
}
