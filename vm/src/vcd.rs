//! Value Change Dump text (IEEE 1364 VCD) of sampled variables: `gutta-vm --vcd` and
//! `gutta-cc test --vcd` write it, any wave viewer (GTKWave, Surfer) reads it. One
//! signal per variable, named after its symbol or address, `wire` of the variable's
//! width or `real` for REAL values; time in virtual milliseconds. It only formats
//! text: the callers sample the VM and write the file.

use std::fmt::Write as _;

use gutta_catalog::{ValueFormat, Width};

/// One signal of the dump.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Signal {
    /// The symbol's name or the address (`Lamp`, `Q0.0`); written with `.` and blanks
    /// as `_`, because `.` separates scopes in wave viewers.
    pub name: String,
    /// Bits of the variable: 1, 8, 16 or 32.
    pub bits: u32,
    /// A REAL: written as a `real` signal with its value.
    pub real: bool,
}

impl Signal {
    /// The signal of a variable named `name` of `width`, shown in `format` (REAL values
    /// become a `real` signal).
    pub fn of(name: &str, width: Width, format: ValueFormat) -> Signal {
        Signal {
            name: name.to_string(),
            bits: width.bits(),
            real: format == ValueFormat::Real,
        }
    }
}

/// VCD identifier of the i-th signal: printable ASCII `!`..`~`, base 94.
fn vcd_id(mut i: usize) -> String {
    let mut id = String::new();
    loop {
        id.push(char::from(b'!' + (i % 94) as u8));
        i /= 94;
        if i == 0 {
            return id;
        }
        i -= 1;
    }
}

/// A dump being written: the header with the first values, then [`Dump::sample`]s.
#[derive(Debug, Clone)]
pub struct Dump {
    signals: Vec<Signal>,
    text: String,
    last: Vec<u32>,
    time: u64,
}

impl Dump {
    /// The header (`tool` names the writer) and the values at time 0.
    pub fn new(tool: &str, signals: Vec<Signal>, initial: &[u32]) -> Dump {
        let mut s = String::new();
        let _ = writeln!(s, "$version {tool} $end");
        let _ = writeln!(s, "$timescale 1 ms $end");
        let _ = writeln!(s, "$scope module plc $end");
        for (i, v) in signals.iter().enumerate() {
            let name = v.name.replace(['.', ' '], "_");
            // Wave viewers take REAL signals as 64-bit `real` vars.
            let (kind, size) = if v.real {
                ("real", 64)
            } else {
                ("wire", v.bits)
            };
            let _ = writeln!(s, "$var {kind} {size} {} {name} $end", vcd_id(i));
        }
        let _ = writeln!(s, "$upscope $end");
        let _ = writeln!(s, "$enddefinitions $end");
        let _ = writeln!(s, "#0");
        let _ = writeln!(s, "$dumpvars");
        let mut dump = Dump {
            signals,
            text: s,
            last: initial.to_vec(),
            time: 0,
        };
        for i in 0..dump.signals.len() {
            let raw = initial.get(i).copied().unwrap_or(0);
            dump.value(i, raw);
        }
        dump.text.push_str("$end\n");
        dump
    }

    /// The values at `time_ms` (not before the last sample's): only changes are written.
    pub fn sample(&mut self, time_ms: u64, values: &[u32]) {
        let mut stamped = false;
        for (i, &raw) in values.iter().enumerate().take(self.signals.len()) {
            if self.last.get(i) == Some(&raw) {
                continue;
            }
            if !stamped && time_ms != self.time {
                let _ = writeln!(self.text, "#{time_ms}");
                self.time = time_ms;
            }
            stamped = true;
            self.value(i, raw);
            if let Some(slot) = self.last.get_mut(i) {
                *slot = raw;
            }
        }
    }

    /// The dump so far, ending at `end_ms` (so a viewer shows the last values).
    pub fn finish(mut self, end_ms: u64) -> String {
        if end_ms > self.time {
            let _ = writeln!(self.text, "#{end_ms}");
        }
        self.text
    }

    fn value(&mut self, i: usize, raw: u32) {
        let id = vcd_id(i);
        let signal = &self.signals[i];
        if signal.real {
            let _ = writeln!(self.text, "r{} {id}", f32::from_bits(raw));
        } else if signal.bits == 1 {
            let _ = writeln!(self.text, "{}{id}", raw & 1);
        } else {
            let _ = writeln!(self.text, "b{raw:b} {id}");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vcd_ids_are_unique() {
        let ids: std::collections::HashSet<String> = (0..20_000).map(vcd_id).collect();
        assert_eq!(ids.len(), 20_000);
    }

    #[test]
    fn only_changes_are_written_at_their_time() {
        let signals = vec![
            Signal {
                name: "Q0.0".into(),
                bits: 1,
                real: false,
            },
            Signal {
                name: "Temp".into(),
                bits: 32,
                real: true,
            },
        ];
        let mut dump = Dump::new("t", signals, &[0, 1.5f32.to_bits()]);
        dump.sample(10, &[0, 1.5f32.to_bits()]);
        dump.sample(20, &[1, 1.5f32.to_bits()]);
        dump.sample(20, &[1, 2.0f32.to_bits()]);
        let text = dump.finish(30);
        assert!(text.contains("$var wire 1 ! Q0_0 $end"));
        assert!(text.contains("$var real 64 \" Temp $end"));
        let body = text.split("$end\n").last().expect("body");
        assert_eq!(body, "#20\n1!\nr2 \"\n#30\n");
    }
}
