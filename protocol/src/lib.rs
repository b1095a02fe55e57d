//! The GUTTA PLC communication protocol as plain data: Modbus RTU and TCP framing,
//! splitting frames out of a byte stream, the GUTTA messages carried inside Modbus
//! function 13 (UM4001), packetisation of pages, standard Modbus functions 01-06/15/16
//! (AN2002), one sans-I/O master state machine, and the FX-style programming port
//! (`fx.rs`, seed 001).
//!
//! This crate never does I/O, never reads a clock and never sleeps: bytes and the
//! current time (milliseconds, any epoch) come in as arguments, bytes to write go out as
//! return values. The simulator, the download client and the VM's EXCH do the I/O.
//! No input makes it panic; every failure is a typed error. See `docs/protocol.md`.

pub mod function;
pub mod fx;
pub mod fx_client;
pub mod gateway;
pub mod gutta;
pub mod master;
pub mod message;
pub mod modbus;
pub mod modbus_registry;
pub mod registry;
pub mod relay;
pub mod rtu;
pub mod stream;
pub mod tcp;
pub mod transfer;

pub use function::{Function, PageArea, PageRef};
pub use gateway::{answer_to_rtu, DropReason, Forwarded, Gateway, NotTheAnswer};
pub use gutta::{GuttaError, GuttaFrame, FAILURE_BIT, LAST_PACKET};
pub use master::{expects_answer, Master, MasterConfig, MasterError, MasterEvent};
pub use message::{
    Breakpoint, Command, DebugInfo, DebugStep, MessageError, Reply, Request, Response,
};
pub use modbus::{ExceptionCode, ModbusError, ModbusRequest, ModbusResponse};
pub use modbus_registry::{ModbusFunction, MODBUS_FUNCTIONS};
pub use registry::{FunctionSpec, Needs, Packets, Payload, FUNCTIONS};
pub use rtu::{crc16, decode_rtu, encode_rtu, FrameError, RtuFrame};
pub use stream::{RtuSplitter, Side, TcpSplitter};
pub use tcp::{decode_tcp, encode_tcp, MbapHeader, TcpFrame};
pub use transfer::{PackSize, Progress, Reassembler, TransferError};
