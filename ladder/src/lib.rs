//! Ladder diagrams of GUTTA programs (docs/ladder.md): `model.rs` (the rung model),
//! `build.rs` (a checked program's networks into rungs, or the reason one is not a
//! rung), `svg.rs` (layout and SVG), `html.rs` (the self-contained page). No I/O:
//! `gutta-cc ladder` reads the program and writes the file.

pub mod build;
pub mod live;
pub mod model;

pub use build::build;
