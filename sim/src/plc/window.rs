//! The download safety rule: PLC_CLEAR opens a download window owned by the connection
//! that cleared, and until that connection's STATUS_RESET (or its connection closes, or
//! [`WINDOW_TIMEOUT_MS`] pass without a request from it) every other connection may
//! look but not touch. This module only decides who may do what and when a window
//! ends, and how the PLC tracks it; `Plc::dispatch` asks `busy_for` before any
//! function. No I/O, no clock: connection identities come from the binary, time as
//! `now_ms`.

use gutta_protocol::function::Function;

use super::{Plc, Refusal};

/// Who a request comes from: a number the binary gives each connection it serves (a
/// Modbus TCP connection, an RTU-over-TCP connection, a serial line), unique for the
/// life of the process.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct ConnectionId(pub u64);

impl std::fmt::Display for ConnectionId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "connection {}", self.0)
    }
}

/// A window ends when its owner has sent no request for this long (30 s), so a client
/// that crashed or lost its line cannot keep the PLC from being programmed.
pub const WINDOW_TIMEOUT_MS: u64 = 30_000;

/// An open download window: between one connection's PLC_CLEAR and its STATUS_RESET.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DownloadWindow {
    pub owner: ConnectionId,
    /// When the owner's PLC_CLEAR opened it.
    pub opened_ms: u64,
    /// The owner's last request.
    pub last_request_ms: u64,
}

impl DownloadWindow {
    pub(super) fn open(owner: ConnectionId, now_ms: u64) -> DownloadWindow {
        DownloadWindow {
            owner,
            opened_ms: now_ms,
            last_request_ms: now_ms,
        }
    }

    /// The owner has been silent for the timeout: the window has ended.
    pub(super) fn expired(&self, now_ms: u64) -> bool {
        now_ms.saturating_sub(self.last_request_ms) >= WINDOW_TIMEOUT_MS
    }
}

/// What another connection may do while a window is open: everything that only looks
/// (names, page lists and pages, the status, variables, forces, the debugger's state)
/// and PLC_ATTACH (the login is the PLC's, shared by every connection; reads need it).
/// Everything that changes the flash, the run state, memory, forces, the debugger or
/// the login (PLC_CLEAR, PLC_DETACH, page writes, STATUS_WRITE, STATUS_SCAN,
/// STATUS_RESET, STATUS_VAR_WRITE, STATUS_VAR_FORCE_WRITE, the debug writes) is busy.
pub(super) fn open_to_others(function: Function) -> bool {
    match function {
        Function::PlcAttach
        | Function::GetPlcName
        | Function::GetPlcInfor
        | Function::PageList(_)
        | Function::PageAsk(_)
        | Function::PageRead(_)
        | Function::StatusRead
        | Function::VarRead
        | Function::ForceRead
        | Function::DebugRead
        | Function::DebugInforRead => true,
        Function::PlcClear
        | Function::PlcDetach
        | Function::PageWrite(_)
        | Function::StatusWrite
        | Function::StatusScan
        | Function::StatusReset
        | Function::VarWrite
        | Function::ForceWrite
        | Function::DebugWrite
        | Function::DebugScan
        | Function::DebugReset
        | Function::DebugInforWrite => false,
    }
}

impl Plc {
    /// The open download window, if any.
    pub fn download_window(&self) -> Option<&DownloadWindow> {
        self.window.as_ref()
    }

    /// `connection` has closed: a download window it owns ends unfinished (its pages
    /// are erased; the PLC stays cleared and stopped).
    pub fn disconnect(&mut self, connection: ConnectionId) {
        if self.window.is_some_and(|w| w.owner == connection) {
            self.abandon_window();
        }
    }

    /// A window that ends without its owner's STATUS_RESET: the pages it wrote may be
    /// half an image, so they are erased and the flash locked. The PLC stays stopped
    /// as PLC_CLEAR left it, its status saying the download was interrupted (the
    /// flash says so already: PLC_CLEAR committed it cleared).
    fn abandon_window(&mut self) {
        self.window = None;
        self.pages.clear();
        self.image_error = false;
        self.flash_fault = Some(super::FlashFault::DownloadInterrupted);
    }

    /// Every request: a window whose owner has been silent for the timeout ends; one
    /// from the owner keeps its window alive.
    pub(super) fn track_window(&mut self, from: ConnectionId, now_ms: u64) {
        if self.window.is_some_and(|w| w.expired(now_ms)) {
            self.abandon_window();
        }
        if let Some(window) = self.window.as_mut().filter(|w| w.owner == from) {
            window.last_request_ms = now_ms;
        }
    }

    /// The busy refusal `from` gets while another connection's window is open.
    pub(super) fn busy_for(&self, from: ConnectionId) -> Option<Refusal> {
        self.window
            .filter(|w| w.owner != from)
            .map(|w| Refusal::Busy {
                owner: w.owner,
                opened_ms: w.opened_ms,
            })
    }
}
