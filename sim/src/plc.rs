//! The simulated PLC as UM4001 describes it, without I/O: user flash (the downloaded
//! pages), the login, the run state, and the VM that runs the image. `gutta` answers
//! one GUTTA request (the data inside Modbus function 13); `modbus` one standard Modbus
//! data request; `scan` runs the program. Transports and time live in the binary.
//!
//! Rules (UM4001, and what we decided where it is silent; docs/simulator.md):
//! - Everything but PLC_CLEAR, STATUS_RESET and DEBUG_RESET needs a login (ATTACH).
//! - PLC_CLEAR erases the pages and the password, stops the PLC and unlocks the flash;
//!   STATUS_RESET locks it again. Page writes need the flash unlocked and the PLC
//!   stopped. STATUS_RESET then loads the pages: an image that verifies runs; one that
//!   does not leaves the PLC stopped with ERROR set.
//! - A failed ATTACH counts; from the third failure in a row every ATTACH is refused
//!   for a lockout that doubles from 1 s up to 60 s; a good password resets it.
//! - Requests are decoded with gutta-protocol's `message::Request`. One the target's
//!   ExchSupport does not allow, or that does not decode (payload length, packet
//!   number 0x8000 for single-packet functions, debug step 1..3), fails: function
//!   code with bit 15 set, no payload.

use std::collections::BTreeMap;
use std::sync::Arc;

use gutta_catalog::Target;
use gutta_format::{verify, ArgumentPage, Image, LineSettings, PageId, PageKind};
use gutta_protocol::gutta::{GuttaFrame, PageArea};
use gutta_protocol::message::{
    Command, DebugInfo, DebugStep, MessageError, Reply, Request, Response, VarAddress,
};
use gutta_vm::{Position, ScanEnd, Step, Vm, VmConfig};

use crate::modbus_data;
use crate::ports::PortFactory;

/// The factory password: 16 x 0xFF.
pub const FACTORY_PASSWORD: [u8; 16] = [0xFF; 16];

/// The USE field value that makes STATUS_VAR_FORCE_WRITE release a force (our
/// extension; docs/simulator.md).
pub const RELEASE_USE: u32 = 0xF;

/// Bit 15 of a packet number: the last packet of a transfer.
pub const LAST_PACKET: u16 = gutta_protocol::gutta::LAST_PACKET;

/// Why a request failed (for logs and tests; on the wire every failure looks alike).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Refusal {
    NotAttached,
    WrongPassword,
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
    FlashLocked,
    NoSuchPage,
    BadPacket,
    NoProgram,
    Access(String),
    Debug(String),
}

/// Login failures and the lockout after them.
#[derive(Debug, Clone, Default)]
struct LoginGuard {
    failures: u32,
    locked_until_ms: u64,
}

impl LoginGuard {
    const FREE_FAILURES: u32 = 2;
    const MAX_LOCKOUT_MS: u64 = 60_000;

    fn fail(&mut self, now_ms: u64) {
        self.failures += 1;
        if self.failures > Self::FREE_FAILURES {
            let doublings = (self.failures - Self::FREE_FAILURES - 1).min(6);
            let lockout = (1000u64 << doublings).min(Self::MAX_LOCKOUT_MS);
            self.locked_until_ms = now_ms + lockout;
        }
    }
}

/// The simulated PLC.
#[derive(Debug)]
pub struct Plc {
    target: Arc<Target>,
    config: VmConfig,
    /// User flash: the pages last written.
    pages: BTreeMap<PageId, Vec<u8>>,
    /// PLC_CLEAR unlocks the flash for writing; STATUS_RESET locks it.
    unlocked: bool,
    attached: bool,
    password: [u8; 16],
    guard: LoginGuard,
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
            unlocked: false,
            attached: false,
            password: FACTORY_PASSWORD,
            guard: LoginGuard::default(),
            vm,
            image_error: false,
            last_refusal: None,
            port_factory: None,
            active_ports: Vec::new(),
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

    /// STATUS_RESET (and power-on): lock the flash, drop the login, load the pages. An
    /// image that verifies runs; otherwise the PLC is stopped, with ERROR set when
    /// pages were there.
    pub fn reset(&mut self) {
        self.unlocked = false;
        self.attached = false;
        let image = Image {
            plc_type: self.target.name().to_string(),
            pages: self.pages.clone(),
        };
        let system = self
            .pages
            .get(&PageId::new(PageKind::System, 0))
            .and_then(|b| gutta_format::SystemPage::decode(b).ok());
        self.password = system.as_ref().map_or(FACTORY_PASSWORD, |s| s.password);
        self.active_ports = system.map(|s| s.ports).unwrap_or_default();
        let loaded = verify(&image, &self.target)
            .ok()
            .and_then(|v| Vm::new(v, Arc::clone(&self.target), self.config).ok());
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
        status.error |= self.image_error;
        status.run &= !self.image_error;
        status.byte()
    }

    /// Answer one GUTTA request at time `now_ms` (for the login lockout): the answer
    /// frame, the request's function with bit 15 set and no payload on failure.
    pub fn answer(&mut self, request: &GuttaFrame, now_ms: u64) -> GuttaFrame {
        let result = if !self.target.plc.exch_support.supports(request.function) {
            Err(Refusal::Unsupported)
        } else {
            Request::decode(request)
                .map_err(Refusal::from)
                .and_then(|r| self.dispatch(r, now_ms))
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
    pub fn gutta(&mut self, function: u16, packet: u16, payload: &[u8], now_ms: u64) -> GuttaFrame {
        self.answer(&GuttaFrame::new(function, packet, payload.to_vec()), now_ms)
    }

    fn dispatch(&mut self, request: Request, now_ms: u64) -> Result<Reply, Refusal> {
        let function = request.function();
        if function.needs_login() && !self.attached {
            return Err(Refusal::NotAttached);
        }
        let ack = Ok(Reply::Ack(function));
        match request.command {
            Command::PlcClear => {
                self.pages.clear();
                self.password = FACTORY_PASSWORD;
                // The station and the serial lines revert to their defaults (UM4001).
                self.active_ports.clear();
                self.unlocked = true;
                self.image_error = false;
                self.vm.set_running(false);
                ack
            }
            Command::PlcAttach { password } => {
                if now_ms < self.guard.locked_until_ms {
                    return Err(Refusal::LockedOut {
                        until_ms: self.guard.locked_until_ms,
                    });
                }
                if password != self.password {
                    self.guard.fail(now_ms);
                    return Err(Refusal::WrongPassword);
                }
                self.guard = LoginGuard::default();
                self.attached = true;
                self.vm.set_attached(true);
                ack
            }
            Command::PlcDetach => {
                self.attached = false;
                self.vm.set_attached(false);
                ack
            }
            Command::GetPlcName => Ok(Reply::PlcName(padded(self.target.name()))),
            Command::GetPlcInfor => Ok(Reply::PlcInfor(padded(&self.target.plc.information))),
            Command::PageList(area) => Ok(Reply::PageList(area, self.page_list(area))),
            Command::PageAsk(page) => {
                let len = self
                    .pages
                    .get(&page.page_id())
                    .ok_or(Refusal::NoSuchPage)?
                    .len();
                Ok(Reply::PageLength(
                    page,
                    u16::try_from(len).unwrap_or(u16::MAX),
                ))
            }
            Command::PageRead(page) => {
                let bytes = self.pages.get(&page.page_id()).ok_or(Refusal::NoSuchPage)?;
                let size = self.pack_size();
                let start = usize::from(request.packet & !LAST_PACKET) * size;
                if start > bytes.len() || (start == bytes.len() && start > 0) {
                    return Err(Refusal::BadPacket);
                }
                let end = bytes.len().min(start + size);
                Ok(Reply::PageData(page, bytes[start..end].to_vec()))
            }
            Command::PageWrite(page, data) => {
                if self.vm.is_running() && !self.image_error && self.has_program() {
                    return Err(Refusal::Running);
                }
                if !self.unlocked {
                    return Err(Refusal::FlashLocked);
                }
                self.write_packet(page.page_id(), request.packet, &data)?;
                ack
            }
            Command::StatusRead => Ok(Reply::Status(self.status_byte())),
            Command::StatusWrite { run } => {
                if run != 0 && (self.image_error || !self.has_program()) {
                    return Err(Refusal::NoProgram);
                }
                self.vm.set_running(run != 0);
                ack
            }
            Command::StatusScan { count } => {
                self.vm
                    .scan_while_stopped(count)
                    .map_err(|f| Refusal::Access(f.to_string()))?;
                ack
            }
            Command::StatusReset => {
                self.reset();
                ack
            }
            Command::VarRead(addresses) => Ok(Reply::VarValues(
                self.read_each(&addresses, |vm, a| vm.read_packed(a))?,
            )),
            Command::ForceRead(addresses) => Ok(Reply::ForceValues(
                self.read_each(&addresses, |vm, a| vm.read_force_packed(a))?,
            )),
            Command::VarWrite(pairs) => {
                self.check_each(&pairs)?;
                for (address, value) in pairs {
                    self.vm
                        .write_packed(address.0, value)
                        .map_err(|e| Refusal::Access(e.0))?;
                }
                ack
            }
            Command::ForceWrite(pairs) => {
                self.check_each(&pairs)?;
                for (address, value) in pairs {
                    if u32::from(address.use_field()) == RELEASE_USE {
                        // Our extension: USE 15 releases the force (UM4001 has no
                        // unforce; a PLC that ignores USE forces the value sent, which
                        // the client makes the current value).
                        let op = gutta_format::PackedOperand(address.0);
                        if let Some(a) = op.width().map(|width| gutta_catalog::Address {
                            slot: op.slot(),
                            width,
                            offset: u32::from(op.offset()),
                            bit: op.bit() & 7,
                        }) {
                            self.vm.unforce(a);
                        }
                    } else {
                        self.vm
                            .force_packed(address.0, value)
                            .map_err(|e| Refusal::Access(e.0))?;
                    }
                }
                ack
            }
            Command::DebugRead => Ok(Reply::DebugState(self.vm.debug_byte())),
            Command::DebugWrite { run } => {
                if run == 0 {
                    self.vm
                        .debug_stop()
                        .map_err(|e| Refusal::Debug(e.to_string()))?;
                } else {
                    self.vm.debug_run();
                }
                ack
            }
            Command::DebugScan(step) => {
                let step = match step {
                    DebugStep::In => Step::In,
                    DebugStep::Over => Step::Over,
                    DebugStep::Out => Step::Out,
                };
                self.vm
                    .debug_step(step)
                    .map_err(|e| Refusal::Debug(e.to_string()))?;
                ack
            }
            Command::DebugReset => {
                self.vm
                    .debug_reset()
                    .map_err(|e| Refusal::Debug(e.to_string()))?;
                ack
            }
            Command::DebugInforRead => {
                Ok(Reply::DebugInfo(DebugInfo::decode(&self.vm.debug_info())))
            }
            Command::DebugInforWrite(breakpoint) => {
                let at = (breakpoint.index != 0xFF).then_some(Position {
                    function: breakpoint.index,
                    network: breakpoint.network,
                    step: breakpoint.step,
                });
                self.vm
                    .set_breakpoint(at)
                    .map_err(|e| Refusal::Debug(e.to_string()))?;
                ack
            }
        }
    }

    /// Every address read, or the first refusal.
    fn read_each(
        &self,
        addresses: &[VarAddress],
        read: impl Fn(&Vm, u32) -> Result<[u8; 4], gutta_vm::AccessError>,
    ) -> Result<Vec<u32>, Refusal> {
        addresses
            .iter()
            .map(|a| {
                read(&self.vm, a.0)
                    .map(u32::from_le_bytes)
                    .map_err(|e| Refusal::Access(e.0))
            })
            .collect()
    }

    /// Every address of a write checked first, so a bad one writes nothing.
    fn check_each(&self, pairs: &[(VarAddress, u32)]) -> Result<(), Refusal> {
        for (address, _) in pairs {
            self.vm
                .read_packed(address.0)
                .map_err(|e| Refusal::Access(e.0))?;
        }
        Ok(())
    }

    fn has_program(&self) -> bool {
        self.pages
            .contains_key(&PageId::new(PageKind::Instruction, 0))
    }

    fn pack_size(&self) -> usize {
        (self.target.plc.exch_pack_size as usize).max(1)
    }

    /// DATA_ASK, SYSTEM_ASK, PROGRAM_ASK: the numbers of the pages present (for the
    /// program: the instruction pages).
    fn page_list(&self, area: PageArea) -> Vec<u8> {
        let kind = match area {
            PageArea::Data => PageKind::Data,
            PageArea::System => PageKind::System,
            PageArea::Program => PageKind::Instruction,
        };
        self.pages
            .keys()
            .filter(|id| id.kind == kind)
            .map(|id| id.number)
            .collect()
    }

    /// A write packet: packet 0 starts the page, each next packet continues at
    /// packet x ExchPackSize; the last packet ends the page.
    fn write_packet(&mut self, id: PageId, packet: u16, payload: &[u8]) -> Result<(), Refusal> {
        let size = self.pack_size();
        let number = usize::from(packet & !LAST_PACKET);
        let last = packet & LAST_PACKET != 0;
        if payload.len() > size || (!last && payload.len() != size) {
            return Err(Refusal::BadPacket);
        }
        let page = self.pages.entry(id).or_default();
        if number == 0 {
            page.clear();
        } else if page.len() != number * size {
            return Err(Refusal::BadPacket);
        }
        page.extend_from_slice(payload);
        Ok(())
    }
}

/// A name or information text as the fixed-size answer field: cut to N bytes, or
/// padded with zeros (which also terminates it).
fn padded<const N: usize>(text: &str) -> [u8; N] {
    let mut out = [0u8; N];
    let bytes = text.as_bytes();
    let n = bytes.len().min(N);
    out[..n].copy_from_slice(&bytes[..n]);
    out
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lockout_doubles_after_two_free_failures() {
        let mut g = LoginGuard::default();
        g.fail(0);
        g.fail(0);
        assert_eq!(g.locked_until_ms, 0);
        g.fail(10);
        assert_eq!(g.locked_until_ms, 1010);
        g.fail(2000);
        assert_eq!(g.locked_until_ms, 4000);
        for _ in 0..20 {
            g.fail(5000);
        }
        assert_eq!(g.locked_until_ms, 65_000);
    }
}
