//! The simulated PLC as UM4001 describes it, without I/O: user flash (the downloaded
//! pages), the login, the run state, and the VM that runs the image. `gutta` answers
//! one GUTTA request (the data inside Modbus function 13); `modbus` one standard Modbus
//! data request; `scan` runs the program. Transports and time live in the binary.
//!
//! `dispatch` applies the login and stop conditions of gutta-protocol's function
//! registry and hands each function to its family: `identity` (login, name), `flash`
//! (pages), `run_state`, `variables` (reading, writing, forcing), `debugger`.
//!
//! Rules (UM4001, and what we decided where it is silent; docs/simulator.md):
//! - A function needs a login (ATTACH) when its registry row says so: everything but
//!   PLC_CLEAR, PLC_ATTACH, PLC_DETACH, STATUS_RESET and DEBUG_RESET.
//! - PLC_CLEAR erases the pages and the password, stops the PLC and opens a download
//!   window owned by the connection that cleared (`window`, the download safety rule):
//!   only that connection writes pages, and until its STATUS_RESET (or its connection
//!   closes, or 30 s pass without a request from it) other connections may only look;
//!   what would change the PLC is refused as busy. A window that ends without its
//!   owner's reset erases the pages. Page writes also need the PLC stopped.
//!   STATUS_RESET then loads the pages: an image that verifies runs; one that does not
//!   leaves the PLC stopped with ERROR set.
//! - With a flash store (`power`, `gutta-sim --flash`), PLC_CLEAR, STATUS_RESET and
//!   STATUS_WRITE are made durable before they are answered; a failed commit refuses
//!   the request and changes nothing. Power-on loads what the last commit left; a
//!   cleared or broken flash gives no program, with ERROR and a code saying why.
//! - A failed ATTACH counts; from the third failure in a row every ATTACH is refused
//!   for a lockout that doubles from 1 s up to 60 s (answered as Modbus exception 04,
//!   a wrong password as the failure form); a good password resets it.
//! - Requests are decoded with gutta-protocol's `message::Request`. One the target's
//!   ExchSupport does not allow, or that does not decode (payload length, packet
//!   number 0x8000 for single-packet functions, debug step 1..3), fails: function
//!   code with bit 15 set, no payload.

use std::collections::BTreeMap;
use std::sync::Arc;

use gutta_catalog::Target;
use gutta_format::{verify, ArgumentPage, Image, LineSettings, PageId, PageKind};
use gutta_protocol::gutta::GuttaFrame;
use gutta_protocol::message::{Command, MessageError, Reply, Request, Response};
use gutta_vm::{ScanEnd, Vm, VmConfig};

use crate::modbus_data;
use crate::ports::PortFactory;

mod debugger;
mod flash;
mod identity;
mod power;
mod run_state;
mod variables;
mod window;

pub use power::{
    FlashFault, PowerOn, ERROR_DOWNLOAD_INTERRUPTED, ERROR_FLASH_CHECK, ERROR_IMAGE_INVALID,
};
pub use variables::RELEASE_USE;
pub use window::{ConnectionId, DownloadWindow, WINDOW_TIMEOUT_MS};

/// The factory password: 16 x 0xFF (gutta-protocol's).
pub use gutta_protocol::message::FACTORY_PASSWORD;

/// Bit 15 of a packet number: the last packet of a transfer.
pub const LAST_PACKET: u16 = gutta_protocol::gutta::LAST_PACKET;

/// Why a request failed (for logs and tests; on the wire every failure looks alike).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Refusal {
    NotAttached,
    WrongPassword,
    /// PLC_ATTACH during the lockout: the session answers Modbus exception 04, Server
    /// Device Failure, so a client can tell it from a wrong password.
    LockedOut {
        until_ms: u64,
    },
    /// The payload's length is not the function's (UM4001's success conditions).
    BadLength,
    /// Otherwise not a well-formed request (packet number, debug step, page number).
    Malformed(String),
    Unsupported,
    UnknownFunction,
    Running,
    /// Another connection's download window is open (the download safety rule): the
    /// session answers Modbus exception 06, Server Device Busy.
    Busy {
        owner: ConnectionId,
        opened_ms: u64,
    },
    /// A page write outside a download window of the requesting connection.
    FlashLocked,
    NoSuchPage,
    BadPacket,
    NoProgram,
    Access(String),
    Debug(String),
    /// The flash store could not make the request's state durable: the request is
    /// refused and the PLC stays as it was (docs/simulator.md, "Flash and power-on").
    FlashFailed(String),
}

/// The simulated PLC.
#[derive(Debug)]
pub struct Plc {
    target: Arc<Target>,
    config: VmConfig,
    /// User flash: the pages last written.
    pages: BTreeMap<PageId, Vec<u8>>,
    /// The download window PLC_CLEAR opened (the flash is unlocked for its owner only);
    /// STATUS_RESET closes it.
    window: Option<DownloadWindow>,
    attached: bool,
    password: [u8; 16],
    guard: identity::LoginGuard,
    /// The running image; a blank one (empty MAIN) when there is none, so memory and
    /// Modbus still work.
    vm: Vm,
    /// The image in flash does not verify (STATUS_READ's ERROR).
    image_error: bool,
    /// The last refusal, for logs and tests.
    last_refusal: Option<Refusal>,
    /// Makes the PLC's serial ports (for EXCH); they are attached to every loaded VM.
    port_factory: Option<Box<dyn PortFactory>>,
    /// The ports of the system page as of the last reset (empty: defaults). Writing a
    /// new system page changes nothing until STATUS_RESET; PLC_CLEAR reverts them.
    active_ports: Vec<gutta_format::PortEntry>,
    /// Where PLC_CLEAR, STATUS_RESET and STATUS_WRITE are made durable (`power`);
    /// none: a volatile PLC.
    store: Option<Box<dyn crate::persist::FlashStore>>,
    /// Why the PLC has no program (a download cut short, a flash that failed its
    /// check): STATUS_READ's ERROR and a code in the debug block.
    flash_fault: Option<FlashFault>,
}

fn blank_image(target: &Target) -> Image {
    let mut pages = BTreeMap::new();
    pages.insert(
        PageId::new(PageKind::Argument, 0),
        ArgumentPage {
            subroutine: false,
            unit_number: 0,
            locals: Vec::new(),
        }
        .encode(),
    );
    pages.insert(PageId::new(PageKind::Instruction, 0), Vec::new());
    pages.insert(PageId::new(PageKind::Const, 0), Vec::new());
    Image {
        plc_type: target.name().to_string(),
        pages,
    }
}

impl Plc {
    /// A PLC with `pages` in its flash (e.g. an image directory read at start), already
    /// reset: a verified image runs, else the PLC is stopped (with ERROR when there were
    /// pages that do not verify).
    /// Fails only when the target cannot hold even an empty program.
    pub fn new(
        target: Arc<Target>,
        pages: BTreeMap<PageId, Vec<u8>>,
        config: VmConfig,
    ) -> Result<Plc, String> {
        let blank = verify(&blank_image(&target), &target)
            .map_err(|e| format!("{}: an empty program does not verify: {e}", target.name()))?;
        let vm = Vm::new(blank, Arc::clone(&target), config)
            .map_err(|e| format!("{}: an empty program does not load: {e}", target.name()))?;
        let mut plc = Plc {
            target,
            config,
            pages,
            window: None,
            attached: false,
            password: FACTORY_PASSWORD,
            guard: identity::LoginGuard::default(),
            vm,
            image_error: false,
            last_refusal: None,
            port_factory: None,
            active_ports: Vec::new(),
            store: None,
            flash_fault: None,
        };
        plc.reset();
        Ok(plc)
    }

    pub fn target(&self) -> &Arc<Target> {
        &self.target
    }

    pub fn vm(&self) -> &Vm {
        &self.vm
    }

    pub fn vm_mut(&mut self) -> &mut Vm {
        &mut self.vm
    }

    pub fn pages(&self) -> &BTreeMap<PageId, Vec<u8>> {
        &self.pages
    }

    pub fn is_attached(&self) -> bool {
        self.attached
    }

    pub fn last_refusal(&self) -> Option<&Refusal> {
        self.last_refusal.as_ref()
    }

    /// The station address: port 0's in the system page of the last reset (1 without
    /// one, and after PLC_CLEAR).
    pub fn station(&self) -> u8 {
        self.active_ports.first().map_or(1, |p| p.address)
    }

    /// Serial port `n`'s line: as the system page of the last reset says, else (and
    /// after PLC_CLEAR) 19200 8E1.
    pub fn line(&self, n: usize) -> LineSettings {
        self.active_ports
            .get(n)
            .map_or(LineSettings::DEFAULT, |p| p.line())
    }

    /// STATUS_RESET (and power-on): close the download window (locking the flash),
    /// drop the login, load the pages. An image that verifies runs; otherwise the PLC
    /// is stopped, with ERROR set when pages were there.
    pub fn reset(&mut self) {
        let loaded = self.load_pages();
        self.apply_reset(loaded);
    }

    /// The pages in flash as a VM, if they verify.
    fn load_pages(&self) -> Option<Vm> {
        let image = Image {
            plc_type: self.target.name().to_string(),
            pages: self.pages.clone(),
        };
        verify(&image, &self.target)
            .ok()
            .and_then(|v| Vm::new(v, Arc::clone(&self.target), self.config).ok())
    }

    /// STATUS_RESET through the protocol: committed first (the pages, and RUN when
    /// they verify), so a refused commit leaves the window, the pages and the run
    /// state as they were.
    fn reset_committed(&mut self) -> Result<(), Refusal> {
        let loaded = self.load_pages();
        let pages = self.pages.clone();
        self.commit(
            crate::persist::FlashState::Committed,
            loaded.is_some(),
            &pages,
        )?;
        self.apply_reset(loaded);
        Ok(())
    }

    fn apply_reset(&mut self, loaded: Option<Vm>) {
        self.window = None;
        self.attached = false;
        self.flash_fault = None;
        let system = self
            .pages
            .get(&PageId::new(PageKind::System, 0))
            .and_then(|b| gutta_format::SystemPage::decode(b).ok());
        self.password = system.as_ref().map_or(FACTORY_PASSWORD, |s| s.password);
        self.active_ports = system.map(|s| s.ports).unwrap_or_default();
        match loaded {
            Some(vm) => {
                self.vm = vm;
                self.image_error = false;
            }
            None => {
                self.image_error = !self.pages.is_empty();
                self.vm.reset();
                self.vm.set_running(false);
            }
        }
        self.vm.set_attached(false);
        self.attach_ports();
    }

    /// Take the PLC's serial ports from `factory`, now and at every reset: EXCH on a
    /// port talks through what the factory made for it.
    pub fn set_port_factory(&mut self, factory: Box<dyn PortFactory>) {
        self.port_factory = Some(factory);
        self.attach_ports();
    }

    /// Ask the port factory (if any) for each serial port of the target, with the line
    /// of the last reset, and attach what it makes to the VM.
    fn attach_ports(&mut self) {
        let lines: Vec<LineSettings> = (0..self.target.memory.serial_ports)
            .map(|n| self.line(usize::from(n)))
            .collect();
        let Some(factory) = self.port_factory.as_mut() else {
            return;
        };
        for (n, line) in (0u8..).zip(lines) {
            if let Some(port) = factory.port(n, line) {
                self.vm.attach_port(n, port);
            }
        }
    }

    /// One scan of the program (no-op when stopped or paused).
    pub fn scan(&mut self) -> Result<ScanEnd, gutta_vm::Fault> {
        self.vm.run_scan()
    }

    /// A standard Modbus data request (01-06/15/16), answered from memory.
    pub fn modbus(&mut self, pdu: &[u8]) -> Vec<u8> {
        modbus_data::serve(&mut self.vm, pdu)
    }

    /// STATUS_READ's byte: RUN, RESET, ATTACH, ERROR.
    pub fn status_byte(&self) -> u8 {
        let mut status = self.vm.status();
        status.attach = self.attached;
        status.error |= self.image_error || self.flash_fault.is_some();
        status.run &= !self.image_error && self.flash_fault.is_none();
        status.byte()
    }

    /// Answer one GUTTA request from connection `from` at time `now_ms` (for the login
    /// lockout and the download window's timeout): the answer frame, the request's
    /// function with bit 15 set and no payload on failure (`last_refusal` says why; a
    /// `Refusal::Busy` the session turns into Modbus exception 06, `LockedOut` into 04).
    pub fn answer(&mut self, from: ConnectionId, request: &GuttaFrame, now_ms: u64) -> GuttaFrame {
        self.track_window(from, now_ms);
        let result = if !self.target.plc.exch_support.supports(request.function) {
            Err(Refusal::Unsupported)
        } else {
            Request::decode(request)
                .map_err(Refusal::from)
                .and_then(|r| self.dispatch(from, r, now_ms))
                .and_then(|reply| {
                    Response {
                        packet: request.packet,
                        reply,
                    }
                    .encode()
                    .map_err(Refusal::from)
                })
        };
        match result {
            Ok(frame) => {
                self.last_refusal = None;
                frame
            }
            Err(why) => {
                self.last_refusal = Some(why);
                GuttaFrame::failure_of(request)
            }
        }
    }

    /// `answer` for a request given by its fields.
    pub fn gutta(
        &mut self,
        from: ConnectionId,
        function: u16,
        packet: u16,
        payload: &[u8],
        now_ms: u64,
    ) -> GuttaFrame {
        self.answer(
            from,
            &GuttaFrame::new(function, packet, payload.to_vec()),
            now_ms,
        )
    }

    /// One decoded request: another connection's download window first, the registry's
    /// login and stop conditions next, then the function's family (`identity`,
    /// `flash`, `run_state`, `variables`, `debugger`).
    fn dispatch(
        &mut self,
        from: ConnectionId,
        request: Request,
        now_ms: u64,
    ) -> Result<Reply, Refusal> {
        let function = request.function();
        if let Some(busy) = self.busy_for(from) {
            let refused = match &request.command {
                // Another client's login with the password the window's CLEAR erased
                // is not a wrong password: it came during a download (and it does not
                // count towards the lockout).
                Command::PlcAttach { password } => *password != self.password,
                _ => !window::open_to_others(function),
            };
            if refused {
                return Err(busy);
            }
        }
        if function.needs_login() && !self.attached {
            return Err(Refusal::NotAttached);
        }
        if function.needs_stop() && self.runs_program() {
            return Err(Refusal::Running);
        }
        let ack = Reply::Ack(function);
        let packet = request.packet;
        match request.command {
            Command::PlcClear => {
                self.commit(crate::persist::FlashState::Cleared, false, &BTreeMap::new())?;
                self.clear(from, now_ms);
                Ok(ack)
            }
            Command::PlcAttach { password } => self.attach(password, now_ms).map(|()| ack),
            Command::PlcDetach => {
                self.detach();
                Ok(ack)
            }
            Command::GetPlcName => Ok(Reply::PlcName(self.name())),
            Command::GetPlcInfor => Ok(Reply::PlcInfor(self.information())),
            Command::PageList(area) => Ok(Reply::PageList(area, self.page_list(area))),
            Command::PageAsk(page) => Ok(Reply::PageLength(page, self.page_length(page)?)),
            Command::PageRead(page) => Ok(Reply::PageData(page, self.read_page(page, packet)?)),
            Command::PageWrite(page, data) => {
                self.write_page(from, page, packet, &data).map(|()| ack)
            }
            Command::StatusRead => Ok(Reply::Status(self.status_byte())),
            Command::StatusWrite { run } => self.set_running(run != 0).map(|()| ack),
            Command::StatusScan { count } => self.scan_stopped(count).map(|()| ack),
            Command::StatusReset => self.reset_committed().map(|()| ack),
            Command::VarRead(addresses) => self.read_vars(&addresses).map(Reply::VarValues),
            Command::VarWrite(pairs) => self.write_vars(pairs).map(|()| ack),
            Command::ForceRead(addresses) => self.read_forces(&addresses).map(Reply::ForceValues),
            Command::ForceWrite(pairs) => self.write_forces(pairs).map(|()| ack),
            Command::DebugRead => Ok(Reply::DebugState(self.vm.debug_byte())),
            Command::DebugWrite { run } => self.debug_run(run != 0).map(|()| ack),
            Command::DebugScan(step) => self.debug_step(step).map(|()| ack),
            Command::DebugReset => self.debug_reset().map(|()| ack),
            Command::DebugInforRead => Ok(Reply::DebugInfo(self.debug_info())),
            Command::DebugInforWrite(breakpoint) => self.set_breakpoint(breakpoint).map(|()| ack),
        }
    }

    /// The PLC runs a program that verified (page writes need it stopped).
    fn runs_program(&self) -> bool {
        self.vm.is_running() && !self.image_error && self.has_program()
    }

    fn has_program(&self) -> bool {
        self.pages
            .contains_key(&PageId::new(PageKind::Instruction, 0))
    }
}

impl From<MessageError> for Refusal {
    fn from(e: MessageError) -> Self {
        match e {
            MessageError::UnknownFunction { .. } | MessageError::FailureBitInRequest { .. } => {
                Refusal::UnknownFunction
            }
            MessageError::PayloadLength { .. } => Refusal::BadLength,
            other => Refusal::Malformed(other.to_string()),
        }
    }
}
