//! The conveyor plant (issue 31): a program shaped like a real one, 40 stations of the
//! same pattern with every family real programs are made of (a start/stop latch, a TON
//! start delay, a CTU with reset counting parts, EU and ED, S and R, word compares,
//! moves, +I, and a JMP around a block), generated twice from one description: as LAD
//! text for the VM and as the native Rust a careful programmer would write for it (the
//! benchmark's limit). tests/agree.rs holds the two to each other, scan by scan.
//! It must not use the compiler or the VM.

use std::fmt::Write;

/// One station's operands, all derived from its number.
struct Station {
    k: usize,
}

impl Station {
    /// The station's M bytes: bits in the first, words after it.
    fn base(&self) -> usize {
        100 + 16 * self.k
    }
    /// `(byte, bit)` of an input of group `group` (0 start, 1 stop, 2 acknowledge).
    fn input(&self, group: usize) -> (usize, usize) {
        (group * 5 + self.k / 8, self.k % 8)
    }
    /// `(byte, bit)` of an output of group `group` (0 motor, 1 alarm lamp).
    fn output(&self, group: usize) -> (usize, usize) {
        (group * 5 + self.k / 8, self.k % 8)
    }
    fn timer(&self) -> usize {
        10 + self.k
    }
    fn counter(&self) -> usize {
        self.k
    }
    fn label(&self) -> usize {
        self.k + 1
    }
}

/// Bits of a station's first M byte.
const RUN: usize = 0;
const FULL: usize = 1;
const ALARM: usize = 2;
const HALF: usize = 3;
const RESET: usize = 4;

/// The start delay (100 ms units) and the parts per batch.
const DELAY: i64 = 3;
const BATCH: i64 = 5;
/// The compare of the batch total.
const TOTAL_LIMIT: i64 = 1000;

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
        let (start, stop, ack) = (s.input(0), s.input(1), s.input(2));
        let (motor, lamp) = (s.output(0), s.output(1));
        let i = |(byte, bit): (usize, usize)| format!("I{byte}.{bit}");
        let q = |(byte, bit): (usize, usize)| format!("Q{byte}.{bit}");
        let (t, c, l) = (s.timer(), s.counter(), s.label());
        network(
            &mut code,
            format!(
                "LD {}\nO {}\nAN {}\n= {}\n",
                i(start),
                m(RUN),
                i(stop),
                m(RUN)
            ),
        );
        network(
            &mut code,
            format!("LD {}\nTON T{t}, {DELAY}\n= {}\n", m(RUN), q(motor)),
        );
        network(
            &mut code,
            format!(
                "LD {}\nA SM0.6\nLD {}\nCTU C{c}, {BATCH}\n= {}\n",
                q(motor),
                m(RESET),
                m(FULL)
            ),
        );
        network(
            &mut code,
            format!("LDW>= C{c}, {BATCH}\nA {}\n= {}\n", m(FULL), m(RESET)),
        );
        network(
            &mut code,
            format!("LD {}\nEU\nS {}, 1\n", m(FULL), m(ALARM)),
        );
        network(&mut code, format!("LD {}\nED\nR {}, 1\n", i(ack), m(ALARM)));
        network(&mut code, format!("LD {}\n= {}\n", m(ALARM), q(lamp)));
        network(&mut code, format!("LD SM0.0\nMOVW C{c}, MW{}\n", b + 2));
        network(&mut code, format!("LD {}\n+I 1, MW{}\n", m(RUN), b + 4));
        network(&mut code, format!("LDN {}\nJMP {l}\n", m(RUN)));
        network(
            &mut code,
            format!(
                "LD SM0.0\nMOVW MW{w4}, MW{w6}\n+I MW{w2}, MW{w6}\n",
                w2 = b + 2,
                w4 = b + 4,
                w6 = b + 6
            ),
        );
        network(
            &mut code,
            format!("LDW> MW{}, {TOTAL_LIMIT}\n= {}\n", b + 6, m(HALF)),
        );
        network(&mut code, format!("LBL {l}\n"));
    }
    format!("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n{code}END_ORGANIZATION_BLOCK\n")
}

/// The native Rust of the same `stations` stations: `conveyor_scan(&mut Plant)`, the
/// VM's semantics written out (timers count the scan's milliseconds per execution, a
/// counter and an edge remember their input, math sets SM1.0-SM1.2).
pub fn native(stations: usize) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "/// The conveyor plant's scan, natively ({stations} stations).\n\
         pub fn conveyor_scan(p: &mut Plant) {{\n\
         p.begin_scan();\n\
         let scan_ms = p.scan_ms;"
    );
    for k in 0..stations {
        let s = Station { k };
        let b = s.base();
        let (t, c) = (s.timer(), s.counter());
        let (start, stop, ack) = (s.input(0), s.input(1), s.input(2));
        let (motor, lamp) = (s.output(0), s.output(1));
        let _ = write!(
            out,
            "// station {k}\n\
             {{\n\
             let run = (bit(&p.mem.i, {sb}, {sn}) || bit(&p.mem.m, {b}, {RUN})) && !bit(&p.mem.i, {pb}, {pn});\n\
             set_bit(&mut p.mem.m, {b}, {RUN}, run);\n\
             let done = p.ton({t}, run, {DELAY}, scan_ms);\n\
             set_bit(&mut p.mem.q, {mb}, {mn}, done);\n\
             let cu = bit(&p.mem.q, {mb}, {mn}) && bit(&p.mem.sm, 0, 6);\n\
             let full = p.ctu({c}, cu, bit(&p.mem.m, {b}, {RESET}), {BATCH});\n\
             set_bit(&mut p.mem.m, {b}, {FULL}, full);\n\
             let reset = i64::from(word(&p.c, {c2})) >= {BATCH} && bit(&p.mem.m, {b}, {FULL});\n\
             set_bit(&mut p.mem.m, {b}, {RESET}, reset);\n\
             if p.edge({e0}, bit(&p.mem.m, {b}, {FULL}), true) {{ set_bit(&mut p.mem.m, {b}, {ALARM}, true); }}\n\
             if p.edge({e1}, bit(&p.mem.i, {ab}, {an}), false) {{ set_bit(&mut p.mem.m, {b}, {ALARM}, false); }}\n\
             let alarm = bit(&p.mem.m, {b}, {ALARM});\n\
             set_bit(&mut p.mem.q, {lb}, {ln}, alarm);\n\
             let count = word(&p.c, {c2});\n\
             set_word(&mut p.mem.m, {w2}, count);\n\
             if bit(&p.mem.m, {b}, {RUN}) {{ add_int(&mut p.mem, 1, {w4}); }}\n\
             if bit(&p.mem.m, {b}, {RUN}) {{\n\
             let v = word(&p.mem.m, {w4});\n\
             set_word(&mut p.mem.m, {w6}, v);\n\
             let v = word(&p.mem.m, {w2});\n\
             add_int(&mut p.mem, v, {w6});\n\
             let half = i64::from(word(&p.mem.m, {w6})) > {TOTAL_LIMIT};\n\
             set_bit(&mut p.mem.m, {b}, {HALF}, half);\n\
             }}\n\
             }}\n",
            sb = start.0,
            sn = start.1,
            pb = stop.0,
            pn = stop.1,
            ab = ack.0,
            an = ack.1,
            mb = motor.0,
            mn = motor.1,
            lb = lamp.0,
            ln = lamp.1,
            c2 = 2 * c,
            e0 = 2 * k,
            e1 = 2 * k + 1,
            w2 = b + 2,
            w4 = b + 4,
            w6 = b + 6,
        );
    }
    out.push_str("p.end_scan();\n}\n");
    let _ = writeln!(
        out,
        "\n/// Stations of the conveyor plant.\npub const CONVEYOR_STATIONS: usize = {stations};"
    );
    out
}
