//! Issue 27's bars for the studio's page in Chromium, on a 1,000-network program: the
//! page interactive within 1 s (from navigation start until `page.js` has made the
//! toolbar's commands work), and an edit to its redrawn rung with diagnostics within
//! 50 ms (p95), both measured in the browser with `performance.now()`.
//!
//! The program is the ladder model bench's program of real networks
//! (ladder/benches/corpus_program), 1,000 networks, in a project in a temporary folder
//! whose gutta.toml names the front end's bench target (compiler/benches/target). The
//! real `gutta-cc studio` serves it; `studio_page.py` beside this file drives Debian's
//! Chromium with Playwright (`$GUTTA_PYTHON`, the .ci venv's Python; `chromium` on
//! PATH or `$GUTTA_CHROMIUM`): 5 page loads, then 50 edits through the page's own
//! `guttaStudio.edit` (the first contact of the drawn network nearest the middle of
//! MAIN toggled NO/NC), each timed until the answer is in place and the next frame
//! drawn. Last, the program simulated: the live updates the page paints per second
//! (power flow, values and the status bar from `/api/live`; bar 20 a second), counted by
//! the page over 3 s. `cargo bench -p gutta-cli --bench studio_page`.

#![allow(
    clippy::disallowed_macros,
    clippy::disallowed_methods,
    reason = "a bench writes its project, runs the studio and prints what it measured"
)]

use std::process::Command;

#[path = "studio_project/mod.rs"]
mod studio_project;

/// The tests' real-studio helper: started on a folder, killed when dropped.
#[allow(
    dead_code,
    reason = "the bench only starts it; the tests also call its routes"
)]
#[path = "../tests/common/studio.rs"]
mod studio;

use studio_project::project;

fn quantile(sorted: &[f64], q: f64) -> f64 {
    let i = ((sorted.len() as f64 - 1.0) * q).round() as usize;
    sorted[i.min(sorted.len() - 1)]
}

fn main() {
    // `cargo test --benches` runs benches with --bench absent: nothing to measure then.
    if !std::env::args().any(|a| a == "--bench") {
        return;
    }
    let python = std::env::var("GUTTA_PYTHON").unwrap_or_else(|_| {
        panic!("GUTTA_PYTHON must name a Python with playwright (the .ci venv's)")
    });
    let root = project("page");
    let studio = studio::Studio::start(&root);
    let url = format!("http://{}/?token={}", studio.address, studio.token);
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/benches/studio_page.py");
    let out = Command::new(&python)
        .arg(script)
        .arg(&url)
        .output()
        .expect("the page bench's script runs");
    drop(studio);
    let _ = std::fs::remove_dir_all(&root);
    assert!(
        out.status.success(),
        "studio_page.py failed:\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let figures: serde_json::Value =
        serde_json::from_slice(&out.stdout).expect("the script's JSON");
    let list = |key: &str| -> Vec<f64> {
        let mut v: Vec<f64> = figures[key]
            .as_array()
            .expect(key)
            .iter()
            .filter_map(|x| x.as_f64())
            .collect();
        v.sort_by(f64::total_cmp);
        v
    };
    let (load, edit, server) = (list("load_ms"), list("edit_ms"), list("server_ms"));
    let page = list("page_ms");
    println!(
        "studio_page: {} networks drawn, {} bytes of page",
        figures["networks"], figures["bytes"]
    );
    println!(
        "studio_page/load (navigation to interactive): median {:.0} ms, max {:.0} ms over {} loads (bar 1000 ms)",
        quantile(&load, 0.5),
        quantile(&load, 1.0),
        load.len()
    );
    println!(
        "studio_page/edit (edit to redrawn rung with diagnostics): median {:.1} ms, p95 {:.1} ms over {} edits (bar 50 ms p95)",
        quantile(&edit, 0.5),
        quantile(&edit, 0.95),
        edit.len()
    );
    println!(
        "studio_page/edit-request (the server's part: request to JSON read): median {:.1} ms, p95 {:.1} ms; {} bytes an answer",
        quantile(&server, 0.5),
        quantile(&server, 0.95),
        figures["answer_bytes"]
    );
    println!(
        "studio_page/live (simulated power flow painted in the page): {:.1} updates/s (bar 20)",
        figures["live_per_s"].as_f64().unwrap_or(0.0)
    );
    if !page.is_empty() {
        println!(
            "studio_page/edit-page (the page's part: answer received to drawing and diagnostics in place): median {:.1} ms, p95 {:.1} ms",
            quantile(&page, 0.5),
            quantile(&page, 0.95)
        );
    }
}
