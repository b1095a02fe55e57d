//! Issue 26's speed bar for the ladder model (docs/ladder.md, "Speed of the model"):
//! model -> STL and STL -> model for a 1,000-network program under 20 ms each.
//!
//! The program is made of the repository's real networks (`corpus_program/mod.rs`:
//! the MAIN networks of examples/, tests/data/run and tests/data/microwin with their
//! titles and comments, their symbols in one SYMBOLS block and their subroutines,
//! renamed per program, cycled until 1,000 networks; label numbers moved per copy),
//! checked on the front end's bench target (compiler/benches/target/: program limits a
//! program this size needs). `tests/corpus_program.rs` holds it to compiling with no
//! error and to its shapes, untimed.
//!
//! Each step has its own id:
//! - `stl_to_model/1000`: the program text to the JSON `Model` (parse, check, ladder
//!   build, `json::model_of`); `build_to_model/1000`: the same from the checked program
//!   (the ladder build and `model_of` only), so the split is visible;
//! - `model_to_stl/1000`: `json::program_of`, the model written as program text;
//!   `validate_write/1000`: `json::validate` then `program_of`; `check/1000`:
//!   `json::check`, what `gutta-cc ladder MODEL.json` does (validate, the program
//!   written with its source map, the compiler's whole pipeline on it, the diagnostics
//!   mapped to the model);
//! - `model_json/1000`: the model's JSON text read (`json::read_model`) and written again
//!   (`Model::to_json`); `read_model/1000` and `to_json/1000` each alone.
//!
//! `cargo bench -p gutta-ladder --bench model`; `cargo test --benches` runs each once.

#![allow(clippy::disallowed_macros, reason = "a bench prints what it measured")]

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use gutta_compiler::check_source;
use gutta_compiler::source::SourceFile;
use gutta_ladder::json::{check, model_of, program_of, read_model, validate, NetworkBody};

#[path = "corpus_program/mod.rs"]
mod corpus_program;

#[path = "../../compiler/benches/scale_program/mod.rs"]
#[allow(dead_code, reason = "only its bench target is used here")]
mod scale_program;

/// The program's size, in networks.
const NETWORKS: usize = 1_000;

fn bench_model(c: &mut Criterion) {
    let target = scale_program::bench_target();
    let text = corpus_program::generate(NETWORKS, &target);
    let checked = check_source(SourceFile::new("model.lad", text.as_str()), Some(&target));
    assert!(!checked.has_errors(), "the program checks clean");
    let set = &checked.target.instructions;
    let model = model_of(&checked, &gutta_ladder::build(&checked));
    let networks = model.blocks.iter().flat_map(|b| &b.networks);
    let drawn = networks
        .clone()
        .filter(|n| matches!(n.body, NetworkBody::Rung { .. }))
        .count();
    let total = networks.count();
    assert!(total >= NETWORKS, "{total} networks");
    let json = model.to_json();
    assert_eq!(read_model(json.as_bytes()).as_ref(), Ok(&model));
    validate(&model, set).expect("the model validates");
    let written = program_of(&model, set).expect("the model writes");
    println!(
        "model: {total} networks ({drawn} drawn), {} lines of STL, {} bytes of JSON, {} lines written",
        text.lines().count(),
        json.len(),
        written.lines().count()
    );

    c.bench_function("stl_to_model/1000", |b| {
        b.iter_batched(
            || SourceFile::new("model.lad", text.as_str()),
            |file| {
                let checked = check_source(file, Some(&target));
                black_box(model_of(&checked, &gutta_ladder::build(&checked)))
            },
            BatchSize::SmallInput,
        )
    });
    c.bench_function("build_to_model/1000", |b| {
        b.iter(|| {
            let checked = black_box(&checked);
            black_box(model_of(checked, &gutta_ladder::build(checked)))
        })
    });
    c.bench_function("model_to_stl/1000", |b| {
        b.iter(|| black_box(program_of(black_box(&model), set)))
    });
    c.bench_function("validate_write/1000", |b| {
        b.iter(|| {
            let model = black_box(&model);
            validate(model, set).expect("valid");
            black_box(program_of(model, set))
        })
    });
    c.bench_function("check/1000", |b| {
        b.iter(|| {
            let checked = check(black_box(&model), &target);
            assert!(!checked.has_errors());
            black_box(checked)
        })
    });
    c.bench_function("model_json/1000", |b| {
        b.iter(|| {
            let model = read_model(black_box(json.as_bytes())).expect("read");
            black_box(model.to_json())
        })
    });
    c.bench_function("read_model/1000", |b| {
        b.iter(|| black_box(read_model(black_box(json.as_bytes()))))
    });
    c.bench_function("to_json/1000", |b| {
        b.iter(|| black_box(black_box(&model).to_json()))
    });
}

criterion_group!(benches, bench_model);
criterion_main!(benches);
