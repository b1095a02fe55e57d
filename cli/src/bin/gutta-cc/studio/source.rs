//! The studio's STL and symbol endpoints (docs/studio.md, "STL and symbols"), merged
//! into `api::router` (behind its guard): `PUT /api/stl` (a block's STL, or with
//! `network` one network's lines, replaced: the session's `set_stl`/`set_network_stl`),
//! `GET /api/stl/block` and `/api/stl/network` (the text and its offset in the buffer),
//! `GET /api/stl/diagnostics`, `/api/stl/hover`, `/api/stl/complete` (the editor
//! analysis on the text), `GET /api/symbols` (the table with where each is declared, the
//! tables' dirt) and `POST /api/symbols` (`{op: add|set|rename, ...}`: the Updates of the
//! files it changed). Every answer is made from the session's buffers; nothing here
//! reads or writes a file.

use std::sync::Arc;

use axum::body::Bytes;
use axum::extract::State;
use axum::http::Uri;
use axum::response::Response;
use axum::routing::{get, put};
use gutta_cli::studio::{Session, SymbolChange};
use serde_json::{json, Value};

use super::api::{self, answer, body_json, file_of, update_json, Studio};
use super::refusal::Refusal;
use super::security::query_value;

/// The routes of this file, merged into `api::router`.
pub(crate) fn routes() -> axum::Router<Arc<Studio>> {
    axum::Router::new()
        .route("/api/stl", put(set_stl))
        .route("/api/stl/block", get(block_stl))
        .route("/api/stl/network", get(network_stl))
        .route("/api/stl/diagnostics", get(diagnostics))
        .route("/api/stl/hover", get(hover))
        .route("/api/stl/complete", get(complete))
        .route("/api/symbols", get(symbols).post(change_symbols))
}

/// `work` on the session off the server's threads (the lock is held only for it),
/// answered as JSON or as the refusal.
async fn with_session(
    studio: &Arc<Studio>,
    work: impl FnOnce(&mut Session) -> Result<Value, Refusal> + Send + 'static,
) -> Response {
    answer(api::with_session(studio, work).await)
}

/// A number in the query (`block`, `network`, `offset`); `default` when absent.
fn number(uri: &Uri, name: &str, default: Option<usize>) -> Result<usize, Refusal> {
    match query_value(uri, name) {
        Some(v) => v
            .parse()
            .map_err(|_| Refusal::BadRequest(format!("{name}={v} is not a number (0, 1, ...)"))),
        None => default.ok_or_else(|| Refusal::BadRequest(format!("the request needs ?{name}="))),
    }
}

fn to_value<T: serde::Serialize>(value: &T) -> Result<Value, Refusal> {
    serde_json::to_value(value).map_err(|e| Refusal::Io(e.to_string()))
}

/// `PUT /api/stl` `{"file", "block", "network"?, "text"}`.
async fn set_stl(State(studio): State<Arc<Studio>>, body: Bytes) -> Response {
    let draw = studio.draw_options();
    with_session(&studio, move |session| {
        let value = body_json(&body)?;
        let file = match value.get("file") {
            Some(Value::String(f)) => f.clone(),
            Some(_) => return Err(Refusal::BadRequest("\"file\" is not text".into())),
            None => session
                .files()
                .first()
                .map(|f| f.to_string())
                .ok_or_else(|| Refusal::BadRequest("the studio has no file open".into()))?,
        };
        let place = |key: &str| -> Result<Option<usize>, Refusal> {
            match value.get(key) {
                None | Some(Value::Null) => Ok(None),
                Some(v) => v
                    .as_u64()
                    .and_then(|n| usize::try_from(n).ok())
                    .map(Some)
                    .ok_or_else(|| {
                        Refusal::BadRequest(format!("\"{key}\" is not a place (0, 1, ...)"))
                    }),
            }
        };
        let block = place("block")?.unwrap_or(0);
        let Some(text) = value.get("text").and_then(Value::as_str) else {
            return Err(Refusal::BadRequest(
                "the body needs \"text\": the STL".into(),
            ));
        };
        let update = match place("network")? {
            Some(network) => session.set_network_stl(&file, block, network, text)?,
            None => session.set_stl(&file, block, text)?,
        };
        update_json(session, &update, &draw)
    })
    .await
}

async fn block_stl(State(studio): State<Arc<Studio>>, uri: Uri) -> Response {
    with_session(&studio, move |session| {
        let file = file_of(&uri, session)?;
        let block = number(&uri, "block", Some(0))?;
        to_value(&session.stl_text(&file, block)?)
    })
    .await
}

async fn network_stl(State(studio): State<Arc<Studio>>, uri: Uri) -> Response {
    with_session(&studio, move |session| {
        let file = file_of(&uri, session)?;
        let block = number(&uri, "block", Some(0))?;
        let network = number(&uri, "network", None)?;
        to_value(&session.network_stl(&file, block, network)?)
    })
    .await
}

async fn diagnostics(State(studio): State<Arc<Studio>>, uri: Uri) -> Response {
    with_session(&studio, move |session| {
        let file = file_of(&uri, session)?;
        let block = number(&uri, "block", Some(0))?;
        Ok(json!({
            "file": file,
            "block": block,
            "diagnostics": to_value(&session.stl_diagnostics(&file, block)?)?,
        }))
    })
    .await
}

async fn hover(State(studio): State<Arc<Studio>>, uri: Uri) -> Response {
    with_session(&studio, move |session| {
        let file = file_of(&uri, session)?;
        let offset = number(&uri, "offset", None)?;
        to_value(&session.stl_hover(&file, offset)?)
    })
    .await
}

async fn complete(State(studio): State<Arc<Studio>>, uri: Uri) -> Response {
    with_session(&studio, move |session| {
        let file = file_of(&uri, session)?;
        let offset = number(&uri, "offset", None)?;
        to_value(&session.stl_complete(&file, offset)?)
    })
    .await
}

async fn symbols(State(studio): State<Arc<Studio>>) -> Response {
    with_session(&studio, move |session| {
        let tables: Vec<Value> = session
            .tables()
            .iter()
            .map(|t| json!({"name": t, "dirty": session.table_is_dirty(t).unwrap_or(false)}))
            .collect();
        Ok(json!({"symbols": to_value(&session.symbol_table())?, "tables": tables}))
    })
    .await
}

/// `POST /api/symbols` `{"op": "add"|"set"|"rename", ...}`: the Updates of the files it
/// changed.
async fn change_symbols(State(studio): State<Arc<Studio>>, body: Bytes) -> Response {
    let draw = studio.draw_options();
    with_session(&studio, move |session| {
        let change: SymbolChange = serde_json::from_slice(&body).map_err(|e| {
            Refusal::BadRequest(format!(
                "the body is not a symbol change ({{\"op\": \"add\"|\"set\"|\"rename\", ...}}): {e}"
            ))
        })?;
        let updates = session.change_symbols(&change)?;
        let updates = updates
            .iter()
            .map(|u| update_json(session, u, &draw))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(json!({"updates": updates}))
    })
    .await
}
