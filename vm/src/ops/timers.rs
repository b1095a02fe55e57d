//! Timers (TON, TOF, TONR) and counters (CTU, CTD, CTUD), as ManagerFun.xml describes
//! them, chosen by the instruction's `Kind` ([`semantics`]). All six are Flow `Stack`: they run on every execution, whatever the power
//! flow, and leave their done state on top of the logic stack.
//!
//! Time: each execution of a timer counts `scan_ms` virtual milliseconds since its
//! previous execution. The first execution of a run (TON/TONR with `IN` = 1 after
//! `IN` = 0 or reset, TOF with `IN` = 0 after `IN` = 1) only starts the clock, so a
//! `TON T4, 20` is done at the execution 2000 ms of virtual time after the one that
//! first saw `IN` = 1.
//!
//! Hidden state is kept per timer / counter number (`cell_word` of its word in T/C),
//! so every instruction driving the same number shares it:
//! - timers: word 0 = milliseconds elapsed but not yet counted as a whole unit,
//!   word 1 = flags (`RUNNING`: the clock is started; `ARMED`: TOF's armed bit);
//! - counters: word 0 = flags (`PREV_UP`, `PREV_DOWN`: the previous up/down inputs).

use super::{Control, Exec, Handler};
use crate::fault::Fault;
use gutta_catalog::{Address, TimerCounterKind};

const RUNNING: u32 = 1;
const ARMED: u32 = 2;

const PREV_UP: u32 = 1;
const PREV_DOWN: u32 = 2;

const TIMER_MAX: i64 = i16::MAX as i64;

/// The timer operand (operand 0): its location and its resolution in ms.
fn timer(e: &Exec<'_>) -> Result<(Address, u32), Fault> {
    let loc = e.locate(0)?;
    let n = loc.offset / 2;
    let res = e
        .target()
        .memory
        .timer_resolution(n)
        .ok_or_else(|| e.fault(format!("T{n} has no resolution on this target")))?;
    Ok((loc, res.max(1)))
}

/// The signed current value of a timer or counter word.
fn current(e: &Exec<'_>, loc: Address) -> Result<i64, Fault> {
    Ok(e.read_at(loc)? as u16 as i16 as i64)
}

fn store(e: &mut Exec<'_>, loc: Address, v: i64) -> Result<(), Fault> {
    e.write_at(loc, v as i16 as u16 as u32)
}

/// Advance the timer clock by one execution: returns the whole units elapsed since
/// the previous advancing execution (0 when this execution starts the clock) and
/// keeps the uncounted remainder.
fn advance(e: &mut Exec<'_>, loc: Address, res: u32) -> i64 {
    let scan = e.scan_ms();
    let flags = e.cell_word(loc, 1);
    if flags & RUNNING == 0 {
        e.set_cell_word(loc, 1, flags | RUNNING);
        e.set_cell_word(loc, 0, 0);
        return 0;
    }
    let total = e.cell_word(loc, 0) as u64 + scan as u64;
    e.set_cell_word(loc, 0, (total % res as u64) as u32);
    (total / res as u64) as i64
}

/// Stop the timer clock: the uncounted fraction of a unit is dropped.
fn stop(e: &mut Exec<'_>, loc: Address) {
    let flags = e.cell_word(loc, 1);
    e.set_cell_word(loc, 0, 0);
    e.set_cell_word(loc, 1, flags & !RUNNING);
}

fn ton(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let (loc, res) = timer(e)?;
    let pt = e.get_signed(1)?;
    let done = if e.top() {
        let units = advance(e, loc, res);
        let mut t = current(e, loc)?;
        if units > 0 && t < TIMER_MAX {
            t = (t + units).min(TIMER_MAX);
            store(e, loc, t)?;
        }
        pt <= 0 || t >= pt
    } else {
        stop(e, loc);
        store(e, loc, 0)?;
        false
    };
    e.set_top(done);
    Ok(Control::Next)
}

fn tof(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let (loc, res) = timer(e)?;
    let pt = e.get_signed(1)?;
    let out = if e.top() {
        stop(e, loc);
        let flags = e.cell_word(loc, 1);
        e.set_cell_word(loc, 1, flags | ARMED);
        store(e, loc, 0)?;
        true
    } else if e.cell_word(loc, 1) & ARMED != 0 {
        let units = advance(e, loc, res);
        let mut t = current(e, loc)?;
        if units > 0 && t < pt {
            t = (t + units).min(pt);
            store(e, loc, t)?;
        }
        if t < pt {
            true
        } else {
            stop(e, loc);
            let flags = e.cell_word(loc, 1);
            e.set_cell_word(loc, 1, flags & !ARMED);
            false
        }
    } else {
        false
    };
    e.set_top(out);
    Ok(Control::Next)
}

fn tonr(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let (loc, res) = timer(e)?;
    let pt = e.get_signed(1)?;
    let mut t = current(e, loc)?;
    if e.top() {
        let units = advance(e, loc, res);
        if units > 0 && t < TIMER_MAX {
            t = (t + units).min(TIMER_MAX);
            store(e, loc, t)?;
        }
    } else {
        stop(e, loc);
    }
    e.set_top(t >= pt);
    Ok(Control::Next)
}

/// The counter operand (operand 0), its preset (operand 1) and the upper limit.
fn counter(e: &Exec<'_>) -> Result<(Address, i64, i64), Fault> {
    let loc = e.locate(0)?;
    let pv = e.get_signed(1)?;
    let max = (e.target().memory.counter_max as i64).min(i16::MAX as i64);
    Ok((loc, pv, max))
}

/// Record the up (or down) input of a counter; true on its rising edge.
fn edge(e: &mut Exec<'_>, loc: Address, bit: u32, now: bool) -> bool {
    let flags = e.cell_word(loc, 0);
    let before = flags & bit != 0;
    e.set_cell_word(loc, 0, if now { flags | bit } else { flags & !bit });
    now && !before
}

fn ctu(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let (loc, pv, max) = counter(e)?;
    let r = e.pop();
    let cu = e.pop();
    let up = edge(e, loc, PREV_UP, cu);
    let mut c = current(e, loc)?;
    if r {
        c = 0;
        store(e, loc, c)?;
    } else if up && c < max {
        c += 1;
        store(e, loc, c)?;
    }
    e.push(c >= pv);
    Ok(Control::Next)
}

fn ctd(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let (loc, pv, _) = counter(e)?;
    let ld = e.pop();
    let cd = e.pop();
    let down = edge(e, loc, PREV_DOWN, cd);
    let mut c = current(e, loc)?;
    if ld {
        c = pv;
        store(e, loc, c)?;
    } else if down && c > 0 {
        c -= 1;
        store(e, loc, c)?;
    }
    e.push(c == 0);
    Ok(Control::Next)
}

fn ctud(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let (loc, pv, max) = counter(e)?;
    let r = e.pop();
    let cd = e.pop();
    let cu = e.pop();
    let up = edge(e, loc, PREV_UP, cu);
    let down = edge(e, loc, PREV_DOWN, cd);
    let mut c = current(e, loc)?;
    if r {
        c = 0;
        store(e, loc, c)?;
    } else if up && !down && c < max {
        c += 1;
        store(e, loc, c)?;
    } else if down && !up && c > i16::MIN as i64 {
        c -= 1;
        store(e, loc, c)?;
    }
    e.push(c >= pv);
    Ok(Control::Next)
}

/// The semantics of a timer or counter kind.
pub fn semantics(kind: TimerCounterKind) -> Handler {
    match kind {
        TimerCounterKind::OnDelay => ton,
        TimerCounterKind::OffDelay => tof,
        TimerCounterKind::RetentiveOnDelay => tonr,
        TimerCounterKind::CountUp => ctu,
        TimerCounterKind::CountDown => ctd,
        TimerCounterKind::CountUpDown => ctud,
    }
}
