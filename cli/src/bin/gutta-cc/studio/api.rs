//! The studio's HTTP endpoints (docs/studio.md, "The server"): `GET /` the page (the
//! project's ladder as `gutta-cc ladder` draws it, a status bar, `page.js` inline with
//! the token), `GET /api/project` (files, blocks, symbols, diagnostic counts), `GET
//! /api/file?path=REL` (a project file's text), `PUT /api/file?path=REL` (a `.lad`
//! source written atomically). Every route sits behind `security.rs`'s guard; paths go
//! through `files.rs`. The page and the answers are made from the files on disk at each
//! request; nothing is cached.

use std::sync::Arc;

use axum::body::Bytes;
use axum::extract::{DefaultBodyLimit, Request, State};
use axum::http::{header, Uri};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use gutta_compiler::CheckedFile;
use gutta_ladder::html::{ladder_html, HtmlOptions};
use gutta_ladder::model::Body;
use gutta_ladder::svg::escape;
use serde_json::json;

use super::files::{Access, ProgramFiles};
use super::refusal::Refusal;
use super::security::{query_value, Guard, Token};

/// The page's script: selection, the token on every request, the status bar's time.
const SCRIPT: &str = include_str!("page.js");

/// Styles the studio adds to the ladder page: the status bar and the selection.
const STYLE: &str = "\
body{margin-bottom:48px}\
.status{position:fixed;left:0;right:0;bottom:0;padding:6px 16px;background:#1f2937;color:#f9fafb;\
font:14px monospace;display:flex;gap:24px}\
.status .mode{font-weight:bold}\
.selected .symbol-line,.selected rect{stroke:#b45309;stroke-width:3}\
";

/// The largest `.lad` a PUT may carry.
const MAX_BODY: usize = 64 * 1024 * 1024;

/// What every handler shares.
pub(crate) struct Studio {
    pub files: ProgramFiles,
    pub token: Token,
    /// Held while a file is written: two PUTs of one file would share gutta-io's
    /// temporary sibling (named by the process).
    pub writing: std::sync::Mutex<()>,
}

/// The routes, each behind `guard`.
pub(crate) fn router(studio: Arc<Studio>, guard: Guard) -> axum::Router {
    axum::Router::new()
        .route("/", get(page))
        .route("/api/project", get(project))
        .route("/api/file", get(read_file).put(write_file))
        .with_state(studio)
        .layer(DefaultBodyLimit::max(MAX_BODY))
        .layer(axum::middleware::from_fn(
            move |request: Request, next: Next| {
                let checked = guard.check(request.headers(), request.uri());
                async move {
                    match checked {
                        Ok(()) => next.run(request).await,
                        Err(refusal) => refusal.into_response(),
                    }
                }
            },
        ))
}

/// The checked program now on disk, off the server's threads.
async fn checked(studio: &Arc<Studio>) -> Result<CheckedFile, Refusal> {
    let studio = studio.clone();
    tokio::task::spawn_blocking(move || studio.files.check())
        .await
        .map_err(|e| Refusal::Io(e.to_string()))?
        .map_err(|e| Refusal::Io(e.message))
}

async fn page(State(studio): State<Arc<Studio>>) -> Response {
    match checked(&studio).await {
        Ok(checked) => (
            [
                (header::CONTENT_TYPE, "text/html; charset=utf-8"),
                (header::CACHE_CONTROL, "no-store"),
                // The address holds the token: no page it links to may see it.
                (header::REFERRER_POLICY, "no-referrer"),
                (header::X_FRAME_OPTIONS, "DENY"),
                (
                    header::CONTENT_SECURITY_POLICY,
                    "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; \
                     connect-src 'self'; img-src 'self' data:",
                ),
            ],
            page_html(&studio, &checked),
        )
            .into_response(),
        Err(refusal) => refusal.into_response(),
    }
}

/// The ladder page of `gutta-cc ladder` with the status bar and the script.
fn page_html(studio: &Studio, checked: &CheckedFile) -> String {
    let ladder = gutta_ladder::build(checked);
    let name = &studio.files.name;
    let script = format!(
        "const GUTTA_TOKEN = {};\n{SCRIPT}",
        serde_json::Value::from(studio.token.as_str())
    );
    let html = ladder_html(
        &ladder,
        &HtmlOptions {
            title: format!("{name}: GUTTA Studio"),
            live_script: Some(script),
        },
    );
    let errors = checked
        .diagnostics()
        .iter()
        .filter(|d| d.is_error())
        .count();
    let status = format!(
        "<div class=\"status\" data-mode=\"EDIT\"><span class=\"mode\">EDIT</span>\
         <span class=\"program\">{} ({})</span><span class=\"diagnostics\" data-errors=\"{errors}\">{}</span>\
         <span class=\"updated\"></span></div>\n",
        escape(name),
        escape(&ladder.plc),
        gutta_cli::plural::count(errors, "error"),
    );
    html.replacen("</head>", &format!("<style>{STYLE}</style>\n</head>"), 1)
        .replacen("<body>\n", &format!("<body>\n{status}"), 1)
}

async fn project(State(studio): State<Arc<Studio>>) -> Response {
    match checked(&studio).await {
        Ok(checked) => json_response(&project_json(&studio.files, &checked)),
        Err(refusal) => refusal.into_response(),
    }
}

/// `/api/project`: the program's files, blocks and symbols.
fn project_json(files: &ProgramFiles, checked: &CheckedFile) -> serde_json::Value {
    let ladder = gutta_ladder::build(checked);
    let listed = |paths: &[std::path::PathBuf], role: &str| -> Vec<serde_json::Value> {
        paths
            .iter()
            .map(|p| json!({"path": files.relative(p), "role": role}))
            .collect()
    };
    let mut file_list = listed(&files.sources, "source");
    file_list.extend(listed(&files.tables, "symbols"));
    let blocks: Vec<serde_json::Value> = ladder
        .blocks
        .iter()
        .map(|b| {
            let drawn = b
                .networks
                .iter()
                .filter(|n| matches!(n.body, Body::Rung(_)))
                .count();
            json!({
                "name": b.name,
                "numbered": b.numbered,
                "title": b.title,
                "networks": b.networks.len(),
                "drawn": drawn,
            })
        })
        .collect();
    let diagnostics = checked.diagnostics();
    let errors = diagnostics.iter().filter(|d| d.is_error()).count();
    json!({
        "name": files.name,
        "plc": ladder.plc,
        "files": file_list,
        "blocks": blocks,
        "symbols": checked.symbols().symbols,
        "diagnostics": {"errors": errors, "warnings": diagnostics.len() - errors},
    })
}

/// The `?path=` of a request.
fn requested_path(uri: &Uri) -> Result<String, Refusal> {
    query_value(uri, "path").ok_or(Refusal::PathMissing)
}

async fn read_file(State(studio): State<Arc<Studio>>, uri: Uri) -> Response {
    let read = || -> Result<Vec<u8>, Refusal> {
        let relative = requested_path(&uri)?;
        let path = studio.files.resolve(&relative, Access::Read)?;
        std::fs::read(&path).map_err(|e| Refusal::Io(format!("cannot read {relative}: {e}")))
    };
    match read() {
        Ok(bytes) => {
            let kind = if std::str::from_utf8(&bytes).is_ok() {
                "text/plain; charset=utf-8"
            } else {
                "application/octet-stream"
            };
            (
                [
                    (header::CONTENT_TYPE, kind),
                    (header::CACHE_CONTROL, "no-store"),
                ],
                bytes,
            )
                .into_response()
        }
        Err(refusal) => refusal.into_response(),
    }
}

async fn write_file(State(studio): State<Arc<Studio>>, uri: Uri, body: Bytes) -> Response {
    let write = move || -> Result<serde_json::Value, Refusal> {
        let relative = requested_path(&uri)?;
        let path = studio.files.resolve(&relative, Access::WriteLad)?;
        let _one_at_a_time = studio.writing.lock().unwrap_or_else(|e| e.into_inner());
        gutta_io::write_file_atomically(&path, &body)
            .map_err(|e| Refusal::Io(format!("cannot write {relative}: {e}")))?;
        Ok(json!({"written": studio.files.relative(&path), "bytes": body.len()}))
    };
    match tokio::task::spawn_blocking(write).await {
        Ok(Ok(answer)) => json_response(&answer),
        Ok(Err(refusal)) => refusal.into_response(),
        Err(e) => Refusal::Io(e.to_string()).into_response(),
    }
}

fn json_response(value: &serde_json::Value) -> Response {
    (
        [
            (header::CONTENT_TYPE, "application/json"),
            (header::CACHE_CONTROL, "no-store"),
        ],
        value.to_string(),
    )
        .into_response()
}
