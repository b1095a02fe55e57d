//! The in-process test client: the server on a thread over `Connection::memory()`, a
//! client that opens documents, sends requests and notifications, and collects what
//! the server publishes. Every test file of lsp/tests uses it (`mod common;`). It does
//! not judge answers: tests snapshot them.
#![allow(dead_code, clippy::unwrap_used)]

use std::collections::HashMap;
use std::path::Path;
use std::thread::JoinHandle;
use std::time::Duration;

use lsp_server::{Connection, Message, Notification, Request, RequestId, Response};
use lsp_types::notification::Notification as _;
use lsp_types::request::Request as _;
use lsp_types::{
    ClientCapabilities, Diagnostic, InitializeParams, Position, PublishDiagnosticsParams,
    TextDocumentContentChangeEvent, TextDocumentIdentifier, TextDocumentPositionParams, Uri,
};
use serde_json::Value;

/// How long to wait for one message before the test fails (the server never takes
/// this long; a hang is a bug).
const TIMEOUT: Duration = Duration::from_secs(30);

/// A running server and the client side of its connection.
pub struct TestServer {
    client: Connection,
    thread: Option<JoinHandle<Result<(), String>>>,
    next_id: i32,
    /// Every notification received, in order.
    pub notifications: Vec<Notification>,
    /// The latest diagnostics published for each URI.
    pub diagnostics: HashMap<String, Vec<Diagnostic>>,
    /// How many times diagnostics were published for each URI.
    pub publish_counts: HashMap<String, usize>,
    /// The `initialize` result.
    pub initialize_result: Value,
    /// Requests the server sent the client (each answered with `null`).
    pub server_requests: Vec<Request>,
}

impl TestServer {
    /// A server initialized with default client capabilities.
    pub fn start() -> TestServer {
        TestServer::start_with(InitializeParams {
            capabilities: ClientCapabilities::default(),
            ..InitializeParams::default()
        })
    }

    /// A server whose client can register file watchers (as VS Code can).
    pub fn start_watching() -> TestServer {
        let capabilities = ClientCapabilities {
            workspace: Some(lsp_types::WorkspaceClientCapabilities {
                did_change_watched_files: Some(
                    lsp_types::DidChangeWatchedFilesClientCapabilities {
                        dynamic_registration: Some(true),
                        relative_pattern_support: None,
                    },
                ),
                ..Default::default()
            }),
            ..Default::default()
        };
        TestServer::start_with(InitializeParams {
            capabilities,
            ..InitializeParams::default()
        })
    }

    /// Tell the server that files changed on disk, and wait.
    pub fn files_changed(&mut self, uris: &[&Uri]) {
        self.notify::<lsp_types::notification::DidChangeWatchedFiles>(
            lsp_types::DidChangeWatchedFilesParams {
                changes: uris
                    .iter()
                    .map(|u| {
                        lsp_types::FileEvent::new((*u).clone(), lsp_types::FileChangeType::CHANGED)
                    })
                    .collect(),
            },
        );
        self.sync();
    }

    pub fn start_with(params: InitializeParams) -> TestServer {
        let (server, client) = Connection::memory();
        let thread = std::thread::spawn(move || gutta_lsp::serve(&server));
        let mut t = TestServer {
            client,
            thread: Some(thread),
            next_id: 0,
            notifications: Vec::new(),
            diagnostics: HashMap::new(),
            publish_counts: HashMap::new(),
            initialize_result: Value::Null,
            server_requests: Vec::new(),
        };
        let response = t.request_raw(
            lsp_types::request::Initialize::METHOD,
            serde_json::to_value(params).unwrap(),
        );
        t.initialize_result = response.result.expect("initialize answers a result");
        t.notify::<lsp_types::notification::Initialized>(lsp_types::InitializedParams {});
        t
    }

    /// Send a request and wait for its response, collecting notifications meanwhile.
    pub fn request_raw(&mut self, method: &str, params: Value) -> Response {
        self.next_id += 1;
        let id = RequestId::from(self.next_id);
        self.client
            .sender
            .send(Message::Request(Request::new(
                id.clone(),
                method.into(),
                params,
            )))
            .unwrap();
        loop {
            match self.receive() {
                Message::Response(r) if r.id == id => return r,
                Message::Response(_) => {}
                Message::Notification(n) => self.record(n),
                // The server asks for refreshes; answer them.
                Message::Request(r) => {
                    let _ = self.client.sender.send(Message::Response(Response::new_ok(
                        r.id.clone(),
                        Value::Null,
                    )));
                    self.server_requests.push(r);
                }
            }
        }
    }

    /// A typed request that must succeed.
    pub fn request<R: lsp_types::request::Request>(&mut self, params: R::Params) -> R::Result {
        let response = self.request_raw(R::METHOD, serde_json::to_value(params).unwrap());
        if let Some(e) = response.error {
            panic!("{} failed: {} {}", R::METHOD, e.code, e.message);
        }
        serde_json::from_value(response.result.unwrap_or(Value::Null)).unwrap()
    }

    pub fn notify<N: lsp_types::notification::Notification>(&mut self, params: N::Params) {
        self.client
            .sender
            .send(Message::Notification(Notification::new(
                N::METHOD.into(),
                params,
            )))
            .unwrap();
    }

    pub fn notify_raw(&mut self, method: &str, params: Value) {
        self.client
            .sender
            .send(Message::Notification(Notification {
                method: method.into(),
                params,
            }))
            .unwrap();
    }

    /// Wait until the server has handled everything sent so far: a request it does not
    /// serve is answered after every earlier message.
    pub fn sync(&mut self) {
        let r = self.request_raw("gutta/testBarrier", Value::Null);
        assert!(r.error.is_some(), "the barrier is not a served method");
    }

    /// Open a document (languageId `gutta`, version 1) and wait for its handling.
    pub fn open(&mut self, uri: &Uri, text: &str) {
        self.open_as(uri, "gutta", text);
    }

    pub fn open_as(&mut self, uri: &Uri, language: &str, text: &str) {
        self.notify::<lsp_types::notification::DidOpenTextDocument>(
            lsp_types::DidOpenTextDocumentParams {
                text_document: lsp_types::TextDocumentItem::new(
                    uri.clone(),
                    language.into(),
                    1,
                    text.into(),
                ),
            },
        );
        self.sync();
    }

    /// Send incremental (or full, with `range: None`) changes and wait.
    pub fn change(
        &mut self,
        uri: &Uri,
        version: i32,
        changes: Vec<TextDocumentContentChangeEvent>,
    ) {
        self.notify::<lsp_types::notification::DidChangeTextDocument>(
            lsp_types::DidChangeTextDocumentParams {
                text_document: lsp_types::VersionedTextDocumentIdentifier::new(
                    uri.clone(),
                    version,
                ),
                content_changes: changes,
            },
        );
        self.sync();
    }

    /// Replace the whole text.
    pub fn replace(&mut self, uri: &Uri, version: i32, text: &str) {
        self.change(
            uri,
            version,
            vec![TextDocumentContentChangeEvent {
                range: None,
                range_length: None,
                text: text.into(),
            }],
        );
    }

    pub fn close(&mut self, uri: &Uri) {
        self.notify::<lsp_types::notification::DidCloseTextDocument>(
            lsp_types::DidCloseTextDocumentParams {
                text_document: TextDocumentIdentifier::new(uri.clone()),
            },
        );
        self.sync();
    }

    /// The latest diagnostics published for `uri` (panics if none were).
    pub fn diagnostics_of(&self, uri: &Uri) -> &[Diagnostic] {
        self.diagnostics
            .get(uri.as_str())
            .unwrap_or_else(|| panic!("no diagnostics published for {}", uri.as_str()))
    }

    /// Notifications of `method` received so far.
    pub fn received(&self, method: &str) -> Vec<&Notification> {
        self.notifications
            .iter()
            .filter(|n| n.method == method)
            .collect()
    }

    /// `shutdown`, `exit`, and the server thread's result.
    pub fn shutdown(mut self) -> Result<(), String> {
        let r = self.request_raw(lsp_types::request::Shutdown::METHOD, Value::Null);
        assert!(r.error.is_none());
        self.notify::<lsp_types::notification::Exit>(());
        self.thread.take().unwrap().join().unwrap()
    }

    fn receive(&mut self) -> Message {
        self.client
            .receiver
            .recv_timeout(TIMEOUT)
            .expect("the server answers within the timeout")
    }

    fn record(&mut self, n: Notification) {
        if n.method == lsp_types::notification::PublishDiagnostics::METHOD {
            let p: PublishDiagnosticsParams = serde_json::from_value(n.params.clone()).unwrap();
            let key = p.uri.as_str().to_string();
            *self.publish_counts.entry(key.clone()).or_default() += 1;
            self.diagnostics.insert(key, p.diagnostics);
        }
        self.notifications.push(n);
    }
}

impl Drop for TestServer {
    fn drop(&mut self) {
        if let Some(thread) = self.thread.take() {
            // Ends the loop: exit without shutdown.
            let _ = self
                .client
                .sender
                .send(Message::Notification(Notification::new(
                    lsp_types::notification::Exit::METHOD.into(),
                    (),
                )));
            let _ = thread.join();
        }
    }
}

/// A URI for a file that need not exist (`file:///test/NAME`).
pub fn uri(name: &str) -> Uri {
    format!("file:///test/{name}").parse().unwrap()
}

/// The `file:` URI of a real path.
pub fn file_uri(path: &Path) -> Uri {
    gutta_lsp::documents::path_to_uri(path).unwrap()
}

/// Text document + position params.
pub fn at(uri: &Uri, line: u32, character: u32) -> TextDocumentPositionParams {
    TextDocumentPositionParams::new(
        TextDocumentIdentifier::new(uri.clone()),
        Position::new(line, character),
    )
}

/// The position of the `n`th (0-based) occurrence of `needle` in `text`, plus `shift`
/// UTF-16 units, as LSP counts.
pub fn find(text: &str, needle: &str, n: usize, shift: u32) -> Position {
    let offset = text
        .match_indices(needle)
        .nth(n)
        .unwrap_or_else(|| panic!("`{needle}` #{n} not in the text"))
        .0;
    let before = &text[..offset];
    let line = before.matches('\n').count() as u32;
    let start = before.rfind('\n').map(|i| i + 1).unwrap_or(0);
    Position::new(line, before[start..].encode_utf16().count() as u32 + shift)
}

/// An answer as JSON text with the machine's paths and the docs' location replaced, for
/// snapshots.
pub fn redact(value: &impl serde::Serialize, roots: &[&Path]) -> String {
    let mut text = serde_json::to_string_pretty(value).unwrap();
    for root in roots {
        let uri = file_uri(root);
        text = text.replace(uri.as_str(), "file:///ROOT");
    }
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let repo = std::fs::canonicalize(repo).unwrap();
    text.replace(file_uri(&repo).as_str(), "file:///REPO")
}

/// A project on disk: `gutta.toml` naming `src/main.lad` and `src/motor.lad` as
/// sources and `symbols.csv` as a table, in a fresh temporary folder.
pub struct ProjectDir {
    pub dir: tempfile::TempDir,
}

pub const MAIN_LAD: &str = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1 // start the motor\nLD     Start\nCALL   MOTOR, M0.0\n=      Lamp\nEND_ORGANIZATION_BLOCK\n";
pub const MOTOR_LAD: &str = "SUBROUTINE_BLOCK MOTOR:SBR0\nVAR_INPUT\n  run : BOOL; // run request\nEND_VAR\nBEGIN\nNetwork 1 // drive\nLD     #run\n=      Motor\nEND_SUBROUTINE_BLOCK\n";
pub const SYMBOLS_CSV: &str =
    "Symbol,Address,Comment\nStart,I0.0,push button\nLamp,Q0.0,indicator\nMotor,Q0.1,main drive\n";

impl ProjectDir {
    pub fn new() -> ProjectDir {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path();
        std::fs::create_dir_all(root.join("src")).unwrap();
        std::fs::write(
            root.join("gutta.toml"),
            "[program]\nplc = \"CPU-EC20\"\nsources = [\"src/main.lad\", \"src/motor.lad\"]\nsymbols = [\"symbols.csv\"]\n",
        )
        .unwrap();
        std::fs::write(root.join("src/main.lad"), MAIN_LAD).unwrap();
        std::fs::write(root.join("src/motor.lad"), MOTOR_LAD).unwrap();
        std::fs::write(root.join("symbols.csv"), SYMBOLS_CSV).unwrap();
        ProjectDir { dir }
    }

    pub fn root(&self) -> std::path::PathBuf {
        std::fs::canonicalize(self.dir.path()).unwrap()
    }

    pub fn uri(&self, relative: &str) -> Uri {
        file_uri(&self.root().join(relative))
    }
}

/// A location as `FILE L:C-L:C` (0-based, as LSP counts), the file shortened to its
/// path under `root` (or its name for `file:///test/` URIs).
pub fn show_location(l: &lsp_types::Location, root: Option<&Path>) -> String {
    format!("{} {}", show_uri(&l.uri, root), show_range(&l.range))
}

pub fn show_range(r: &lsp_types::Range) -> String {
    format!(
        "{}:{}-{}:{}",
        r.start.line, r.start.character, r.end.line, r.end.character
    )
}

pub fn show_uri(uri: &Uri, root: Option<&Path>) -> String {
    let text = uri.as_str();
    if let Some(root) = root {
        let prefix = format!("{}/", file_uri(root).as_str());
        if let Some(rest) = text.strip_prefix(&prefix) {
            return rest.to_string();
        }
    }
    text.strip_prefix("file:///test/")
        .unwrap_or(text)
        .to_string()
}
