//! gutta-cc's login: where the password comes from (`--password`, `GUTTA_PASSWORD`, the
//! factory password, then a no-echo prompt on a terminal) and what a failed login says
//! (refused or locked out). It sends PLC_ATTACH only; it does not connect or print
//! anything but the `--password` warning and the prompt.

use std::io::IsTerminal;

use gutta_cli::fatal::Fatal;
use gutta_link::{Client, LinkError, FACTORY_PASSWORD};

use crate::args::LinkArgs;

/// The environment variable that holds the password (an empty value means unset).
pub(crate) const PASSWORD_ENV: &str = "GUTTA_PASSWORD";

/// The PLC_ATTACH function code: a `Refused` from it is a wrong password.
const PLC_ATTACH: u16 = 0x0110;

/// Where the password of a login came from.
enum Source {
    Flag(String),
    Environment(String),
    Factory,
}

fn source(args: &LinkArgs) -> Source {
    if let Some(p) = &args.password {
        return Source::Flag(p.clone());
    }
    match std::env::var(PASSWORD_ENV) {
        Ok(p) if !p.is_empty() => Source::Environment(p),
        _ => Source::Factory,
    }
}

/// How the user named the PLC, for the prompt.
fn endpoint(args: &LinkArgs) -> &str {
    args.tcp
        .as_deref()
        .or(args.rtu_tcp.as_deref())
        .or(args.serial.as_deref())
        .unwrap_or("?")
}

/// Log `client` in with the password the options, the environment or the user give;
/// the 16 password bytes that worked (download and upload log in again with them).
pub(crate) fn log_in(client: &mut Client, args: &LinkArgs) -> Result<[u8; 16], Fatal> {
    let source = source(args);
    let password = match &source {
        Source::Flag(p) => {
            eprintln!(
                "gutta-cc: warning: --password is visible to other users of this machine \
                 (ps, shell history); prefer {PASSWORD_ENV} or the prompt"
            );
            gutta_format::password_bytes(Some(p))
        }
        Source::Environment(p) => gutta_format::password_bytes(Some(p)),
        Source::Factory => FACTORY_PASSWORD,
    };
    match client.attach(&password) {
        Ok(()) => Ok(password),
        Err(e) if is_wrong_password(&e) && matches!(source, Source::Factory) => {
            if !std::io::stdin().is_terminal() {
                return Err(Fatal::link(format!(
                    "refused: the PLC has a password (the factory password was refused); \
                     set {PASSWORD_ENV}, or pass --password (visible to other users)"
                )));
            }
            let typed =
                rpassword::prompt_password(format!("Password for PLC at {}: ", endpoint(args)))
                    .map_err(|e| {
                        Fatal::io(format!("cannot read the password from the terminal: {e}"))
                    })?;
            let password = gutta_format::password_bytes(Some(&typed));
            client.attach(&password).map_err(failure)?;
            Ok(password)
        }
        Err(e) => Err(failure(e)),
    }
}

fn is_wrong_password(e: &LinkError) -> bool {
    matches!(e, LinkError::Refused { function, .. } if *function == PLC_ATTACH)
}

/// A failed login as the user reads it: refused (a wrong password, and the
/// simulator's lockout policy) or locked out (docs/simulator.md, password policy).
pub(crate) fn failure(e: LinkError) -> Fatal {
    if is_wrong_password(&e) {
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
