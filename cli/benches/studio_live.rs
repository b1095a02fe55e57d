//! Issue 27's bar for simulated power flow: 20 updates a second or more. Measured here
//! in Rust through `studio::Simulator::state()`, what `GET /api/live` answers in
//! SIMULATE: one short lock of the VM to copy every drawn operand's value, then power
//! flow through `gutta_ladder::live::rung_power` for every drawn network, the values in
//! their formats, as JSON text, while the program scans every 10 ms on the simulator's
//! own thread.
//!
//! The program is the ladder model bench's program of real networks
//! (ladder/benches/corpus_program), 1,000 networks, in a project in a temporary folder
//! whose gutta.toml names the front end's bench target (compiler/benches/target), as
//! `studio_edit` makes it. Besides criterion's figure the bench prints how many states
//! one caller gets in 2 s back to back (updates per second). `cargo bench -p gutta-cli
//! --bench studio_live`; `cargo test -p gutta-cli --bench studio_live` runs it once.

#![allow(
    clippy::disallowed_macros,
    clippy::disallowed_methods,
    reason = "a bench writes its project and prints what it measured"
)]

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, Criterion};
use gutta_cli::studio::{Session, Simulator};

#[path = "studio_project/mod.rs"]
mod studio_project;

use studio_project::project;

fn bench_studio_live(c: &mut Criterion) {
    let root = project("live");
    let session = Session::open(std::slice::from_ref(&root)).expect("the project opens");
    let program = session.run_program().expect("the program compiles");
    let sim = Simulator::start(program).expect("the simulator starts");
    let start = Instant::now();
    while sim.scans() < 10 && start.elapsed() < Duration::from_secs(10) {
        std::thread::sleep(Duration::from_millis(10));
    }
    let state = sim.state();
    assert_eq!(state["run"], true, "{}", state["message"]);
    let networks = state["networks"].as_array().expect("networks").len();
    let values = state["values"].as_object().expect("values").len();
    assert!(networks >= 900, "{networks} drawn networks");

    // Updates per second: states as JSON text, back to back, for 2 s.
    let (start, mut updates, mut bytes) = (Instant::now(), 0u64, 0usize);
    while start.elapsed() < Duration::from_secs(2) {
        bytes = sim.state().to_string().len();
        updates += 1;
    }
    let per_second = updates as f64 / start.elapsed().as_secs_f64();
    println!(
        "studio_live: {networks} drawn networks, {values} operands, {bytes} bytes a state; \
         {per_second:.0} updates/s ({} scans meanwhile)",
        sim.scans()
    );

    c.bench_function("studio/live_state", |b| {
        b.iter(|| black_box(sim.state().to_string()));
    });
    drop(sim);
    let _ = std::fs::remove_dir_all(&root);
}

criterion_group!(benches, bench_studio_live);
criterion_main!(benches);
