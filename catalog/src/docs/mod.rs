//! Reference pages generated from the catalog's tables: the instruction reference
//! (`docs/instructions.md`) and the stdlib PLC types (`docs/targets.md`). Pure text: no
//! I/O, and each output depends only on the tables it is given, so a test can compare
//! the checked-in file with a fresh rendering.

mod instructions;
mod targets;

pub use instructions::instruction_reference;
pub use targets::target_reference;

fn yes_no(b: bool) -> &'static str {
    if b {
        "yes"
    } else {
        "no"
    }
}

/// Escape the one character that breaks a table cell.
fn cell(text: &str) -> String {
    text.replace('|', "\\|")
}
