//! A scripted editor session against the in-process server, shared by the robustness
//! proptest (lsp/tests/robustness.rs) and the cargo-fuzz target
//! (fuzz/fuzz_targets/lsp_session.rs, through `#[path]`): `Op`s (open, edits with any
//! UTF-16 range, requests at any position, malformed requests, configuration and
//! commands) decoded from bytes or generated, played by `play`, which panics when the
//! server breaks a rule: it must never die, answer every request exactly once (in
//! bounded time), and answer a malformed request with an LSP error. No timing bars
//! here: speed is the benchmark's (lsp/benches/latency.rs).

#![allow(dead_code)]

use std::thread::JoinHandle;
use std::time::Duration;

use lsp_server::{Connection, Message, Notification, Request, RequestId, Response};
use serde_json::{json, Value};

/// How long one answer may take before the session calls the server hung. Generous:
/// a debug build on a loaded 2-core machine, with a 1 MB document.
pub const ANSWER_WITHIN: Duration = Duration::from_secs(60);

/// Documents the sessions start from: an example, corpus files (CRLF line ends, labels
/// and jumps, locals and calls), a text with CJK, emoji (UTF-16 surrogate pairs) and a
/// BOM, and nothing.
pub const SEEDS: &[&str] = &[
    include_str!("../../../examples/blink.lad"),
    include_str!("../../../tests/data/check/ok/crlf.lad"),
    include_str!("../../../tests/data/check/ok/jumps_and_labels.lad"),
    include_str!("../../../tests/data/check/ok/locals_and_calls.lad"),
    "\u{feff}// 日本語 😀 ü\nSYMBOLS\n  Größe : MW20 // 😀😀\nEND_SYMBOLS\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1 // 🚦\nLD SM0.5\n= Q0.0\nEND_ORGANIZATION_BLOCK\n",
    "",
];

/// What a request's params are built from.
#[derive(Debug, Clone, Copy)]
enum Shape {
    Position,
    Range,
    Document,
    Query,
}

/// Requests an editor sends about a document (served or not: unserved ones must get
/// MethodNotFound, never silence).
const REQUESTS: &[(&str, Shape)] = &[
    ("textDocument/hover", Shape::Position),
    ("textDocument/definition", Shape::Position),
    ("textDocument/references", Shape::Position),
    ("textDocument/documentHighlight", Shape::Position),
    ("textDocument/completion", Shape::Position),
    ("textDocument/signatureHelp", Shape::Position),
    ("textDocument/prepareRename", Shape::Position),
    ("textDocument/rename", Shape::Position),
    ("textDocument/inlayHint", Shape::Range),
    ("textDocument/inlineValue", Shape::Range),
    ("textDocument/semanticTokens/range", Shape::Range),
    ("textDocument/rangeFormatting", Shape::Range),
    ("textDocument/codeAction", Shape::Range),
    ("textDocument/documentSymbol", Shape::Document),
    ("textDocument/foldingRange", Shape::Document),
    ("textDocument/formatting", Shape::Document),
    ("textDocument/semanticTokens/full", Shape::Document),
    ("workspace/symbol", Shape::Query),
];

/// One step of a session.
#[derive(Debug, Clone)]
pub enum Op {
    /// Open (or reopen) the document with a seed's text.
    Open {
        seed: usize,
    },
    /// Replace `range` (UTF-16 line/character, maybe outside the text) with `text`.
    Edit {
        range: [u32; 4],
        text: String,
    },
    /// Replace the whole text.
    Replace {
        text: String,
    },
    Close,
    /// A request at a position (ranges start there and end at `end`).
    Ask {
        request: usize,
        at: [u32; 2],
        end: [u32; 2],
    },
    /// A request whose params do not fit its method: it must answer an error.
    Malformed {
        request: usize,
        params: usize,
    },
    /// Live values on or off by configuration, or toggled by the command.
    Configure {
        live: bool,
    },
    Toggle,
    /// A notification nobody serves, and a cancel of a request that never was.
    Noise,
}

/// The JSON-RPC code of an internal error: the server's answer to a panic.
const INTERNAL_ERROR: i32 = -32603;

/// The document every session edits (no gutta.toml above it).
pub const URI: &str = "file:///gutta-lsp-session/doc.lad";

fn malformed(kind: usize) -> Value {
    match kind % 5 {
        0 => Value::Null,
        1 => json!(17),
        2 => json!("text"),
        3 => json!({"textDocument": 5, "position": "here"}),
        _ => json!([{"uri": URI}]),
    }
}

/// Reads ops off fuzz bytes: each takes its bytes or ends the session.
pub fn ops_from_bytes(mut data: &[u8]) -> Vec<Op> {
    let mut ops = Vec::new();
    let mut next = |n: usize| -> Option<Vec<u8>> {
        if data.len() < n {
            return None;
        }
        let (head, rest) = data.split_at(n);
        data = rest;
        Some(head.to_vec())
    };
    while let Some(kind) = next(1) {
        let op = match kind[0] % 9 {
            0 => Op::Open {
                seed: usize::from(next(1).map_or(0, |b| b[0])),
            },
            1 => {
                let Some(h) = next(5) else { break };
                let text = next(usize::from(h[4] % 24)).unwrap_or_default();
                Op::Edit {
                    range: [h[0], h[1], h[2], h[3]].map(u32::from),
                    text: String::from_utf8_lossy(&text).into_owned(),
                }
            }
            2 => {
                let Some(n) = next(1) else { break };
                let text = next(usize::from(n[0])).unwrap_or_default();
                Op::Replace {
                    text: String::from_utf8_lossy(&text).into_owned(),
                }
            }
            3 => Op::Close,
            4 | 5 => {
                let Some(b) = next(5) else { break };
                Op::Ask {
                    request: usize::from(b[0]),
                    at: [u32::from(b[1]), u32::from(b[2])],
                    end: [u32::from(b[3]), u32::from(b[4])],
                }
            }
            6 => {
                let Some(b) = next(2) else { break };
                Op::Malformed {
                    request: usize::from(b[0]),
                    params: usize::from(b[1]),
                }
            }
            7 => Op::Configure {
                live: next(1).is_some_and(|b| b[0] & 1 == 1),
            },
            _ => {
                if next(1).is_some_and(|b| b[0] & 1 == 1) {
                    Op::Toggle
                } else {
                    Op::Noise
                }
            }
        };
        ops.push(op);
    }
    ops
}

/// A running server and the client end of its connection.
pub struct Session {
    pub client: Connection,
    /// The methods of the requests the server sent (refreshes), in order.
    pub server_requests: Vec<String>,
    /// The notifications the server sent, in order.
    pub notifications: Vec<Notification>,
    server: Option<JoinHandle<Result<(), String>>>,
    next_id: i32,
    version: i32,
    open: bool,
}

impl Session {
    /// A server on a thread, initialized with `options` as initializationOptions.
    pub fn start(options: Value) -> Session {
        let (server, client) = Connection::memory();
        let handle = std::thread::spawn(move || gutta_lsp::serve(&server));
        let mut session = Session {
            client,
            server_requests: Vec::new(),
            notifications: Vec::new(),
            server: Some(handle),
            next_id: 0,
            version: 0,
            open: false,
        };
        let init = json!({
            "processId": null,
            "rootUri": null,
            "capabilities": {
                "workspace": {
                    "inlayHint": {"refreshSupport": true},
                    "inlineValue": {"refreshSupport": true},
                    "configuration": false
                }
            },
            "initializationOptions": options
        });
        let answer = session.request("initialize", init);
        assert!(answer.error.is_none(), "initialize: {answer:?}");
        session.notify("initialized", json!({}));
        session
    }

    pub fn notify(&self, method: &str, params: Value) {
        let n = Notification::new(method.to_string(), params);
        self.client
            .sender
            .send(Message::Notification(n))
            .unwrap_or_else(|e| panic!("the server is gone (sending {method}): {e}"));
    }

    /// Send a request and wait for its answer; the server's own requests (refreshes)
    /// get a null result, its notifications are dropped.
    pub fn request(&mut self, method: &str, params: Value) -> Response {
        self.next_id += 1;
        let id = RequestId::from(self.next_id);
        let r = Request::new(id.clone(), method.to_string(), params);
        self.client
            .sender
            .send(Message::Request(r))
            .unwrap_or_else(|e| panic!("the server is gone (sending {method}): {e}"));
        loop {
            match self.client.receiver.recv_timeout(ANSWER_WITHIN) {
                Ok(Message::Response(response)) => {
                    assert_eq!(response.id, id, "an answer to another request ({method})");
                    // The server answers a handler's panic with InternalError, and only then.
                    let panicked = response.error.as_ref().filter(|e| e.code == INTERNAL_ERROR);
                    assert!(panicked.is_none(), "{method} panicked: {panicked:?}");
                    return response;
                }
                Ok(Message::Request(r)) => self.answer_server(r),
                Ok(Message::Notification(n)) => self.notifications.push(n),
                Err(e) => panic!("no answer to {method} within {ANSWER_WITHIN:?}: {e}"),
            }
        }
    }

    fn answer_server(&mut self, r: Request) {
        self.server_requests.push(r.method.clone());
        let ok = Response::new_ok(r.id, Value::Null);
        let _ = self.client.sender.send(Message::Response(ok));
    }

    pub fn open(&mut self, text: &str) {
        self.open_at(URI, text);
    }

    /// Open `uri` with `text` (version: the session's next).
    pub fn open_at(&mut self, uri: &str, text: &str) {
        self.version += 1;
        self.notify(
            "textDocument/didOpen",
            json!({"textDocument": {"uri": uri, "languageId": "gutta", "version": self.version, "text": text}}),
        );
        self.open = true;
    }

    /// Play one op; panics when the server breaks a rule.
    pub fn play(&mut self, op: &Op) {
        match op {
            Op::Open { seed } => self.open(SEEDS[seed % SEEDS.len()]),
            Op::Edit { range, text } => {
                self.version += 1;
                let [l0, c0, l1, c1] = *range;
                self.notify(
                    "textDocument/didChange",
                    json!({"textDocument": {"uri": URI, "version": self.version},
                           "contentChanges": [{"range": {"start": {"line": l0, "character": c0},
                                                         "end": {"line": l1, "character": c1}},
                                               "text": text}]}),
                );
            }
            Op::Replace { text } => {
                self.version += 1;
                self.notify(
                    "textDocument/didChange",
                    json!({"textDocument": {"uri": URI, "version": self.version},
                           "contentChanges": [{"text": text}]}),
                );
            }
            Op::Close => {
                self.notify(
                    "textDocument/didClose",
                    json!({"textDocument": {"uri": URI}}),
                );
                self.open = false;
            }
            Op::Ask { request, at, end } => {
                let (method, shape) = REQUESTS[request % REQUESTS.len()];
                let doc = json!({"uri": URI});
                let start = json!({"line": at[0], "character": at[1]});
                let range = json!({"start": start, "end": {"line": end[0], "character": end[1]}});
                let params = match shape {
                    Shape::Position => json!({"textDocument": doc, "position": start,
                        "context": {"includeDeclaration": true}, "newName": "Renamed"}),
                    Shape::Range => json!({"textDocument": doc, "range": range,
                        "context": {"diagnostics": [], "frameId": 0,
                                    "stoppedLocation": range},
                        "options": {"tabSize": 4, "insertSpaces": true}}),
                    Shape::Document => json!({"textDocument": doc,
                        "options": {"tabSize": 4, "insertSpaces": true}}),
                    Shape::Query => json!({"query": "la"}),
                };
                let _ = self.request(method, params);
            }
            Op::Malformed { request, params } => {
                let (method, _) = REQUESTS[request % REQUESTS.len()];
                let answer = self.request(method, malformed(*params));
                assert!(
                    answer.error.is_some(),
                    "{method} with malformed params answered {answer:?}"
                );
            }
            Op::Configure { live } => self.notify(
                "workspace/didChangeConfiguration",
                json!({"settings": {"gutta": {"liveValues": live}}}),
            ),
            Op::Toggle => {
                let answer = self.request(
                    "workspace/executeCommand",
                    json!({"command": "gutta.toggleLiveValues", "arguments": []}),
                );
                assert!(answer.error.is_none(), "toggle: {answer:?}");
            }
            Op::Noise => {
                self.notify("gutta/unknownNotification", json!({"x": 1}));
                self.notify("$/cancelRequest", json!({"id": 987_654}));
            }
        }
    }

    /// After the ops: the server still answers, then shuts down cleanly.
    pub fn finish(mut self) {
        let alive = self.request("workspace/symbol", json!({"query": ""}));
        assert_eq!(alive.id, RequestId::from(self.next_id));
        let bye = self.request("shutdown", Value::Null);
        assert!(bye.error.is_none(), "shutdown: {bye:?}");
        self.notify("exit", Value::Null);
        let served = self.server.take().map(|h| {
            h.join()
                .unwrap_or_else(|_| Err("the server thread panicked".into()))
        });
        assert_eq!(served, Some(Ok(())), "the server ended badly");
    }
}

/// A whole session: start, open the first seed, play `ops`, finish.
pub fn run(ops: &[Op]) {
    let mut session = Session::start(json!({}));
    session.open(SEEDS[0]);
    for op in ops {
        session.play(op);
    }
    session.finish();
}
