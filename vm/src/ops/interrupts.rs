//! Interrupts: ENI/DISI (global enable), ATCH/DTCH (event -> interrupt routine), and
//! RETI/CRETI (return from an interrupt routine). Events are raised and routines run
//! by the engine after MAIN (`interrupts.rs`, `engine.rs`).

use gutta_format::Operand;

use super::{Control, Exec, Handler};
use crate::fault::Fault;

/// ENI: interrupts enabled (the enable byte in the flat memory, `Memory::enable_at`).
fn eni(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let memory = &mut e.machine.memory;
    let at = memory.enable_at();
    memory.bytes[at] = 1;
    Ok(Control::Next)
}

/// DISI: interrupts disabled; events that occur are kept pending.
fn disi(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let memory = &mut e.machine.memory;
    let at = memory.enable_at();
    memory.bytes[at] = 0;
    Ok(Control::Next)
}

/// ATCH INT, EVNT: event EVNT now runs interrupt routine INT.
fn atch(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let Operand::Unit(routine) = e.operand(0)? else {
        return Err(e.fault("INT is not a program unit".into()));
    };
    let page = routine
        .page(&e.program.target.plc)
        .ok_or_else(|| e.fault(format!("{routine}: no such unit on the target")))?;
    let event = e.get(1)?;
    e.interrupts.attach(event, page);
    Ok(Control::Next)
}

/// DTCH EVNT: event EVNT runs nothing any more (pending occurrences are dropped).
fn dtch(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let event = e.get(0)?;
    e.interrupts.detach(event);
    e.interrupts.pending.remove(&event);
    Ok(Control::Next)
}

fn reti(_: &mut Exec<'_>) -> Result<Control, Fault> {
    Ok(Control::Return)
}

pub fn lookup(m: &str) -> Option<Handler> {
    Some(match m {
        "ENI" => eni,
        "DISI" => disi,
        "ATCH" => atch,
        "DTCH" => dtch,
        "RETI" | "CRETI" => reti,
        _ => return None,
    })
}
