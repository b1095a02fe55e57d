//! Why the studio's server refuses a request: one row per reason, with its stable code,
//! its HTTP status and its wording, answered as `{"code", "message", "error": {"code",
//! "message"}}` (an edit's L code also with its `path`). Every refusal of the server is
//! one of these; the checks that decide them are `security.rs`'s (token, origin),
//! `files.rs`'s (paths) and the session's (`StudioError`: files, edits).

use axum::http::{header, StatusCode};
use axum::response::{IntoResponse, Response};
use gutta_cli::studio::StudioError;
use serde_json::json;

/// A refused request.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Refusal {
    /// No token in the query, `X-Gutta-Token` or `Authorization: Bearer`.
    TokenMissing,
    /// A token that is not this run's.
    TokenWrong,
    /// An `Origin` header that is not the studio's own origin.
    OriginForeign(String),
    /// A path that leaves the project (`..`, absolute, a symlink out).
    PathEscape(String),
    /// A path that is empty or not valid text.
    PathInvalid(String),
    /// A write to a file that is not a `.lad` source.
    NotLad(String),
    /// A project file that does not exist.
    NotFound(String),
    /// A request without `?path=`.
    PathMissing,
    /// Reading or writing failed.
    Io(String),
    /// A file the session has not open.
    NotOpen(String),
    /// A block or network the file does not have.
    NoBlock(String),
    /// An edit, undo or redo the model refused: its L code, the JSON path at fault.
    Edit {
        code: String,
        path: String,
        message: String,
    },
    /// A request the server cannot read (a body that is not the JSON asked for, a
    /// missing field).
    BadRequest(String),
}

impl From<StudioError> for Refusal {
    fn from(e: StudioError) -> Refusal {
        match e {
            StudioError::Escape { path, .. } => Refusal::PathEscape(path),
            StudioError::NotOpen { file } => Refusal::NotOpen(file),
            StudioError::NoBlock { .. } => Refusal::NoBlock(e.to_string()),
            StudioError::Edit(m) => Refusal::Edit {
                code: m.code.as_str().to_string(),
                path: m.path.clone(),
                message: m.message,
            },
            StudioError::Io { .. } => Refusal::Io(e.to_string()),
            StudioError::NotAProgram { .. }
            | StudioError::NotUtf8 { .. }
            | StudioError::Project(_) => Refusal::BadRequest(e.to_string()),
        }
    }
}

impl Refusal {
    /// The stable code pages and scripts match on.
    pub(crate) fn code(&self) -> &str {
        match self {
            Refusal::TokenMissing => "token-missing",
            Refusal::TokenWrong => "token-wrong",
            Refusal::OriginForeign(_) => "origin-foreign",
            Refusal::PathEscape(_) => "path-escape",
            Refusal::PathInvalid(_) => "path-invalid",
            Refusal::NotLad(_) => "path-not-lad",
            Refusal::NotFound(_) => "not-found",
            Refusal::PathMissing => "path-missing",
            Refusal::Io(_) => "io",
            Refusal::NotOpen(_) => "not-open",
            Refusal::NoBlock(_) => "no-block",
            Refusal::Edit { code, .. } => code,
            Refusal::BadRequest(_) => "bad-request",
        }
    }

    pub(crate) fn status(&self) -> StatusCode {
        match self {
            Refusal::TokenMissing
            | Refusal::TokenWrong
            | Refusal::OriginForeign(_)
            | Refusal::PathEscape(_) => StatusCode::FORBIDDEN,
            Refusal::PathInvalid(_) | Refusal::NotLad(_) | Refusal::PathMissing => {
                StatusCode::BAD_REQUEST
            }
            Refusal::NotFound(_) | Refusal::NotOpen(_) | Refusal::NoBlock(_) => {
                StatusCode::NOT_FOUND
            }
            Refusal::Edit { .. } => StatusCode::UNPROCESSABLE_ENTITY,
            Refusal::BadRequest(_) => StatusCode::BAD_REQUEST,
            Refusal::Io(_) => StatusCode::INTERNAL_SERVER_ERROR,
        }
    }

    pub(crate) fn message(&self) -> String {
        match self {
            Refusal::TokenMissing => {
                "the request carries no token: open the address gutta-cc studio printed (with ?token=), or send X-Gutta-Token".into()
            }
            Refusal::TokenWrong => {
                "the token is not this studio's: use the address gutta-cc studio printed when it started".into()
            }
            Refusal::OriginForeign(origin) => {
                format!("a request from the page of {origin} is not the studio's own")
            }
            Refusal::PathEscape(path) => {
                format!("{path} is outside the project: the studio reads and writes only the project's files")
            }
            Refusal::PathInvalid(path) => format!("{path:?} is not a file path of the project"),
            Refusal::NotLad(path) => {
                format!("{path} is not a .lad source: the studio writes only the program's .lad files")
            }
            Refusal::NotFound(path) => format!("{path}: no such file in the project"),
            Refusal::PathMissing => "the request needs ?path=FILE (relative to the project)".into(),
            Refusal::Io(message) | Refusal::NoBlock(message) | Refusal::BadRequest(message) => {
                message.clone()
            }
            Refusal::NotOpen(file) => format!("{file} is not a file the studio has open"),
            Refusal::Edit { message, .. } => message.clone(),
        }
    }
}

impl IntoResponse for Refusal {
    fn into_response(self) -> Response {
        let (code, message) = (self.code(), self.message());
        let mut body = json!({
            "code": code,
            "message": message,
            "error": {"code": code, "message": message},
        });
        if let Refusal::Edit { path, .. } = &self {
            body["path"] = json!(path);
        }
        (
            self.status(),
            [
                (header::CONTENT_TYPE, "application/json"),
                (header::CACHE_CONTROL, "no-store"),
            ],
            body.to_string(),
        )
            .into_response()
    }
}
