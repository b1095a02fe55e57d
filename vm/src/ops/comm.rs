//! Communication: EXCH (ManagerFun.xml, AN2002). The handler only queues the table;
//! `exch::service` carries the exchange out at the end of the scan.

use super::{Control, Exec, Handler};
use crate::exch::{self, Queued};
use crate::fault::Fault;

pub fn lookup(m: &str) -> Option<Handler> {
    Some(match m {
        "EXCH" => exch_op,
        _ => return None,
    })
}

/// EXCH TBL, PORT: queue the table unless it is queued already or the queue is full
/// (then nothing happens). Queuing sets A := 1, D := 0, E := 0, error := 0. A table
/// whose ten bytes do not lie inside M is done at once with E and error 1.
fn exch_op(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let loc = e.locate(0)?;
    let port = e.get(1)? as u8;
    let slot = loc.slot;
    let table = loc.offset;
    if e.exch.is_queued(slot, table) || e.exch.is_full() {
        return Ok(Control::Next);
    }
    let size = e.machine.memory.area(slot).map_or(0, <[u8]>::len) as u64;
    if exch::m_slot(&e.program.target) != Some(slot) || u64::from(table) + 10 > size {
        if u64::from(table) + 2 <= size {
            exch::write_status(
                &mut e.machine.memory,
                slot,
                table,
                false,
                true,
                exch::ERR_TABLE,
            );
        }
        return Ok(Control::Next);
    }
    exch::write_status(&mut e.machine.memory, slot, table, true, false, 0);
    let scan = e.clock.scans;
    e.exch.0.push(Queued {
        slot,
        table,
        port,
        scan,
    });
    Ok(Control::Next)
}
