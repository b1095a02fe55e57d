//! Planned CALLs (docs/vm.md, CALL): a CALL whose arguments are plain variables of their
//! parameters' widths runs from its plan (`decode::CallPlan`) on flat memory indices.
//! The same semantics as the general CALL in `ops/control.rs`, without resolving
//! operands at run time.

use crate::decode::Unit;
use crate::fast::{load, store};
use crate::fault::Fault;
use crate::machine::{CallSave, Machine};
use crate::program::Program;

/// Enter a planned CALL: arguments read in the caller's context, the caller's L saved
/// and cleared, inputs copied into the parameters, a new frame.
pub(crate) fn enter_planned(
    machine: &mut Machine,
    program: &Program,
    unit: &Unit,
    plan: u32,
) -> Result<(), Fault> {
    let limit = program.target.instructions.call_depth;
    if machine.frames.len() > usize::from(limit) {
        return Err(Fault::CallDepth { limit });
    }
    let Some(p) = unit.calls.get(plan as usize) else {
        return Ok(());
    };
    let mem = &machine.memory.bytes;
    machine.scratch.clear();
    for a in &p.args {
        machine.scratch.push(if a.input {
            load(mem, a.var, a.width)
        } else {
            0
        });
    }
    let l_mark = machine.save_local(machine.memory.span(program.slots.local));
    let mem = &mut machine.memory.bytes;
    for (a, &v) in p.args.iter().zip(&machine.scratch) {
        if a.input {
            store(mem, a.param, a.width, v);
        }
    }
    let saved_stack = machine.stack;
    machine.push_frame(
        p.callee,
        Some(CallSave {
            l_mark,
            saved_stack,
            plan: Some(plan),
        }),
    );
    Ok(())
}

/// The return of a planned CALL (its frame popped): outputs read from L, the caller's L
/// and stack restored, outputs stored, the caller continues after it.
pub(crate) fn return_planned(machine: &mut Machine, program: &Program, plan: u32, save: CallSave) {
    let Some((page, pc)) = machine.frames.last().map(|f| (f.page, f.pc)) else {
        return;
    };
    let Some(p) = program.unit(page).and_then(|u| u.calls.get(plan as usize)) else {
        return;
    };
    let mem = &machine.memory.bytes;
    machine.scratch.clear();
    for a in &p.args {
        machine.scratch.push(if a.output {
            load(mem, a.param, a.width)
        } else {
            0
        });
    }
    machine.restore_local(machine.memory.span(program.slots.local), save.l_mark);
    machine.stack = save.saved_stack;
    let mem = &mut machine.memory.bytes;
    for (a, &v) in p.args.iter().zip(&machine.scratch) {
        if a.output {
            store(mem, a.var, a.width, v);
        }
    }
    machine.set_pc(pc + 1);
}
