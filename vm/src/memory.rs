//! PLC memory: the areas (slots) of a target at their ManagerVar.xml sizes, little-endian,
//! widths overlapping (MB0 and MW0 share a byte). All areas live in one byte array, so a
//! pre-decoded operation addresses a byte by one index (docs/vm.md, "Speed"). Operands
//! arrive decoded (`gutta_format::Operand`); pointers are followed with
//! `gutta_format::Pointer`, so nothing here takes an operand word or a pointer value
//! apart. Every access is bounds-checked.

use gutta_catalog::{Address, AreaKind, MemoryMap, Width};
use gutta_format::{Operand, PackedOperand, Pointer};

/// The areas of a target.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Memory {
    /// Every area, in slot order.
    pub(crate) bytes: Vec<u8>,
    /// Slot -> (start in `bytes`, length); slots without an area have length 0.
    spans: Vec<(usize, usize)>,
    /// Hidden state (docs/vm.md, "Hidden state"), after the areas in `bytes`, so the
    /// fast path and the compiled tier reach it by a constant index like any variable:
    /// per T and C area (slot, start of its cells): `CELL_STATE` bytes per byte of the
    /// area, then the interrupt enable byte (`enable`), then (appended by `add_hidden`
    /// at load) one byte per EU/ED record.
    cells: Vec<(u8, usize)>,
    /// The flat index of the interrupt enable byte: 1 after ENI, 0 after DISI and at
    /// every reset (interrupts are off when the PLC enters RUN). In the flat memory, so
    /// the fast path and compiled code run ENI and DISI as a store of a constant.
    enable: usize,
}

/// Bytes of hidden state per byte of a T or C area: two little-endian u32 words (a
/// timer: the milliseconds not yet counted as a unit, then its flags; a counter: its
/// flags, then 0).
pub(crate) const CELL_STATE: usize = 8;

/// An access outside an area, or to a slot that does not exist.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AccessError(pub String);

/// Read a location's bytes from an area, zero-extended (bits read as 0 or 1).
pub(crate) fn read_in(area: &[u8], loc: Address) -> Result<u32, AccessError> {
    let b = bytes_of(area, loc)?;
    Ok(match loc.width {
        Width::Bit => ((b[0] >> (loc.bit & 7)) & 1) as u32,
        Width::Byte => b[0] as u32,
        Width::Word => u16::from_le_bytes([b[0], b[1]]) as u32,
        Width::Dword => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
    })
}

/// Write a location into an area (the value truncated to its width; bits take value & 1).
pub(crate) fn write_in(area: &mut [u8], loc: Address, value: u32) -> Result<(), AccessError> {
    bytes_of(area, loc)?;
    let at = loc.offset as usize;
    match loc.width {
        Width::Bit => {
            let mask = 1u8 << (loc.bit & 7);
            if value & 1 == 1 {
                area[at] |= mask;
            } else {
                area[at] &= !mask;
            }
        }
        Width::Byte => area[at] = value as u8,
        Width::Word => area[at..at + 2].copy_from_slice(&(value as u16).to_le_bytes()),
        Width::Dword => area[at..at + 4].copy_from_slice(&value.to_le_bytes()),
    }
    Ok(())
}

fn bytes_of(area: &[u8], loc: Address) -> Result<&[u8], AccessError> {
    let start = loc.offset as usize;
    let end = start + loc.width.bytes() as usize;
    area.get(start..end).ok_or_else(|| {
        AccessError(format!(
            "slot {} bytes {start}..{end} outside its {} bytes",
            loc.slot,
            area.len()
        ))
    })
}

impl Memory {
    pub fn new(map: &MemoryMap) -> Memory {
        let slots = map
            .areas
            .iter()
            .map(|a| a.slot as usize + 1)
            .max()
            .unwrap_or(0);
        let mut spans = vec![(0, 0); slots];
        let mut sorted: Vec<_> = map.areas.iter().collect();
        sorted.sort_by_key(|a| a.slot);
        let mut total = 0usize;
        for a in &sorted {
            spans[a.slot as usize] = (total, a.size as usize);
            total += a.size as usize;
        }
        let mut cells = Vec::new();
        for a in &sorted {
            if matches!(a.kind, AreaKind::Timer | AreaKind::Counter) {
                cells.push((a.slot, total));
                total += a.size as usize * CELL_STATE;
            }
        }
        let enable = total;
        total += 1;
        Memory {
            bytes: vec![0; total],
            spans,
            cells,
            enable,
        }
    }

    /// The flat index of the interrupt enable byte (ENI: 1, DISI: 0).
    #[inline]
    pub(crate) fn enable_at(&self) -> usize {
        self.enable
    }

    /// Whether interrupts are enabled (ENI ran since DISI or the last reset).
    #[inline]
    pub(crate) fn interrupts_enabled(&self) -> bool {
        self.bytes[self.enable] != 0
    }

    /// The flat index of the hidden state of the T or C cell at byte `offset` of `slot`
    /// (`CELL_STATE` bytes); None for any other slot or an offset outside the area.
    pub(crate) fn cell_state_at(&self, slot: u8, offset: u32) -> Option<usize> {
        let &(_, start) = self.cells.iter().find(|&&(s, _)| s == slot)?;
        let (_, len) = self.span(slot)?;
        ((offset as usize) < len).then(|| start + offset as usize * CELL_STATE)
    }

    /// The hidden state: every byte after the areas (timers', counters', the interrupt
    /// enable's and EU/ED records' state, docs/vm.md "Hidden state"). Read-only, for
    /// tests and tools.
    pub fn hidden(&self) -> &[u8] {
        let end = self.spans.iter().map(|&(s, l)| s + l).max().unwrap_or(0);
        &self.bytes[end..]
    }

    /// Grow the hidden state by `n` zeroed bytes (per-instruction state, at load);
    /// returns the flat index of the first.
    pub(crate) fn add_hidden(&mut self, n: usize) -> usize {
        let at = self.bytes.len();
        self.bytes.resize(at + n, 0);
        at
    }

    /// Word `k` (0 or 1) of a cell's hidden state at flat index `at` (`cell_state_at`).
    #[inline]
    pub(crate) fn state_word(&self, at: usize, k: usize) -> u32 {
        let i = at + 4 * k;
        u32::from_le_bytes([
            self.bytes[i],
            self.bytes[i + 1],
            self.bytes[i + 2],
            self.bytes[i + 3],
        ])
    }

    #[inline]
    pub(crate) fn set_state_word(&mut self, at: usize, k: usize, v: u32) {
        let i = at + 4 * k;
        self.bytes[i..i + 4].copy_from_slice(&v.to_le_bytes());
    }

    /// Clear every area.
    pub(crate) fn clear(&mut self) {
        self.bytes.fill(0);
    }

    /// Where slot `slot` starts in the flat byte array, and its length.
    pub(crate) fn span(&self, slot: u8) -> Option<(usize, usize)> {
        self.spans.get(slot as usize).copied()
    }

    /// The index in the flat byte array of a location's first byte, if it lies inside
    /// its area.
    pub(crate) fn index_of(&self, loc: Address) -> Option<usize> {
        let (start, len) = self.span(loc.slot)?;
        let end = loc.offset as usize + loc.width.bytes() as usize;
        (end <= len).then_some(start + loc.offset as usize)
    }

    pub fn area(&self, slot: u8) -> Option<&[u8]> {
        let (start, len) = self.span(slot)?;
        Some(&self.bytes[start..start + len])
    }

    pub fn area_mut(&mut self, slot: u8) -> Option<&mut [u8]> {
        let (start, len) = self.span(slot)?;
        Some(&mut self.bytes[start..start + len])
    }

    fn area_of(&self, slot: u8) -> Result<&[u8], AccessError> {
        self.area(slot)
            .ok_or_else(|| AccessError(format!("no area in slot {slot}")))
    }

    /// Read a location, zero-extended to 32 bits (bits read as 0 or 1).
    pub fn read(&self, loc: Address) -> Result<u32, AccessError> {
        read_in(self.area_of(loc.slot)?, loc)
    }

    /// Write a location (the value truncated to its width; bits take value & 1).
    pub fn write(&mut self, loc: Address, value: u32) -> Result<(), AccessError> {
        let area = self
            .area_mut(loc.slot)
            .ok_or_else(|| AccessError(format!("no area in slot {}", loc.slot)))?;
        write_in(area, loc, value)
    }

    /// Where a memory operand's access goes: the variable itself, or (`*holder`) the
    /// variable the pointer held in `holder` points to. Other operands have no place.
    pub fn locate(&self, op: Operand) -> Result<Address, AccessError> {
        match op {
            Operand::Value(a) => Ok(a),
            Operand::Pointer { holder, width } => Ok(Pointer(self.read(holder)?).target(width)),
            _ => Err(AccessError(format!("{op:?} is not a memory operand"))),
        }
    }

    /// The value an operand stands for: a variable's value, a pointer value for `&`, a
    /// label's or literal's number.
    pub fn value(&self, op: Operand) -> Result<u32, AccessError> {
        match op {
            Operand::AddressOf { byte, .. } => Ok(Pointer::to(byte).0),
            Operand::Value(_) | Operand::Pointer { .. } => self.read(self.locate(op)?),
            Operand::Literal(n) | Operand::Label(n) => Ok(u32::from(n)),
            Operand::Unit(_) => Err(AccessError(format!("{op:?} has no value"))),
        }
    }

    /// Store into an operand's place.
    pub fn store(&mut self, op: Operand, value: u32) -> Result<(), AccessError> {
        let a = self.locate(op)?;
        self.write(a, value)
    }
}

/// An operand word decoded (strictly, as `gutta_format` defines it).
pub fn operand(word: PackedOperand) -> Result<Operand, AccessError> {
    word.decode()
        .map_err(|e| AccessError(format!("operand {word:?}: {e}")))
}
