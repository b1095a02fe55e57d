//! Micro/WIN's system symbols (`Always_On`, `Clock_1s`): the target's data names them
//! (`SystemBit MicroWin=`, `MemoryMap::microwin_system_bit`). This stage hands them to
//! the checker as predefined names (plain data) and warns (W0206) where a user symbol
//! takes one of them, as in Micro/WIN the user's symbol wins.

use gutta_catalog::Target;

use crate::check::PredefinedName;
use crate::diagnostics::{Code, Diagnostic};
use crate::syntax::ast::Program;

/// The target's Micro/WIN system symbols, in its order, with the address each stands
/// for (None when the target's address does not parse: the name is still offered as a
/// suggestion, but resolves to nothing).
pub(super) fn system_names(target: &Target) -> Vec<PredefinedName> {
    target
        .memory
        .system_bits
        .iter()
        .filter_map(|b| {
            Some(PredefinedName {
                name: b.microwin.clone()?,
                address: target.memory.parse_address(&b.address).ok(),
            })
        })
        .collect()
}

/// W0206 for every user symbol (SYMBOLS block or symbol table) named like one of the
/// target's Micro/WIN system symbols: the user's symbol wins, as in Micro/WIN.
pub(super) fn shadowed_system_names(
    program: &Program,
    text: &str,
    target: &Target,
) -> Vec<Diagnostic> {
    program
        .symbols
        .iter()
        .filter_map(|s| {
            let name = text.get(s.name.range())?;
            let bit = target.memory.microwin_system_bit(name)?;
            Some(
                Diagnostic::new(
                    Code::SystemNameShadowed,
                    s.name,
                    format!(
                        "symbol `{name}` hides Micro/WIN's system symbol for {}",
                        bit.address
                    ),
                )
                .label("this symbol is used")
                .help(format!(
                    "rename it to use {} under this name, or keep it on purpose",
                    bit.address
                )),
            )
        })
        .collect()
}
