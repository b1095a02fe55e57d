//! Bit logic: loads, combines, outputs, stack operations, edges. Immediate variants
//! (LDI, =I, ...) act on the same I/Q image as their plain forms in the VM.

use super::{Control, Exec, Handler};
use crate::fault::Fault;

fn ld(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let v = e.get(0)? == 1;
    e.push(v);
    Ok(Control::Next)
}
fn ldn(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let v = e.get(0)? == 1;
    e.push(!v);
    Ok(Control::Next)
}
fn and(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let v = e.get(0)? == 1;
    let t = e.top();
    e.set_top(t && v);
    Ok(Control::Next)
}
fn and_not(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let v = e.get(0)? == 1;
    let t = e.top();
    e.set_top(t && !v);
    Ok(Control::Next)
}
fn or(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let v = e.get(0)? == 1;
    let t = e.top();
    e.set_top(t || v);
    Ok(Control::Next)
}
fn or_not(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let v = e.get(0)? == 1;
    let t = e.top();
    e.set_top(t || !v);
    Ok(Control::Next)
}
fn not(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let t = e.top();
    e.set_top(!t);
    Ok(Control::Next)
}
fn assign(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let t = e.top();
    e.set(0, u32::from(t))?;
    Ok(Control::Next)
}
/// S/R BIT, N: while the top is 1, set or reset N consecutive bits from BIT.
fn set_reset(e: &mut Exec<'_>, value: u32) -> Result<Control, Fault> {
    if !e.top() {
        return Ok(Control::Next);
    }
    let first = e.locate(0)?;
    let n = e.get(1)?;
    for k in 0..n {
        let bit = first.bit as u32 + k;
        let loc = gutta_catalog::Address {
            offset: first.offset + bit / 8,
            bit: (bit % 8) as u8,
            ..first
        };
        e.write_at(loc, value)?;
    }
    Ok(Control::Next)
}
fn set(e: &mut Exec<'_>) -> Result<Control, Fault> {
    set_reset(e, 1)
}
fn reset(e: &mut Exec<'_>) -> Result<Control, Fault> {
    set_reset(e, 0)
}
fn ald(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let a = e.pop();
    let b = e.top();
    e.set_top(a && b);
    Ok(Control::Next)
}
fn old(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let a = e.pop();
    let b = e.top();
    e.set_top(a || b);
    Ok(Control::Next)
}
fn lps(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let t = e.top();
    e.push(t);
    Ok(Control::Next)
}
fn lrd(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let second = e.level(1);
    e.set_top(second);
    Ok(Control::Next)
}
fn lpp(e: &mut Exec<'_>) -> Result<Control, Fault> {
    e.pop();
    Ok(Control::Next)
}
fn lds(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let n = e.get(0)?;
    let v = e.level(n);
    e.push(v);
    Ok(Control::Next)
}
/// EU/ED: the top becomes 1 for one execution when it rose (fell) since this
/// instruction's previous execution; each instance keeps its own edge memory.
fn edge(e: &mut Exec<'_>, rising: bool) -> Result<Control, Fault> {
    let now = e.top();
    let before = match e.edge_state() {
        Some(at) => {
            let mem = &mut e.machine.memory.bytes;
            let before = mem[at] != 0;
            mem[at] = u8::from(now);
            before
        }
        None => return Err(e.fault("EU/ED without its edge state".to_string())),
    };
    e.set_top(if rising {
        now && !before
    } else {
        !now && before
    });
    Ok(Control::Next)
}
fn eu(e: &mut Exec<'_>) -> Result<Control, Fault> {
    edge(e, true)
}
fn ed(e: &mut Exec<'_>) -> Result<Control, Fault> {
    edge(e, false)
}

pub fn lookup(m: &str) -> Option<Handler> {
    Some(match m {
        "LD" | "LDI" => ld,
        "LDN" | "LDNI" => ldn,
        "A" | "AI" => and,
        "AN" | "ANI" => and_not,
        "O" | "OI" => or,
        "ON" | "ONI" => or_not,
        "NOT" => not,
        "=" | "=I" => assign,
        "S" | "SI" => set,
        "R" | "RI" => reset,
        "ALD" => ald,
        "OLD" => old,
        "LPS" => lps,
        "LRD" => lrd,
        "LPP" => lpp,
        "LDS" => lds,
        "EU" => eu,
        "ED" => ed,
        _ => return None,
    })
}
