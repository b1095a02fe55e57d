//! Shared helpers of the VM tests: compile a program with gutta-cc's library on the
//! default PLC type, verify it, load it; read and write variables by name.

#![allow(dead_code)]

use std::sync::Arc;

use gutta_catalog::stdlib;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};
use gutta_vm::{Vm, VmConfig};

/// Compile, verify and load a whole program on the default PLC type.
/// Every area's bytes, in the target's order (what a test compares area by area; the
/// whole memory, hidden state included, compares with `Vm::memory`'s `==`).
pub fn areas(vm: &Vm) -> Vec<Vec<u8>> {
    vm.target()
        .memory
        .areas
        .iter()
        .map(|a| vm.memory().area(a.slot).unwrap_or(&[]).to_vec())
        .collect()
}

pub fn load(text: &str, config: VmConfig) -> Vm {
    load_on(stdlib::DEFAULT, text, config)
}

/// Compile, verify and load `text` on the PLC type `target`.
pub fn load_on(target: &str, text: &str, config: VmConfig) -> Vm {
    let target = stdlib::shared(target).expect("target");
    let explicit = ExplicitTarget {
        target: target.clone(),
        origin: "test".into(),
    };
    let c = compile(SourceFile::new("t.lad", text), Some(&explicit));
    let image = c
        .image
        .unwrap_or_else(|| panic!("does not compile: {:?}", c.checked.diagnostics()));
    let verified = gutta_format::verify(&image, &target).expect("verifies");
    Vm::new(verified, Arc::clone(&target), config).expect("loads")
}

/// A variable's value (`MW24`, `Q0.0`), zero-extended.
pub fn read(vm: &Vm, var: &str) -> u32 {
    let a = vm.target().memory.parse_address(var).expect("address");
    vm.read(a).expect("read")
}

/// Set a variable (an input's terminal for I and AI).
pub fn set(vm: &mut Vm, var: &str, v: u32) {
    let a = vm.target().memory.parse_address(var).expect("address");
    vm.write(a, v).expect("write");
}

/// The three engines the tier tests compare, from `base`: the generic semantics (`fast`
/// off, every instruction through `ops/`), the interpreter (`native_after: None`) and
/// the compiled tier at load (`native_after: Some(0)`).
pub fn three_engines(base: VmConfig) -> [VmConfig; 3] {
    [
        VmConfig {
            fast: false,
            ..base
        },
        VmConfig {
            native_after: None,
            ..base
        },
        VmConfig {
            native_after: Some(0),
            ..base
        },
    ]
}

/// After scan `scan` of the three engines (`three_engines`' order): the interpreter's
/// and the compiled tier's instruction count and whole memory (hidden state included)
/// equal the reference engine's.
pub fn same_as_reference(vms: &[Vm; 3], scan: u32) {
    for vm in &vms[1..] {
        assert_eq!(
            vm.executed_last_scan(),
            vms[0].executed_last_scan(),
            "scan {scan}"
        );
        assert!(vm.memory() == vms[0].memory(), "memory after scan {scan}");
    }
}
