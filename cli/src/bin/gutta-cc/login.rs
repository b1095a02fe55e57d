//! gutta-cc's side of the login: the `--password` warning, the no-echo prompt on a
//! terminal, and what a failed login says (refused or locked out). Where the password
//! comes from (`--password`, `GUTTA_PASSWORD`, the factory password, then the prompt)
//! is gutta-link's `Credentials` and `Session::log_in`; this file only reads the
//! environment, asks the terminal and prints.

use std::io::IsTerminal;

use gutta_cli::fatal::Fatal;
use gutta_link::{
    Client, Credentials, LinkError, LoginError, PasswordPrompt, PasswordSource, Session,
    PASSWORD_ENV,
};

use crate::args::LinkArgs;

/// The password lookup of `args` and the environment; warns when it is the flag's.
fn credentials(args: &LinkArgs) -> Credentials {
    let environment = std::env::var(PASSWORD_ENV).ok();
    let credentials = Credentials::lookup(args.password.as_deref(), environment.as_deref());
    if matches!(credentials.source, PasswordSource::Flag(_)) {
        eprintln!(
            "gutta-cc: warning: --password is visible to other users of this machine \
             (ps, shell history); prefer {PASSWORD_ENV} or the prompt"
        );
    }
    credentials
}

/// The no-echo prompt, when stdin is a terminal.
struct TerminalPrompt;

impl PasswordPrompt for TerminalPrompt {
    fn ask(&mut self, endpoint: &str) -> Result<Option<String>, String> {
        if !std::io::stdin().is_terminal() {
            return Ok(None);
        }
        rpassword::prompt_password(format!("Password for PLC at {endpoint}: "))
            .map(Some)
            .map_err(|e| e.to_string())
    }
}

/// Log `client` (connected to the PLC at `endpoint`) in with the password the options,
/// the environment or the user give.
pub(crate) fn log_in(client: Client, endpoint: &str, args: &LinkArgs) -> Result<Session, Fatal> {
    let credentials = credentials(args);
    Session::log_in(client, endpoint, &credentials, &mut TerminalPrompt).map_err(|e| match e {
        LoginError::Link(e) => failure(e),
        LoginError::PasswordNeeded(_) => Fatal::link(format!(
            "refused: the PLC has a password (the factory password was refused); \
             set {PASSWORD_ENV}, or pass --password (visible to other users)"
        )),
        LoginError::Prompt(e) => {
            Fatal::io(format!("cannot read the password from the terminal: {e}"))
        }
    })
}

/// A failed login as the user reads it: refused (a wrong password, and the
/// simulator's lockout policy) or locked out (docs/simulator.md, password policy).
pub(crate) fn failure(e: LinkError) -> Fatal {
    if gutta_link::session::is_wrong_password(&e) {
        return Fatal::link(
            "refused: wrong password (the PLC locks ATTACH from the third wrong password \
             in a row: 1 s, doubling up to 60 s)",
        );
    }
    match e {
        LinkError::LockedOut => Fatal::link(
            "locked: the PLC refuses logins for 1 s to 60 s (doubling) after repeated \
             wrong passwords; wait and retry",
        ),
        e => Fatal::link(e.to_string()),
    }
}
