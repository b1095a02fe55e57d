//! Compares: `LD`/`A`/`O` x `B` (unsigned byte), `W` (INT), `D` (DINT), `R` (REAL) x
//! `=`, `<>`, `<`, `<=`, `>`, `>=`. The mnemonic spells the whole behaviour, so one
//! semantic serves all 72.

use super::{Control, Exec, Handler};
use crate::fault::Fault;

fn parse(m: &str) -> Option<(char, char, &str)> {
    let (form, rest) = if let Some(r) = m.strip_prefix("LD") {
        ('L', r)
    } else {
        (m.chars().next()?, m.get(1..)?)
    };
    if !matches!(form, 'L' | 'A' | 'O') {
        return None;
    }
    let ty = rest.chars().next()?;
    let op = rest.get(1..)?;
    (matches!(ty, 'B' | 'W' | 'D' | 'R') && matches!(op, "=" | "<>" | "<" | "<=" | ">" | ">="))
        .then_some((form, ty, op))
}

fn holds<T: PartialOrd>(a: T, b: T, op: &str) -> bool {
    match op {
        "=" => a == b,
        "<>" => a != b,
        "<" => a < b,
        "<=" => a <= b,
        ">" => a > b,
        _ => a >= b,
    }
}

fn compare(e: &mut Exec<'_>) -> Result<Control, Fault> {
    let Some((form, ty, op)) = parse(e.at.mnemonic) else {
        return Err(Fault::NoSemantics {
            mnemonic: e.at.mnemonic.to_string(),
        });
    };
    let r = match ty {
        'B' => holds(e.get(0)?, e.get(1)?, op),
        'R' => holds(e.get_real(0)?, e.get_real(1)?, op),
        _ => holds(e.get_signed(0)?, e.get_signed(1)?, op),
    };
    match form {
        'L' => e.push(r),
        'A' => {
            let t = e.top();
            e.set_top(t && r)
        }
        _ => {
            let t = e.top();
            e.set_top(t || r)
        }
    }
    Ok(Control::Next)
}

pub fn lookup(m: &str) -> Option<Handler> {
    parse(m).map(|_| compare as Handler)
}
