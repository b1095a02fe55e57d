//! The server loop: the handshake, then every message dispatched through one table of
//! request and notification handlers (`handlers::requests()` / `notifications()`).
//! Each handler runs under `catch_unwind`, so a bug answers an LSP error instead of
//! killing the server; params that do not deserialize answer InvalidParams; unknown
//! requests answer MethodNotFound; `$/cancelRequest` and unknown notifications are
//! ignored (every request is answered before the next message is read). It holds the
//! server's state but knows no feature: features are rows in handlers/mod.rs.

use std::collections::{HashMap, HashSet};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

use crossbeam_channel::Sender;
use lsp_server::{
    Connection, ErrorCode, Message, Notification, Request, RequestId, Response, ResponseError,
};
use lsp_types::notification::Notification as LspNotification;
use lsp_types::request::Request as LspRequest;
use lsp_types::{InitializeParams, InitializeResult, MessageType, ServerInfo, ShowMessageParams};
use serde_json::Value;

use crate::documents::Documents;
use crate::workspace::Workspace;
use crate::{capabilities, handlers};

/// Everything the handlers share: open documents, the programs they belong to, what
/// the client said at `initialize`, and a way to send it messages.
#[derive(Debug)]
pub struct State {
    pub documents: Documents,
    pub workspace: Workspace,
    /// The client's `initialize` params (capabilities, initializationOptions).
    pub init: InitializeParams,
    /// Where docs/diagnostics.md is installed, as a `file:` URI (for `codeDescription`).
    pub diagnostics_doc: Option<String>,
    /// Warnings already shown to the person (each is shown once per session).
    pub warned: HashSet<String>,
    /// Live values from the PLC (live.rs): the setting and the pollers.
    pub live: crate::live::Live,
    sender: Sender<Message>,
    next_request: i32,
}

/// Why a request failed: an LSP error code and a message for the client.
#[derive(Debug, Clone)]
pub struct HandlerError {
    pub code: ErrorCode,
    pub message: String,
}

impl HandlerError {
    pub fn invalid_params(message: impl Into<String>) -> HandlerError {
        HandlerError {
            code: ErrorCode::InvalidParams,
            message: message.into(),
        }
    }

    pub fn failed(message: impl Into<String>) -> HandlerError {
        HandlerError {
            code: ErrorCode::RequestFailed,
            message: message.into(),
        }
    }
}

/// A request handler: typed params in, typed result out.
pub type RequestHandler<R> =
    fn(&mut State, <R as LspRequest>::Params) -> Result<<R as LspRequest>::Result, HandlerError>;

/// A notification handler.
pub type NotificationHandler<N> =
    fn(&mut State, <N as LspNotification>::Params) -> Result<(), HandlerError>;

type ErasedHandler = Box<dyn Fn(&mut State, Value) -> Result<Value, HandlerError>>;

/// One row of the dispatch table: an LSP method and its handler.
pub struct Row {
    pub method: &'static str,
    run: ErasedHandler,
}

impl std::fmt::Debug for Row {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Row").field("method", &self.method).finish()
    }
}

/// The row for request `R` answered by `handler`.
pub fn request<R>(handler: RequestHandler<R>) -> Row
where
    R: LspRequest + 'static,
{
    Row {
        method: R::METHOD,
        run: Box::new(move |state, params| {
            let params = serde_json::from_value(params)
                .map_err(|e| HandlerError::invalid_params(format!("{}: {e}", R::METHOD)))?;
            let result = handler(state, params)?;
            serde_json::to_value(result).map_err(|e| HandlerError::failed(e.to_string()))
        }),
    }
}

/// The row for notification `N` handled by `handler`.
pub fn notification<N>(handler: NotificationHandler<N>) -> Row
where
    N: LspNotification + 'static,
{
    Row {
        method: N::METHOD,
        run: Box::new(move |state, params| {
            let params = serde_json::from_value(params)
                .map_err(|e| HandlerError::invalid_params(format!("{}: {e}", N::METHOD)))?;
            handler(state, params)?;
            Ok(Value::Null)
        }),
    }
}

impl State {
    fn new(init: InitializeParams, sender: Sender<Message>) -> State {
        State {
            live: crate::live::Live::from_init(&init, sender.clone()),
            documents: Documents::default(),
            workspace: Workspace::default(),
            init,
            diagnostics_doc: crate::convert::find_diagnostics_doc(),
            warned: HashSet::new(),
            sender,
            next_request: 0,
        }
    }

    /// Send notification `N` to the client.
    pub fn notify<N: LspNotification>(&self, params: N::Params) {
        let note = Notification::new(N::METHOD.to_string(), params);
        // A closed channel means the client is gone; the loop ends on its own then.
        let _ = self.sender.send(Message::Notification(note));
    }

    /// Send request `R` to the client (its answer is ignored), e.g. a refresh.
    pub fn request_client<R: LspRequest>(&mut self, params: R::Params) {
        self.next_request += 1;
        let id = RequestId::from(format!("gutta-{}", self.next_request));
        let _ = self.sender.send(Message::Request(Request::new(
            id,
            R::METHOD.to_string(),
            params,
        )));
    }

    /// A message for the person (window/showMessage).
    pub fn show_message(&self, typ: MessageType, message: impl Into<String>) {
        self.notify::<lsp_types::notification::ShowMessage>(ShowMessageParams {
            typ,
            message: message.into(),
        });
    }

    /// A clone of the channel to the client, for threads that send on their own.
    pub fn sender(&self) -> Sender<Message> {
        self.sender.clone()
    }

    /// The workspace folders the client named at `initialize`, as paths.
    pub fn workspace_roots(&self) -> Vec<PathBuf> {
        self.init
            .workspace_folders
            .iter()
            .flatten()
            .filter_map(|f| crate::documents::uri_to_path(&f.uri))
            .collect()
    }
}

/// Serve `connection` until the client says `exit` (after `shutdown`, or without it).
pub fn run(connection: &Connection) -> Result<(), String> {
    let (id, params) = connection
        .initialize_start()
        .map_err(|e| format!("initialize: {e}"))?;
    let init: InitializeParams = match serde_json::from_value(params) {
        Ok(init) => init,
        Err(e) => {
            let response = Response::new_err(
                id,
                ErrorCode::InvalidParams as i32,
                format!("initialize: {e}"),
            );
            let _ = connection.sender.send(Message::Response(response));
            return Err(format!("initialize: {e}"));
        }
    };
    let result = InitializeResult {
        capabilities: capabilities(),
        server_info: Some(ServerInfo {
            name: "gutta-lsp".into(),
            version: Some(env!("CARGO_PKG_VERSION").into()),
        }),
    };
    let value = serde_json::to_value(result).map_err(|e| e.to_string())?;
    connection
        .initialize_finish(id, value)
        .map_err(|e| format!("initialize: {e}"))?;

    let requests = table(handlers::requests());
    let notifications = table(handlers::notifications());
    let mut state = State::new(init, connection.sender.clone());
    handlers::initialized(&mut state);
    for message in &connection.receiver {
        match message {
            Message::Request(request) => {
                if connection
                    .handle_shutdown(&request)
                    .map_err(|e| e.to_string())?
                {
                    return Ok(());
                }
                let response = answer(&mut state, &requests, request);
                connection
                    .sender
                    .send(Message::Response(response))
                    .map_err(|e| e.to_string())?;
            }
            Message::Notification(note) => {
                if note.method == lsp_types::notification::Exit::METHOD {
                    return Ok(());
                }
                notify(&mut state, &notifications, note);
            }
            // Answers to our refresh requests: nothing to do.
            Message::Response(_) => {}
        }
    }
    Ok(())
}

fn table(rows: Vec<Row>) -> HashMap<&'static str, Row> {
    rows.into_iter().map(|row| (row.method, row)).collect()
}

fn answer(state: &mut State, table: &HashMap<&'static str, Row>, request: Request) -> Response {
    let Some(row) = table.get(request.method.as_str()) else {
        return Response::new_err(
            request.id,
            ErrorCode::MethodNotFound as i32,
            format!("gutta-lsp does not serve `{}`", request.method),
        );
    };
    match run_guarded(state, row, request.params) {
        Ok(value) => Response {
            id: request.id,
            result: Some(value),
            error: None,
        },
        Err(e) => Response {
            id: request.id,
            result: None,
            error: Some(ResponseError {
                code: e.code as i32,
                message: e.message,
                data: None,
            }),
        },
    }
}

fn notify(state: &mut State, table: &HashMap<&'static str, Row>, note: Notification) {
    // `$/cancelRequest`, `$/setTrace` and anything else unknown: nothing to do (every
    // request is answered before the next message is read, so none can be cancelled).
    let Some(row) = table.get(note.method.as_str()) else {
        return;
    };
    if let Err(e) = run_guarded(state, row, note.params) {
        state.notify::<lsp_types::notification::LogMessage>(lsp_types::LogMessageParams {
            typ: MessageType::ERROR,
            message: format!("gutta-lsp: {}: {}", note.method, e.message),
        });
    }
}

/// Run a handler; a panic becomes an InternalError naming the method.
fn run_guarded(state: &mut State, row: &Row, params: Value) -> Result<Value, HandlerError> {
    match catch_unwind(AssertUnwindSafe(|| (row.run)(state, params))) {
        Ok(result) => result,
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_default();
            Err(HandlerError {
                code: ErrorCode::InternalError,
                message: format!("gutta-lsp: internal error in {}: {what}", row.method),
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lsp_types::request::{HoverRequest, Shutdown};

    fn state() -> State {
        let (sender, _receiver) = crossbeam_channel::unbounded();
        State::new(InitializeParams::default(), sender)
    }

    fn panicking(_: &mut State, _: ()) -> Result<(), HandlerError> {
        panic!("deliberate")
    }

    #[test]
    fn a_panicking_handler_answers_internal_error_and_bad_params_invalid_params() {
        let mut state = state();
        let table = table(vec![
            request::<Shutdown>(panicking),
            request::<HoverRequest>(crate::handlers::navigation::hover),
        ]);
        let ask = |method: &str, params: Value| Request {
            id: RequestId::from(1),
            method: method.into(),
            params,
        };
        let r = answer(&mut state, &table, ask("shutdown", Value::Null));
        let e = r.error.expect("an error");
        assert_eq!(e.code, ErrorCode::InternalError as i32);
        assert!(e.message.contains("deliberate"), "{}", e.message);
        let r = answer(
            &mut state,
            &table,
            ask("textDocument/hover", serde_json::json!({"textDocument": 5})),
        );
        assert_eq!(
            r.error.expect("an error").code,
            ErrorCode::InvalidParams as i32
        );
        let r = answer(&mut state, &table, ask("gutta/none", Value::Null));
        assert_eq!(
            r.error.expect("an error").code,
            ErrorCode::MethodNotFound as i32
        );
        // The state survives: a valid request still answers.
        let r = answer(
            &mut state,
            &table,
            ask(
                "textDocument/hover",
                serde_json::json!({"textDocument": {"uri": "file:///x.lad"}, "position": {"line": 0, "character": 0}}),
            ),
        );
        assert_eq!(r.result, Some(Value::Null));
    }
}
