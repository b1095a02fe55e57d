//! Micro/WIN's system symbols (`Always_On`, `Clock_1s`): the target's data names them
//! (`SystemBit MicroWin=`, `MemoryMap::microwin_system_bit`); and MicroWIN SMART's
//! default I/O names (`CPU_输入0`, `CPU_Output3`), one per bit of the target's I and Q
//! areas by the catalog's rule (`gutta_catalog::s7200_io`). This stage hands them to
//! the checker as predefined names (plain data) and warns (W0206) where a user symbol
//! takes one of them for another address, as in Micro/WIN the user's symbol wins.

use gutta_catalog::s7200_io::{smart_io_name, smart_io_names, SmartIoName};
use gutta_catalog::Target;

use crate::check::PredefinedName;
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;
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
        .chain(
            smart_io_names(&target.memory)
                .into_iter()
                .map(|(name, a)| PredefinedName {
                    name,
                    address: Some(a),
                }),
        )
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
            if let Some(io) = smart_io_name(name) {
                return smart_io_shadowed(s.name, name, io, text.get(s.address.range())?, target);
            }
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

/// W0206 for a user symbol named like SMART's default I/O name of a bit the target has,
/// declared at another address; a symbol table that repeats SMART's own I/O table (the
/// same bit) hides nothing and says nothing.
fn smart_io_shadowed(
    span: Span,
    name: &str,
    io: SmartIoName,
    declared: &str,
    target: &Target,
) -> Option<Diagnostic> {
    let memory = &target.memory;
    let bit = io.address(memory).ok()?;
    if memory.parse_address(declared.trim()).ok() == Some(bit) {
        return None;
    }
    let here = memory.format_address(&bit);
    Some(
        Diagnostic::new(
            Code::SystemNameShadowed,
            span,
            format!("symbol `{name}` hides MicroWIN SMART's default symbol for {here}"),
        )
        .label("this symbol is used")
        .help(format!(
            "rename it to use {here} under this name, or keep it on purpose"
        )),
    )
}
