//! Tables (ATT, FIFO, LIFO, FND=, FND<>, FND<, FND>), as ManagerFun.xml describes
//! them. Layout (S7-200): word 0 = maximum entries, word 1 = count, then the entries,
//! one word each. `TBL` names word 0 for all of them (also FND, unlike S7-200). An
//! illegal table (negative maximum or count, count above maximum, entries running
//! past the area) changes nothing and sets SM1.1.

use gutta_catalog::Width;

use super::{Control, Exec, Handler};
use crate::fault::Fault;
use gutta_catalog::Address;

/// A legal table: where word 0 is, and its count.
struct Table {
    base: Address,
    count: u32,
}

impl Table {
    fn word(&self, byte: u32) -> Address {
        Address {
            slot: self.base.slot,
            offset: self.base.offset + byte,
            width: Width::Word,
            bit: 0,
        }
    }
    fn count_at(&self) -> Address {
        self.word(2)
    }
    fn entry(&self, i: u32) -> Address {
        self.word(4 + 2 * i)
    }
}

/// Read and check the table at operand `i`: `None` when it is illegal.
fn table(e: &Exec<'_>, i: usize) -> Result<Option<Table>, Fault> {
    let mut base = e.locate(i)?;
    base.width = Width::Word;
    base.bit = 0;
    let t = Table { base, count: 0 };
    let area = e.machine.memory.area(base.slot).map_or(0, <[u8]>::len) as u64;
    if u64::from(base.offset) + 4 > area {
        return Ok(None);
    }
    let max = e.read_at(base)? as u16 as i16;
    let count = e.read_at(t.count_at())? as u16 as i16;
    if max < 0 || count < 0 || count > max {
        return Ok(None);
    }
    if u64::from(base.offset) + 4 + 2 * max as u64 > area {
        return Ok(None);
    }
    Ok(Some(Table {
        base,
        count: count as u32,
    }))
}

/// ATT DATA, TBL: append DATA; a full table sets SM1.4.
fn att(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let data = e.get(0)?;
    let Some(t) = table(e, 1)? else {
        e.flag(1, true);
        e.flag(4, false);
        return Ok(Control::Next);
    };
    let max = e.read_at(t.base)?;
    let full = t.count >= max;
    if !full {
        e.write_at(t.entry(t.count), data)?;
        e.write_at(t.count_at(), t.count + 1)?;
    }
    e.flag(1, false);
    e.flag(4, full);
    Ok(Control::Next)
}

/// FIFO/LIFO TBL, DATA: take the first (oldest) or last (newest) entry; an empty
/// table sets SM1.5 and leaves DATA.
fn take(e: &mut Exec<'_>, first: bool) -> Result<Control, Fault> {
    let Some(t) = table(e, 0)? else {
        e.flag(1, true);
        e.flag(5, false);
        return Ok(Control::Next);
    };
    let empty = t.count == 0;
    if !empty {
        let n = t.count;
        let value = if first {
            let v = e.read_at(t.entry(0))?;
            for i in 1..n {
                let next = e.read_at(t.entry(i))?;
                e.write_at(t.entry(i - 1), next)?;
            }
            v
        } else {
            e.read_at(t.entry(n - 1))?
        };
        e.write_at(t.count_at(), n - 1)?;
        e.set(1, value)?;
    }
    e.flag(1, false);
    e.flag(5, empty);
    Ok(Control::Next)
}
fn fifo(e: &mut Exec<'_>) -> Result<Control, Fault> {
    take(e, true)
}
fn lifo(e: &mut Exec<'_>) -> Result<Control, Fault> {
    take(e, false)
}

/// FNDx TBL, PTN, INDX: INDX := the number of the first entry from INDX (a negative
/// INDX starts at 0) for which `entry x PTN` holds, comparing signed INTs, or the
/// count when none does.
fn find(e: &mut Exec<'_>, rel: fn(i16, i16) -> bool) -> Result<Control, Fault> {
    let Some(t) = table(e, 0)? else {
        e.flag(1, true);
        return Ok(Control::Next);
    };
    let ptn = e.get(1)? as u16 as i16;
    let from = (e.get(2)? as u16 as i16).max(0) as u32;
    let mut found = t.count;
    for i in from..t.count {
        if rel(e.read_at(t.entry(i))? as u16 as i16, ptn) {
            found = i;
            break;
        }
    }
    e.set(2, found)?;
    e.flag(1, false);
    Ok(Control::Next)
}
fn fnd_eq(e: &mut Exec<'_>) -> Result<Control, Fault> {
    find(e, |a, b| a == b)
}
fn fnd_ne(e: &mut Exec<'_>) -> Result<Control, Fault> {
    find(e, |a, b| a != b)
}
fn fnd_lt(e: &mut Exec<'_>) -> Result<Control, Fault> {
    find(e, |a, b| a < b)
}
fn fnd_gt(e: &mut Exec<'_>) -> Result<Control, Fault> {
    find(e, |a, b| a > b)
}

pub fn lookup(m: &str) -> Option<Handler> {
    Some(match m {
        "ATT" => att,
        "FIFO" => fifo,
        "LIFO" => lifo,
        "FND=" => fnd_eq,
        "FND<>" => fnd_ne,
        "FND<" => fnd_lt,
        "FND>" => fnd_gt,
        _ => return None,
    })
}
