//! gutta-lsp: the language server for GUTTA PLC programs (docs/editors.md). The server
//! loop runs over any `lsp_server::Connection` (stdio in the binary, memory in tests);
//! every answer comes from gutta-compiler's analysis API. Only this crate knows LSP
//! types and UTF-16 positions.

pub mod live;

use lsp_server::{Connection, Message, Response};
use lsp_types::{InitializeResult, ServerCapabilities, ServerInfo};

/// What the server can do, as told to the client in `initialize`.
pub fn capabilities() -> ServerCapabilities {
    ServerCapabilities::default()
}

/// Serve `connection` until the client says `exit`: the handshake, then every message.
pub fn serve(connection: &Connection) -> Result<(), String> {
    let (id, _params) = connection
        .initialize_start()
        .map_err(|e| format!("initialize: {e}"))?;
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
    for message in &connection.receiver {
        match message {
            Message::Request(request) => {
                if connection
                    .handle_shutdown(&request)
                    .map_err(|e| e.to_string())?
                {
                    return Ok(());
                }
                let response = Response::new_err(
                    request.id,
                    lsp_server::ErrorCode::MethodNotFound as i32,
                    format!("gutta-lsp does not serve `{}`", request.method),
                );
                connection
                    .sender
                    .send(Message::Response(response))
                    .map_err(|e| e.to_string())?;
            }
            Message::Notification(_) | Message::Response(_) => {}
        }
    }
    Ok(())
}
