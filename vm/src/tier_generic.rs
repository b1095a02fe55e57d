//! The compiled tier's steps for instructions the interpreter runs through `ops/`
//! (`Op::Generic`): conversions, shifts, word logic, INC/DEC, ... decoded here from the
//! record's operands into `gutta_jit::Step`s with exactly the semantics of their
//! handler in `ops/` (docs/vm-jit.md, "What is compiled").

use gutta_jit::Step;

use crate::decode::Unit;
use crate::memory::Memory;

/// The step of generic record `pc` of `unit`, if the tier compiles it (it then counts
/// 1 instruction and makes no CALL). The target is `unit.target`.
pub(crate) fn generic_step(unit: &Unit, pc: usize, memory: &Memory) -> Option<Step> {
    let _ = (unit, pc, memory);
    None
}
