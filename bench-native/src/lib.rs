//! The VM benchmark's programs and their native Rust transcriptions (issue 4: the VM
//! within 5x of native code for the same program). `build/` generates the LAD text and
//! translates it into the functions below; tests/agree.rs runs both against the VM.
//! This crate knows nothing of the compiler or the VM: it is plain memory and plain code.

/// Bytes of the areas the programs touch, as ManagerVar.xml of EC30-EKSTM32-XC gives
/// them (tests/agree.rs checks them against the catalog).
pub const I_BYTES: usize = 32;
pub const Q_BYTES: usize = 32;
pub const M_BYTES: usize = 3072;
pub const SM_BYTES: usize = 256;

/// LogicStackDepth of the stdlib ManagerFun.xml: deeper pushes lose the bottom level.
pub const LOGIC_STACK_DEPTH: u32 = 9;

/// The memory the transcriptions work on: one byte array per area, little-endian like
/// the VM's.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Memory {
    pub i: [u8; I_BYTES],
    pub q: [u8; Q_BYTES],
    pub m: [u8; M_BYTES],
    pub sm: [u8; SM_BYTES],
}

impl Default for Memory {
    fn default() -> Memory {
        Memory {
            i: [0; I_BYTES],
            q: [0; Q_BYTES],
            m: [0; M_BYTES],
            sm: [0; SM_BYTES],
        }
    }
}

impl Memory {
    /// What the VM does before MAIN that the programs can see: SM0.0 always on.
    #[inline(always)]
    pub fn set_system_bits(&mut self) {
        set_bit(&mut self.sm, 0, 0, true);
    }

    /// The flags of integer math: SM1.0 zero, SM1.1 overflow, SM1.2 negative; SM1.3
    /// (divide by zero) cleared.
    #[inline(always)]
    pub fn math_flags(&mut self, zero: bool, overflow: bool, negative: bool) {
        self.sm[1] = (self.sm[1] & !0b1111)
            | u8::from(zero)
            | (u8::from(overflow) << 1)
            | (u8::from(negative) << 2);
    }
}

/// The logic stack as bits, bit 0 the top; a network starts with `EMPTY`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LogicStack(u32);

impl LogicStack {
    pub const EMPTY: LogicStack = LogicStack(0);
    const MASK: u32 = (1 << LOGIC_STACK_DEPTH) - 1;

    #[inline(always)]
    pub fn push(&mut self, v: bool) {
        self.0 = ((self.0 << 1) | u32::from(v)) & Self::MASK;
    }

    #[inline(always)]
    pub fn and(&mut self, v: bool) {
        self.0 &= !1 | u32::from(v);
    }

    #[inline(always)]
    pub fn or(&mut self, v: bool) {
        self.0 |= u32::from(v);
    }

    #[inline(always)]
    pub fn top(self) -> bool {
        self.0 & 1 == 1
    }
}

/// Between two networks of a `_fenced` scan: the compiler must assume anything may have
/// read or changed `mem`, so every network reads its operands from memory and writes its
/// results back. Without it the optimizer carries values from network to network and,
/// on a repetitive program like BIT_LOGIC, computes a repeated network only once.
#[inline(always)]
pub fn network_boundary(mem: &mut Memory) {
    std::hint::black_box(mem);
}

/// Bit `n` of byte `byte`.
#[inline(always)]
pub fn bit(area: &[u8], byte: usize, n: u32) -> bool {
    (area[byte] >> n) & 1 == 1
}

#[inline(always)]
pub fn set_bit(area: &mut [u8], byte: usize, n: u32, v: bool) {
    area[byte] = (area[byte] & !(1 << n)) | (u8::from(v) << n);
}

/// The INT at `byte` (little-endian).
#[inline(always)]
pub fn word(area: &[u8], byte: usize) -> i16 {
    i16::from_le_bytes([area[byte], area[byte + 1]])
}

#[inline(always)]
pub fn set_word(area: &mut [u8], byte: usize, v: i16) {
    area[byte..byte + 2].copy_from_slice(&v.to_le_bytes());
}

/// The DINT at `byte` (little-endian).
#[inline(always)]
pub fn dword(area: &[u8], byte: usize) -> i32 {
    i32::from_le_bytes([area[byte], area[byte + 1], area[byte + 2], area[byte + 3]])
}

#[inline(always)]
pub fn set_dword(area: &mut [u8], byte: usize, v: i32) {
    area[byte..byte + 4].copy_from_slice(&v.to_le_bytes());
}

include!(concat!(env!("OUT_DIR"), "/programs.rs"));
