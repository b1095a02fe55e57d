//! `gutta-lsp`: the language server on standard input and output (docs/editors.md).
//! Exit status 0 after `shutdown` and `exit`, 1 when the connection breaks; `--help`
//! and `--version` print and exit 0, any other argument is a usage error (status 2).
//! Only the arguments are read here: serving is `gutta_lsp::serve`.

use std::process::ExitCode;

const USAGE: &str = "Usage: gutta-lsp [--stdio]\n       gutta-lsp --help | --version";

fn help() -> String {
    format!(
        "gutta-lsp {}: the language server for GUTTA PLC programs\n\n\
         An editor starts it and speaks the Language Server Protocol with it on standard\n\
         input and output (diagnostics, completion, hover, go to definition, rename,\n\
         formatting, live values); it is not run by hand. docs/editors.md shows how to\n\
         set it up in VS Code, Neovim and other editors.\n\n\
         {USAGE}\n\n\
         Options:\n  \
           --stdio        Serve on standard input and output (the default; editors may pass it)\n  \
           -h, --help     Print this help\n  \
           -V, --version  Print the version\n",
        env!("CARGO_PKG_VERSION")
    )
}

/// What the command line asks for.
enum Command {
    Serve,
    Help,
    Version,
}

/// The command line without the program name; the first argument that is none of ours
/// is the error.
fn command(args: impl IntoIterator<Item = String>) -> Result<Command, String> {
    let mut command = Command::Serve;
    for arg in args {
        match arg.as_str() {
            "--stdio" => {}
            "-h" | "--help" => command = Command::Help,
            "-V" | "--version" => {
                if !matches!(command, Command::Help) {
                    command = Command::Version;
                }
            }
            _ => return Err(arg),
        }
    }
    Ok(command)
}

fn main() -> ExitCode {
    match command(std::env::args().skip(1)) {
        Ok(Command::Serve) => serve(),
        Ok(Command::Help) => {
            print!("{}", help());
            ExitCode::SUCCESS
        }
        Ok(Command::Version) => {
            println!("gutta-lsp {}", env!("CARGO_PKG_VERSION"));
            ExitCode::SUCCESS
        }
        Err(arg) => {
            eprintln!(
                "gutta-lsp: unexpected argument `{arg}`\n\n{USAGE}\n\n\
                 An editor starts gutta-lsp on stdio (docs/editors.md); try `gutta-lsp --help`."
            );
            ExitCode::from(2)
        }
    }
}

fn serve() -> ExitCode {
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
