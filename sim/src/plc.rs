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
//! - A request the target's ExchSupport does not allow, or with a payload of the wrong
//!   length, fails (function code with bit 15 set, no payload).

use std::collections::BTreeMap;
use std::sync::Arc;

use gutta_catalog::Target;
use gutta_format::{verify, ArgumentPage, Image, PageId, PageKind};
use gutta_protocol::gutta::{Function, PageArea};
use gutta_vm::{Position, ScanEnd, Step, Vm, VmConfig};

use crate::modbus_data;

/// The factory password: 16 x 0xFF.
pub const FACTORY_PASSWORD: [u8; 16] = [0xFF; 16];

/// The USE field value that makes STATUS_VAR_FORCE_WRITE release a force (our
/// extension; docs/simulator.md).
pub const RELEASE_USE: u32 = 0xF;

/// Bit 15 of a packet number: the last packet of a transfer.
pub const LAST_PACKET: u16 = 0x8000;

/// An answer to one GUTTA request.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Reply {
    /// The request's function code, or with bit 15 set for a failure.
    pub function: u16,
    pub packet: u16,
    pub payload: Vec<u8>,
}

impl Reply {
    pub fn is_failure(&self) -> bool {
        self.function & 0x8000 != 0
    }
}

/// Why a request failed (for logs and tests; on the wire every failure looks alike).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Refusal {
    NotAttached,
    WrongPassword,
    LockedOut { until_ms: u64 },
    BadLength,
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
    /// Where the PLC's serial ports lead (for EXCH); attached to every loaded VM.
    ports: BTreeMap<u8, crate::ports::PortSpec>,
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
        tool: "gutta-sim".into(),
        source: String::new(),
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
            ports: BTreeMap::new(),
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

    /// The station address: the first port of the system page (default 1).
    pub fn station(&self) -> u8 {
        self.pages
            .get(&PageId::new(PageKind::System, 0))
            .and_then(|b| gutta_format::SystemPage::decode(b).ok())
            .and_then(|s| s.ports.first().map(|p| p.address))
            .unwrap_or(1)
    }

    /// STATUS_RESET (and power-on): lock the flash, drop the login, load the pages. An
    /// image that verifies runs; otherwise the PLC is stopped, with ERROR set when
    /// pages were there.
    pub fn reset(&mut self) {
        self.unlocked = false;
        self.attached = false;
        let image = Image {
            plc_type: self.target.name().to_string(),
            tool: "flash".into(),
            source: String::new(),
            pages: self.pages.clone(),
        };
        self.password = gutta_format::SystemPage::decode(
            self.pages
                .get(&PageId::new(PageKind::System, 0))
                .map_or(&[][..], Vec::as_slice),
        )
        .map_or(FACTORY_PASSWORD, |s| s.password);
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
        for (n, spec) in &self.ports {
            self.vm
                .attach_port(*n, Box::new(crate::ports::StreamPort::new(spec.clone())));
        }
    }

    /// Lead serial port `n` to `spec`: EXCH on that port talks through it.
    pub fn set_port(&mut self, n: u8, spec: crate::ports::PortSpec) {
        self.vm
            .attach_port(n, Box::new(crate::ports::StreamPort::new(spec.clone())));
        self.ports.insert(n, spec);
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

    /// Answer one GUTTA request at time `now_ms` (for the login lockout).
    pub fn gutta(&mut self, function: u16, packet: u16, payload: &[u8], now_ms: u64) -> Reply {
        let result = if !self.target.plc.exch_support.supports(function) {
            Err(Refusal::Unsupported)
        } else {
            self.dispatch(function, packet, payload, now_ms)
        };
        match result {
            Ok(payload) => {
                self.last_refusal = None;
                Reply {
                    function,
                    packet,
                    payload,
                }
            }
            Err(why) => {
                self.last_refusal = Some(why);
                Reply {
                    function: function | 0x8000,
                    packet,
                    payload: Vec::new(),
                }
            }
        }
    }

    fn need_login(&self) -> Result<(), Refusal> {
        if self.attached {
            Ok(())
        } else {
            Err(Refusal::NotAttached)
        }
    }

    fn dispatch(
        &mut self,
        function: u16,
        packet: u16,
        payload: &[u8],
        now_ms: u64,
    ) -> Result<Vec<u8>, Refusal> {
        let empty = |p: &[u8]| {
            if p.is_empty() {
                Ok(())
            } else {
                Err(Refusal::BadLength)
            }
        };
        let Some(f) = Function::from_code(function) else {
            return Err(Refusal::UnknownFunction);
        };
        match f {
            Function::PlcClear => {
                empty(payload)?;
                self.pages.clear();
                self.password = FACTORY_PASSWORD;
                self.unlocked = true;
                self.image_error = false;
                self.vm.set_running(false);
                Ok(Vec::new())
            }
            Function::PlcAttach => {
                if payload.len() != 16 {
                    return Err(Refusal::BadLength);
                }
                if now_ms < self.guard.locked_until_ms {
                    return Err(Refusal::LockedOut {
                        until_ms: self.guard.locked_until_ms,
                    });
                }
                if payload != self.password {
                    self.guard.fail(now_ms);
                    return Err(Refusal::WrongPassword);
                }
                self.guard = LoginGuard::default();
                self.attached = true;
                self.vm.set_attached(true);
                Ok(Vec::new())
            }
            Function::PlcDetach => {
                empty(payload)?;
                self.attached = false;
                self.vm.set_attached(false);
                Ok(Vec::new())
            }
            Function::GetPlcName | Function::GetPlcInfor => {
                self.need_login()?;
                empty(payload)?;
                let (text, size) = if f == Function::GetPlcName {
                    (self.target.name().to_string(), 16)
                } else {
                    (self.target.plc.information.clone(), 64)
                };
                let mut out = text.into_bytes();
                out.truncate(size);
                out.resize(size, 0);
                Ok(out)
            }
            Function::PageList(area) => {
                self.need_login()?;
                empty(payload)?;
                Ok(self.page_list(area))
            }
            Function::PageAsk(page) => {
                self.need_login()?;
                empty(payload)?;
                let id = page.page_id();
                let len = self.pages.get(&id).ok_or(Refusal::NoSuchPage)?.len();
                Ok(u16::try_from(len)
                    .unwrap_or(u16::MAX)
                    .to_be_bytes()
                    .to_vec())
            }
            Function::PageRead(page) => {
                self.need_login()?;
                empty(payload)?;
                let id = page.page_id();
                let page = self.pages.get(&id).ok_or(Refusal::NoSuchPage)?;
                let size = self.pack_size();
                let start = usize::from(packet & !LAST_PACKET) * size;
                if start > page.len() || (start == page.len() && start > 0) {
                    return Err(Refusal::BadPacket);
                }
                Ok(page[start..page.len().min(start + size)].to_vec())
            }
            Function::PageWrite(page) => {
                self.need_login()?;
                if self.vm.is_running() && !self.image_error && self.has_program() {
                    return Err(Refusal::Running);
                }
                if !self.unlocked {
                    return Err(Refusal::FlashLocked);
                }
                self.write_packet(page.page_id(), packet, payload)?;
                Ok(Vec::new())
            }
            Function::StatusRead => {
                self.need_login()?;
                empty(payload)?;
                Ok(vec![self.status_byte()])
            }
            Function::StatusWrite => {
                self.need_login()?;
                let &[run] = payload else {
                    return Err(Refusal::BadLength);
                };
                if run != 0 && (self.image_error || !self.has_program()) {
                    return Err(Refusal::NoProgram);
                }
                self.vm.set_running(run != 0);
                Ok(Vec::new())
            }
            Function::StatusScan => {
                self.need_login()?;
                let &[n] = payload else {
                    return Err(Refusal::BadLength);
                };
                self.vm
                    .scan_while_stopped(n)
                    .map_err(|f| Refusal::Access(f.to_string()))?;
                Ok(Vec::new())
            }
            Function::StatusReset => {
                empty(payload)?;
                self.reset();
                Ok(Vec::new())
            }
            Function::VarRead | Function::ForceRead => {
                self.need_login()?;
                if payload.len() % 4 != 0 {
                    return Err(Refusal::BadLength);
                }
                let mut out = Vec::with_capacity(payload.len());
                for a in payload.chunks_exact(4) {
                    let address = u32::from_le_bytes([a[0], a[1], a[2], a[3]]);
                    let value = if f == Function::VarRead {
                        self.vm.read_packed(address)
                    } else {
                        self.vm.read_force_packed(address)
                    }
                    .map_err(|e| Refusal::Access(e.0))?;
                    out.extend(value);
                }
                Ok(out)
            }
            Function::VarWrite | Function::ForceWrite => {
                self.need_login()?;
                if payload.len() % 8 != 0 {
                    return Err(Refusal::BadLength);
                }
                // Check every pair first, so a bad one writes nothing.
                let pairs: Vec<(u32, u32)> = payload
                    .chunks_exact(8)
                    .map(|p| {
                        (
                            u32::from_le_bytes([p[0], p[1], p[2], p[3]]),
                            u32::from_le_bytes([p[4], p[5], p[6], p[7]]),
                        )
                    })
                    .collect();
                for &(address, _) in &pairs {
                    self.vm
                        .read_packed(address)
                        .map_err(|e| Refusal::Access(e.0))?;
                }
                for (address, value) in pairs {
                    if f == Function::VarWrite {
                        self.vm
                            .write_packed(address, value)
                            .map_err(|e| Refusal::Access(e.0))?;
                    } else if address & 0xF == RELEASE_USE {
                        // Our extension: USE 15 releases the force (UM4001 has no
                        // unforce; a PLC that ignores USE forces the value sent, which
                        // the client makes the current value).
                        let op = gutta_format::PackedOperand(address);
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
                            .force_packed(address, value)
                            .map_err(|e| Refusal::Access(e.0))?;
                    }
                }
                Ok(Vec::new())
            }
            Function::DebugRead => {
                self.need_login()?;
                empty(payload)?;
                Ok(vec![self.vm.debug_byte()])
            }
            Function::DebugWrite => {
                self.need_login()?;
                let &[run] = payload else {
                    return Err(Refusal::BadLength);
                };
                if run == 0 {
                    self.vm
                        .debug_stop()
                        .map_err(|e| Refusal::Debug(e.to_string()))?;
                } else {
                    self.vm.debug_run();
                }
                Ok(Vec::new())
            }
            Function::DebugScan => {
                self.need_login()?;
                let step = match payload {
                    [1] => Step::In,
                    [2] => Step::Over,
                    [3] => Step::Out,
                    _ => return Err(Refusal::BadLength),
                };
                self.vm
                    .debug_step(step)
                    .map_err(|e| Refusal::Debug(e.to_string()))?;
                Ok(Vec::new())
            }
            Function::DebugReset => {
                empty(payload)?;
                self.vm
                    .debug_reset()
                    .map_err(|e| Refusal::Debug(e.to_string()))?;
                Ok(Vec::new())
            }
            Function::DebugInforRead => {
                self.need_login()?;
                empty(payload)?;
                Ok(self.vm.debug_info().to_vec())
            }
            Function::DebugInforWrite => {
                self.need_login()?;
                let &[function, n1, n2, s1, s2] = payload else {
                    return Err(Refusal::BadLength);
                };
                let network = u16::from_be_bytes([n1, n2]);
                let step = u16::from_be_bytes([s1, s2]);
                let at = (function != 0xFF).then_some(Position {
                    function,
                    network,
                    step,
                });
                self.vm
                    .set_breakpoint(at)
                    .map_err(|e| Refusal::Debug(e.to_string()))?;
                Ok(Vec::new())
            }
        }
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
