//! MicroWIN SMART's default I/O symbols (docs/microwin.md, "MicroWIN SMART's I/O
//! symbols"): its I/O symbol table names a CPU's onboard inputs `CPU_输入0`,
//! `CPU_输入1`, ... (`CPU_Input0`, ... in the English UI) and its outputs `CPU_输出0`,
//! ... (`CPU_Output0`, ...), counting the bits of I and Q from I0.0 and Q0.0: input n
//! is I(n/8).(n%8). A rule as data (the name patterns and their area); which names a
//! target has follows from the size of its I and Q areas. Plain data and parsing, no
//! diagnostics: the Micro/WIN dialect offers the names, the checker reports the rest.

use crate::{Address, AreaKind, MemoryMap, Width};

/// One pattern of MicroWIN SMART's default I/O names: `prefix` then the point's number
/// in decimal, for a bit of the area of kind `area`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SmartIoPattern {
    /// As SMART writes it (`CPU_输入`, `CPU_Input`); ASCII letters match in any case.
    pub prefix: &'static str,
    pub area: AreaKind,
    /// `input` or `output`, for messages.
    pub what: &'static str,
}

/// Every pattern: the Chinese and the English UI's names of inputs and outputs.
pub const SMART_IO_PATTERNS: &[SmartIoPattern] = &[
    SmartIoPattern {
        prefix: "CPU_输入",
        area: AreaKind::DigitalInput,
        what: "input",
    },
    SmartIoPattern {
        prefix: "CPU_Input",
        area: AreaKind::DigitalInput,
        what: "input",
    },
    SmartIoPattern {
        prefix: "CPU_输出",
        area: AreaKind::DigitalOutput,
        what: "output",
    },
    SmartIoPattern {
        prefix: "CPU_Output",
        area: AreaKind::DigitalOutput,
        what: "output",
    },
];

/// The onboard points of the S7-200 SMART standard CPUs (inputs, outputs), as the
/// SMART system manual lists them: for docs and tests; a GUTTA target's names come
/// from its own I and Q areas.
pub const SMART_CPU_POINTS: &[(&str, u32, u32)] = &[
    ("CPU SR20 / ST20", 12, 8),
    ("CPU SR30 / ST30", 18, 12),
    ("CPU SR40 / ST40 / CR40", 24, 16),
    ("CPU SR60 / ST60 / CR60", 36, 24),
];

/// A name of SMART's pattern: which pattern, which point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SmartIoName {
    pub pattern: &'static SmartIoPattern,
    /// The point's number, counted over the area's bits from bit 0 of byte 0.
    pub point: u32,
}

impl SmartIoName {
    /// The byte and bit the point is in: `(point / 8, point % 8)`.
    pub fn byte_and_bit(&self) -> (u32, u8) {
        (self.point / 8, (self.point % 8) as u8)
    }

    /// The bit address as text in the area named `area` (`I1.3` for input 11).
    pub fn address_text(&self, area: &str) -> String {
        let (byte, bit) = self.byte_and_bit();
        format!("{area}{byte}.{bit}")
    }

    /// The bit on `memory`'s area of the pattern's kind; `Err` with that area's name
    /// and size in bytes when it has no such bit (or `None` when it has no such area).
    pub fn address(&self, memory: &MemoryMap) -> Result<Address, Option<(String, u32)>> {
        let area = memory.area_of_kind(self.pattern.area).ok_or(None)?;
        let (byte, bit) = self.byte_and_bit();
        if byte >= area.size {
            return Err(Some((area.name.clone(), area.size)));
        }
        Ok(Address {
            slot: area.slot,
            width: Width::Bit,
            offset: byte,
            bit,
        })
    }
}

/// The SMART I/O name `name` is (any case of its ASCII letters), if it is one: a
/// pattern's prefix and a decimal number without leading zeros.
pub fn smart_io_name(name: &str) -> Option<SmartIoName> {
    SMART_IO_PATTERNS.iter().find_map(|pattern| {
        let head = name.get(..pattern.prefix.len())?;
        if !head.eq_ignore_ascii_case(pattern.prefix) {
            return None;
        }
        let digits = &name[pattern.prefix.len()..];
        let canonical = !digits.is_empty()
            && digits.bytes().all(|b| b.is_ascii_digit())
            && (digits == "0" || !digits.starts_with('0'));
        let point = digits.parse().ok().filter(|_| canonical)?;
        Some(SmartIoName { pattern, point })
    })
}

/// Every SMART I/O name `memory` has a bit for, with that bit: each pattern's names
/// for the bits of its area, in pattern then point order.
pub fn smart_io_names(memory: &MemoryMap) -> Vec<(String, Address)> {
    let mut out = Vec::new();
    for pattern in SMART_IO_PATTERNS {
        let Some(area) = memory.area_of_kind(pattern.area) else {
            continue;
        };
        for point in 0..area.size * 8 {
            let name = SmartIoName { pattern, point };
            if let Ok(a) = name.address(memory) {
                out.push((format!("{}{point}", pattern.prefix), a));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stdlib;

    #[test]
    fn names_parse_in_any_case_without_leading_zeros() {
        let input = |n: &str| smart_io_name(n).map(|s| (s.pattern.area, s.point));
        assert_eq!(input("CPU_输入0"), Some((AreaKind::DigitalInput, 0)));
        assert_eq!(input("cpu_input11"), Some((AreaKind::DigitalInput, 11)));
        assert_eq!(input("CPU_OUTPUT7"), Some((AreaKind::DigitalOutput, 7)));
        assert_eq!(input("CPU_输出23"), Some((AreaKind::DigitalOutput, 23)));
        for not in [
            "CPU_Input",
            "CPU_Input01",
            "CPU_Input1a",
            "CPU_In0",
            "CPU_输入-1",
            "输入0",
        ] {
            assert_eq!(input(not), None, "{not}");
        }
        assert_eq!(input("CPU_Input99999999999"), None);
    }

    #[test]
    fn points_count_the_bits_from_i0_0() {
        let target = stdlib::shared(stdlib::DEFAULT).expect("default target");
        let memory = &target.memory;
        let at = |n: &str| {
            let a = smart_io_name(n)
                .expect("a name")
                .address(memory)
                .expect("in I/Q");
            memory.format_address(&a)
        };
        assert_eq!(at("CPU_Input0"), "I0.0");
        assert_eq!(at("CPU_输入11"), "I1.3");
        assert_eq!(at("CPU_Output9"), "Q1.1");
        // CPU-EC20 has 8 bytes of I: 64 inputs.
        let past = smart_io_name("CPU_Input64").expect("a name");
        assert_eq!(past.address(memory), Err(Some(("I".to_string(), 8))));
        assert_eq!(past.address_text("I"), "I8.0");
    }

    #[test]
    fn every_stdlib_target_names_each_bit_of_i_and_q_four_times_over() {
        for name in stdlib::names() {
            let target = stdlib::shared(name).expect("stdlib target loads");
            let memory = &target.memory;
            let bits = |kind| memory.area_of_kind(kind).map_or(0, |a| a.size * 8);
            let names = smart_io_names(memory);
            let expected = 2 * (bits(AreaKind::DigitalInput) + bits(AreaKind::DigitalOutput));
            assert_eq!(names.len() as u32, expected, "{name}");
            // Each SMART CPU's onboard I/O fits every stdlib target.
            for (cpu, inputs, outputs) in SMART_CPU_POINTS {
                assert!(*inputs <= bits(AreaKind::DigitalInput), "{name}: {cpu}");
                assert!(*outputs <= bits(AreaKind::DigitalOutput), "{name}: {cpu}");
            }
        }
    }
}
