//! The program the ladder model's speed bench measures (`benches/model.rs`, made by
//! `benches/corpus_program/mod.rs` from the repository's real networks) is what the
//! bench says: it compiles with no error, holds at least 1,000 networks, most of them
//! drawn as rungs, and has the shapes of real programs (a SYMBOLS block, subroutine
//! calls, timers, counters, compares, MOVW boxes, parallel outputs, STL networks); its
//! model validates, writes, and the written program checks clean. Not timed.

#![allow(
    clippy::disallowed_macros,
    reason = "the test prints what the program holds"
)]

#[path = "../benches/corpus_program/mod.rs"]
mod corpus_program;
#[path = "../../compiler/benches/scale_program/mod.rs"]
#[allow(dead_code, reason = "only its bench target is used here")]
mod scale_program;

use gutta_catalog::{InstructionSet, LadderClass};
use gutta_compiler::source::SourceFile;
use gutta_compiler::{check_source, compile};
use gutta_ladder::json::{model_of, program_of, validate, Element, NetworkBody};
use gutta_ladder::model::{Body, BranchEnd, Rung};

/// How many of each shape the program holds.
#[derive(Debug, Default)]
struct Shapes {
    calls: usize,
    timers: usize,
    counters: usize,
    compares: usize,
    movw: usize,
    /// Rungs with two or more outputs in parallel.
    parallel_outputs: usize,
}

impl Shapes {
    fn element(&mut self, e: &Element, set: &InstructionSet) {
        match e {
            Element::Series { series: v } | Element::Parallel { parallel: v } => {
                v.iter().for_each(|e| self.element(e, set))
            }
            Element::Contact { contact, .. } => {
                let spec = set.lookup(contact).map(|id| set.get(id));
                if spec.is_some_and(|s| s.ladder == LadderClass::Compare) {
                    self.compares += 1;
                }
            }
            Element::Coil { .. } => {}
            Element::Box {
                mnemonic, inputs, ..
            } => {
                let spec = set.get(set.lookup(mnemonic).expect("a known box"));
                match spec.kind {
                    Some(kind) if kind.is_timer() => self.timers += 1,
                    Some(_) => self.counters += 1,
                    None if spec.call_arguments => self.calls += 1,
                    None if spec.mnemonic == "MOVW" => self.movw += 1,
                    None => {}
                }
                inputs.iter().for_each(|e| self.element(e, set));
            }
        }
    }
}

fn outputs(rung: &Rung) -> usize {
    fn ends(end: &BranchEnd) -> usize {
        match end {
            BranchEnd::Split(v) => v.iter().map(|b| ends(&b.end)).sum(),
            _ => 1,
        }
    }
    rung.outputs.iter().map(|b| ends(&b.end)).sum()
}

#[test]
fn the_bench_program_compiles_and_is_shaped_like_real_ones() {
    let target = scale_program::bench_target();
    let text = corpus_program::generate(1_000, &target);
    let compiled = compile(SourceFile::new("model.lad", text.as_str()), Some(&target));
    let errors: Vec<String> = compiled
        .checked
        .diagnostics()
        .iter()
        .filter(|d| d.is_error())
        .map(|d| format!("{:?}: {}", d.code, d.message))
        .collect();
    assert!(errors.is_empty(), "{errors:#?}");
    assert!(compiled.image.is_some(), "the program compiles to an image");
    assert!(text.starts_with("SYMBOLS\n"), "a SYMBOLS block");

    let checked = &compiled.checked;
    let set = &checked.target.instructions;
    assert!(
        checked.symbols().symbols.len() >= 5,
        "symbols from the corpus"
    );
    let ladder = gutta_ladder::build(checked);
    let networks: Vec<_> = ladder.blocks.iter().flat_map(|b| &b.networks).collect();
    let drawn = networks
        .iter()
        .filter(|n| matches!(n.body, Body::Rung(_)))
        .count();
    let stl = networks.len() - drawn;
    let mut shapes = Shapes::default();
    let model = model_of(checked, &ladder);
    for net in model.blocks.iter().flat_map(|b| &b.networks) {
        if let NetworkBody::Rung { rung } = &net.body {
            shapes.element(rung, set);
        }
    }
    shapes.parallel_outputs = networks
        .iter()
        .filter(|n| matches!(&n.body, Body::Rung(r) if outputs(r) >= 2))
        .count();
    println!(
        "{} networks in {} blocks: {drawn} drawn, {stl} STL; {shapes:?}",
        networks.len(),
        ladder.blocks.len()
    );
    assert!(networks.len() >= 1_000, "{} networks", networks.len());
    assert!(
        drawn * 10 >= networks.len() * 8,
        "most networks drawn: {drawn} of {}",
        networks.len()
    );
    assert!(stl >= 10, "some networks are STL: {stl}");
    assert!(ladder.blocks.len() >= 3, "subroutines besides MAIN");
    for (what, n) in [
        ("CALL boxes", shapes.calls),
        ("timers", shapes.timers),
        ("counters", shapes.counters),
        ("compares", shapes.compares),
        ("MOVW boxes", shapes.movw),
        ("rungs with parallel outputs", shapes.parallel_outputs),
    ] {
        assert!(n >= 10, "{what}: {n}");
    }

    // The model the bench writes back validates, and its program checks clean.
    validate(&model, set).expect("the model validates");
    let written = program_of(&model, set).expect("the model writes");
    let again = check_source(SourceFile::new("written.lad", written), Some(&target));
    assert!(!again.has_errors(), "{:#?}", again.diagnostics());
}
