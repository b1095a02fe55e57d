//! What an edited network must pass before the edit is kept: `json::validate`'s and
//! `json::program_of`'s checks of one network (the same functions, not a copy), and
//! the power rules STL needs that the model's checks do not say (L0013): nothing that
//! needs power first on the rail, no box that runs without power flow inside a rung.
//! What an instruction needs comes from the catalog (`Flow`), never its mnemonic.

use gutta_catalog::{Flow, InstructionSet};

use super::{ElementPath, Step};
use crate::json::{
    network_fields_one_line, network_instructions, validate_network, Element, ModelError,
    ModelErrorCode as Code, NetworkBody, NetworkJson,
};

type Edited<T> = Result<T, ModelError>;

/// Network `n` of block `b` checked as `validate` and `program_of` check it, and its
/// rung's power taken from the rail.
pub(super) fn check_network(
    set: &InstructionSet,
    net: &NetworkJson,
    b: usize,
    n: usize,
) -> Edited<()> {
    validate_network(set, net, b, n)?;
    network_fields_one_line(net, b, n)?;
    network_instructions(set, net, b, n)?;
    if let NetworkBody::Rung { rung } = &net.body {
        let at = ElementPath::rung(b, n);
        starts_powered(set, rung, &at)?;
        if !matches!(rung, Element::Box { .. }) {
            no_box_off_power(set, rung, &at)?;
        }
    }
    Ok(())
}

/// L0013 when a box that runs without power flow (the catalog's `Flow::Always`: `ENI`,
/// `LBL`) is part of a rung: it stands alone on the rail, a network of its own.
fn no_box_off_power(set: &InstructionSet, e: &Element, at: &ElementPath) -> Edited<()> {
    let each = |list: &[Element], step: fn(usize) -> Step| {
        list.iter()
            .enumerate()
            .try_for_each(|(i, x)| no_box_off_power(set, x, &at.then(step(i))))
    };
    match e {
        Element::Series { series } => each(series, Step::Series),
        Element::Parallel { parallel } => each(parallel, Step::Parallel),
        Element::Box {
            mnemonic, inputs, ..
        } => {
            let takes_no_power = set
                .lookup(mnemonic)
                .is_some_and(|id| set.get(id).flow == Flow::Always);
            if takes_no_power {
                return Err(ModelError::new(
                    Code::Unwritable,
                    &at.to_string(),
                    format!("`{mnemonic}` runs without power flow: it stands alone on the rail, in a network of its own"),
                ));
            }
            each(inputs, Step::Input)
        }
        Element::Contact { .. } | Element::Coil { .. } => Ok(()),
    }
}

/// L0013 when an element that needs power comes first on the rail (a coil, a box the
/// catalog does not mark `Flow::Always`): its STL would say `=` with nothing loaded. A box that
/// runs without power flow (`Flow::Always`: `LBL`, `ENI`) stands on the rail.
fn starts_powered(set: &InstructionSet, e: &Element, at: &ElementPath) -> Edited<()> {
    let needs_power = |mnemonic: &str| {
        set.lookup(mnemonic)
            .map(|id| set.get(id))
            .is_some_and(|spec| spec.ladder.is_coil() || spec.flow != Flow::Always)
    };
    let unpowered = |mnemonic: &str| {
        ModelError::new(
            Code::Unwritable,
            &at.to_string(),
            format!("`{mnemonic}` needs power, but it comes first on the left rail: put a contact before it"),
        )
    };
    match e {
        Element::Series { series } => match series.first() {
            Some(first) => starts_powered(set, first, &at.then(Step::Series(0))),
            None => Ok(()),
        },
        Element::Parallel { parallel } => parallel
            .iter()
            .enumerate()
            .try_for_each(|(i, p)| starts_powered(set, p, &at.then(Step::Parallel(i)))),
        Element::Coil { coil: m, .. } | Element::Box { mnemonic: m, .. } if needs_power(m) => {
            Err(unpowered(m))
        }
        _ => Ok(()),
    }
}
