//! The host's side of the I/O: input terminals (what the host set on I and AI, copied
//! into the input image at every scan start) and forces (byte-level mask and value
//! images of the forcing areas, I and Q). docs/vm.md, "Forcing and inputs". It knows
//! no protocol: the simulator frames UM4001's STATUS_VAR_* payloads from these
//! operations.

use std::collections::HashMap;

use gutta_catalog::{Address, AreaKind, Target, Width};

use crate::memory::{self, AccessError, Memory};

/// Why a variable cannot be forced.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ForceError(pub String);

impl std::fmt::Display for ForceError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ForceError {}

/// Input terminals and force images.
#[derive(Debug, Default)]
pub(crate) struct Terminals {
    /// Terminal images of the input areas (I, AI), by slot (two or so: a list, which
    /// the start of every scan walks faster than a map).
    inputs: Vec<(u8, Vec<u8>)>,
    /// Where each input area of `inputs` (same order) starts in the flat memory, found
    /// once at load: the start of a scan copies without looking the area up.
    input_at: Vec<usize>,
    /// Force images of the forcing areas (I, Q): slot -> (mask, value), byte per byte.
    forces: HashMap<u8, (Vec<u8>, Vec<u8>)>,
}

/// The bits an address covers, per byte from its first.
fn bit_mask(a: Address) -> Vec<u8> {
    match a.width {
        Width::Bit => vec![1 << (a.bit & 7)],
        w => vec![0xFF; w.bytes() as usize],
    }
}

impl Terminals {
    /// Terminals of `target`'s input areas, all 0; nothing forced. `memory` (the
    /// target's, laid out by `Memory::new`) gives where each area starts.
    pub fn new(target: &Target, memory: &Memory) -> Terminals {
        let (inputs, input_at) = target
            .memory
            .areas
            .iter()
            .filter(|a| matches!(a.kind, AreaKind::DigitalInput | AreaKind::AnalogInput))
            .filter_map(|a| {
                let (start, len) = memory.span(a.slot)?;
                Some(((a.slot, vec![0; len]), start))
            })
            .unzip();
        Terminals {
            inputs,
            input_at,
            forces: HashMap::new(),
        }
    }

    /// A host write: an input's terminal takes the value too (it holds across scans).
    pub fn write(
        &mut self,
        memory: &mut Memory,
        address: Address,
        value: u32,
    ) -> Result<(), AccessError> {
        if let Some(terminal) = self.terminal_mut(address.slot) {
            memory::write_in(terminal, address, value)?;
        }
        memory.write(address, value)
    }

    /// After a host write: the forced bits of `address` take their new memory value as
    /// their force value, so the write holds.
    pub fn hold_written(&mut self, memory: &Memory, address: Address) {
        if let (Some((mask, image)), Some(area)) = (
            self.forces.get_mut(&address.slot),
            memory.area(address.slot),
        ) {
            for (k, m) in bit_mask(address).iter().enumerate() {
                let at = address.offset as usize + k;
                let forced = mask[at] & m;
                image[at] = (image[at] & !forced) | (area[at] & forced);
            }
        }
    }

    /// Force `address` to `value`, then apply the forces to `memory`.
    pub fn force(
        &mut self,
        memory: &mut Memory,
        target: &Target,
        address: Address,
        value: u32,
    ) -> Result<(), ForceError> {
        if !target.memory.can_force(address.slot) {
            let area = target
                .memory
                .area_by_slot(address.slot)
                .map(|a| a.name.clone())
                .unwrap_or_default();
            let forcing = target
                .memory
                .forcing
                .iter()
                .filter_map(|s| target.memory.area_by_slot(*s))
                .map(|a| a.name.clone())
                .collect::<Vec<_>>()
                .join(", ");
            return Err(ForceError(format!(
                "area {area} cannot be forced (only {forcing})"
            )));
        }
        let size = memory.area(address.slot).map(<[u8]>::len).unwrap_or(0);
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
                Width::Bit => {
                    let m = 1u8 << (address.bit & 7);
                    (m, if value & 1 == 1 { m } else { 0 })
                }
                _ => (0xFF, byte),
            };
            mask[at] |= m;
            image[at] = (image[at] & !m) | (v & m);
        }
        self.apply_forces(memory);
        Ok(())
    }

    /// Remove the force of one variable (its bits; the rest of the byte stays forced).
    pub fn unforce(&mut self, address: Address) {
        if let Some((mask, _)) = self.forces.get_mut(&address.slot) {
            for (k, m) in bit_mask(address).iter().enumerate() {
                if let Some(b) = mask.get_mut(address.offset as usize + k) {
                    *b &= !m;
                }
            }
        }
    }

    pub fn unforce_all(&mut self) {
        self.forces.clear();
    }

    /// The force mask and value image of a slot (all zero when nothing is forced; empty
    /// for a slot without an area).
    pub fn force_image(&self, memory: &Memory, slot: u8) -> (Vec<u8>, Vec<u8>) {
        let size = memory.area(slot).map(<[u8]>::len).unwrap_or(0);
        self.forces
            .get(&slot)
            .cloned()
            .unwrap_or_else(|| (vec![0; size], vec![0; size]))
    }

    /// The terminal image of input slot `slot`.
    fn terminal_mut(&mut self, slot: u8) -> Option<&mut Vec<u8>> {
        self.inputs
            .iter_mut()
            .find(|(s, _)| *s == slot)
            .map(|(_, t)| t)
    }

    /// The input areas take their terminals' values (start of scan).
    pub fn refresh_inputs(&self, memory: &mut Memory) {
        for ((_, terminal), &at) in self.inputs.iter().zip(&self.input_at) {
            if let Some(area) = memory.bytes.get_mut(at..at + terminal.len()) {
                copy_image(area, terminal);
            }
        }
    }

    /// Forced bits take their force values. Twice a scan: without forces, one test
    /// inline; the walk is out of line.
    #[inline(always)]
    pub fn apply_forces(&self, memory: &mut Memory) {
        if !self.forces.is_empty() {
            self.lay_forces(memory);
        }
    }

    #[inline(never)]
    fn lay_forces(&self, memory: &mut Memory) {
        for (slot, (mask, image)) in &self.forces {
            if let Some(area) = memory.area_mut(*slot) {
                for ((b, m), v) in area.iter_mut().zip(mask).zip(image) {
                    *b = (*b & !m) | (v & m);
                }
            }
        }
    }

    /// The physical input byte `at` of `slot` (its terminal with the forces laid over
    /// it), or None for a slot without terminals.
    pub fn input_byte(&self, slot: u8, at: usize) -> Option<u8> {
        let terminal = *self
            .inputs
            .iter()
            .find(|(s, _)| *s == slot)
            .map(|(_, t)| t)?
            .get(at)?;
        Some(match self.forces.get(&slot) {
            Some((mask, image)) => {
                let m = mask.get(at).copied().unwrap_or(0);
                let f = image.get(at).copied().unwrap_or(0);
                (terminal & !m) | (f & m)
            }
            None => terminal,
        })
    }
}

/// `dst.copy_from_slice(src)` (same lengths) for an input area, every scan: the
/// default target's sizes (8 and 16 bytes) as register moves, inline, without a call;
/// other sizes by the general copy (`memcpy`).
#[inline(always)]
fn copy_image(dst: &mut [u8], src: &[u8]) {
    if let (Ok(d), Ok(s)) = (
        <&mut [u8; 16]>::try_from(&mut *dst),
        <&[u8; 16]>::try_from(src),
    ) {
        *d = *s;
    } else if let (Ok(d), Ok(s)) = (
        <&mut [u8; 8]>::try_from(&mut *dst),
        <&[u8; 8]>::try_from(src),
    ) {
        *d = *s;
    } else {
        dst.copy_from_slice(src);
    }
}
