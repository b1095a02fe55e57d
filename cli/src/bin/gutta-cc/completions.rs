//! `gutta-cc completions SHELL` and `gutta-cc man [COMMAND] [--output DIR]`: the shell
//! completion script and the man pages, generated from the same clap command the
//! parser uses (so they never miss a subcommand or flag). It must not parse or run
//! anything else.

use std::io::Write;
use std::path::Path;
use std::process::ExitCode;

use gutta_cli::fatal::Fatal;
use gutta_cli::shell::{self, Shell};

/// Print the completion script for `shell` on stdout.
pub(crate) fn completions(shell: Shell) -> Result<ExitCode, Fatal> {
    let script = shell::completion_script(crate::args::cli_command(), "gutta-cc", shell);
    write_stdout(&script)
}

/// Write every man page into `output`, or print one (gutta-cc's, or `subcommand`'s) on
/// stdout.
pub(crate) fn man(subcommand: Option<&str>, output: Option<&Path>) -> Result<ExitCode, Fatal> {
    let mut command = crate::args::cli_command();
    command.build();
    if let Some(dir) = output {
        let written = shell::write_man_pages(&command, dir)?;
        eprintln!(
            "gutta-cc: wrote {} man pages into {}",
            written.len(),
            dir.display()
        );
        return Ok(ExitCode::SUCCESS);
    }
    let page = match subcommand {
        None => shell::man_page(&command)?,
        Some(name) => {
            let sub = command.find_subcommand(name).ok_or_else(|| {
                Fatal::usage(format!("no command '{name}' to show a man page of"))
            })?;
            shell::subcommand_page(&command, sub)?
        }
    };
    write_stdout(&page)
}

fn write_stdout(bytes: &[u8]) -> Result<ExitCode, Fatal> {
    let mut out = std::io::stdout().lock();
    match out.write_all(bytes).and_then(|()| out.flush()) {
        Ok(()) => Ok(ExitCode::SUCCESS),
        // A closed pipe (`| head`) is the reader's choice, not an error.
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(ExitCode::SUCCESS),
        Err(e) => Err(Fatal::io(format!("cannot write to stdout: {e}"))),
    }
}
