//! The Value Change Dump `gutta-vm --vcd` writes: one signal per --read variable, named
//! after its symbol (or address), `wire` of the address width, `real` for REAL values.
//! It only formats text; main.rs samples the VM and writes the file.

use std::fmt::Write as _;

use gutta_catalog::{ValueFormat, Width};

use crate::vars::Var;

/// VCD identifier of the i-th variable: printable ASCII `!`..`~`, base 94.
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

pub fn header(reads: &[Var], initial: &[u32]) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "$version gutta-vm {} $end", env!("CARGO_PKG_VERSION"));
    let _ = writeln!(s, "$timescale 1 ms $end");
    let _ = writeln!(s, "$scope module plc $end");
    for (i, v) in reads.iter().enumerate() {
        // `.` separates scopes in wave viewers: Q0.0 is written Q0_0; blanks would end
        // the name. A symbol's name stands for its address.
        let name = v.name().replace(['.', ' '], "_");
        let kind = if v.format == ValueFormat::Real {
            "real"
        } else {
            "wire"
        };
        // Wave viewers take REAL signals as 64-bit `real` vars.
        let size = if kind == "real" {
            64
        } else {
            v.address.width.bits()
        };
        let _ = writeln!(s, "$var {kind} {size} {} {name} $end", vcd_id(i));
    }
    let _ = writeln!(s, "$upscope $end");
    let _ = writeln!(s, "$enddefinitions $end");
    let _ = writeln!(s, "#0");
    let _ = writeln!(s, "$dumpvars");
    for (i, (v, raw)) in reads.iter().zip(initial).enumerate() {
        value(&mut s, v, *raw, i);
    }
    let _ = writeln!(s, "$end");
    s
}

pub fn value(s: &mut String, var: &Var, value: u32, i: usize) {
    if var.format == ValueFormat::Real {
        let _ = writeln!(s, "r{} {}", var.show(value), vcd_id(i));
    } else if var.address.width == Width::Bit {
        let _ = writeln!(s, "{}{}", value & 1, vcd_id(i));
    } else {
        let _ = writeln!(s, "b{value:b} {}", vcd_id(i));
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
}
