//! Program control: JMP/LBL, CALL with arguments through L, RET/CRET, END, NOP.

use gutta_catalog::Address;
use gutta_format::{LocalEntry, LocalSection, Operand};

use super::{Control, Exec, Handler};
use crate::fault::Fault;
use crate::machine::{CallSave, LoopFrame, Machine};
use crate::memory::{self, AccessError, Memory};
use crate::program::Program;

fn jmp(e: &mut Exec<'_>) -> Result<Control, Fault> {
    match e.operand(0)? {
        Operand::Label(n) => Ok(Control::Jump(n)),
        op => Err(e.fault(format!("{op:?} is not a label"))),
    }
}
fn next(_: &mut Exec<'_>) -> Result<Control, Fault> {
    Ok(Control::Next)
}
fn ret(_: &mut Exec<'_>) -> Result<Control, Fault> {
    Ok(Control::Return)
}
fn end(_: &mut Exec<'_>) -> Result<Control, Fault> {
    Ok(Control::EndScan)
}

/// CALL SBR, args: In and InOut arguments are read in the caller's context and copied
/// into the callee's L (cleared first); the callee runs on its own L and logic stack
/// (a new frame). `finish_call` is the return.
fn call(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let Operand::Unit(unit) = e.operand(0)? else {
        return Err(Fault::NoSemantics {
            mnemonic: "CALL without a unit".into(),
        });
    };
    let page = unit
        .page(&e.program.target.plc)
        .ok_or_else(|| Fault::NoSemantics {
            mnemonic: format!("CALL {unit}: no such unit on the target"),
        })?;
    let limit = e.program.target.instructions.call_depth;
    // Frames: MAIN (or an interrupt routine) and one per open call.
    if e.machine.frames.len() > usize::from(limit) {
        return Err(Fault::CallDepth { limit });
    }
    let program = e.program;
    let param = |k: usize| -> Option<LocalEntry> { program.unit(page)?.params.get(k).copied() };
    // Read the inputs in the caller's context (into a reused buffer).
    let mut args = std::mem::take(&mut e.machine.scratch);
    args.clear();
    let mut k = 0;
    while let Some(p) = param(k) {
        let v = if p.section == LocalSection::Output {
            0
        } else {
            e.get(k + 1)?
        };
        args.push(v);
        k += 1;
    }
    // Save the caller's L on the L stack, clear L, pass the arguments.
    let local_area = program.local_span;
    let l_mark = e.machine.save_local(local_area);
    for (k, v) in args.iter().enumerate() {
        if let Some(p) = param(k) {
            let at = local(&e.machine.memory, &p).map_err(|err| e.fault(err.0))?;
            e.write_at(at, *v)?;
        }
    }
    e.machine.scratch = args;
    let saved_stack = e.machine.stack;
    e.machine.push_frame(
        page,
        Some(CallSave {
            l_mark,
            saved_stack,
            plan: None,
        }),
    );
    Ok(Control::Enter)
}

/// The variable in L a parameter is.
fn local(memory: &Memory, p: &LocalEntry) -> Result<Address, AccessError> {
    memory.locate(memory::operand(p.operand)?)
}

/// The return from a subroutine `callee` (its frame already popped): InOut and Out
/// parameters are read from its L, the caller's L and logic stack are restored, the
/// values are stored through the CALL's operands, and the caller continues after its
/// CALL.
pub(crate) fn finish_call(
    machine: &mut Machine,
    program: &Program,
    callee: u8,
    save: CallSave,
) -> Result<(), Fault> {
    let Some((page, pc)) = machine.frames.last().map(|f| (f.page, f.pc)) else {
        return Ok(());
    };
    let params: &[LocalEntry] = program.unit(callee).map_or(&[], |u| &u.params);
    let mut outputs = std::mem::take(&mut machine.scratch);
    outputs.clear();
    for p in params {
        let v = if p.section == LocalSection::Input {
            0
        } else {
            local(&machine.memory, p)
                .and_then(|at| machine.memory.read(at))
                .map_err(|err| Fault::BadAccess {
                    page: callee,
                    offset: 0,
                    detail: err.0,
                })?
        };
        outputs.push(v);
    }
    machine.restore_local(program.local_span, save.l_mark);
    machine.stack = save.saved_stack;
    // The values go through the CALL's operands, in the caller's context.
    let (offset, operands) = program
        .unit(page)
        .and_then(|u| u.instruction(pc))
        .map_or((0, &[][..]), |(_, offset, operands)| (offset, operands));
    let fault = |detail: String| Fault::BadAccess {
        page,
        offset,
        detail: format!("CALL: {detail}"),
    };
    for (k, (p, v)) in params.iter().zip(&outputs).enumerate() {
        if p.section != LocalSection::Input {
            let operand = operands
                .get(k + 1)
                .ok_or_else(|| fault(format!("operand {} missing", k + 1)))?;
            memory::operand(*operand)
                .and_then(|op| machine.memory.store(op, *v))
                .map_err(|err| fault(err.0))?;
        }
    }
    machine.scratch = outputs;
    machine.set_pc(pc + 1);
    Ok(())
}

/// FOR INDX, INIT, FINAL: INDX := INIT, FINAL read once; skip to after NEXT when
/// INDX > FINAL.
fn for_loop(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let Some(&next) = e.at.unit.loops.get(&e.at.index) else {
        return Ok(Control::Next);
    };
    let init = e.get(1)?;
    let last = e.get_signed(2)?;
    e.set(0, init)?;
    let indx = e.get_signed(0)?;
    if indx > last {
        return Ok(Control::Goto(next + 1));
    }
    let frame = LoopFrame {
        page: e.page(),
        body: e.at.index + 1,
        indx: e.operand(0)?,
        last,
        stack: e.machine.stack,
    };
    e.machine.loops.push(frame);
    Ok(Control::Next)
}

/// NEXT: while INDX < FINAL, INDX += 1 and run the body again (with the stack FOR had);
/// else INDX += 1 (wrapping) and continue after NEXT.
fn next_loop(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let page = e.page();
    let Some(frame) = e.machine.loops.last().copied().filter(|f| f.page == page) else {
        return Ok(Control::Next);
    };
    let value = e
        .machine
        .memory
        .value(frame.indx)
        .map_err(|err| Fault::BadAccess {
            page,
            offset: e.at.offset,
            detail: err.0,
        })?;
    let indx = value as u16 as i16 as i64;
    let bumped = (indx as i16).wrapping_add(1) as u16 as u32;
    e.machine
        .memory
        .store(frame.indx, bumped)
        .map_err(|err| Fault::BadAccess {
            page,
            offset: e.at.offset,
            detail: err.0,
        })?;
    e.machine.stack = frame.stack;
    if indx < frame.last {
        Ok(Control::Goto(frame.body))
    } else {
        e.machine.loops.pop();
        Ok(Control::Next)
    }
}

/// WDR: restart the watchdog's count for this scan.
fn wdr(e: &mut Exec<'_>) -> Result<Control, Fault> {
    e.clock.executed = 0;
    Ok(Control::Next)
}

/// STOP: end the scan; the PLC stays in STOP until set running.
fn stop(_: &mut Exec<'_>) -> Result<Control, Fault> {
    Ok(Control::Stop)
}

pub fn lookup(m: &str) -> Option<Handler> {
    Some(match m {
        "JMP" => jmp,
        "LBL" | "NOP" => next,
        "CALL" => call,
        "RET" | "CRET" => ret,
        "END" => end,
        "FOR" => for_loop,
        "NEXT" => next_loop,
        "WDR" => wdr,
        "STOP" => stop,
        _ => return None,
    })
}
