//! The loaded program: the target, the verified image's data (constants, data pages,
//! system block), the run configuration and every unit pre-decoded. It is what the
//! scan reads, never what it writes (only the debugger patches a breakpoint into a
//! unit). It holds no run state: that is the machine's (`machine.rs`).

use std::collections::BTreeMap;
use std::sync::Arc;

use gutta_catalog::{AreaKind, Target};
use gutta_format::{LocalEntry, VerifiedImage};

use crate::decode::Unit;
use crate::memory::Memory;

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
    /// The compiled tier (docs/vm-jit.md): after this many completed scans, the units'
    /// straight-line operations are compiled to native code (`Some(0)`: at load); `None`
    /// never. Only with `fast` and the crate feature `jit` (on by default).
    pub native_after: Option<u64>,
}

/// Scans after which the compiled tier compiles by default: short runs (a unit test of
/// a few scans, a single `gutta-vm` scan) never pay for compiling.
pub const DEFAULT_NATIVE_AFTER: u64 = 100;

impl Default for VmConfig {
    fn default() -> Self {
        VmConfig {
            scan_ms: 10,
            watchdog: 10_000_000,
            fast: true,
            native_after: Some(DEFAULT_NATIVE_AFTER),
        }
    }
}

/// Well-known slots, found by area kind.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Slots {
    pub sm: u8,
    pub local: u8,
    pub constant: u8,
}

impl Slots {
    pub fn of(target: &Target) -> Slots {
        let slot = |k: AreaKind| target.memory.area_of_kind(k).map(|a| a.slot).unwrap_or(0);
        Slots {
            sm: slot(AreaKind::System),
            local: slot(AreaKind::Local),
            constant: slot(AreaKind::Constant),
        }
    }
}

/// A program ready to run.
#[derive(Debug)]
pub(crate) struct Program {
    pub target: Arc<Target>,
    /// The image without its units (they are decoded into `units`).
    pub image: VerifiedImage,
    pub config: VmConfig,
    pub slots: Slots,
    /// Each unit (by page) decoded; shared so a running frame does not copy it.
    pub units: Vec<Option<Arc<Unit>>>,
    /// Index of SMB1 (the math flags) in the flat memory.
    pub flags_at: usize,
    /// Index of SMB0 (the system bits a scan's start writes) in the flat memory; None
    /// for a target without SM.
    pub smb0_at: Option<usize>,
    /// L's start and length in the flat memory (what a CALL saves and clears), found
    /// at load.
    pub local_span: Option<(usize, usize)>,
}

/// What a reset puts into cleared memory: K from the const page, then the data pages.
pub(crate) fn initial_values(memory: &mut Memory, image: &VerifiedImage, constant: u8) {
    if let Some(k) = memory.area_mut(constant) {
        let consts = image.constants();
        let n = consts.len().min(k.len());
        k[..n].copy_from_slice(&consts[..n]);
    }
    for item in image.data().values().flatten() {
        // Verified: in-area, value fits; a failure here would be a verifier bug.
        let _ = crate::memory::operand(item.operand).and_then(|op| memory.store(op, item.value));
    }
}

impl Program {
    /// Decode `image`'s units for `target` on `memory`'s layout (growing its hidden
    /// state by what the units' instructions keep).
    pub fn new(
        mut image: VerifiedImage,
        target: Arc<Target>,
        config: VmConfig,
        memory: &mut Memory,
    ) -> Program {
        let slots = Slots::of(&target);
        let verified_units = image.take_units();
        let parameters: BTreeMap<u8, Vec<LocalEntry>> = verified_units
            .iter()
            .map(|(&page, u)| (page, u.parameters().copied().collect()))
            .collect();
        // K as every reset leaves it: S/R's N (a constant in K) is folded at load.
        let mut reset = Memory::new(&target.memory);
        initial_values(&mut reset, &image, slots.constant);
        let k = reset.area(slots.constant).unwrap_or(&[]);
        let mut units = vec![None; 256];
        for (page, unit) in &verified_units {
            units[*page as usize] = Some(Arc::new(crate::decode::decode(
                unit,
                &target,
                memory,
                config.fast,
                config.scan_ms,
                (slots.constant, k),
                &parameters,
            )));
        }
        let flags_at = memory
            .span(slots.sm)
            .filter(|&(_, len)| len > 1)
            .map_or(0, |(start, _)| start + 1);
        let smb0_at = memory
            .span(slots.sm)
            .filter(|&(_, len)| len > 0)
            .map(|(start, _)| start);
        let local_span = memory.span(slots.local);
        Program {
            target,
            image,
            config,
            slots,
            units,
            flags_at,
            smb0_at,
            local_span,
        }
    }

    /// The decoded unit on `page`.
    pub fn unit(&self, page: u8) -> Option<&Arc<Unit>> {
        self.units[page as usize].as_ref()
    }
}
