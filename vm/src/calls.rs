//! Planned CALLs (docs/vm.md, CALL): a CALL whose arguments are plain variables of their
//! parameters' widths (BOOL ones too) runs from its plan (`decode::CallPlan`) on flat
//! memory indices.
//! The same semantics as the general CALL in `ops/control.rs`, without resolving
//! operands at run time, and in one pass over the arguments: the caller's L is saved
//! first, so an argument in the caller's L is read from (or, returning, written into)
//! its saved copy, which the return then restores.

use crate::decode::{ArgPlan, Unit};
use crate::fast::{load, store};
use crate::fault::Fault;
use crate::machine::{CallSave, Frame, Machine};
use crate::program::Program;

/// Where a variable of `width` bytes at `var` lies in the L area (`local`: its start
/// and length in the flat memory): its offset in L, or None outside L.
#[inline(always)]
fn in_local(local: Option<(usize, usize)>, var: u32, width: u8) -> Option<usize> {
    let (start, len) = local?;
    let off = (var as usize).checked_sub(start)?;
    (off + usize::from(width) <= len).then_some(off)
}

/// An argument's value at `at` in `mem` (its variable, `param` false, or its parameter):
/// its bytes, or a BOOL's bit (0 or 1).
#[inline(always)]
fn arg_load(mem: &[u8], at: u32, a: &ArgPlan, param: bool) -> u32 {
    match a.bits {
        Some((var_bit, param_bit)) => {
            let bit = if param { param_bit } else { var_bit };
            u32::from(mem[at as usize] >> bit) & 1
        }
        None => load(mem, at, a.width),
    }
}

/// Store an argument's value at `at` in `mem`: its bytes, or for a BOOL the low bit of
/// `v` into its bit, the byte's other bits kept (`memory::write_in`).
#[inline(always)]
fn arg_store(mem: &mut [u8], at: u32, a: &ArgPlan, param: bool, v: u32) {
    match a.bits {
        Some((var_bit, param_bit)) => {
            let bit = if param { param_bit } else { var_bit };
            let byte = &mut mem[at as usize];
            *byte = (*byte & !(1 << bit)) | (((v & 1) as u8) << bit);
        }
        None => store(mem, at, a.width, v),
    }
}

/// Enter a planned CALL: arguments read in the caller's context, the caller's L saved
/// and cleared, inputs copied into the parameters, a new frame.
#[inline]
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
    let local = program.local_span;
    let l_mark = machine.save_local(local);
    let (mem, saved) = (&mut machine.memory.bytes, &machine.l_stack[l_mark..]);
    for a in p.args.iter().filter(|a| a.input) {
        let v = match in_local(local, a.var, a.width) {
            Some(off) => arg_load(saved, off as u32, a, false),
            None => arg_load(mem, a.var, a, false),
        };
        arg_store(mem, a.param, a, true, v);
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
#[inline]
pub(crate) fn return_planned(machine: &mut Machine, program: &Program, plan: u32, save: CallSave) {
    finish(machine, program, plan, save.l_mark, save.saved_stack);
}

/// If the top frame is a subroutine entered by a planned CALL, leave it (what
/// `Engine::leave` does for it) and return true. Its save is read field by field from
/// the frame in place: moving the frame out whole made the compiler copy it through
/// the stack with a wide store that a narrower load right after could not forward from.
#[inline]
pub(crate) fn leave_planned(machine: &mut Machine, program: &Program) -> bool {
    let Some(Frame {
        call:
            Some(CallSave {
                l_mark,
                saved_stack,
                plan: Some(plan),
            }),
        loops_at_entry,
        ..
    }) = machine.frames.last()
    else {
        return false;
    };
    let (l_mark, saved_stack, plan, loops) = (*l_mark, *saved_stack, *plan, *loops_at_entry);
    machine.frames.pop();
    machine.loops.truncate(loops);
    finish(machine, program, plan, l_mark, saved_stack);
    true
}

#[inline(always)]
fn finish(machine: &mut Machine, program: &Program, plan: u32, l_mark: usize, saved_stack: u32) {
    let Some((page, pc)) = machine.frames.last().map(|f| (f.page, f.pc)) else {
        return;
    };
    let Some(p) = program.unit(page).and_then(|u| u.calls.get(plan as usize)) else {
        return;
    };
    let local = program.local_span;
    let mem = &mut machine.memory.bytes;
    let saved = machine.l_stack.get_mut(l_mark..).unwrap_or_default();
    for a in p.args.iter().filter(|a| a.output) {
        let v = arg_load(mem, a.param, a, true);
        match in_local(local, a.var, a.width) {
            // The caller's L comes back from its saved copy: the output goes there.
            Some(off) => arg_store(saved, off as u32, a, false, v),
            None => arg_store(mem, a.var, a, false, v),
        }
    }
    machine.restore_local(local, l_mark);
    machine.stack = saved_stack;
    machine.set_pc(pc + 1);
}
