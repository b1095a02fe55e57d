//! The interrupt check after MAIN against a model of its documented semantics
//! (docs/vm.md, "Semantics implemented", Interrupts): over random scans a program
//! attaches and detaches edge and timed events (event 10 to one routine or another),
//! changes the period bytes while attached, switches ENI/DISI and drops pending
//! occurrences with CEVNT, all from its inputs. Every routine counts its runs and
//! stamps the order it ran in, so which scan an event fires in, how often, in which
//! order and what stays pending are compared with the model after every scan, for the
//! reference engine, the interpreter and the compiled tier. The scan's plan of
//! attached events is rebuilt only when an attachment changes: this is what holds it
//! to the semantics (a plan left stale after DTCH or ATCH fails it).

mod common;

use std::collections::{BTreeMap, BTreeSet};

use common::{load, read, set, three_engines};
use gutta_vm::VmConfig;

/// Events 0..3 attach to routines A..D; event 10 to A or B (I2.2), event 11 to C.
const PROGRAM: &str = "
ORGANIZATION_BLOCK MAIN:OB1
BEGIN
NETWORK 1
LD     SM0.0
MOVB   IB3, SMB10
MOVB   IB4, SMB11
NETWORK 2
LD     I1.0
ATCH   A, 0
NETWORK 3
LDN    I1.0
DTCH   0
NETWORK 4
LD     I1.1
ATCH   B, 1
NETWORK 5
LDN    I1.1
DTCH   1
NETWORK 6
LD     I1.2
ATCH   C, 2
NETWORK 7
LDN    I1.2
DTCH   2
NETWORK 8
LD     I1.3
ATCH   D, 3
NETWORK 9
LDN    I1.3
DTCH   3
NETWORK 10
LD     I1.4
A      I2.2
ATCH   A, 10
NETWORK 11
LD     I1.4
AN     I2.2
ATCH   B, 10
NETWORK 12
LDN    I1.4
DTCH   10
NETWORK 13
LD     I1.5
ATCH   C, 11
NETWORK 14
LDN    I1.5
DTCH   11
NETWORK 15
LD     I2.1
CEVNT  10
NETWORK 16
LD     I2.0
JMP    1
NETWORK 17
DISI
NETWORK 18
LD     SM0.0
JMP    2
NETWORK 19
LBL    1
NETWORK 20
ENI
NETWORK 21
LBL    2
END_ORGANIZATION_BLOCK

INTERRUPT_BLOCK A:INT1
BEGIN
NETWORK 1
LD     SM0.0
INCW   MW40
MOVW   MW100, MW50
INCW   MW100
END_INTERRUPT_BLOCK

INTERRUPT_BLOCK B:INT2
BEGIN
NETWORK 1
LD     SM0.0
INCW   MW42
MOVW   MW100, MW52
INCW   MW100
END_INTERRUPT_BLOCK

INTERRUPT_BLOCK C:INT3
BEGIN
NETWORK 1
LD     SM0.0
INCW   MW44
MOVW   MW100, MW54
INCW   MW100
END_INTERRUPT_BLOCK

INTERRUPT_BLOCK D:INT4
BEGIN
NETWORK 1
LD     SM0.0
INCW   MW46
MOVW   MW100, MW56
INCW   MW100
END_INTERRUPT_BLOCK
";

/// One scan's inputs.
#[derive(Debug, Clone, Copy, Default)]
struct Inputs {
    /// I0.0, I0.1: the edge events' inputs.
    i0: u8,
    /// Attach bits: I1.0..I1.3 events 0..3, I1.4 event 10, I1.5 event 11.
    i1: u8,
    /// I2.0 ENI (else DISI), I2.1 CEVNT 10, I2.2 event 10 to A (else B).
    i2: u8,
    /// The periods of events 10 and 11 (SMB10, SMB11), in ms.
    i3: u8,
    i4: u8,
}

/// The documented semantics, scan by scan.
#[derive(Debug, Default)]
struct Model {
    enabled: bool,
    /// Event -> routine (0..3 for A..D).
    attached: BTreeMap<u32, usize>,
    elapsed: BTreeMap<u32, u32>,
    pending: BTreeSet<u32>,
    last_i0: Option<u8>,
    /// (event, rising, bit of IB0) of the edge events 0..3, from the target.
    edges: Vec<(u32, bool, u8)>,
    runs: [u16; 4],
    stamps: [u16; 4],
    seq: u16,
}

impl Model {
    fn scan(&mut self, x: Inputs, scan_ms: u32) {
        // MAIN.
        let attach = |m: &mut Model, bit: u8, event: u32, routine: usize| {
            if x.i1 & (1 << bit) != 0 {
                m.attached.insert(event, routine);
            } else {
                m.attached.remove(&event);
                m.pending.remove(&event);
            }
        };
        for k in 0..4u8 {
            attach(self, k, u32::from(k), usize::from(k));
        }
        attach(self, 4, 10, if x.i2 & 4 != 0 { 0 } else { 1 });
        attach(self, 5, 11, 2);
        if x.i2 & 2 != 0 {
            self.pending.remove(&10);
        }
        self.enabled = x.i2 & 1 != 0;
        // After MAIN: timed events, then edges.
        let mut occurred = Vec::new();
        for (event, period) in [(10, u32::from(x.i3)), (11, u32::from(x.i4))] {
            if !self.attached.contains_key(&event) {
                self.elapsed.remove(&event);
                continue;
            }
            if period == 0 {
                continue;
            }
            let acc = self.elapsed.entry(event).or_insert(0);
            *acc += scan_ms;
            while *acc >= period {
                *acc -= period;
                occurred.push(event);
            }
        }
        if let Some(last) = self.last_i0 {
            for &(event, rising, bit) in &self.edges {
                let before = last >> bit & 1 == 1;
                let now = x.i0 >> bit & 1 == 1;
                let edge = if rising {
                    now && !before
                } else {
                    before && !now
                };
                if edge && self.attached.contains_key(&event) {
                    occurred.push(event);
                }
            }
        }
        self.last_i0 = Some(x.i0);
        occurred.sort_unstable();
        if !self.enabled {
            self.pending.extend(occurred);
            return;
        }
        let queue: Vec<u32> = std::mem::take(&mut self.pending)
            .into_iter()
            .chain(occurred)
            .collect();
        for event in queue {
            if let Some(&r) = self.attached.get(&event) {
                self.runs[r] = self.runs[r].wrapping_add(1);
                self.stamps[r] = self.seq;
                self.seq = self.seq.wrapping_add(1);
            }
        }
    }
}

/// xorshift64: the scans' inputs from a seed.
fn next(state: &mut u64) -> u64 {
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    *state
}

fn run(seed: u64, config: VmConfig, scans: usize) {
    let mut vm = load(PROGRAM, config);
    let mut model = Model::default();
    for event in 0..4u32 {
        let e = vm
            .target()
            .memory
            .events
            .iter()
            .find(|e| e.number == event)
            .expect("edge event on the target")
            .clone();
        let input = vm
            .target()
            .memory
            .parse_address(e.input.as_deref().expect("an input"))
            .expect("input address");
        let i0 = vm.target().memory.parse_address("I0.0").expect("I0.0");
        assert_eq!((input.slot, input.offset), (i0.slot, i0.offset), "{e:?}");
        assert!(input.bit < 2, "{e:?}");
        model
            .edges
            .push((event, e.kind.eq_ignore_ascii_case("RisingEdge"), input.bit));
    }
    let mut state = seed;
    let mut x = Inputs::default();
    for scan in 0..scans {
        let r = next(&mut state);
        if r.is_multiple_of(3) {
            x.i0 = (r >> 8) as u8 & 3;
        }
        if (r >> 16).is_multiple_of(8) {
            x.i1 = (r >> 24) as u8 & 0x3F;
        }
        if (r >> 32).is_multiple_of(8) {
            x.i2 = (r >> 40) as u8 & 7;
        }
        if (r >> 44).is_multiple_of(16) {
            x.i3 = ((r >> 48) % 36) as u8;
        }
        if (r >> 54).is_multiple_of(16) {
            x.i4 = ((r >> 58) % 36) as u8;
        }
        set(&mut vm, "IB0", u32::from(x.i0));
        set(&mut vm, "IB1", u32::from(x.i1));
        set(&mut vm, "IB2", u32::from(x.i2));
        set(&mut vm, "IB3", u32::from(x.i3));
        set(&mut vm, "IB4", u32::from(x.i4));
        vm.scan().expect("scan");
        model.scan(x, config.scan_ms);
        let got = (
            [0, 2, 4, 6].map(|k| read(&vm, &format!("MW{}", 40 + k)) as u16),
            [0, 2, 4, 6].map(|k| read(&vm, &format!("MW{}", 50 + k)) as u16),
            read(&vm, "MW100") as u16,
        );
        let want = (model.runs, model.stamps, model.seq);
        assert_eq!(
            got, want,
            "seed {seed}, scan {scan}, inputs {x:?}, fast {}",
            config.fast
        );
    }
    // The inputs did make every routine run, many times.
    assert!(
        model.runs.iter().all(|&n| n > 2) && model.seq > 100,
        "seed {seed}: too few runs {:?}",
        model.runs
    );
}

#[test]
fn interrupts_follow_the_model_over_random_scans() {
    for seed in [1, 0x9E37_79B9_7F4A_7C15, 0xDEAD_BEEF_1234_5678, 42] {
        for config in three_engines(VmConfig::default()) {
            run(seed, config, 600);
        }
    }
}

#[test]
fn short_scans_let_a_timed_event_occur_several_times_a_scan() {
    // 25 ms scans against periods down to 1 ms: the while loop of the accumulator.
    let config = VmConfig {
        scan_ms: 25,
        ..VmConfig::default()
    };
    for seed in [7, 99] {
        run(seed, config, 300);
    }
}
