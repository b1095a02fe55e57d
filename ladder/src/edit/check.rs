//! What an edited network must pass before the edit is kept: `json::validate`'s and
//! `json::program_of`'s checks of one network (the same functions, not a copy; the
//! power rules STL needs, L0013, are among validate's, in `json/power.rs`).

use gutta_catalog::InstructionSet;

use crate::json::{
    network_fields_one_line, network_instructions, validate_network, ModelError, NetworkJson,
};

type Edited<T> = Result<T, ModelError>;

/// Network `n` of block `b` checked as `validate` and `program_of` check it.
pub(super) fn check_network(
    set: &InstructionSet,
    net: &NetworkJson,
    b: usize,
    n: usize,
) -> Edited<()> {
    validate_network(set, net, b, n)?;
    network_fields_one_line(net, b, n)?;
    network_instructions(set, net, b, n)?;
    Ok(())
}
