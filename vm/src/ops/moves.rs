//! Moves: MOVB/MOVW/MOVD/MOVR, SWAP, block moves BMB/BMW/BMD and FILL.

use super::{Control, Exec, Handler};
use crate::fault::Fault;
use gutta_catalog::Address;

fn mov(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let v = e.get(0)?;
    e.set(1, v)?;
    Ok(Control::Next)
}

fn swap(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let v = e.get(0)? as u16;
    e.set(0, v.swap_bytes() as u32)?;
    Ok(Control::Next)
}

/// Address `k` items after `loc`.
fn nth(loc: Address, k: u32) -> Address {
    Address {
        offset: loc.offset + k * loc.width.bytes(),
        ..loc
    }
}

/// Whether `n` items from `loc` lie inside its area.
fn fits(e: &Exec<'_>, loc: Address, n: u32) -> bool {
    let len = e.machine.memory.area(loc.slot).map_or(0, <[u8]>::len) as u64;
    u64::from(loc.offset) + u64::from(n) * u64::from(loc.width.bytes()) <= len
}

/// BMx IN, OUT, N: copy N items (all read before any is written, so overlap is safe).
/// A block past the end of its area moves nothing and sets SM1.1; else SM1.1 is cleared.
fn block_move(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let (src, dst, n) = (e.locate(0)?, e.locate(1)?, e.get(2)?);
    if !fits(e, src, n) || !fits(e, dst, n) {
        e.flag(1, true);
        return Ok(Control::Next);
    }
    let values = (0..n)
        .map(|k| e.read_at(nth(src, k)))
        .collect::<Result<Vec<_>, _>>()?;
    for (k, v) in values.into_iter().enumerate() {
        e.write_at(nth(dst, k as u32), v)?;
    }
    e.flag(1, false);
    Ok(Control::Next)
}

/// FILL IN, OUT, N: write the word IN into N words from OUT; past the end of the area,
/// nothing is written and SM1.1 is set; else SM1.1 is cleared.
fn fill(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let (v, dst, n) = (e.get(0)?, e.locate(1)?, e.get(2)?);
    if !fits(e, dst, n) {
        e.flag(1, true);
        return Ok(Control::Next);
    }
    for k in 0..n {
        e.write_at(nth(dst, k), v)?;
    }
    e.flag(1, false);
    Ok(Control::Next)
}

pub fn lookup(m: &str) -> Option<Handler> {
    Some(match m {
        "MOVB" | "MOVW" | "MOVD" | "MOVR" => mov,
        "SWAP" => swap,
        "BMB" | "BMW" | "BMD" => block_move,
        "FILL" => fill,
        _ => return None,
    })
}
