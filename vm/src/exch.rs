//! EXCH: the PLC as a Modbus RTU master on its serial ports (AN2002). Exchanges queued
//! by the EXCH instruction are carried out at the end of the scan through ports the
//! host attaches.

use crate::{Fault, Vm};

/// Queued exchanges and attached ports.
#[derive(Debug, Default)]
pub struct ExchState {}

/// End-of-scan communication: carry out queued exchanges.
pub(crate) fn service(_vm: &mut Vm) -> Result<(), Fault> {
    Ok(())
}
