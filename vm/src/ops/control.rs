//! Program control: JMP/LBL, CALL with arguments through L, RET/CRET, END, NOP.

use gutta_catalog::Width;
use gutta_format::{LocalEntry, LocalSection, Use};

use super::{Control, Exec, Handler};
use crate::engine::CallSave;
use crate::{Fault, Location, Vm};

fn jmp(e: &mut Exec<'_>) -> Result<Control, Fault> {
    Ok(Control::Jump(e.operand(0)?.offset()))
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
    let unit = e.operand(0)?;
    if unit.use_() != Some(Use::Unit) {
        return Err(Fault::NoSemantics {
            mnemonic: "CALL without a unit".into(),
        });
    }
    let page = if unit.slot() == 1 {
        e.vm.target.plc.program_block_page_int_size + unit.offset() as u32
    } else {
        unit.offset() as u32
    };
    let page = u8::try_from(page).map_err(|_| Fault::NoSemantics {
        mnemonic: "CALL page".into(),
    })?;
    let limit = e.vm.target.instructions.call_depth;
    // Frames: MAIN (or an interrupt routine) and one per open call.
    if e.vm.frames.len() > usize::from(limit) {
        return Err(Fault::CallDepth { limit });
    }
    let param = |vm: &Vm, k: usize| -> Option<LocalEntry> {
        vm.units[page as usize].as_ref()?.params.get(k).copied()
    };
    // Read the inputs in the caller's context (into a reused buffer).
    let mut args = std::mem::take(&mut e.vm.scratch);
    args.clear();
    let mut k = 0;
    while let Some(p) = param(e.vm, k) {
        let v = if p.section == LocalSection::Output {
            0
        } else {
            e.get(k + 1)?
        };
        args.push(v);
        k += 1;
    }
    // Save the caller's L on the L stack, clear L, pass the arguments.
    let l_mark = e.vm.l_stack.len();
    if let Some((start, len)) = e.vm.memory.span(e.vm.slots.local) {
        let vm = &mut *e.vm;
        vm.l_stack
            .extend_from_slice(&vm.memory.bytes[start..start + len]);
        vm.memory.bytes[start..start + len].fill(0);
    }
    for (k, v) in args.iter().enumerate() {
        if let Some(p) = param(e.vm, k) {
            e.write_at(local(&p), *v)?;
        }
    }
    e.vm.scratch = args;
    let saved_stack = e.vm.stack;
    e.vm.push_frame(
        page,
        Some(CallSave {
            l_mark,
            saved_stack,
            plan: None,
        }),
    );
    Ok(Control::Enter)
}

fn local(p: &LocalEntry) -> Location {
    Location {
        slot: p.operand.slot(),
        offset: p.operand.offset() as u32,
        width: p.operand.width().unwrap_or(Width::Byte),
        bit: p.operand.bit(),
    }
}

/// The return from a subroutine `callee` (its frame already popped): InOut and Out
/// parameters are read from its L, the caller's L and logic stack are restored, the
/// values are stored through the CALL's operands, and the caller continues after its
/// CALL.
pub(crate) fn finish_call(vm: &mut Vm, callee: u8, save: CallSave) -> Result<(), Fault> {
    let Some((page, pc)) = vm.frames.last().map(|f| (f.page, f.pc)) else {
        return Ok(());
    };
    let mut outputs = std::mem::take(&mut vm.scratch);
    outputs.clear();
    if let Some(unit) = vm.units[callee as usize].as_ref() {
        for p in &unit.params {
            let v = if p.section == LocalSection::Input {
                0
            } else {
                vm.memory.read(local(p)).map_err(|err| Fault::BadAccess {
                    page: callee,
                    offset: 0,
                    detail: err.0,
                })?
            };
            outputs.push(v);
        }
    }
    if let Some((start, len)) = vm.memory.span(vm.slots.local) {
        let saved = vm.l_stack.get(save.l_mark..).unwrap_or(&[]);
        let n = saved.len().min(len);
        vm.memory.bytes[start..start + n].copy_from_slice(&saved[..n]);
    }
    vm.l_stack.truncate(save.l_mark);
    vm.stack = save.saved_stack;
    // The CALL's operands, copied so the caller's unit is not borrowed while storing.
    let mut operands = std::mem::take(&mut vm.call_operands);
    operands.clear();
    let mut offset = 0;
    if let Some((_, at, ops)) = vm.units[page as usize]
        .as_ref()
        .and_then(|u| u.instruction(pc))
    {
        operands.extend_from_slice(ops);
        offset = at;
    }
    let mut e = Exec {
        vm,
        operands: &operands,
        page,
        index: pc,
        offset,
        mnemonic: "CALL",
    };
    for (k, v) in outputs.iter().enumerate() {
        let section = e.vm.units[callee as usize]
            .as_ref()
            .and_then(|u| u.params.get(k))
            .map(|p| p.section);
        if section.is_some_and(|s| s != LocalSection::Input) {
            e.set(k + 1, *v)?;
        }
    }
    vm.call_operands = operands;
    vm.scratch = outputs;
    if let Some(f) = vm.frames.last_mut() {
        f.pc = pc + 1;
    }
    Ok(())
}

/// FOR INDX, INIT, FINAL: INDX := INIT, FINAL read once; skip to after NEXT when
/// INDX > FINAL.
fn for_loop(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let Some(&next) = e.vm.for_pairs.get(&(e.page, e.index)) else {
        return Ok(Control::Next);
    };
    let init = e.get(1)?;
    let last = e.get_signed(2)?;
    e.set(0, init)?;
    let indx = e.get_signed(0)?;
    if indx > last {
        return Ok(Control::Goto(next + 1));
    }
    let frame = super::LoopFrame {
        page: e.page,
        body: e.index + 1,
        indx: e.operand(0)?,
        last,
        stack: e.vm.stack,
    };
    e.vm.loops.push(frame);
    Ok(Control::Next)
}

/// NEXT: while INDX < FINAL, INDX += 1 and run the body again (with the stack FOR had);
/// else INDX += 1 (wrapping) and continue after NEXT.
fn next_loop(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let Some(frame) = e.vm.loops.last().copied().filter(|f| f.page == e.page) else {
        return Ok(Control::Next);
    };
    let value =
        e.vm.memory
            .value(frame.indx)
            .map_err(|err| Fault::BadAccess {
                page: e.page,
                offset: e.offset,
                detail: err.0,
            })?;
    let indx = value as u16 as i16 as i64;
    let bumped = (indx as i16).wrapping_add(1) as u16 as u32;
    e.vm.memory
        .store(frame.indx, bumped)
        .map_err(|err| Fault::BadAccess {
            page: e.page,
            offset: e.offset,
            detail: err.0,
        })?;
    e.vm.stack = frame.stack;
    if indx < frame.last {
        Ok(Control::Goto(frame.body))
    } else {
        e.vm.loops.pop();
        Ok(Control::Next)
    }
}

/// WDR: restart the watchdog's count for this scan.
fn wdr(e: &mut Exec<'_>) -> Result<Control, Fault> {
    e.vm.executed = 0;
    Ok(Control::Next)
}

/// STOP: end the scan; the PLC stays in STOP until set running.
fn stop(e: &mut Exec<'_>) -> Result<Control, Fault> {
    e.vm.stopped = true;
    Ok(Control::EndScan)
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
