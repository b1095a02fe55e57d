//! The waveform `gutta-vm --vcd` writes: one signal per --read variable, named after
//! its symbol (or address), in the variable's format (`gutta_vm::vcd` writes the text).

use gutta_vm::vcd::{Dump, Signal};

use gutta_cli::vars::Var;

/// The dump of `reads`, starting at their `initial` values.
pub fn dump(reads: &[Var], initial: &[u32]) -> Dump {
    let signals = reads
        .iter()
        .map(|v| Signal::of(v.name(), v.address.width, v.format))
        .collect();
    Dump::new(
        concat!("gutta-vm ", env!("CARGO_PKG_VERSION")),
        signals,
        initial,
    )
}
