//! The studio's HTTP endpoints (docs/studio.md, "The server", "The page", "Editing").
//! The session (`gutta_cli::studio::Session`) is the page's one truth: every answer is
//! made from its buffers, never from the disk. `GET /` the page (the open file drawn,
//! toolbar, side bar, status bar, `page.js` and the other scripts inline with the
//! token), `GET /api/project`, `GET /api/file?file=|path=` (a buffer, or another file
//! of the folder), `PUT /api/file?path=` (a `.lad` written atomically; an open file is
//! read again), `GET /api/drawing?file=`, `GET /api/model?file=`
//! (the ladder model's JSON: what copy takes), `POST /api/edit|undo|redo|save`, `GET
//! /api/stl?file=&block=`, `GET /api/complete?...`. Every route sits behind
//! `security.rs`'s guard; paths go through `files.rs`. The session's mutex is held only
//! while it works, never across I/O of the network.

use std::fmt::Write as _;
use std::sync::{Arc, Mutex, MutexGuard};

use axum::body::Bytes;
use axum::extract::{DefaultBodyLimit, Request, State};
use axum::http::{header, StatusCode, Uri};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use gutta_cli::studio::{CompletionRequest, Session, Update, Wanted};
use gutta_ladder::json::ModelDiagnostic;
use gutta_ladder::layout::block_heading;
use gutta_ladder::svg::{escape, DrawOptions};
use serde_json::{json, Value};

use super::drawing::network_html;
use super::files::{resolve, Access};
use super::live::LiveSource;
use super::refusal::Refusal;
use super::security::{query_value, Guard, Token};

/// The page's scripts, inlined in this order: `page.js` makes `window.guttaStudio`,
/// the others use it.
const SCRIPTS: [&str; 4] = [
    include_str!("page.js"),
    include_str!("live.js"),
    include_str!("online.js"),
    include_str!("source.js"),
];

/// The page's styles (the drawing's own come from `gutta_ladder::svg::STYLE`).
const PAGE_CSS: &str = include_str!("page.css");

/// The commands of the toolbar: `data-command` name, label, key shown in the tooltip.
pub(crate) const COMMANDS: [(&str, &str, &str); 20] = [
    ("edit", "Edit", "Esc"),
    ("contact-no", "─┤ ├─", "F4"),
    ("contact-nc", "─┤/├─", "Shift+F4"),
    ("coil", "─( )", "F6"),
    ("coil-set", "─(S)", "Shift+F6"),
    ("coil-reset", "─(R)", "Ctrl+F6"),
    ("box", "[box]", "F9"),
    ("branch", "branch", "F7"),
    ("delete", "Delete", "Del"),
    ("network-new", "+ Network", "Ctrl+Enter"),
    ("undo", "Undo", "Ctrl+Z"),
    ("redo", "Redo", "Ctrl+Y"),
    ("save", "Save", "Ctrl+S"),
    ("view-stl", "LAD/STL", "Ctrl+L"),
    ("symbol-info", "Symbol info", "Alt+I"),
    ("simulate", "Simulate", "F5"),
    ("stop", "Stop", "Shift+F5"),
    ("online", "Online", "Ctrl+F5"),
    ("download", "Download", "Ctrl+D"),
    ("test", "Test", "Ctrl+T"),
];

/// The largest body a request may carry.
const MAX_BODY: usize = 64 * 1024 * 1024;

/// What every handler shares.
pub(crate) struct Studio {
    /// The open files with their buffers: the page's one truth.
    pub session: Arc<Mutex<Session>>,
    /// The simulator or the connected PLC, when one runs.
    pub live: Mutex<Option<Box<dyn LiveSource>>>,
    pub token: Token,
    /// Held while a file is written by PUT: two PUTs of one file would share gutta-io's
    /// temporary sibling (named by the process).
    pub writing: Mutex<()>,
    /// How the page's networks are drawn (the `symbol-info` command sets
    /// `symbol_info`, `POST /api/view`).
    pub draw: Mutex<DrawOptions>,
}

impl Studio {
    /// The session, even after a handler panicked holding it.
    pub(crate) fn session(&self) -> MutexGuard<'_, Session> {
        self.session.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// How the networks are drawn now.
    pub(crate) fn draw_options(&self) -> DrawOptions {
        *self.draw.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// The routes, each behind `guard`.
pub(crate) fn router(studio: Arc<Studio>, guard: Guard) -> axum::Router {
    axum::Router::new()
        .route("/", get(page))
        .route("/api/project", get(project))
        .route("/api/file", get(read_file).put(write_file))
        .route("/api/drawing", get(drawing))
        .route("/api/view", post(view))
        .route("/api/model", get(model))
        .route("/api/edit", post(edit))
        .route("/api/undo", post(undo))
        .route("/api/redo", post(redo))
        .route("/api/save", post(save))
        .route("/api/stl", get(stl))
        .route("/api/complete", get(complete))
        // The other parts' routes (`fn routes() -> axum::Router<Arc<Studio>>` in their own
        // files) are merged here, one `.merge(xxx::routes())` line each.
        .merge(super::live::routes())
        .merge(super::online::routes())
        .merge(super::source::routes())
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

/// `work` on the session off the server's threads.
pub(super) async fn with_session<T: Send + 'static>(
    studio: &Arc<Studio>,
    work: impl FnOnce(&mut Session) -> Result<T, Refusal> + Send + 'static,
) -> Result<T, Refusal> {
    let studio = studio.clone();
    tokio::task::spawn_blocking(move || work(&mut studio.session()))
        .await
        .map_err(|e| Refusal::Io(e.to_string()))?
}

/// A result as the routes answer it: the JSON, or the refusal with its code.
pub(super) fn answer(result: Result<Value, Refusal>) -> Response {
    match result {
        Ok(value) => json_response(&value),
        Err(refusal) => refusal.into_response(),
    }
}

/// The file a request names (`?file=`), else the session's first.
pub(super) fn file_of(uri: &Uri, session: &Session) -> Result<String, Refusal> {
    match query_value(uri, "file") {
        Some(file) => Ok(file),
        None => session
            .files()
            .first()
            .map(|f| f.to_string())
            .ok_or_else(|| Refusal::BadRequest("the studio has no file open".into())),
    }
}

async fn page(State(studio): State<Arc<Studio>>, uri: Uri) -> Response {
    let token = studio.token.as_str().to_string();
    let draw = studio.draw_options();
    let made = with_session(&studio, move |session| {
        let file = file_of(&uri, session)?;
        page_html(session, &file, &token, &draw)
    })
    .await;
    match made {
        Ok(html) => (
            [
                (header::CONTENT_TYPE, "text/html; charset=utf-8"),
                (header::CACHE_CONTROL, "no-store"),
                // The address holds the token: no page it links to may see it.
                (header::REFERRER_POLICY, "no-referrer"),
                // Framed only by itself and by the VS Code extension's webview (docs/
                // studio.md, "VS Code"); a foreign page cannot frame it.
                (
                    header::CONTENT_SECURITY_POLICY,
                    "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; \
                     connect-src 'self'; img-src 'self' data:; \
                     frame-ancestors 'self' vscode-webview:",
                ),
            ],
            html,
        )
            .into_response(),
        Err(refusal) => refusal.into_response(),
    }
}

/// The page: toolbar, side bar, the file's blocks and networks, the status bar, the
/// scripts with the token and the file's state.
fn page_html(
    session: &Session,
    file: &str,
    token: &str,
    draw: &DrawOptions,
) -> Result<String, Refusal> {
    let ladder = session.ladder(file)?;
    let diagnostics = session.diagnostics(file)?;
    let dirty = session.is_dirty(file)?;
    let (can_undo, can_redo) = session.history(file)?;
    let summary = session.project();
    let name = escape(&summary.name);
    let networks: usize = ladder.blocks.iter().map(|b| b.networks.len()).sum();
    let mut out = String::with_capacity(networks * 6000 + 16_384);
    let _ = write!(
        out,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n\
         <title>{name}: GUTTA Studio</title>\n<link rel=\"icon\" href=\"data:,\">\n\
         <style>{}{PAGE_CSS}</style>\n</head>\n<body data-mode=\"EDIT\" data-view=\"LAD\" \
         data-symbol-info=\"{}\">\n",
        gutta_ladder::svg::STYLE,
        if draw.symbol_info { "on" } else { "off" }
    );
    out.push_str("<header class=\"toolbar\" role=\"toolbar\">");
    for (command, label, key) in COMMANDS {
        let _ = write!(
            out,
            "<button type=\"button\" data-command=\"{command}\" title=\"{command} ({key})\">{}</button>",
            escape(label)
        );
    }
    let _ = writeln!(
        out,
        "<span class=\"file\">{}</span><span class=\"dirty\" title=\"unsaved changes\"></span></header>",
        escape(file)
    );
    // The side bar: files, blocks, symbols, tests.
    out.push_str("<aside class=\"sidebar\"><h3>Project</h3><ul class=\"files\">");
    for f in &summary.files {
        let _ = write!(out, "<li data-file=\"{0}\">{0}</li>", escape(&f.name));
    }
    out.push_str("</ul><h3>Blocks</h3><ul class=\"blocks\">");
    for (b, block) in ladder.blocks.iter().enumerate() {
        let _ = write!(
            out,
            "<li><a href=\"#block-{b}\" data-b=\"{b}\">{}</a></li>",
            escape(&block_heading(block))
        );
    }
    out.push_str("</ul><h3>Symbols</h3><table class=\"symbols\">");
    for s in &summary.symbols {
        let _ = write!(
            out,
            "<tr><td>{}</td><td>{}</td></tr>",
            escape(&s.name),
            escape(&s.address)
        );
    }
    out.push_str("</table><h3>Tests</h3><ul class=\"tests\">");
    for t in &summary.tests {
        let _ = write!(out, "<li>{}</li>", escape(t));
    }
    out.push_str("</ul></aside>\n<main class=\"editor\">\n<div class=\"messages\"></div>\n");
    for (b, block) in ladder.blocks.iter().enumerate() {
        let _ = writeln!(
            out,
            "<section class=\"block\" id=\"block-{b}\" data-b=\"{b}\" data-block=\"{}\">\
             <h2>{}</h2><div class=\"networks\">",
            escape(&block.name),
            escape(&block_heading(block))
        );
        for (n, net) in block.networks.iter().enumerate() {
            let _ = writeln!(
                out,
                "<div class=\"network-view\" data-b=\"{b}\" data-n=\"{n}\">{}</div>",
                network_html(b, n, block, net, draw)
            );
        }
        out.push_str("</div></section>\n");
    }
    out.push_str("</main>\n<div class=\"panels\"></div>\n");
    let errors = diagnostics.iter().filter(|d| d.is_error()).count();
    let _ = writeln!(
        out,
        "<div class=\"status\" data-mode=\"EDIT\"><span class=\"mode\">EDIT</span>\
         <span class=\"run\"></span><span class=\"where\"></span>\
         <span class=\"program\">{name} ({})</span>\
         <span class=\"diagnostics\" data-errors=\"{errors}\">{}</span>\
         <span class=\"updated\"></span></div>",
        escape(&ladder.plc),
        gutta_cli::plural::count(errors, "error"),
    );
    let state = json!({
        "file": file,
        "diagnostics": diagnostics,
        "dirty": dirty,
        "can_undo": can_undo,
        "can_redo": can_redo,
    });
    let mut script = format!(
        "const GUTTA_TOKEN = {};\nconst GUTTA_STATE = {};\n",
        Value::from(token),
        state
    );
    for s in SCRIPTS {
        script.push_str(s);
        script.push('\n');
    }
    // Inside <script> only `</script` can end the element early.
    let safe = script.replace("</script", "<\\/script");
    let _ = write!(out, "<script>\n{safe}</script>\n</body>\n</html>\n");
    Ok(out)
}

async fn project(State(studio): State<Arc<Studio>>) -> Response {
    answer(with_session(&studio, |session| Ok(project_json(session))).await)
}

/// `/api/project`: the session's summary (files with their blocks, symbols, tests),
/// each file also by `path` with its role, the symbol tables, every block of the first
/// file by name, and the diagnostic counts of every open file.
fn project_json(session: &Session) -> Value {
    let summary = session.project();
    let mut value = serde_json::to_value(&summary).unwrap_or_default();
    let mut files: Vec<Value> = Vec::new();
    for (i, f) in summary.files.iter().enumerate() {
        let mut entry = value["files"][i].clone();
        entry["path"] = json!(f.name);
        entry["role"] = json!("source");
        files.push(entry);
    }
    for table in session.tables() {
        files.push(json!({"path": table, "role": "symbols"}));
    }
    value["files"] = Value::Array(files);
    let (mut errors, mut warnings) = (0, 0);
    let mut blocks = Vec::new();
    for name in session.files() {
        if let Ok(d) = session.diagnostics(name) {
            let e = d.iter().filter(|d| d.is_error()).count();
            errors += e;
            warnings += d.len() - e;
        }
        if blocks.is_empty() {
            if let Ok(ladder) = session.ladder(name) {
                blocks = ladder
                    .blocks
                    .iter()
                    .map(|b| {
                        json!({
                            "name": b.name,
                            "numbered": b.numbered,
                            "title": b.title,
                            "networks": b.networks.len(),
                        })
                    })
                    .collect();
            }
        }
    }
    value["blocks"] = Value::Array(blocks);
    value["diagnostics"] = json!({"errors": errors, "warnings": warnings});
    value
}

async fn read_file(State(studio): State<Arc<Studio>>, uri: Uri) -> Response {
    let read = move |session: &mut Session| -> Result<(Vec<u8>, bool), Refusal> {
        if let Some(file) = query_value(&uri, "file") {
            return Ok((session.text(&file)?.as_bytes().to_vec(), true));
        }
        let relative = query_value(&uri, "path").ok_or(Refusal::PathMissing)?;
        let root = gutta_cli::studio::Root::new(session.root()).map_err(Refusal::from)?;
        let path = resolve(&root, &relative, Access::Read)?;
        // An open file is its buffer; any other file of the folder as it is on disk.
        let name = root.name_of(&path);
        if let Ok(text) = session.text(&name) {
            return Ok((text.as_bytes().to_vec(), true));
        }
        let bytes = std::fs::read(&path)
            .map_err(|e| Refusal::Io(format!("cannot read {relative}: {e}")))?;
        let text = std::str::from_utf8(&bytes).is_ok();
        Ok((bytes, text))
    };
    match with_session(&studio, read).await {
        Ok((bytes, text)) => (
            [
                (
                    header::CONTENT_TYPE,
                    if text {
                        "text/plain; charset=utf-8"
                    } else {
                        "application/octet-stream"
                    },
                ),
                (header::CACHE_CONTROL, "no-store"),
            ],
            bytes,
        )
            .into_response(),
        Err(refusal) => refusal.into_response(),
    }
}

async fn write_file(State(studio): State<Arc<Studio>>, uri: Uri, body: Bytes) -> Response {
    let shared = studio.clone();
    let write = move |session: &mut Session| -> Result<Value, Refusal> {
        let relative = query_value(&uri, "path").ok_or(Refusal::PathMissing)?;
        let root = gutta_cli::studio::Root::new(session.root()).map_err(Refusal::from)?;
        let path = resolve(&root, &relative, Access::WriteLad)?;
        let _one_at_a_time = shared.writing.lock().unwrap_or_else(|e| e.into_inner());
        gutta_io::write_file_atomically(&path, &body)
            .map_err(|e| Refusal::Io(format!("cannot write {relative}: {e}")))?;
        // An open file follows what was written: its buffer is the file again.
        let reloaded = session.reload(&path).map_err(Refusal::from)?;
        Ok(json!({"written": root.name_of(&path), "bytes": body.len(), "reloaded": reloaded}))
    };
    answer(with_session(&studio, write).await)
}

/// Every network of a file drawn, by block.
fn drawing_json(session: &Session, file: &str, draw: &DrawOptions) -> Result<Value, Refusal> {
    let ladder = session.ladder(file)?;
    let blocks: Vec<Value> = ladder
        .blocks
        .iter()
        .enumerate()
        .map(|(b, block)| {
            let networks: Vec<Value> = block
                .networks
                .iter()
                .enumerate()
                .map(|(n, net)| {
                    json!({"block": b, "network": n, "number": net.number,
                           "html": network_html(b, n, block, net, draw)})
                })
                .collect();
            json!({"name": block.name, "heading": block_heading(block),
                   "title": block.title, "networks": networks})
        })
        .collect();
    Ok(json!({
        "file": file,
        "plc": ladder.plc,
        "blocks": blocks,
        "diagnostics": session.diagnostics(file)?,
        "dirty": session.is_dirty(file)?,
    }))
}

async fn drawing(State(studio): State<Arc<Studio>>, uri: Uri) -> Response {
    let draw = studio.draw_options();
    answer(
        with_session(&studio, move |session| {
            let file = file_of(&uri, session)?;
            drawing_json(session, &file, &draw)
        })
        .await,
    )
}

/// `POST /api/view` `{"symbol_info": true|false}`: how the networks are drawn from now
/// on; answers the file's drawing (`GET /api/drawing`) drawn so.
async fn view(State(studio): State<Arc<Studio>>, body: Bytes) -> Response {
    let value = match body_json(&body) {
        Ok(value) => value,
        Err(refusal) => return refusal.into_response(),
    };
    let Some(symbol_info) = value.get("symbol_info").and_then(Value::as_bool) else {
        return Refusal::BadRequest("the body needs \"symbol_info\": true or false".into())
            .into_response();
    };
    let draw = {
        let mut draw = studio.draw.lock().unwrap_or_else(|e| e.into_inner());
        draw.symbol_info = symbol_info;
        *draw
    };
    answer(
        with_session(&studio, move |session| {
            let file = body_file(&value, session)?;
            let mut drawing = drawing_json(session, &file, &draw)?;
            drawing["symbol_info"] = Value::Bool(draw.symbol_info);
            Ok(drawing)
        })
        .await,
    )
}

async fn model(State(studio): State<Arc<Studio>>, uri: Uri) -> Response {
    answer(
        with_session(&studio, move |session| {
            let file = file_of(&uri, session)?;
            serde_json::to_value(session.model(&file)?)
                .map_err(|e| Refusal::Io(format!("the model as JSON: {e}")))
        })
        .await,
    )
}

/// An update as the page takes it: the redrawn networks as `<svg>` with paths.
pub(super) fn update_json(
    session: &Session,
    update: &Update,
    draw: &DrawOptions,
) -> Result<Value, Refusal> {
    let ladder = session.ladder(&update.file)?;
    let networks: Vec<Value> = update
        .networks
        .iter()
        .filter_map(|d| {
            let block = ladder.blocks.get(d.block)?;
            let net = block.networks.get(d.network)?;
            Some(
                json!({"block": d.block, "network": d.network, "number": net.number,
                        "html": network_html(d.block, d.network, block, net, draw)}),
            )
        })
        .collect();
    let blocks: Vec<Value> = ladder
        .blocks
        .iter()
        .map(|b| {
            json!({"name": b.name, "heading": block_heading(b), "title": b.title,
                   "networks": b.networks.len()})
        })
        .collect();
    Ok(json!({
        "file": update.file,
        "networks": networks,
        "blocks": blocks,
        "diagnostics": update.diagnostics,
        "errors": errors(&update.diagnostics),
        "dirty": update.dirty,
        "can_undo": update.can_undo,
        "can_redo": update.can_redo,
    }))
}

/// An edit's, undo's or redo's answer: the update, without its diagnostics when they
/// are the ones the page already has (`before`): a big program's warnings are sent once,
/// not at every step (the page keeps its list when the answer has none).
fn step_json(
    session: &Session,
    update: &Update,
    before: &[ModelDiagnostic],
    draw: &DrawOptions,
) -> Result<Value, Refusal> {
    let mut value = update_json(session, update, draw)?;
    if update.diagnostics == before {
        if let Some(object) = value.as_object_mut() {
            object.remove("diagnostics");
        }
    }
    Ok(value)
}

fn errors(diagnostics: &[ModelDiagnostic]) -> usize {
    diagnostics.iter().filter(|d| d.is_error()).count()
}

/// A POST body's JSON object.
pub(super) fn body_json(body: &Bytes) -> Result<Value, Refusal> {
    let value: Value = serde_json::from_slice(body)
        .map_err(|e| Refusal::BadRequest(format!("the body is not JSON: {e}")))?;
    if value.is_object() {
        Ok(value)
    } else {
        Err(Refusal::BadRequest("the body is not a JSON object".into()))
    }
}

fn body_file(value: &Value, session: &Session) -> Result<String, Refusal> {
    match value.get("file") {
        Some(Value::String(file)) => Ok(file.clone()),
        Some(_) => Err(Refusal::BadRequest("\"file\" is not text".into())),
        None => session
            .files()
            .first()
            .map(|f| f.to_string())
            .ok_or_else(|| Refusal::BadRequest("the studio has no file open".into())),
    }
}

async fn edit(State(studio): State<Arc<Studio>>, body: Bytes) -> Response {
    let draw = studio.draw_options();
    answer(
        with_session(&studio, move |session| {
            let value = body_json(&body)?;
            let file = body_file(&value, session)?;
            let edit = value.get("edit").ok_or_else(|| {
                Refusal::BadRequest("the body needs \"edit\": an edit operation".into())
            })?;
            let before = session.diagnostics(&file)?.to_vec();
            let update = session.apply(&file, &edit.to_string())?;
            step_json(session, &update, &before, &draw)
        })
        .await,
    )
}

async fn undo(State(studio): State<Arc<Studio>>, body: Bytes) -> Response {
    let draw = studio.draw_options();
    answer(
        with_session(&studio, move |session| {
            let file = body_file(&body_json(&body)?, session)?;
            let before = session.diagnostics(&file)?.to_vec();
            let update = session.undo(&file)?;
            step_json(session, &update, &before, &draw)
        })
        .await,
    )
}

async fn redo(State(studio): State<Arc<Studio>>, body: Bytes) -> Response {
    let draw = studio.draw_options();
    answer(
        with_session(&studio, move |session| {
            let file = body_file(&body_json(&body)?, session)?;
            let before = session.diagnostics(&file)?.to_vec();
            let update = session.redo(&file)?;
            step_json(session, &update, &before, &draw)
        })
        .await,
    )
}

async fn save(State(studio): State<Arc<Studio>>, body: Bytes) -> Response {
    answer(
        with_session(&studio, move |session| {
            let file = body_file(&body_json(&body)?, session)?;
            session.save(&file)?;
            Ok(json!({"file": file, "saved": true, "dirty": session.is_dirty(&file)?}))
        })
        .await,
    )
}

async fn stl(State(studio): State<Arc<Studio>>, uri: Uri) -> Response {
    answer(
        with_session(&studio, move |session| {
            let file = file_of(&uri, session)?;
            let block = match query_value(&uri, "block") {
                None => 0,
                Some(b) => b.parse::<usize>().map_err(|_| {
                    Refusal::BadRequest(format!("block={b} is not a block's place (0, 1, ...)"))
                })?,
            };
            let text = session.stl(&file, block)?;
            Ok(json!({"file": file, "block": block, "text": text}))
        })
        .await,
    )
}

async fn complete(State(studio): State<Arc<Studio>>, uri: Uri) -> Response {
    answer(
        with_session(&studio, move |session| {
            let file = file_of(&uri, session)?;
            let wanted = match query_value(&uri, "kind").as_deref() {
                None | Some("operand") => Wanted::Operand,
                Some("mnemonic") => Wanted::Mnemonic,
                Some(other) => {
                    return Err(Refusal::BadRequest(format!(
                        "kind={other}: ask for kind=operand or kind=mnemonic"
                    )))
                }
            };
            let element = query_value(&uri, "element").unwrap_or_else(|| "contact".into());
            if !matches!(element.as_str(), "contact" | "coil" | "box") {
                return Err(Refusal::BadRequest(format!(
                    "element={element}: ask for contact, coil or box"
                )));
            }
            let mnemonic = query_value(&uri, "mnemonic").filter(|m| !m.is_empty());
            let pin = query_value(&uri, "pin")
                .map(|p| p.parse::<usize>())
                .transpose()
                .map_err(|_| Refusal::BadRequest("pin= is an operand's place (0, 1, ...)".into()))?
                .unwrap_or(0);
            let prefix = query_value(&uri, "prefix").unwrap_or_default();
            let items = session.complete(
                &file,
                &CompletionRequest {
                    wanted,
                    element: &element,
                    mnemonic: mnemonic.as_deref(),
                    pin,
                    prefix: &prefix,
                },
            )?;
            Ok(json!({"items": items}))
        })
        .await,
    )
}

fn json_response(value: &Value) -> Response {
    json_answer(StatusCode::OK, value)
}

/// A JSON answer with `status`, never cached (every studio route answers this way).
pub(super) fn json_answer(status: StatusCode, value: &Value) -> Response {
    (
        status,
        [
            (header::CONTENT_TYPE, "application/json"),
            (header::CACHE_CONTROL, "no-store"),
        ],
        value.to_string(),
    )
        .into_response()
}
