//! `gutta-lsp`: the language server on standard input and output (docs/editors.md).
//! Exit status 0 after `shutdown` and `exit`, 1 when the connection breaks.

use std::process::ExitCode;

fn main() -> ExitCode {
    let (connection, io_threads) = lsp_server::Connection::stdio();
    let served = gutta_lsp::serve(&connection);
    drop(connection);
    let joined = io_threads.join();
    match (served, joined) {
        (Ok(()), Ok(())) => ExitCode::SUCCESS,
        (Err(e), _) => {
            eprintln!("gutta-lsp: {e}");
            ExitCode::from(1)
        }
        (_, Err(e)) => {
            eprintln!("gutta-lsp: {e}");
            ExitCode::from(1)
        }
    }
}
