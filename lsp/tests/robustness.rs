//! The server survives anything an editor (or a broken one) sends: a proptest plays
//! random sessions (documents from the corpus, random edits with any UTF-16 range, also
//! past the end and inside surrogate pairs, random requests at random positions,
//! malformed params, configuration and commands) through the session driver the
//! lsp_session fuzz target uses (session/mod.rs): the server never dies, answers every
//! request, answers malformed ones with an error, and never panics. A 1 MB document is
//! opened, edited and hovered (answers in bounded time; the time itself is measured
//! by lsp/benches/latency.rs, not here). Inputs the fuzzer crashed on are replayed
//! from lsp/tests/data/fuzz/.

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]

mod session;

use proptest::prelude::*;
use serde_json::json;
use session::{Op, Session, SEEDS, URI};

/// Text an edit inserts: program pieces, line ends, and characters of 2, 3 and 4 UTF-8
/// bytes (the 4-byte ones are UTF-16 surrogate pairs).
fn insert_text() -> impl Strategy<Value = String> {
    prop::collection::vec(
        prop_oneof![
            Just("LD     SM0.5\n".to_string()),
            Just("=      Q0.0".to_string()),
            Just("NETWORK 9 //".to_string()),
            Just("END_ORGANIZATION_BLOCK".to_string()),
            Just("\r\n".to_string()),
            Just("\n".to_string()),
            Just("😀".to_string()),
            Just("日本".to_string()),
            Just("ü".to_string()),
            "[ -~]{0,6}",
        ],
        0..4,
    )
    .prop_map(|parts| parts.concat())
}

fn op() -> impl Strategy<Value = Op> {
    let position = || (0u32..40, 0u32..90);
    prop_oneof![
        1 => (0usize..SEEDS.len()).prop_map(|seed| Op::Open { seed }),
        6 => (position(), position(), insert_text()).prop_map(|((l0, c0), (l1, c1), text)| {
            Op::Edit { range: [l0, c0, l1, c1], text }
        }),
        1 => insert_text().prop_map(|text| Op::Replace { text }),
        1 => Just(Op::Close),
        8 => (any::<usize>(), position(), position())
            .prop_map(|(request, (l0, c0), (l1, c1))| Op::Ask { request, at: [l0, c0], end: [l1, c1] }),
        2 => (any::<usize>(), any::<usize>())
            .prop_map(|(request, params)| Op::Malformed { request, params }),
        1 => any::<bool>().prop_map(|live| Op::Configure { live }),
        1 => Just(Op::Toggle),
        1 => Just(Op::Noise),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 40, ..ProptestConfig::default() })]

    #[test]
    fn random_sessions_never_break_the_server(ops in prop::collection::vec(op(), 1..40)) {
        session::run(&ops);
    }
}

#[test]
fn every_malformed_request_of_every_method_is_an_error() {
    let ops: Vec<Op> = (0..40)
        .flat_map(|request| (0..5).map(move |params| Op::Malformed { request, params }))
        .collect();
    session::run(&ops);
}

#[test]
fn positions_far_outside_the_text_are_answered() {
    let far = [u32::MAX, u32::MAX];
    let ops: Vec<Op> = (0..40)
        .map(|request| Op::Ask {
            request,
            at: far,
            end: [0, 0],
        })
        .chain([Op::Edit {
            range: [u32::MAX, 0, 0, u32::MAX],
            text: "x".into(),
        }])
        .chain((0..40).map(|request| Op::Ask {
            request,
            at: [3, 9],
            end: far,
        }))
        .collect();
    session::run(&ops);
}

/// 1 MB of program: the seed's main block repeated.
fn megabyte() -> String {
    let mut text = String::from("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n");
    let mut n = 0;
    while text.len() < 1 << 20 {
        n += 1;
        text.push_str(&format!("NETWORK {n} // step {n}\nLD     I0.{}\nAN     M{}.{}\n=      Q0.{}\nMOVW   {n}, MW{}\n", n % 8, n % 100, n % 8, n % 8, 2 * (n % 200)));
    }
    text.push_str("END_ORGANIZATION_BLOCK\n");
    text
}

#[test]
fn a_megabyte_document_opens_edits_and_hovers() {
    let text = megabyte();
    let mut s = Session::start(json!({}));
    s.open(&text);
    s.play(&Op::Edit {
        range: [1000, 0, 1000, 0],
        text: "LD     I0.1\n".into(),
    });
    for line in [2u32, 5_000, 40_000] {
        // Served or not (MethodNotFound), every hover is answered without a panic.
        s.request(
            "textDocument/hover",
            json!({"textDocument": {"uri": URI}, "position": {"line": line, "character": 8}}),
        );
    }
    let hints = s.request(
        "textDocument/inlayHint",
        json!({"textDocument": {"uri": URI},
               "range": {"start": {"line": 0, "character": 0}, "end": {"line": 60_000, "character": 0}}}),
    );
    let live: Vec<&serde_json::Value> = hints
        .result
        .as_ref()
        .and_then(|r| r.as_array())
        .expect("an inlay hint list")
        .iter()
        .filter(|h| h["label"].as_str().is_some_and(|l| l.starts_with(" = ")))
        .collect();
    assert!(live.is_empty(), "live values are off: {live:?}");
    s.finish();
}

#[test]
fn fuzz_regressions_replay() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fuzz");
    let mut replayed = 0;
    for entry in std::fs::read_dir(&dir)
        .expect("lsp/tests/data/fuzz")
        .flatten()
    {
        let bytes = std::fs::read(entry.path()).expect("a regression input");
        session::run(&session::ops_from_bytes(&bytes));
        replayed += 1;
    }
    assert!(replayed > 0, "no inputs in {}", dir.display());
}
