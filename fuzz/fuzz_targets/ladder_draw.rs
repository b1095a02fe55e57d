//! Fuzz target of the drawing and the live evaluation (docs/ladder.md, "Drawing" and
//! "Live view"): arbitrary bytes as a program (lossily decoded; the first eight bytes
//! also seed the values) checked on the default target and built into a ladder, drawn
//! as SVG with LAD and STL names, with and without symbol information (comment wrapping,
//! CJK widths, system names, pins), then every network evaluated on one snapshot whose
//! values come from the seed: a rung's power flow, a network shown as STL its status
//! per line. It must never panic; every drawing is balanced XML (each `<g` and `<text`
//! closed) and the same ladder draws the same bytes twice; an STL status has one entry
//! per STL line at most, each naming a line of the network.
#![no_main]

use std::collections::BTreeMap;
use std::sync::OnceLock;

use gutta_catalog::stdlib;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{check_source, ExplicitTarget};
use gutta_format::SymbolTable;
use gutta_ladder::live::{operands, rung_power, stl_status, Snapshot};
use gutta_ladder::model::Body;
use gutta_ladder::svg::{ladder_svg_with, DrawOptions, Names};
use libfuzzer_sys::fuzz_target;

/// The default target, loaded once.
fn default_target() -> &'static ExplicitTarget {
    static TARGET: OnceLock<ExplicitTarget> = OnceLock::new();
    TARGET.get_or_init(|| ExplicitTarget {
        target: stdlib::shared(stdlib::DEFAULT).expect("the embedded default target loads"),
        origin: "the fuzzer".to_string(),
    })
}

fn balanced(svg: &str) {
    let opened = svg.matches("<g ").count() + svg.matches("<g>").count();
    assert_eq!(opened, svg.matches("</g>").count(), "every <g> closed");
    assert_eq!(
        svg.matches("<text ").count(),
        svg.matches("</text>").count(),
        "every <text> closed"
    );
    assert!(svg.ends_with("</svg>\n"));
}

fuzz_target!(|data: &[u8]| {
    let (seed, _) = data.split_at(data.len().min(8));
    let mut state = seed.iter().fold(0x9E37_79B9_7F4A_7C15u64, |s, b| {
        s.rotate_left(8) ^ u64::from(*b)
    }) | 1;
    let text = String::from_utf8_lossy(data).into_owned();
    let target = default_target();
    let checked = check_source(SourceFile::new("fuzz.lad", text), Some(target));
    let ladder = gutta_ladder::build(&checked);
    for names in [Names::Lad, Names::Stl] {
        for symbol_info in [false, true] {
            let options = DrawOptions { names, symbol_info };
            let svg = ladder_svg_with(&ladder, &options);
            balanced(&svg);
            assert_eq!(svg, ladder_svg_with(&ladder, &options), "same bytes twice");
        }
    }
    let symbols = SymbolTable::default();
    let mut values = BTreeMap::new();
    for address in operands(&ladder, &target.target, &symbols) {
        // xorshift64: every operand its own value, from the seed.
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        values.insert(address, state as u32);
    }
    let snapshot = Snapshot {
        target: &target.target,
        symbols: &symbols,
        values: &values,
    };
    for block in &ladder.blocks {
        for net in &block.networks {
            match &net.body {
                Body::Rung(rung) => {
                    rung_power(rung, &snapshot);
                }
                Body::Stl { .. } => {
                    let lines = stl_status(&net.stl_code, &snapshot);
                    assert!(lines.len() <= net.stl.len().max(net.stl_code.len()));
                    for line in &lines {
                        assert!(
                            line.index < net.stl.len(),
                            "line {} of {}",
                            line.index,
                            net.stl.len()
                        );
                    }
                }
            }
        }
    }
});
