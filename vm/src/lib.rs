//! The reference VM: runs a verified GUTTA image as the PLC would. It depends only on
//! the image format (and, through it, the target description), never on the compiler.
//! Semantics are in `ops/`, one file per instruction family, keyed by mnemonic; the VM
//! refuses an image that uses an instruction it has no semantics for.

mod debug;
mod decode;
mod engine;
pub mod exch;
mod fault;
mod memory;
pub mod ops;

use std::collections::HashMap;
use std::sync::Arc;

use gutta_catalog::{Address, AreaKind, Target};
use gutta_format::{UnitRecord, VerifiedImage};

pub use debug::{DebugError, Position, Status, Step};
pub use engine::ScanEnd;
pub use fault::Fault;
pub use memory::{AccessError, Location, Memory};
use ops::Handler;

/// How the VM runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct VmConfig {
    /// Virtual time per scan, in milliseconds (timers count it).
    pub scan_ms: u32,
    /// Instructions one scan may execute before the watchdog stops the VM.
    pub watchdog: u64,
    /// Run the frequent instructions as pre-decoded operations (the default). Off,
    /// every instruction runs its semantic from `ops/`; the tests compare both.
    pub fast: bool,
}

impl Default for VmConfig {
    fn default() -> Self {
        VmConfig {
            scan_ms: 10,
            watchdog: 10_000_000,
            fast: true,
        }
    }
}

/// Interrupt state (docs/vm.md, "Interrupts").
#[derive(Debug, Default, Clone, PartialEq, Eq)]
pub(crate) struct Interrupts {
    /// ENI/DISI; off when the PLC enters RUN.
    pub enabled: bool,
    /// Event number -> interrupt routine number.
    pub attached: std::collections::BTreeMap<u32, u32>,
    /// Timed events: milliseconds accumulated towards the next occurrence.
    pub elapsed: std::collections::BTreeMap<u32, u32>,
    /// Events that occurred while interrupts were disabled (one kept per event).
    pub pending: std::collections::BTreeSet<u32>,
    /// Edge events: their input bit at the previous scan.
    pub last_input: std::collections::BTreeMap<u32, bool>,
}

/// Why a variable cannot be forced.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ForceError(pub String);

impl std::fmt::Display for ForceError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ForceError {}

/// Why an image cannot be loaded.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LoadError {
    /// The image was verified against another PLC type.
    WrongTarget { image: String, target: String },
    /// The image uses instructions the VM has no semantics for.
    MissingSemantics(Vec<String>),
}

impl std::fmt::Display for LoadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LoadError::WrongTarget { image, target } => {
                write!(f, "image for {image}, VM target {target}")
            }
            LoadError::MissingSemantics(m) => write!(f, "no semantics for: {}", m.join(", ")),
        }
    }
}

impl std::error::Error for LoadError {}

/// Well-known slots, found by area kind.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Slots {
    pub sm: u8,
    pub local: u8,
    pub constant: u8,
}

/// A loaded PLC.
#[derive(Debug)]
pub struct Vm {
    pub(crate) target: Arc<Target>,
    pub(crate) image: VerifiedImage,
    pub(crate) memory: Memory,
    pub(crate) config: VmConfig,
    pub(crate) slots: Slots,
    pub(crate) handlers: Vec<Option<Handler>>,
    /// Each unit (by page) decoded; shared so a running frame does not copy it.
    pub(crate) units: Vec<Option<Arc<decode::Unit>>>,
    /// The units being run, innermost last.
    pub(crate) frames: Vec<engine::Frame>,
    /// Where the current scan is.
    pub(crate) phase: engine::Phase,
    /// Breakpoint, pause and single-step state.
    pub(crate) debug: debug::Debug,
    /// Index of SMB1 (the math flags) in the flat memory.
    pub(crate) flags_at: usize,
    /// The callers' L areas, saved by CALL, innermost last.
    pub(crate) l_stack: Vec<u8>,
    /// Reused buffers of CALL (argument values, the CALL's operands).
    pub(crate) scratch: Vec<u32>,
    pub(crate) call_operands: Vec<gutta_format::PackedOperand>,
    /// Logic stack: bit 0 is the top; depth from the catalog.
    pub(crate) stack: u32,
    pub(crate) stack_mask: u32,
    /// Edge memory of EU/ED, per (page, record index).
    pub(crate) edges: HashMap<(u8, usize), bool>,
    /// Hidden state of an instruction instance, per (page, record index): four words a
    /// family may use as it documents (e.g. a timer's remainder of a time unit).
    pub(crate) instance_state: HashMap<(u8, usize), [u32; 4]>,
    /// Hidden state of a memory cell, per (slot, byte offset): e.g. a counter's
    /// previous inputs, shared by every instruction driving that counter.
    pub(crate) cell_state: HashMap<(u8, u32), [u32; 4]>,
    /// FOR record -> its NEXT record, per (page, record index).
    pub(crate) for_pairs: HashMap<(u8, usize), usize>,
    /// Open FOR loops, innermost last.
    pub(crate) loops: Vec<ops::LoopFrame>,
    /// STOP was executed: scans do nothing until `set_running(true)`.
    pub(crate) stopped: bool,
    /// STATUS_RESET was requested; the next scan resets first.
    pub(crate) reset_requested: bool,
    /// Terminal images of the input areas (I, AI): what the host set; copied into the
    /// input areas at the start of every scan.
    pub(crate) terminals: HashMap<u8, Vec<u8>>,
    /// Force images of the forcing areas (I, Q): slot -> (mask, value), byte per byte.
    pub(crate) forces: HashMap<u8, (Vec<u8>, Vec<u8>)>,
    /// Interrupt state: global enable, attachments, timed-event clocks, pending events.
    pub(crate) interrupts: Interrupts,
    /// EXCH: queued exchanges and the serial ports the host attached.
    pub(crate) exch: exch::ExchState,
    pub(crate) clock_ms: u64,
    pub(crate) scans: u64,
    pub(crate) executed: u64,
    pub(crate) fault: Option<Fault>,
}

impl Vm {
    /// Load a verified image.
    pub fn new(
        image: VerifiedImage,
        target: Arc<Target>,
        config: VmConfig,
    ) -> Result<Vm, LoadError> {
        if image.target_name() != target.name() {
            return Err(LoadError::WrongTarget {
                image: image.target_name().to_string(),
                target: target.name().to_string(),
            });
        }
        let handlers: Vec<Option<Handler>> = target
            .instructions
            .instructions
            .iter()
            .map(|i| ops::semantics(&i.mnemonic))
            .collect();
        let mut missing: Vec<String> = Vec::new();
        for unit in image.units().values() {
            for r in &unit.records {
                if let UnitRecord::Instruction { id, .. } = r {
                    if handlers.get(id.0 as usize).copied().flatten().is_none() {
                        missing.push(target.instructions.get(*id).mnemonic.clone());
                    }
                }
            }
        }
        missing.sort();
        missing.dedup();
        if !missing.is_empty() {
            return Err(LoadError::MissingSemantics(missing));
        }
        let slot = |k: AreaKind| target.memory.area_of_kind(k).map(|a| a.slot).unwrap_or(0);
        let slots = Slots {
            sm: slot(AreaKind::System),
            local: slot(AreaKind::Local),
            constant: slot(AreaKind::Constant),
        };
        let depth = target.instructions.logic_stack_depth.min(32) as u32;
        let stack_mask = if depth >= 32 {
            u32::MAX
        } else {
            (1u32 << depth) - 1
        };
        // Pair every FOR with its NEXT (the compiler guarantees they match per unit).
        let mut for_pairs = HashMap::new();
        let (for_id, next_id) = (
            target.instructions.lookup("FOR"),
            target.instructions.lookup("NEXT"),
        );
        for (page, unit) in image.units() {
            let mut open = Vec::new();
            for (i, r) in unit.records.iter().enumerate() {
                if let UnitRecord::Instruction { id, .. } = r {
                    if Some(*id) == for_id {
                        open.push(i);
                    } else if Some(*id) == next_id {
                        if let Some(f) = open.pop() {
                            for_pairs.insert((*page, f), i);
                        }
                    }
                }
            }
        }
        let terminals = target
            .memory
            .areas
            .iter()
            .filter(|a| matches!(a.kind, AreaKind::DigitalInput | AreaKind::AnalogInput))
            .map(|a| (a.slot, vec![0; a.size as usize]))
            .collect();
        let memory = Memory::new(&target.memory);
        let mut units = vec![None; 256];
        let mut image = image;
        let verified_units = image.take_units();
        let params = |page: u8| {
            verified_units
                .get(&page)
                .map(|u| u.parameters().copied().collect())
        };
        for (page, unit) in &verified_units {
            units[*page as usize] = Some(Arc::new(decode::decode(
                unit,
                &target,
                &memory,
                config.fast,
                &params,
            )));
        }
        let flags_at = memory
            .span(slots.sm)
            .filter(|&(_, len)| len > 1)
            .map_or(0, |(start, _)| start + 1);
        let mut vm = Vm {
            target,
            image,
            memory,
            config,
            slots,
            handlers,
            units,
            frames: Vec::new(),
            phase: engine::Phase::Idle,
            debug: debug::Debug::default(),
            flags_at,
            l_stack: Vec::new(),
            scratch: Vec::new(),
            call_operands: Vec::new(),
            stack: 0,
            stack_mask,
            edges: HashMap::new(),
            instance_state: HashMap::new(),
            cell_state: HashMap::new(),
            for_pairs,
            loops: Vec::new(),
            stopped: false,
            reset_requested: false,
            forces: HashMap::new(),
            terminals,
            exch: exch::ExchState::default(),
            interrupts: Interrupts::default(),
            clock_ms: 0,
            scans: 0,
            executed: 0,
            fault: None,
        };
        vm.reset();
        Ok(vm)
    }

    /// Power-on reset: memory cleared, K from the const page, data pages applied,
    /// edge memory and clock cleared, the next scan is the first.
    pub fn reset(&mut self) {
        self.memory.clear();
        if let Some(k) = self.memory.area_mut(self.slots.constant) {
            let consts = self.image.constants();
            let n = consts.len().min(k.len());
            k[..n].copy_from_slice(&consts[..n]);
        }
        let items: Vec<_> = self.image.data().values().flatten().copied().collect();
        for item in items {
            // Verified: in-area, value fits; a failure here would be a verifier bug.
            let _ = self.memory.store(item.operand, item.value);
        }
        self.edges.clear();
        self.instance_state.clear();
        self.cell_state.clear();
        self.abandon_scan();
        self.interrupts = Interrupts::default();
        self.exch.queue.clear();
        self.stopped = false;
        self.reset_requested = false;
        self.debug.reset_pending = false;
        self.clock_ms = 0;
        self.scans = 0;
        self.fault = None;
    }

    /// The fault that stopped the VM, if any.
    pub fn fault(&self) -> Option<&Fault> {
        self.fault.as_ref()
    }

    /// Whether the PLC is in RUN (false after STOP).
    pub fn is_running(&self) -> bool {
        !self.stopped
    }

    /// RUN (true) or STOP (false), as STATUS_WRITE does.
    /// Going to STOP abandons a scan paused in the middle.
    pub fn set_running(&mut self, run: bool) {
        self.stopped = !run;
        if !run {
            self.abandon_scan();
        }
    }

    /// Instructions the last scan executed (MAIN, calls and interrupt routines).
    pub fn executed_last_scan(&self) -> u64 {
        self.executed
    }

    pub fn scans(&self) -> u64 {
        self.scans
    }

    pub fn clock_ms(&self) -> u64 {
        self.clock_ms
    }

    pub fn memory(&self) -> &Memory {
        &self.memory
    }

    pub fn target(&self) -> &Target {
        &self.target
    }

    /// Read a variable (e.g. parsed with `MemoryMap::parse_address`).
    pub fn read(&self, address: Address) -> Result<u32, AccessError> {
        self.memory.read(Location::from(address))
    }

    /// Write a variable. Writing an input (I, AI) sets its terminal: the value holds
    /// across scans until changed, as a wired input does. A forced bit keeps its force
    /// value (the force wins at the next scan); `write_packed` is the protocol's write,
    /// which changes the force value too.
    pub fn write(&mut self, address: Address, value: u32) -> Result<(), AccessError> {
        let loc = Location::from(address);
        if let Some(terminal) = self.terminals.get_mut(&address.slot) {
            memory::write_in(terminal, loc, value)?;
        }
        self.memory.write(loc, value)
    }

    /// STATUS_VAR_READ: the 4 bytes from the first byte of a packed address (only SLOT
    /// and OFFSET count). Bytes past the end of the area read as 0; a first byte outside
    /// the area is an error.
    pub fn read_packed(&self, address: u32) -> Result<[u8; 4], AccessError> {
        let op = gutta_format::PackedOperand(address);
        let area = self
            .memory
            .area(op.slot())
            .ok_or_else(|| AccessError(format!("no area in slot {}", op.slot())))?;
        four_bytes(area, op.offset() as usize, op.slot())
    }

    /// STATUS_VAR_WRITE: write `value` where SLOT, WIDTH, BIT_OFFSET and OFFSET say (USE
    /// is ignored), as `write` does; a forced bit takes the value as its force value
    /// too (UM4001), so the write holds.
    pub fn write_packed(&mut self, address: u32, value: u32) -> Result<(), AccessError> {
        let address = packed_address(address)?;
        self.write(address, value)?;
        let loc = Location::from(address);
        if let (Some((mask, image)), Some(area)) = (
            self.forces.get_mut(&address.slot),
            self.memory.area(address.slot),
        ) {
            for (k, m) in bit_mask(loc).iter().enumerate() {
                let at = loc.offset as usize + k;
                let forced = mask[at] & m;
                image[at] = (image[at] & !forced) | (area[at] & forced);
            }
        }
        Ok(())
    }

    /// STATUS_VAR_FORCE_READ: 4 bytes of the force value image from the first byte of a
    /// packed address (0 where nothing is forced; areas that cannot be forced read 0).
    pub fn read_force_packed(&self, address: u32) -> Result<[u8; 4], AccessError> {
        let op = gutta_format::PackedOperand(address);
        let (_, image) = self.force_image(op.slot());
        if image.is_empty() {
            return Err(AccessError(format!("no area in slot {}", op.slot())));
        }
        four_bytes(&image, op.offset() as usize, op.slot())
    }

    /// STATUS_VAR_FORCE_WRITE: force the variable at a packed address to `value` (it
    /// reads, or is written, with that value every scan until unforced).
    pub fn force_packed(&mut self, address: u32, value: u32) -> Result<(), ForceError> {
        let a = packed_address(address).map_err(|e| ForceError(e.0))?;
        self.force(a, value)
    }

    /// Remove the force of one variable (its bits; the rest of the byte stays forced).
    pub fn unforce(&mut self, address: Address) {
        let loc = Location::from(address);
        if let Some((mask, _)) = self.forces.get_mut(&address.slot) {
            for (k, m) in bit_mask(loc).iter().enumerate() {
                if let Some(b) = mask.get_mut(loc.offset as usize + k) {
                    *b &= !m;
                }
            }
        }
    }

    /// STATUS_RESET: request a reset; RESET shows in the status byte until it happens,
    /// at the start of the next scan (or `reset()`).
    pub fn request_reset(&mut self) {
        self.reset_requested = true;
    }

    /// STATUS_SCAN: a PLC in STOP runs `n` scans and stays in STOP. A running PLC is not
    /// affected (it scans anyway).
    pub fn scan_while_stopped(&mut self, n: u8) -> Result<(), Fault> {
        if !self.stopped {
            return Ok(());
        }
        self.stopped = false;
        let mut result = Ok(());
        for _ in 0..n {
            result = self.scan();
            if result.is_err() || self.stopped {
                break;
            }
        }
        self.set_running(false);
        result
    }

    /// One scan: inputs, system bits, MAIN, interrupt routines, forces, EXCH, clock. A
    /// fault stops the VM (ERROR) until reset. While paused (breakpoint, single-step
    /// stop) or in STOP, nothing runs.
    pub fn scan(&mut self) -> Result<(), Fault> {
        self.run_scan().map(|_| ())
    }

    /// Like `scan`, saying how it ended: a paused scan continues where it stopped.
    pub fn run_scan(&mut self) -> Result<ScanEnd, Fault> {
        if let Some(f) = &self.fault {
            return Err(f.clone());
        }
        if self.stopped {
            return Ok(ScanEnd::Stopped);
        }
        if self.debug.paused {
            return Ok(self.position().map_or(ScanEnd::PausedIdle, ScanEnd::Paused));
        }
        if self.reset_requested {
            self.reset();
        }
        self.debug.reset_pending = false;
        self.continue_scan()
            .inspect_err(|f| self.record_fault(f.clone()))
    }

    /// Drop a scan in progress (frames, loops, saved L, pause).
    pub(crate) fn abandon_scan(&mut self) {
        self.frames.clear();
        self.loops.clear();
        self.l_stack.clear();
        self.phase = engine::Phase::Idle;
        self.debug.paused = false;
    }

    /// A fault: SMB2 holds its code, the scan is abandoned (and counted), ERROR is set.
    pub(crate) fn record_fault(&mut self, f: Fault) {
        let sm = self.slots.sm;
        let _ = self.memory.write(
            Location {
                slot: sm,
                offset: 2,
                width: gutta_catalog::Width::Byte,
                bit: 0,
            },
            f.code() as u32,
        );
        if self.phase != engine::Phase::Idle {
            self.end_scan_clock();
        }
        self.abandon_scan();
        self.fault = Some(f);
    }

    /// Force a variable of a forcing area (I, Q): it reads (inputs) and is written
    /// (outputs) with `value` at every scan until unforced. Forces survive `reset()`.
    pub fn force(&mut self, address: Address, value: u32) -> Result<(), ForceError> {
        if !self.target.memory.can_force(address.slot) {
            let area = self
                .target
                .memory
                .area_by_slot(address.slot)
                .map(|a| a.name.clone())
                .unwrap_or_default();
            return Err(ForceError(format!(
                "area {area} cannot be forced (only {})",
                self.forcing_areas()
            )));
        }
        let size = self.memory.area(address.slot).map(<[u8]>::len).unwrap_or(0);
        let end = address.offset as usize + address.width.bytes() as usize;
        if end > size {
            return Err(ForceError(format!("outside the area ({size} bytes)")));
        }
        let (mask, image) = self
            .forces
            .entry(address.slot)
            .or_insert_with(|| (vec![0; size], vec![0; size]));
        let bytes = value.to_le_bytes();
        for (k, &byte) in bytes
            .iter()
            .enumerate()
            .take(address.width.bytes() as usize)
        {
            let at = address.offset as usize + k;
            let (m, v) = match address.width {
                gutta_catalog::Width::Bit => (
                    1u8 << (address.bit & 7),
                    if value & 1 == 1 {
                        1u8 << (address.bit & 7)
                    } else {
                        0
                    },
                ),
                _ => (0xFF, byte),
            };
            mask[at] |= m;
            image[at] = (image[at] & !m) | (v & m);
        }
        self.apply_forces();
        Ok(())
    }

    /// Remove every force.
    pub fn unforce_all(&mut self) {
        self.forces.clear();
    }

    /// The force mask and value image of a slot (all zero when nothing is forced).
    pub fn force_image(&self, slot: u8) -> (Vec<u8>, Vec<u8>) {
        let size = self.memory.area(slot).map(<[u8]>::len).unwrap_or(0);
        self.forces
            .get(&slot)
            .cloned()
            .unwrap_or_else(|| (vec![0; size], vec![0; size]))
    }

    fn forcing_areas(&self) -> String {
        self.target
            .memory
            .forcing
            .iter()
            .filter_map(|s| self.target.memory.area_by_slot(*s))
            .map(|a| a.name.clone())
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The input areas take their terminals' values (start of scan).
    pub(crate) fn refresh_inputs(&mut self) {
        for (slot, terminal) in &self.terminals {
            if let Some(area) = self.memory.area_mut(*slot) {
                let n = area.len().min(terminal.len());
                area[..n].copy_from_slice(&terminal[..n]);
            }
        }
    }

    /// After MAIN: advance the timed events by the scan's virtual time, compare the
    /// edge events' inputs, and return the events whose routines run now, in order
    /// (pending ones first); while interrupts are disabled, one occurrence per event is
    /// kept pending and none run.
    pub(crate) fn occurred_events(&mut self) -> Vec<u32> {
        let scan_ms = self.config.scan_ms;
        let mut occurred: Vec<u32> = Vec::new();
        let timed: Vec<(u32, Option<String>)> = self
            .target
            .memory
            .events
            .iter()
            .filter(|e| e.kind.eq_ignore_ascii_case("Timed"))
            .map(|e| (e.number, e.period.clone()))
            .collect();
        for (event, period) in timed {
            if !self.interrupts.attached.contains_key(&event) {
                self.interrupts.elapsed.remove(&event);
                continue;
            }
            let Some(addr) = period.and_then(|p| self.target.memory.parse_address(&p).ok()) else {
                continue;
            };
            let period_ms = self.memory.read(Location::from(addr)).unwrap_or(0);
            if period_ms == 0 {
                continue;
            }
            let acc = self.interrupts.elapsed.entry(event).or_insert(0);
            *acc += scan_ms;
            while *acc >= period_ms {
                *acc -= period_ms;
                occurred.push(event);
            }
        }
        // Edge events: the input bit now against the previous scan (the first scan only
        // records it, so entering RUN raises no edge).
        let edges: Vec<(u32, bool, Option<String>)> = self
            .target
            .memory
            .events
            .iter()
            .filter(|e| {
                e.kind.eq_ignore_ascii_case("RisingEdge")
                    || e.kind.eq_ignore_ascii_case("FallingEdge")
            })
            .map(|e| {
                (
                    e.number,
                    e.kind.eq_ignore_ascii_case("RisingEdge"),
                    e.input.clone(),
                )
            })
            .collect();
        for (event, rising, input) in edges {
            let Some(a) = input.and_then(|i| self.target.memory.parse_address(&i).ok()) else {
                continue;
            };
            let now = self.memory.read(Location::from(a)).unwrap_or(0) == 1;
            let before = self.interrupts.last_input.insert(event, now);
            if let Some(before) = before {
                if self.interrupts.attached.contains_key(&event)
                    && ((rising && now && !before) || (!rising && !now && before))
                {
                    occurred.push(event);
                }
            }
        }
        occurred.sort_unstable();
        if !self.interrupts.enabled {
            self.interrupts.pending.extend(occurred);
            return Vec::new();
        }
        let mut queue: Vec<u32> = std::mem::take(&mut self.interrupts.pending)
            .into_iter()
            .collect();
        queue.extend(occurred);
        queue
    }

    /// Forced bits take their force values.
    pub(crate) fn apply_forces(&mut self) {
        for (slot, (mask, image)) in &self.forces {
            if let Some(area) = self.memory.area_mut(*slot) {
                for ((b, m), v) in area.iter_mut().zip(mask).zip(image) {
                    *b = (*b & !m) | (v & m);
                }
            }
        }
    }

    fn set_system_bits(&mut self) {
        let sm = self.slots.sm;
        let bit = |b: u8| Location {
            slot: sm,
            offset: 0,
            width: gutta_catalog::Width::Bit,
            bit: b,
        };
        let t = self.clock_ms;
        let _ = self.memory.write(bit(0), 1);
        let _ = self.memory.write(bit(1), u32::from(self.scans == 0));
        let _ = self.memory.write(bit(4), u32::from((t / 30_000) % 2 == 1));
        let _ = self.memory.write(bit(5), u32::from((t / 500) % 2 == 1));
        let _ = self.memory.write(bit(6), u32::from(self.scans % 2 == 1));
    }
}

/// The bits a location covers, per byte from its first.
fn bit_mask(loc: Location) -> Vec<u8> {
    match loc.width {
        gutta_catalog::Width::Bit => vec![1 << (loc.bit & 7)],
        w => vec![0xFF; w.bytes() as usize],
    }
}

/// 4 bytes from `at`, zero past the end; `at` itself must be inside.
fn four_bytes(area: &[u8], at: usize, slot: u8) -> Result<[u8; 4], AccessError> {
    if at >= area.len() {
        return Err(AccessError(format!(
            "slot {slot} byte {at} outside its {} bytes",
            area.len()
        )));
    }
    let mut out = [0u8; 4];
    for (k, b) in area[at..].iter().take(4).enumerate() {
        out[k] = *b;
    }
    Ok(out)
}

/// The variable a packed address names (USE ignored).
fn packed_address(address: u32) -> Result<Address, AccessError> {
    let op = gutta_format::PackedOperand(address);
    let width = op.width().ok_or_else(|| {
        AccessError(format!(
            "bad width code {} in {address:#010X}",
            op.width_code()
        ))
    })?;
    Ok(Address {
        slot: op.slot(),
        width,
        offset: op.offset() as u32,
        bit: if width == gutta_catalog::Width::Bit {
            op.bit() & 7
        } else {
            0
        },
    })
}
