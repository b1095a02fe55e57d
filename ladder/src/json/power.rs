//! The power rules a rung needs so that its STL means what it draws (L0013), beyond the
//! shapes `validate.rs` checks:
//! - nothing that needs power first on the left rail (its STL would say `=` with
//!   nothing loaded);
//! - no outputs in parallel straight from the rail (separate rungs, which one network's
//!   STL cannot say as one);
//! - no box that runs without power flow (`ENI`, `LBL`) inside a rung;
//! - no element that acts on the power it is given (a box, `NOT`, `EU`, `ED`) inside a
//!   parallel of paths that comes after other elements in series. STL loads such a
//!   parallel as a path of its own from the rail and ANDs it on (`ALD`), so the box
//!   would take its power without what stands before the parallel, while the drawing
//!   feeds it through them (the builder's rule, docs/ladder.md "Which networks are
//!   ladder").
//!
//! What an instruction is comes from the catalog (`Flow`, `LadderClass`,
//! `power_output`), never from its mnemonic.

use gutta_catalog::{Flow, InstructionSet, LadderClass};

use super::codes::{ModelError, ModelErrorCode as Code};
use super::Element;

type Check<T> = Result<T, ModelError>;

/// The rung at `path` (already valid in shape) against the power rules.
pub(super) fn rules(set: &InstructionSet, rung: &Element, path: &str) -> Check<()> {
    if matches!(rung, Element::Parallel { .. }) && ends(set, rung) {
        return Err(ModelError::new(
            Code::Unwritable,
            path,
            "outputs in parallel straight from the left rail are separate rungs: start the rung with a contact before the parallel, or put each output in a network of its own",
        ));
    }
    starts_powered(set, rung, path)?;
    if !matches!(rung, Element::Box { .. }) {
        no_box_off_power(set, rung, path)?;
    }
    fed(set, rung, path, false, true)
}

/// L0013 when an element that needs power comes first on the rail (a coil, a box the
/// catalog does not mark `Flow::Always`). A box that runs without power flow (`LBL`,
/// `ENI`) stands on the rail.
fn starts_powered(set: &InstructionSet, e: &Element, path: &str) -> Check<()> {
    let needs_power = |mnemonic: &str| {
        set.lookup(mnemonic)
            .map(|id| set.get(id))
            .is_some_and(|spec| spec.ladder.is_coil() || spec.flow != Flow::Always)
    };
    match e {
        Element::Series { series } => match series.first() {
            Some(first) => starts_powered(set, first, &format!("{path}.series[0]")),
            None => Ok(()),
        },
        Element::Parallel { parallel } => parallel
            .iter()
            .enumerate()
            .try_for_each(|(i, p)| starts_powered(set, p, &format!("{path}.parallel[{i}]"))),
        Element::Coil { coil: m, .. } | Element::Box { mnemonic: m, .. } if needs_power(m) => {
            Err(ModelError::new(
                Code::Unwritable,
                path,
                format!(
                    "`{m}` needs power, but it comes first on the left rail: put a contact before it"
                ),
            ))
        }
        _ => Ok(()),
    }
}

/// L0013 when a box that runs without power flow (the catalog's `Flow::Always`: `ENI`,
/// `LBL`) is part of a rung: it stands alone on the rail, a network of its own.
fn no_box_off_power(set: &InstructionSet, e: &Element, path: &str) -> Check<()> {
    match e {
        Element::Series { series } => series
            .iter()
            .enumerate()
            .try_for_each(|(i, x)| no_box_off_power(set, x, &format!("{path}.series[{i}]"))),
        Element::Parallel { parallel } => parallel
            .iter()
            .enumerate()
            .try_for_each(|(i, x)| no_box_off_power(set, x, &format!("{path}.parallel[{i}]"))),
        Element::Box {
            mnemonic, inputs, ..
        } => {
            let takes_no_power = set
                .lookup(mnemonic)
                .is_some_and(|id| set.get(id).flow == Flow::Always);
            if takes_no_power {
                return Err(ModelError::new(
                    Code::Unwritable,
                    path,
                    format!("`{mnemonic}` runs without power flow: it stands alone on the rail, in a network of its own"),
                ));
            }
            inputs
                .iter()
                .enumerate()
                .try_for_each(|(i, x)| no_box_off_power(set, x, &format!("{path}.inputs[{i}]")))
        }
        Element::Contact { .. } | Element::Coil { .. } => Ok(()),
    }
}

/// L0013 when a parallel of paths whose power comes from elements before it (`is_fed`)
/// holds an element that acts on its power. A series passes its power on to its first
/// element and feeds the others; outputs in parallel are fed (STL copies the power with
/// `LPS`); a box's extra power inputs start at the rail. `at_end`: nothing follows `e`
/// in series, so a parallel of box-ended paths there is outputs; followed by more, it
/// is a path the power goes on through.
fn fed(set: &InstructionSet, e: &Element, path: &str, is_fed: bool, at_end: bool) -> Check<()> {
    match e {
        Element::Series { series } => series.iter().enumerate().try_for_each(|(i, x)| {
            let last = i + 1 == series.len();
            fed(
                set,
                x,
                &format!("{path}.series[{i}]"),
                is_fed || i > 0,
                at_end && last,
            )
        }),
        Element::Parallel { parallel } => {
            let outputs = parallel.iter().any(|x| ends_for_good(set, x))
                || (at_end && parallel.iter().all(|x| ends(set, x)));
            for (i, x) in parallel.iter().enumerate() {
                let at = format!("{path}.parallel[{i}]");
                if is_fed && !outputs {
                    if let Some((acting, mnemonic)) = acting_within(set, x, &at) {
                        return Err(ModelError::new(
                            Code::Unwritable,
                            &acting,
                            format!(
                                "`{mnemonic}` is in a parallel path that comes after other elements in series: STL loads that path from the rail and ANDs it on (`ALD`), so `{mnemonic}` would not take its power through what comes before; put it after the parallel, or start the rung with the parallel"
                            ),
                        ));
                    }
                }
                fed(set, x, &at, is_fed || outputs, outputs)?;
            }
            Ok(())
        }
        Element::Box { inputs, .. } => inputs
            .iter()
            .enumerate()
            .try_for_each(|(i, x)| fed(set, x, &format!("{path}.inputs[{i}]"), false, false)),
        Element::Contact { .. } | Element::Coil { .. } => Ok(()),
    }
}

/// Whether `e` is an output, or outputs: a coil, a box, a series ending in one, a
/// parallel with an output branch or of boxes only (`validate.rs`'s `Ends` and
/// `Either`), as opposed to a path that passes power on.
fn ends(set: &InstructionSet, e: &Element) -> bool {
    match e {
        Element::Coil { .. } | Element::Box { .. } => true,
        Element::Series { series } => series.last().is_some_and(|x| ends(set, x)),
        Element::Parallel { parallel } => {
            parallel.iter().any(|x| ends_for_good(set, x)) || parallel.iter().all(|x| ends(set, x))
        }
        Element::Contact { .. } => false,
    }
}

/// Whether `e` ends the power path for good (`validate.rs`'s `Ends`): a coil, a box
/// without power output, a series ending in one, a parallel with such a branch.
fn ends_for_good(set: &InstructionSet, e: &Element) -> bool {
    match e {
        Element::Coil { .. } => true,
        Element::Box { mnemonic, .. } => set
            .lookup(mnemonic)
            .is_some_and(|id| set.get(id).power_output.is_none()),
        Element::Series { series } => series.last().is_some_and(|x| ends_for_good(set, x)),
        Element::Parallel { parallel } => parallel.iter().any(|x| ends_for_good(set, x)),
        Element::Contact { .. } => false,
    }
}

/// The path and mnemonic of the first element in `e` (a box's inputs aside: they start
/// at the rail) that acts on the power it is given: a box, or a contact of the
/// catalog's `Not`, `RisingEdge` or `FallingEdge` class.
fn acting_within(set: &InstructionSet, e: &Element, path: &str) -> Option<(String, String)> {
    match e {
        Element::Series { series } => series
            .iter()
            .enumerate()
            .find_map(|(i, x)| acting_within(set, x, &format!("{path}.series[{i}]"))),
        Element::Parallel { parallel } => parallel
            .iter()
            .enumerate()
            .find_map(|(i, x)| acting_within(set, x, &format!("{path}.parallel[{i}]"))),
        Element::Box { mnemonic, .. } => Some((path.to_string(), mnemonic.clone())),
        Element::Contact { contact, .. } => {
            let class = set.lookup(contact).map(|id| set.get(id).ladder);
            matches!(
                class,
                Some(LadderClass::Not | LadderClass::RisingEdge | LadderClass::FallingEdge)
            )
            .then(|| (path.to_string(), contact.clone()))
        }
        Element::Coil { .. } => None,
    }
}
