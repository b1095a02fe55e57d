//! The mixing station (issue 31): a second program shaped like a real one, in the
//! manner of AN2002's and tank.lad's tanks, `stations` stations of the same pattern:
//! a sequence of three steps (fill, mix, drain) written as the Micro/WIN dialect
//! compiles SCR (docs/microwin.md: `LDN S` `JMP` `NOT` ... `LBL`), the level as INT
//! math, a TONR timing the fill (reset by a write when the batch ends), a TOF running
//! the agitator on after mixing, a CTUD counting batches up and acknowledgements down
//! with reset, EU/ED on an alarm, and the level converted (ITD, DTR, *R, TRUNC).
//! Generated twice from one description, as LAD text for the VM and as native Rust;
//! tests/agree.rs holds the two to each other, scan by scan. It must not use the
//! compiler or the VM.

use std::fmt::Write;

/// One station's operands, all derived from its number.
struct Station {
    k: usize,
}

impl Station {
    /// The station's M bytes: step and state bits in the first two, words after.
    fn base(&self) -> usize {
        800 + 24 * self.k
    }
    /// `(byte, bit)` of an input of group `group` (0 start, 1 acknowledge).
    fn input(&self, group: usize) -> (usize, usize) {
        (group * 3 + self.k / 8, self.k % 8)
    }
    /// `(byte, bit)` of an output of group `group` (0 agitator, 1 alarm lamp).
    fn output(&self, group: usize) -> (usize, usize) {
        (10 + group * 3 + self.k / 8, self.k % 8)
    }
    /// The agitator's TOF and the fill's TONR (100 ms timers on EC30-EKSTM32-XC).
    fn timers(&self) -> (usize, usize) {
        (60 + 2 * self.k, 61 + 2 * self.k)
    }
    fn counter(&self) -> usize {
        40 + self.k
    }
    /// The three steps' labels.
    fn label(&self, step: usize) -> usize {
        3 * self.k + step + 1
    }
}

/// Bits of a station's first M byte.
const FILL: usize = 0;
const MIX: usize = 1;
const DRAIN: usize = 2;
const BATCH: usize = 3;
const SLOW: usize = 4;
const BATCHES: usize = 6;
const CLEAR: usize = 7;

/// Level added per scan filling, taken draining; the full level; scans of mixing; the
/// fill time (100 ms units) past which the fill is slow; the agitator's run-on; the
/// batches before the counter's done; the REAL scale.
const INFLOW: i64 = 37;
const OUTFLOW: i64 = 53;
const FULL_LEVEL: i64 = 800;
const MIX_SCANS: i64 = 25;
const SLOW_FILL: i64 = 2;
const RUN_ON: i64 = 2;
const BATCH_DONE: i64 = 3;
const SCALE: &str = "0.125";

/// The LAD text of `stations` stations.
pub fn lad(stations: usize) -> String {
    let mut code = String::new();
    let mut net = 1;
    let mut network = |code: &mut String, body: String| {
        let _ = write!(code, "NETWORK {net}\n{body}");
        net += 1;
    };
    for k in 0..stations {
        let s = Station { k };
        let b = s.base();
        let m = |bit: usize| format!("M{b}.{bit}");
        let i = |(byte, bit): (usize, usize)| format!("I{byte}.{bit}");
        let q = |(byte, bit): (usize, usize)| format!("Q{byte}.{bit}");
        let (start, ack) = (i(s.input(0)), i(s.input(1)));
        let (agitator, lamp) = (q(s.output(0)), q(s.output(1)));
        let (tof, tonr) = s.timers();
        let c = s.counter();
        let (level, mixed) = (b + 2, b + 6);
        let (wide, real, whole) = (b + 8, b + 12, b + 16);
        let alarm = format!("M{}.0", b + 1);
        network(
            &mut code,
            format!(
                "LD {start}\nAN {}\nAN {}\nS {}, 1\n",
                m(MIX),
                m(DRAIN),
                m(FILL)
            ),
        );
        // Step fill.
        let l = s.label(0);
        network(&mut code, format!("LDN {}\nJMP {l}\nNOT\n", m(FILL)));
        network(&mut code, format!("LD SM0.0\n+I {INFLOW}, MW{level}\n"));
        network(
            &mut code,
            format!("LD SM0.0\nTONR T{tonr}, {SLOW_FILL}\n= {}\n", m(SLOW)),
        );
        network(
            &mut code,
            format!(
                "LDW>= MW{level}, {FULL_LEVEL}\nS {}, 1\nR {}, 1\n",
                m(MIX),
                m(FILL)
            ),
        );
        network(&mut code, format!("LBL {l}\n"));
        // Step mix.
        let l = s.label(1);
        network(&mut code, format!("LDN {}\nJMP {l}\nNOT\n", m(MIX)));
        network(
            &mut code,
            format!(
                "LD SM0.0\nITD MW{level}, MD{wide}\nDTR MD{wide}, MD{real}\n\
                 *R {SCALE}, MD{real}\nTRUNC MD{real}, MD{whole}\n+I 1, MW{mixed}\n"
            ),
        );
        network(
            &mut code,
            format!(
                "LDW>= MW{mixed}, {MIX_SCANS}\nS {}, 1\nR {}, 1\nMOVW 0, MW{mixed}\n",
                m(DRAIN),
                m(MIX)
            ),
        );
        network(&mut code, format!("LBL {l}\n"));
        // Step drain.
        let l = s.label(2);
        network(&mut code, format!("LDN {}\nJMP {l}\nNOT\n", m(DRAIN)));
        network(&mut code, format!("LD SM0.0\n-I {OUTFLOW}, MW{level}\n"));
        network(
            &mut code,
            format!(
                "LDW<= MW{level}, 0\nS {}, 1\nR {}, 1\nMOVW 0, MW{level}\nMOVW 0, T{tonr}\n",
                m(BATCH),
                m(DRAIN)
            ),
        );
        network(&mut code, format!("LBL {l}\n"));
        // Outside the sequence.
        network(
            &mut code,
            format!("LD {}\nTOF T{tof}, {RUN_ON}\n= {agitator}\n", m(MIX)),
        );
        network(
            &mut code,
            format!(
                "LD {}\nLD {ack}\nLD {}\nCTUD C{c}, {BATCH_DONE}\n= {}\n",
                m(BATCH),
                m(CLEAR),
                m(BATCHES)
            ),
        );
        network(
            &mut code,
            format!("LDW>= C{c}, {BATCH_DONE}\nA {ack}\n= {}\n", m(CLEAR)),
        );
        network(&mut code, format!("LD {}\nR {}, 1\n", m(BATCH), m(BATCH)));
        network(&mut code, format!("LD {}\nEU\nS {alarm}, 1\n", m(SLOW)));
        network(&mut code, format!("LD {ack}\nED\nR {alarm}, 1\n"));
        network(&mut code, format!("LD {alarm}\n= {lamp}\n"));
    }
    format!("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n{code}END_ORGANIZATION_BLOCK\n")
}

/// The native Rust of the same `stations` stations: `mixing_scan(&mut Plant)`, the
/// VM's semantics written out (a step's networks run only when its bit was on at its
/// start; timers count the scan's milliseconds per execution; math sets SM1.0-SM1.2,
/// TRUNC SM1.1).
pub fn native(stations: usize) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "/// The mixing station's scan, natively ({stations} stations).\n\
         pub fn mixing_scan(p: &mut Plant) {{\n\
         p.begin_scan();\n\
         let scan_ms = p.scan_ms;"
    );
    for k in 0..stations {
        let s = Station { k };
        let b = s.base();
        let (tof, tonr) = s.timers();
        let c = s.counter();
        let (start, ack) = (s.input(0), s.input(1));
        let (agitator, lamp) = (s.output(0), s.output(1));
        let _ = write!(
            out,
            "// station {k}\n\
             {{\n\
             if bit(&p.mem.i, {sb}, {sn}) && !bit(&p.mem.m, {b}, {MIX}) && !bit(&p.mem.m, {b}, {DRAIN}) {{ set_bit(&mut p.mem.m, {b}, {FILL}, true); }}\n\
             if bit(&p.mem.m, {b}, {FILL}) {{\n\
             add_int(&mut p.mem, {INFLOW}, {level});\n\
             let slow = p.tonr({tonr}, true, {SLOW_FILL}, scan_ms);\n\
             set_bit(&mut p.mem.m, {b}, {SLOW}, slow);\n\
             if i64::from(word(&p.mem.m, {level})) >= {FULL_LEVEL} {{ set_bit(&mut p.mem.m, {b}, {MIX}, true); set_bit(&mut p.mem.m, {b}, {FILL}, false); }}\n\
             }}\n\
             if bit(&p.mem.m, {b}, {MIX}) {{\n\
             let v = i32::from(word(&p.mem.m, {level}));\n\
             set_dword(&mut p.mem.m, {wide}, v);\n\
             let r = dword(&p.mem.m, {wide}) as f32;\n\
             set_dword(&mut p.mem.m, {real}, r.to_bits() as i32);\n\
             mul_real(&mut p.mem, {SCALE}, {real});\n\
             trunc_real(&mut p.mem, {real}, {whole});\n\
             add_int(&mut p.mem, 1, {mixed});\n\
             if i64::from(word(&p.mem.m, {mixed})) >= {MIX_SCANS} {{ set_bit(&mut p.mem.m, {b}, {DRAIN}, true); set_bit(&mut p.mem.m, {b}, {MIX}, false); set_word(&mut p.mem.m, {mixed}, 0); }}\n\
             }}\n\
             if bit(&p.mem.m, {b}, {DRAIN}) {{\n\
             sub_int(&mut p.mem, {OUTFLOW}, {level});\n\
             if word(&p.mem.m, {level}) <= 0 {{ set_bit(&mut p.mem.m, {b}, {BATCH}, true); set_bit(&mut p.mem.m, {b}, {DRAIN}, false); set_word(&mut p.mem.m, {level}, 0); set_word(&mut p.t, {t2}, 0); }}\n\
             }}\n\
             let run = p.tof({tof}, bit(&p.mem.m, {b}, {MIX}), {RUN_ON}, scan_ms);\n\
             set_bit(&mut p.mem.q, {gb}, {gn}, run);\n\
             let done = p.ctud({c}, bit(&p.mem.m, {b}, {BATCH}), bit(&p.mem.i, {ab}, {an}), bit(&p.mem.m, {b}, {CLEAR}), {BATCH_DONE});\n\
             set_bit(&mut p.mem.m, {b}, {BATCHES}, done);\n\
             let clear = i64::from(word(&p.c, {c2})) >= {BATCH_DONE} && bit(&p.mem.i, {ab}, {an});\n\
             set_bit(&mut p.mem.m, {b}, {CLEAR}, clear);\n\
             if bit(&p.mem.m, {b}, {BATCH}) {{ set_bit(&mut p.mem.m, {b}, {BATCH}, false); }}\n\
             if p.edge({e0}, bit(&p.mem.m, {b}, {SLOW}), true) {{ set_bit(&mut p.mem.m, {b1}, 0, true); }}\n\
             if p.edge({e1}, bit(&p.mem.i, {ab}, {an}), false) {{ set_bit(&mut p.mem.m, {b1}, 0, false); }}\n\
             let alarm = bit(&p.mem.m, {b1}, 0);\n\
             set_bit(&mut p.mem.q, {lb}, {ln}, alarm);\n\
             }}\n",
            sb = start.0,
            sn = start.1,
            ab = ack.0,
            an = ack.1,
            gb = agitator.0,
            gn = agitator.1,
            lb = lamp.0,
            ln = lamp.1,
            b1 = b + 1,
            level = b + 2,
            mixed = b + 6,
            wide = b + 8,
            real = b + 12,
            whole = b + 16,
            t2 = 2 * tonr,
            c2 = 2 * c,
            e0 = 2 * k,
            e1 = 2 * k + 1,
        );
    }
    out.push_str("p.end_scan();\n}\n");
    let _ = writeln!(
        out,
        "\n/// Stations of the mixing station.\npub const MIXING_STATIONS: usize = {stations};"
    );
    out
}
