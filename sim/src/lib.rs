//! The simulated GUTTA PLC: the reference VM behind standard Modbus (01-06/15/16, the
//! memory mapping of the target's ManagerVar.xml) and the GUTTA protocol (UM4001 inside
//! Modbus function 13). Nothing here does I/O (clippy.toml forbids it): the `gutta-sim`
//! binary (package gutta-cli) puts it on TCP and serial transports and gives it its
//! serial ports for EXCH through a [`ports::PortFactory`] (docs/simulator.md). `fx` and
//! `relay` are the other devices of the documents: the FX-style programming port and the
//! Modbus-TCP relay board (docs/devices.md). `persist` is the PLC's flash as bytes, for
//! `gutta-sim --flash DIR` (the binary keeps the files).

pub mod fx;
pub mod modbus_data;
pub mod persist;
pub mod plc;
pub mod ports;
pub mod relay;
pub mod session;
pub mod vm_access;
