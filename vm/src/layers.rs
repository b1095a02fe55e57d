//! The module layers of `lib.rs`'s doc, checked: every `crate::` path in a module names
//! a module of a lower layer, so the module graph has no cycles. Test-only; it reads
//! the sources embedded at compile time, nothing at run time.

/// (module, layer, source). A module may use only modules of a lower layer.
const MODULES: &[(&str, u8, &str)] = &[
    ("fault", 0, include_str!("fault.rs")),
    ("memory", 0, include_str!("memory.rs")),
    ("op", 0, include_str!("op.rs")),
    ("vcd", 0, include_str!("vcd.rs")),
    ("fuse", 1, include_str!("fuse.rs")),
    ("fast", 1, include_str!("fast.rs")),
    ("machine", 1, include_str!("machine.rs")),
    ("clock", 1, include_str!("clock.rs")),
    ("terminals", 1, include_str!("terminals.rs")),
    ("interrupts", 1, include_str!("interrupts.rs")),
    ("exch", 1, include_str!("exch.rs")),
    ("decode", 2, include_str!("decode.rs")),
    ("program", 3, include_str!("program.rs")),
    ("calls", 4, include_str!("calls.rs")),
    ("tier", 4, include_str!("tier.rs")),
    ("ops", 4, include_str!("ops/mod.rs")),
    ("ops", 4, include_str!("ops/bits.rs")),
    ("ops", 4, include_str!("ops/comm.rs")),
    ("ops", 4, include_str!("ops/compare.rs")),
    ("ops", 4, include_str!("ops/control.rs")),
    ("ops", 4, include_str!("ops/convert.rs")),
    ("ops", 4, include_str!("ops/interrupts.rs")),
    ("ops", 4, include_str!("ops/math.rs")),
    ("ops", 4, include_str!("ops/moves.rs")),
    ("ops", 4, include_str!("ops/shift.rs")),
    ("ops", 4, include_str!("ops/special.rs")),
    ("ops", 4, include_str!("ops/table.rs")),
    ("ops", 4, include_str!("ops/timers.rs")),
    ("engine", 5, include_str!("engine.rs")),
    ("debug", 6, include_str!("debug.rs")),
    ("load", 6, include_str!("load.rs")),
];

/// The modules a source names with `crate::` (outside comments).
fn used_modules(source: &str) -> Vec<String> {
    let mut used = Vec::new();
    for line in source.lines() {
        let code = line.split("//").next().unwrap_or("");
        for (at, _) in code.match_indices("crate::") {
            let rest = &code[at + "crate::".len()..];
            let names: Vec<&str> = match rest.strip_prefix('{') {
                Some(group) => group.split('}').next().unwrap_or("").split(',').collect(),
                None => vec![rest],
            };
            for name in names {
                let name: String = name
                    .trim()
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if !name.is_empty() {
                    used.push(name);
                }
            }
        }
    }
    used
}

#[test]
fn module_layers() {
    let layer = |name: &str| MODULES.iter().find(|m| m.0 == name).map(|m| m.1);
    let mut wrong = Vec::new();
    for (module, own, source) in MODULES {
        for used in used_modules(source) {
            match layer(&used) {
                Some(l) if l < *own || used == *module => {}
                Some(l) => wrong.push(format!("{module} (layer {own}) uses {used} (layer {l})")),
                None => wrong.push(format!("{module} uses crate::{used}, not a layered module")),
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "module layers broken:\n{}",
        wrong.join("\n")
    );
}

#[test]
fn the_check_sees_uses() {
    let uses = used_modules(
        "use crate::a::X;\nuse crate::{b::Y, c};\n// crate::d\nlet x = crate::e::f();",
    );
    assert_eq!(uses, ["a", "b", "c", "e"]);
}
