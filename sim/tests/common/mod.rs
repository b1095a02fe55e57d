//! Shared by the simulator's tests: compile a program for CPU-EC20.

use gutta_catalog::stdlib;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};
use gutta_format::Image;

/// `text` compiled for CPU-EC20 (it must compile).
pub fn image(name: &str, text: &str) -> Image {
    let target = stdlib::shared("CPU-EC20").expect("target");
    let c = compile(
        SourceFile::new(name, text),
        Some(&ExplicitTarget {
            target,
            origin: "test".into(),
        }),
    );
    c.image
        .unwrap_or_else(|| panic!("{name} does not compile: {:?}", c.checked.diagnostics()))
}
