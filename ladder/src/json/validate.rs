//! The model against its PLC type's instruction set: every mnemonic known (L0005) and
//! of its element's kind (L0006: a contact in its load form, a coil, a box), every
//! operand count right (L0007), a box's power inputs as many as the catalog names
//! (L0012), outputs only at the end of a series (L0008), every rung and output branch
//! ending in an output (L0009), and the power rules of `power.rs` (L0013: what STL
//! needs so that the rung's text means what it draws). What an instruction is comes from the
//! catalog (`LadderClass`, `join`, `power_output`), never from its mnemonic.

use gutta_catalog::{Instruction, InstructionSet, Join, LadderClass};

use super::codes::{ModelError, ModelErrorCode as Code};
use super::{Element, Model, NetworkBody, NetworkJson};

type Check<T> = Result<T, ModelError>;

/// What an element does to the power path.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Power {
    /// A path that passes power on: contacts.
    Passes,
    /// Ends it: a coil, a box without power output, outputs in parallel.
    Ends,
    /// Passes it on or ends the rung: a box with a power output (`MOVW`, `TON`).
    Either,
}

/// The first error of `model` against `set`, in document order.
pub fn validate(model: &Model, set: &InstructionSet) -> Check<()> {
    for (b, block) in model.blocks.iter().enumerate() {
        for (n, net) in block.networks.iter().enumerate() {
            network(set, net, b, n)?;
        }
    }
    Ok(())
}

/// The first error of network `n` of block `b` (what `validate` checks of each network;
/// the edit operations check the networks they change with it).
pub(crate) fn network(set: &InstructionSet, net: &NetworkJson, b: usize, n: usize) -> Check<()> {
    if let NetworkBody::Rung { rung } = &net.body {
        let path = format!("blocks[{b}].networks[{n}].rung");
        if element(set, rung, &path)? == Power::Passes {
            return Err(ModelError::new(
                Code::NoOutput,
                &path,
                "the rung ends without an output (a coil or a box)",
            ));
        }
        super::power::rules(set, rung, &path)?;
    }
    Ok(())
}

fn element(set: &InstructionSet, e: &Element, path: &str) -> Check<Power> {
    match e {
        Element::Series { series } => in_series(set, series, &format!("{path}.series")),
        Element::Parallel { parallel } => {
            in_parallel(set, parallel, &format!("{path}.parallel"), path)
        }
        Element::Contact { contact, operands } => {
            let spec = known(set, contact, path)?;
            let is_load_contact = spec.ladder.is_contact() && spec.join() == Some(Join::Load);
            let is_series_contact = matches!(
                spec.ladder,
                LadderClass::Not | LadderClass::RisingEdge | LadderClass::FallingEdge
            );
            if !(is_load_contact || is_series_contact) {
                let load_form = set
                    .lookup(contact)
                    .and_then(|id| set.with_join(id, Join::Load))
                    .map(|id| format!(" (its load form is `{}`)", set.get(id).mnemonic))
                    .unwrap_or_default();
                return Err(ModelError::new(
                    Code::WrongElement,
                    path,
                    format!(
                        "`{contact}` is not a contact in its load form{load_form}: a contact is `LD`, `LDN`, `LDW>=`..., `EU`, `ED` or `NOT`"
                    ),
                ));
            }
            count(spec, operands, path)?;
            Ok(Power::Passes)
        }
        Element::Coil { coil, operands } => {
            let spec = known(set, coil, path)?;
            if !spec.ladder.is_coil() {
                return Err(ModelError::new(
                    Code::WrongElement,
                    path,
                    format!("`{coil}` is not a coil: a coil is `=`, `S`, `R`, `=I`..."),
                ));
            }
            count(spec, operands, path)?;
            Ok(Power::Ends)
        }
        Element::Box {
            mnemonic,
            operands,
            inputs,
        } => {
            let spec = known(set, mnemonic, path)?;
            if spec.ladder != LadderClass::Box {
                return Err(ModelError::new(
                    Code::WrongElement,
                    path,
                    format!(
                        "`{mnemonic}` is not a box: it is a contact, a coil or a stack operation"
                    ),
                ));
            }
            count(spec, operands, path)?;
            let extra = spec.power_inputs.get(1..).unwrap_or_default();
            if inputs.len() != extra.len() {
                return Err(ModelError::new(
                    Code::BoxInputs,
                    &format!("{path}.inputs"),
                    format!(
                        "`{}` takes {} power input{} besides its first ({}), found {}",
                        spec.mnemonic,
                        extra.len(),
                        if extra.len() == 1 { "" } else { "s" },
                        if extra.is_empty() {
                            "none".to_string()
                        } else {
                            extra.join(", ")
                        },
                        inputs.len()
                    ),
                ));
            }
            for (i, input) in inputs.iter().enumerate() {
                let at = format!("{path}.inputs[{i}]");
                if element(set, input, &at)? != Power::Passes {
                    return Err(ModelError::new(
                        Code::OutputNotLast,
                        &at,
                        "a box's power input is a path of contacts, without outputs",
                    ));
                }
            }
            Ok(if spec.power_output.is_some() {
                Power::Either
            } else {
                Power::Ends
            })
        }
    }
}

/// Left to right: only the last element may end the power path.
fn in_series(set: &InstructionSet, elements: &[Element], path: &str) -> Check<Power> {
    let mut power = Power::Passes;
    for (i, e) in elements.iter().enumerate() {
        let at = format!("{path}[{i}]");
        if power == Power::Ends {
            return Err(ModelError::new(
                Code::OutputNotLast,
                &format!("{path}[{}]", i - 1),
                "an output in series before another element: only the last element of a series may be a coil, a box without power output or outputs in parallel",
            ));
        }
        power = element(set, e, &at)?;
    }
    if elements.is_empty() {
        return Err(ModelError::new(
            Code::Shape,
            path,
            "a series has at least one element",
        ));
    }
    Ok(power)
}

/// Top to bottom: paths that rejoin (none ends) or outputs (every one ends).
fn in_parallel(
    set: &InstructionSet,
    elements: &[Element],
    path: &str,
    whole: &str,
) -> Check<Power> {
    if elements.is_empty() {
        return Err(ModelError::new(
            Code::Shape,
            path,
            "a parallel has at least one element",
        ));
    }
    let powers = elements
        .iter()
        .enumerate()
        .map(|(i, e)| element(set, e, &format!("{path}[{i}]")))
        .collect::<Check<Vec<Power>>>()?;
    if powers.contains(&Power::Ends) {
        if let Some(i) = powers.iter().position(|p| *p == Power::Passes) {
            return Err(ModelError::new(
                Code::NoOutput,
                &format!("{path}[{i}]"),
                format!("a branch without an output among outputs in parallel ({whole})"),
            ));
        }
        return Ok(Power::Ends);
    }
    if powers.iter().all(|p| *p == Power::Either) {
        return Ok(Power::Either);
    }
    Ok(Power::Passes)
}

/// The catalog's instruction named `mnemonic`.
fn known<'s>(set: &'s InstructionSet, mnemonic: &str, path: &str) -> Check<&'s Instruction> {
    set.lookup(mnemonic).map(|id| set.get(id)).ok_or_else(|| {
        ModelError::new(
            Code::UnknownMnemonic,
            path,
            format!("`{mnemonic}` is not an instruction of this PLC type"),
        )
    })
}

/// The operand count the instruction takes (at least, before CALL arguments).
fn count(spec: &Instruction, operands: &[String], path: &str) -> Check<()> {
    let fixed = spec.operands.len();
    let ok = if spec.call_arguments {
        operands.len() >= fixed
    } else {
        operands.len() == fixed
    };
    if ok {
        // A blank operand is a missing one: `S Q0.0,` has one operand.
        return match operands.iter().position(|o| o.trim().is_empty()) {
            Some(i) => Err(ModelError::new(
                Code::OperandCount,
                &format!("{path}.operands[{i}]"),
                format!("operand {} of `{}` is empty", i + 1, spec.mnemonic),
            )),
            None => Ok(()),
        };
    }
    let names: Vec<&str> = spec.operands.iter().map(|o| o.name.as_str()).collect();
    let want = if spec.call_arguments {
        format!("at least {fixed}")
    } else {
        fixed.to_string()
    };
    Err(ModelError::new(
        Code::OperandCount,
        &format!("{path}.operands"),
        format!(
            "`{}` takes {want} operand{} ({}), found {}",
            spec.mnemonic,
            if fixed == 1 { "" } else { "s" },
            names.join(", "),
            operands.len()
        ),
    ))
}
