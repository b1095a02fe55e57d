//! Live values on the page (docs/studio.md, "Live state"): the one interface the
//! simulator (SIMULATE) and a connected PLC (ONLINE) both offer the server, so the page
//! paints power flow, runs and stops, writes and forces the same way in either mode;
//! the simulator's side of it (`SimSource`, over `gutta_cli::studio::Simulator`); and
//! the routes that drive whichever source is active: `POST /api/simulate`, `GET
//! /api/live`, `POST /api/live/{run,stop,write,force,toggle,read}`, `POST
//! /api/edit-mode`. The session's mutex is held only to compile the program, never
//! while a source scans or talks to a PLC; each request runs off the server's threads.

use std::sync::Arc;

use axum::body::Bytes;
use axum::extract::State;
use axum::http::StatusCode;
use axum::response::Response;
use axum::routing::{get, post};
use gutta_cli::studio::sim::SimError;
use gutta_cli::studio::Simulator;
use serde::Serialize;
use serde_json::{json, Value};

use super::api::{json_answer, Studio};

/// A refusal or failure of a live source: a stable code (`not-running`, `no-operand`,
/// `plc-error`, ...) and a message that says what to do.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub(crate) struct LiveError {
    pub code: &'static str,
    pub message: String,
}

/// One row of the watch table: an operand (symbol or address, as the user typed it) and
/// the format to show it in (`bit`, `signed`, `unsigned`, `hex`, `binary`, `ascii`,
/// `float`; None: the operand's own).
#[derive(Debug, Clone, PartialEq, Eq, serde::Deserialize)]
pub(crate) struct WatchRequest {
    pub operand: String,
    pub format: Option<String>,
}

/// A watch table row's answer: the canonical address, the value shown in its format,
/// whether it is forced, or why it cannot be read.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub(crate) struct WatchValue {
    pub operand: String,
    pub address: Option<String>,
    pub value: Option<String>,
    pub forced: bool,
    pub error: Option<LiveError>,
}

/// The simulator or a PLC, as the server drives it.
pub(crate) trait LiveSource: Send {
    /// `"SIMULATE"` or `"ONLINE"`.
    fn mode(&self) -> &'static str;
    /// One update for the page: the `/api/live` object (docs/studio.md, "Live state").
    fn state(&mut self) -> serde_json::Value;
    /// The program runs (RUN).
    fn run(&mut self) -> Result<(), LiveError>;
    /// The program stops (STOP): outputs as the PLC leaves them, no power flow shown.
    fn stop(&mut self) -> Result<(), LiveError>;
    /// `value` (as `gutta-cc write` takes it: `1`, `-5`, `16#FF`, `2.5`) written into
    /// `operand` (a symbol or an address).
    fn write(&mut self, operand: &str, value: &str) -> Result<(), LiveError>;
    /// `operand` forced to `value`, or released (None).
    fn force(&mut self, operand: &str, value: Option<&str>) -> Result<(), LiveError>;
    /// The watch table's rows read now.
    fn read(&mut self, rows: &[WatchRequest]) -> Vec<WatchValue>;
    /// A click on an input contact: an input bit that is not forced is forced to the
    /// opposite of its value now, a forced one released (docs/studio.md, "Simulate").
    /// By default through `read` and `force`; a source may do it its own way.
    fn toggle(&mut self, operand: &str) -> Result<(), LiveError> {
        let row = self
            .read(&[WatchRequest {
                operand: operand.to_string(),
                format: Some("bool".into()),
            }])
            .pop()
            .ok_or_else(|| not_an_input(operand))?;
        if let Some(error) = row.error {
            return Err(error);
        }
        let address = row.address.unwrap_or_default();
        if !(address.starts_with('I') && address.contains('.')) {
            return Err(not_an_input(operand));
        }
        if row.forced {
            self.force(&address, None)
        } else {
            let flipped = if row.value.as_deref() == Some("1") {
                "0"
            } else {
                "1"
            };
            self.force(&address, Some(flipped))
        }
    }
}

fn not_an_input(operand: &str) -> LiveError {
    LiveError {
        code: "not-an-input",
        message: format!(
            "{operand} is not an input bit: only an I contact toggles; write or force other variables in the watch table"
        ),
    }
}

/// The simulator as a live source (mode SIMULATE).
pub(crate) struct SimSource(pub Simulator);

impl From<SimError> for LiveError {
    fn from(e: SimError) -> LiveError {
        LiveError {
            code: e.code,
            message: e.message,
        }
    }
}

impl LiveSource for SimSource {
    fn mode(&self) -> &'static str {
        "SIMULATE"
    }

    fn state(&mut self) -> Value {
        self.0.state()
    }

    fn run(&mut self) -> Result<(), LiveError> {
        self.0.run();
        Ok(())
    }

    fn stop(&mut self) -> Result<(), LiveError> {
        self.0.stop();
        Ok(())
    }

    fn write(&mut self, operand: &str, value: &str) -> Result<(), LiveError> {
        Ok(self.0.write(operand, value)?)
    }

    fn force(&mut self, operand: &str, value: Option<&str>) -> Result<(), LiveError> {
        match value {
            Some(value) => Ok(self.0.force(operand, value)?),
            None => Ok(self.0.release(operand)?),
        }
    }

    fn read(&mut self, rows: &[WatchRequest]) -> Vec<WatchValue> {
        rows.iter()
            .map(
                |row| match self.0.read(&row.operand, row.format.as_deref()) {
                    Ok(w) => WatchValue {
                        operand: row.operand.clone(),
                        address: Some(w.address),
                        value: Some(w.value),
                        forced: w.forced,
                        error: None,
                    },
                    Err(e) => WatchValue {
                        operand: row.operand.clone(),
                        address: None,
                        value: None,
                        forced: false,
                        error: Some(e.into()),
                    },
                },
            )
            .collect()
    }

    fn toggle(&mut self, operand: &str) -> Result<(), LiveError> {
        Ok(self.0.toggle(operand)?)
    }
}

/// The live routes (merged into `api::router`, behind its guard).
pub(crate) fn routes() -> axum::Router<Arc<Studio>> {
    axum::Router::new()
        .route("/api/simulate", post(simulate))
        .route("/api/live", get(live))
        .route("/api/live/run", post(run))
        .route("/api/live/stop", post(stop))
        .route("/api/live/write", post(write))
        .route("/api/live/force", post(force))
        .route("/api/live/toggle", post(toggle))
        .route("/api/live/read", post(read))
        .route("/api/edit-mode", post(edit_mode))
}

/// A refusal: `{"code", "message"}` with `status`.
fn refused(status: StatusCode, error: &LiveError) -> Response {
    json_answer(
        status,
        &json!({"code": error.code, "message": error.message}),
    )
}

fn refusal(status: StatusCode, code: &'static str, message: impl Into<String>) -> Response {
    refused(
        status,
        &LiveError {
            code,
            message: message.into(),
        },
    )
}

/// `f` off the server's threads (a PLC may take its time; the simulator never does).
async fn blocking(f: impl FnOnce() -> Response + Send + 'static) -> Response {
    tokio::task::spawn_blocking(f)
        .await
        .unwrap_or_else(|e| refusal(StatusCode::INTERNAL_SERVER_ERROR, "internal", e.to_string()))
}

/// `f` on the active source, under the live lock only; `{"mode":"EDIT"}`'s 409 when
/// there is none.
fn with_source(
    studio: &Studio,
    f: impl FnOnce(&mut dyn LiveSource) -> Result<Value, LiveError>,
) -> Response {
    let mut live = studio.live.lock().unwrap_or_else(|e| e.into_inner());
    match live.as_deref_mut() {
        Some(source) => match f(source) {
            Ok(value) => json_answer(StatusCode::OK, &value),
            Err(e) => refused(status_of(&e), &e),
        },
        None => refusal(
            StatusCode::CONFLICT,
            "not-live",
            "the studio is in EDIT: simulate or go online first",
        ),
    }
}

/// A source's refusal: bad input is the request's fault (400), the rest 409 or 502.
fn status_of(e: &LiveError) -> StatusCode {
    match e.code {
        "no-operand" | "bad-value" | "bad-format" | "not-forceable" | "not-an-input"
        | "bad-request" => StatusCode::BAD_REQUEST,
        "plc-error" => StatusCode::BAD_GATEWAY,
        _ => StatusCode::CONFLICT,
    }
}

/// A request body as `T`, or a 400 that says what was expected.
fn body<T: serde::de::DeserializeOwned>(bytes: &[u8], expected: &str) -> Result<T, LiveError> {
    serde_json::from_slice(bytes).map_err(|e| LiveError {
        code: "bad-request",
        message: format!("the body must be JSON {expected}: {e}"),
    })
}

/// `POST /api/simulate`: the session's current program compiled and started in RUN
/// (any source before it stopped first); 409 with the compiler's code when it has an
/// error.
async fn simulate(State(studio): State<Arc<Studio>>) -> Response {
    blocking(move || {
        let program = {
            let session = studio.session.lock().unwrap_or_else(|e| e.into_inner());
            session.run_program()
        };
        let program = match program {
            Ok(p) => p,
            Err(e) => {
                return json_answer(
                    StatusCode::CONFLICT,
                    &json!({
                        "code": e.code,
                        "message": e.to_string(),
                        "file": e.file,
                        "line": e.line,
                        "column": e.column,
                    }),
                )
            }
        };
        // The old source goes first (its thread or connection ends) ...
        let old = studio.live.lock().unwrap_or_else(|e| e.into_inner()).take();
        drop(old);
        // ... then the new one starts.
        match Simulator::start(program) {
            Ok(sim) => {
                let mut source = SimSource(sim);
                let state = source.state();
                *studio.live.lock().unwrap_or_else(|e| e.into_inner()) = Some(Box::new(source));
                json_answer(StatusCode::OK, &state)
            }
            Err(e) => refused(StatusCode::CONFLICT, &e.into()),
        }
    })
    .await
}

/// `GET /api/live`: the active source's state; `{"mode":"EDIT"}` without one.
async fn live(State(studio): State<Arc<Studio>>) -> Response {
    blocking(move || {
        let mut live = studio.live.lock().unwrap_or_else(|e| e.into_inner());
        match live.as_deref_mut() {
            Some(source) => json_answer(StatusCode::OK, &source.state()),
            None => json_answer(StatusCode::OK, &json!({"mode": "EDIT"})),
        }
    })
    .await
}

async fn run(State(studio): State<Arc<Studio>>) -> Response {
    blocking(move || with_source(&studio, |s| s.run().map(|()| s.state()))).await
}

async fn stop(State(studio): State<Arc<Studio>>) -> Response {
    blocking(move || with_source(&studio, |s| s.stop().map(|()| s.state()))).await
}

#[derive(serde::Deserialize)]
struct WriteBody {
    operand: String,
    value: Value,
}

#[derive(serde::Deserialize)]
struct ForceBody {
    operand: String,
    #[serde(default)]
    value: Value,
}

#[derive(serde::Deserialize)]
struct ToggleBody {
    operand: String,
}

#[derive(serde::Deserialize)]
struct ReadBody {
    rows: Vec<WatchRequest>,
}

/// A value as text: `"16#FF"`, `5`, `true` all as `gutta-cc write` takes them.
fn value_text(value: &Value) -> Option<String> {
    match value {
        Value::String(s) => Some(s.clone()),
        Value::Number(n) => Some(n.to_string()),
        Value::Bool(b) => Some(if *b { "1" } else { "0" }.into()),
        _ => None,
    }
}

/// `POST /api/live/write {operand, value}`.
async fn write(State(studio): State<Arc<Studio>>, bytes: Bytes) -> Response {
    blocking(move || {
        with_source(&studio, |s| {
            let b: WriteBody = body(&bytes, "{\"operand\": NAME, \"value\": VALUE}")?;
            let value = value_text(&b.value).ok_or_else(|| LiveError {
                code: "bad-value",
                message: format!("{}: the value must be a number or text", b.operand),
            })?;
            s.write(&b.operand, &value).map(|()| s.state())
        })
    })
    .await
}

/// `POST /api/live/force {operand, value}`; `value` null releases.
async fn force(State(studio): State<Arc<Studio>>, bytes: Bytes) -> Response {
    blocking(move || {
        with_source(&studio, |s| {
            let b: ForceBody = body(&bytes, "{\"operand\": NAME, \"value\": VALUE or null}")?;
            let value = value_text(&b.value);
            if value.is_none() && !b.value.is_null() {
                return Err(LiveError {
                    code: "bad-value",
                    message: format!("{}: the value must be a number, text or null", b.operand),
                });
            }
            s.force(&b.operand, value.as_deref()).map(|()| s.state())
        })
    })
    .await
}

/// `POST /api/live/toggle {operand}`: a click on an input contact.
async fn toggle(State(studio): State<Arc<Studio>>, bytes: Bytes) -> Response {
    blocking(move || {
        with_source(&studio, |s| {
            let b: ToggleBody = body(&bytes, "{\"operand\": NAME}")?;
            s.toggle(&b.operand).map(|()| s.state())
        })
    })
    .await
}

/// `POST /api/live/read {rows: [{operand, format}]}`: `{rows: [...]}` in order.
async fn read(State(studio): State<Arc<Studio>>, bytes: Bytes) -> Response {
    blocking(move || {
        with_source(&studio, |s| {
            let b: ReadBody = body(
                &bytes,
                "{\"rows\": [{\"operand\": NAME, \"format\": FORMAT}]}",
            )?;
            Ok(json!({"rows": s.read(&b.rows)}))
        })
    })
    .await
}

/// `POST /api/edit-mode`: the active source stopped and dropped; back to EDIT.
async fn edit_mode(State(studio): State<Arc<Studio>>) -> Response {
    blocking(move || {
        let old = studio.live.lock().unwrap_or_else(|e| e.into_inner()).take();
        if let Some(mut source) = old {
            if source.mode() == "SIMULATE" {
                let _ = source.stop();
            }
        }
        json_answer(StatusCode::OK, &json!({"mode": "EDIT"}))
    })
    .await
}
