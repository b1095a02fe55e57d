//! The simulated PLC's serial ports (PORT0, PORT1), where EXCH makes it a Modbus RTU
//! master, as the core sees them: a [`PortFactory`] the process shell gives the PLC.
//! This module opens nothing: no socket, pty or serial device (the `gutta-sim` binary's
//! factory does, docs/simulator.md).

use gutta_format::LineSettings;
use gutta_vm::exch::SerialPort;

/// Makes the PLC's serial ports. The PLC asks for each of its ports at every reset,
/// because a port's line follows the system page of the last reset.
pub trait PortFactory: std::fmt::Debug + Send {
    /// Serial port `port` running with `line`; `None` leaves the port unconnected (its
    /// exchanges time out).
    fn port(&mut self, port: u8, line: LineSettings) -> Option<Box<dyn SerialPort>>;
}
