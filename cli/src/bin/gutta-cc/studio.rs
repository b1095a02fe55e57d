//! `gutta-cc studio [PROJECT_DIR | FILE.lad...] [--http HOST:PORT] [--no-open]`
//! (docs/studio.md, "The server"): the studio's HTTP server (axum). It binds loopback
//! on a free port unless told otherwise, prints `gutta-cc studio: http://HOST:PORT/?token=
//! TOKEN` as its first line on stdout, opens the browser (unless `--no-open`), and serves
//! until Ctrl-C (exit 0). The program is opened once as a `gutta_cli::studio::Session`
//! (the page's one truth). Who may ask is `studio/security.rs`'s, which files
//! `studio/files.rs`'s, the endpoints `studio/api.rs`'s, the drawn networks
//! `studio/drawing.rs`'s; this file wires them.

mod api;
mod drawing;
mod files;
mod live;
mod online;
mod refusal;
mod security;
mod source;

use std::process::{ExitCode, Stdio};
use std::sync::Arc;

use gutta_cli::fatal::Fatal;

use crate::args::{Cli, StudioArgs};
use api::Studio;
use files::ProgramFiles;
use security::{Guard, Token};

/// Serve the studio until Ctrl-C: exit 0; a program that cannot be read, a random
/// source or an address that fails, exit 2 before the first line.
pub(crate) fn studio(cli: &Cli, options: &StudioArgs) -> Result<ExitCode, Fatal> {
    let files = ProgramFiles::from_command_line(cli, &options.paths)?;
    // The session reads and checks every file now: one that cannot be read fails
    // before the first line, not at the first request.
    let session = files.open_session()?;
    let token = Token::generate()
        .map_err(|e| Fatal::io(format!("cannot read the system's random source: {e}")))?;
    crate::serve::until_ctrl_c(&options.http, |at| {
        let url = format!("http://{at}/?token={}", token.as_str());
        println!("gutta-cc studio: {url}");
        eprintln!(
            "gutta-cc studio: {} in {} (Ctrl-C ends)",
            files.name,
            files.root.display()
        );
        if !options.no_open {
            open_browser(&url);
        }
        let guard = Guard::new(token.clone(), at);
        api::router(
            Arc::new(Studio {
                session: Arc::new(std::sync::Mutex::new(session)),
                live: std::sync::Mutex::new(None),
                token,
                writing: std::sync::Mutex::new(()),
                draw: std::sync::Mutex::new(gutta_ladder::svg::DrawOptions::default()),
            }),
            guard,
        )
    })?;
    Ok(ExitCode::SUCCESS)
}

/// The platform's opener, started and left alone; if it cannot start, a warning (the
/// address is on stdout).
fn open_browser(url: &str) {
    let mut command = if cfg!(target_os = "macos") {
        std::process::Command::new("open")
    } else if cfg!(windows) {
        let mut c = std::process::Command::new("cmd");
        c.args(["/C", "start", ""]);
        c
    } else {
        std::process::Command::new("xdg-open")
    };
    let started = command
        .arg(url)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn();
    match started {
        // Reap it when it ends, so it never lingers as a zombie.
        Ok(mut child) => {
            std::thread::spawn(move || child.wait());
        }
        Err(e) => eprintln!(
            "warning: cannot open a browser ({:?}: {e}); open the address above",
            command.get_program()
        ),
    }
}
