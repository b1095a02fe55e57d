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

/// Bytes of the timer and counter areas (T0..T127, C0..C63: a word each).
pub const T_BYTES: usize = 256;
pub const C_BYTES: usize = 128;

/// Milliseconds per unit of the timers the conveyor plant uses (T4..T127 on
/// EC30-EKSTM32-XC).
pub const TIMER_UNIT_MS: u32 = 100;

/// The highest count of a counter (the target's `Counters Max`).
pub const COUNTER_MAX: i16 = 32767;

/// What a program with timers, counters and edges keeps besides I, Q, M and SM: the T
/// and C words, each timer's running clock, each counter's last input, each edge's
/// last input, and the scan count and virtual time the system bits derive from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Plant {
    pub mem: Memory,
    pub t: [u8; T_BYTES],
    pub c: [u8; C_BYTES],
    /// Per timer: milliseconds not yet counted as a unit, and whether its clock runs.
    pub timers: [(u32, bool); T_BYTES / 2],
    /// Per counter: its up input at its previous execution.
    pub counters: [bool; C_BYTES / 2],
    /// Per counter: its down input at its previous execution (CTUD).
    pub counters_down: [bool; C_BYTES / 2],
    /// Per timer: TOF's armed state (its input was on; the delay runs when it is off).
    pub armed: [bool; T_BYTES / 2],
    /// Per EU/ED instruction: its input at its previous execution.
    pub edges: [bool; 256],
    pub scans: u64,
    pub ms: u64,
    pub scan_ms: u32,
}

impl Plant {
    /// Everything zero, `scan_ms` virtual milliseconds per scan.
    pub fn new(scan_ms: u32) -> Plant {
        Plant {
            mem: Memory::default(),
            t: [0; T_BYTES],
            c: [0; C_BYTES],
            timers: [(0, false); T_BYTES / 2],
            counters: [false; C_BYTES / 2],
            counters_down: [false; C_BYTES / 2],
            armed: [false; T_BYTES / 2],
            edges: [false; 256],
            scans: 0,
            ms: 0,
            scan_ms,
        }
    }

    /// SMB0 for the scan about to start: SM0.0 on, SM0.1 the first scan, SM0.4 and
    /// SM0.5 the 60 s and 1 s clocks, SM0.6 every other scan.
    #[inline(always)]
    pub fn begin_scan(&mut self) {
        let t = self.ms;
        let bits = 1
            | u8::from(self.scans == 0) << 1
            | u8::from((t / 30_000) % 2 == 1) << 4
            | u8::from((t / 500) % 2 == 1) << 5
            | u8::from(self.scans % 2 == 1) << 6;
        self.mem.sm[0] = (self.mem.sm[0] & !0b0111_0011) | bits;
    }

    #[inline(always)]
    pub fn end_scan(&mut self) {
        self.scans += 1;
        self.ms += u64::from(self.scan_ms);
    }

    /// TON T`n`, `pt` with input `input`: each execution with the input on counts the
    /// scan's milliseconds (the first only starts the clock); off, the timer is 0.
    /// Returns the done state.
    #[inline(always)]
    pub fn ton(&mut self, n: usize, input: bool, pt: i16, scan_ms: u32) -> bool {
        let clock = &mut self.timers[n];
        if !input {
            *clock = (0, false);
            set_word(&mut self.t, 2 * n, 0);
            return false;
        }
        let units = if clock.1 {
            let total = clock.0 + scan_ms;
            clock.0 = total % TIMER_UNIT_MS;
            total / TIMER_UNIT_MS
        } else {
            *clock = (0, true);
            0
        };
        let mut t = word(&self.t, 2 * n);
        if units > 0 && t < i16::MAX {
            t = (i32::from(t) + units as i32).min(i32::from(i16::MAX)) as i16;
            set_word(&mut self.t, 2 * n, t);
        }
        pt <= 0 || t >= pt
    }

    /// One execution of timer `n`'s clock: the whole units since its previous
    /// execution (0 when this one starts it), the remainder kept.
    #[inline(always)]
    fn advance(&mut self, n: usize, scan_ms: u32) -> i32 {
        let clock = &mut self.timers[n];
        if !clock.1 {
            *clock = (0, true);
            return 0;
        }
        let total = clock.0 + scan_ms;
        clock.0 = total % TIMER_UNIT_MS;
        (total / TIMER_UNIT_MS) as i32
    }

    /// TOF T`n`, `pt`: on, the timer is 0 and armed (done); off after on, each
    /// execution counts the scan's milliseconds (the first only starts the clock) until
    /// `pt`, done until then. Returns the done state.
    #[inline(always)]
    pub fn tof(&mut self, n: usize, input: bool, pt: i16, scan_ms: u32) -> bool {
        if input {
            self.timers[n] = (0, false);
            self.armed[n] = true;
            set_word(&mut self.t, 2 * n, 0);
            return true;
        }
        if !self.armed[n] {
            return false;
        }
        let units = self.advance(n, scan_ms);
        let mut t = word(&self.t, 2 * n);
        if units > 0 && t < pt {
            t = (i32::from(t) + units).min(i32::from(pt)) as i16;
            set_word(&mut self.t, 2 * n, t);
        }
        if t < pt {
            true
        } else {
            self.timers[n] = (0, false);
            self.armed[n] = false;
            false
        }
    }

    /// TONR T`n`, `pt`: on, each execution counts the scan's milliseconds (the first
    /// of a run only starts the clock) and keeps the value when off. Returns the done
    /// state.
    #[inline(always)]
    pub fn tonr(&mut self, n: usize, input: bool, pt: i16, scan_ms: u32) -> bool {
        let mut t = word(&self.t, 2 * n);
        if input {
            let units = self.advance(n, scan_ms);
            if units > 0 && t < i16::MAX {
                t = (i32::from(t) + units).min(i32::from(i16::MAX)) as i16;
                set_word(&mut self.t, 2 * n, t);
            }
        } else {
            self.timers[n] = (0, false);
        }
        t >= pt
    }

    /// CTUD C`n`, `pv`: a rising `up` counts up (to the maximum), a rising `down` down
    /// (to -32768), both at once nothing; `reset` clears. Returns count >= `pv`.
    #[inline(always)]
    pub fn ctud(&mut self, n: usize, up: bool, down: bool, reset: bool, pv: i16) -> bool {
        let rose = up && !self.counters[n];
        self.counters[n] = up;
        let fell = down && !self.counters_down[n];
        self.counters_down[n] = down;
        let mut c = word(&self.c, 2 * n);
        if reset {
            c = 0;
            set_word(&mut self.c, 2 * n, c);
        } else if rose && !fell && c < COUNTER_MAX {
            c += 1;
            set_word(&mut self.c, 2 * n, c);
        } else if fell && !rose && c > i16::MIN {
            c -= 1;
            set_word(&mut self.c, 2 * n, c);
        }
        c >= pv
    }

    /// CTU C`n`, `pv` with up input `up` and reset `reset`: counts rising edges of `up`
    /// up to the maximum; reset clears. Returns the done state (count >= `pv`).
    #[inline(always)]
    pub fn ctu(&mut self, n: usize, up: bool, reset: bool, pv: i16) -> bool {
        let rose = up && !self.counters[n];
        self.counters[n] = up;
        let mut c = word(&self.c, 2 * n);
        if reset {
            c = 0;
            set_word(&mut self.c, 2 * n, c);
        } else if rose && c < COUNTER_MAX {
            c += 1;
            set_word(&mut self.c, 2 * n, c);
        }
        c >= pv
    }

    /// EU (`rising`) or ED number `n` on input `now`: true for one execution after the
    /// input rose (fell).
    #[inline(always)]
    pub fn edge(&mut self, n: usize, now: bool, rising: bool) -> bool {
        let before = std::mem::replace(&mut self.edges[n], now);
        if rising {
            now && !before
        } else {
            !now && before
        }
    }
}

/// `+I v, MW[at]`: the sum wraps; SM1.0 zero, SM1.1 overflow, SM1.2 negative, the
/// other flags kept.
#[inline(always)]
pub fn add_int(mem: &mut Memory, v: i16, at: usize) {
    let exact = i32::from(word(&mem.m, at)) + i32::from(v);
    let r = exact as i16;
    set_word(&mut mem.m, at, r);
    let flags = u8::from(r == 0) | (u8::from(i32::from(r) != exact) << 1) | (u8::from(r < 0) << 2);
    mem.sm[1] = (mem.sm[1] & !0x07) | flags;
}

/// `-I v, MW[at]`: the difference wraps; flags as `add_int`.
#[inline(always)]
pub fn sub_int(mem: &mut Memory, v: i16, at: usize) {
    let exact = i32::from(word(&mem.m, at)) - i32::from(v);
    let r = exact as i16;
    set_word(&mut mem.m, at, r);
    let flags = u8::from(r == 0) | (u8::from(i32::from(r) != exact) << 1) | (u8::from(r < 0) << 2);
    mem.sm[1] = (mem.sm[1] & !0x07) | flags;
}

/// `*R v, MD[at]`: SM1.0 zero, SM1.1 not finite, SM1.2 negative.
#[inline(always)]
pub fn mul_real(mem: &mut Memory, v: f32, at: usize) {
    let r = f32::from_bits(dword(&mem.m, at) as u32) * v;
    set_dword(&mut mem.m, at, r.to_bits() as i32);
    let flags = u8::from(r == 0.0) | (u8::from(!r.is_finite()) << 1) | (u8::from(r < 0.0) << 2);
    mem.sm[1] = (mem.sm[1] & !0x07) | flags;
}

/// `TRUNC MD[from], MD[to]`: toward zero when it fits a DINT (else OUT kept); SM1.1
/// when it does not.
#[inline(always)]
pub fn trunc_real(mem: &mut Memory, from: usize, to: usize) {
    let r = f32::from_bits(dword(&mem.m, from) as u32).trunc();
    let ok = r.is_finite() && (-2_147_483_648.0..2_147_483_648.0).contains(&r);
    if ok {
        set_dword(&mut mem.m, to, r as i32);
    }
    mem.sm[1] = (mem.sm[1] & !0x02) | (u8::from(!ok) << 1);
}

include!(concat!(env!("OUT_DIR"), "/programs.rs"));
