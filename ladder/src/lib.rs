//! Ladder diagrams of GUTTA programs (docs/ladder.md): `model.rs` (the rung model),
//! `build.rs` (a checked program's networks into rungs, or the reason one is not a
//! rung), `layout.rs` (where each element and wire goes), `svg.rs` (the SVG), `symbol_info.rs`
//! (the symbol table under a rung), `html.rs`
//! (the self-contained page), `live.rs` (the live view's power flow from a snapshot of
//! the operands), `names.rs` (LAD or STL labels, and the pins of a box's operands),
//! `write.rs` (a rung back into canonical STL), `json/` (the model as JSON: written,
//! read back and validated with coded errors). No I/O: `gutta-cc ladder`
//! reads the program and writes the file; `gutta-cc monitor` reads the PLC.

pub mod build;
pub mod edit;
pub mod html;
pub mod json;
pub mod layout;
pub mod live;
pub mod model;
pub mod names;
pub mod svg;
pub mod symbol_info;
pub mod write;

pub use build::build;
