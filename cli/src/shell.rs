//! Shell completion scripts (clap_complete) and man pages (clap_mangen) generated from a
//! tool's clap command, and the `--completions SHELL` / `--man` flags of the tools
//! without subcommands. It must not know any tool's own arguments.

use std::io::Write;
use std::path::{Path, PathBuf};

use clap::{Arg, ArgAction, ArgMatches, Command};
pub use clap_complete::Shell;

use crate::fatal::Fatal;

/// The completion script of `command` for `shell`, for the binary `bin`.
pub fn completion_script(mut command: Command, bin: &str, shell: Shell) -> Vec<u8> {
    let mut script = Vec::new();
    clap_complete::generate(shell, &mut command, bin, &mut script);
    if shell == Shell::Bash && bin.contains('-') {
        return bash_hyphen_fix(&script, bin);
    }
    script
}

/// clap_complete's bash script for a hyphenated binary (`gutta-cc`) spells a
/// subcommand's case arm `gutta__subcmd__cc__subcmd__status` while its dispatch loop
/// sets `gutta__cc__subcmd__status`, so no subcommand's options or values would
/// complete (clap-rs/clap#6421): spell the arms as the loop does.
fn bash_hyphen_fix(script: &[u8], bin: &str) -> Vec<u8> {
    const SEP: &str = "__subcmd__";
    let text = String::from_utf8_lossy(script);
    let wrong = format!("{}{SEP}", bin.replace('-', SEP));
    let right = format!("{}{SEP}", bin.replace('-', "__"));
    text.replace(&wrong, &right).into_bytes()
}

/// The man page (roff) of `command` alone.
pub fn man_page(command: &Command) -> Result<Vec<u8>, Fatal> {
    let mut page = Vec::new();
    clap_mangen::Man::new(command.clone())
        .render(&mut page)
        .map_err(|e| Fatal::io(format!("cannot render the man page: {e}")))?;
    Ok(page)
}

/// The man page of one subcommand of `command`, titled `BIN-SUBCOMMAND` and carrying
/// the tool's version.
pub fn subcommand_page(command: &Command, sub: &Command) -> Result<Vec<u8>, Fatal> {
    let name = format!("{}-{}", command.get_name(), sub.get_name());
    let mut sub = sub.clone().name(name.clone());
    if let Some(version) = command.get_version() {
        sub = sub.version(version.to_string());
    }
    man_page(&sub)
}

/// Write `BIN.1` and one `BIN-SUBCOMMAND.1` per visible subcommand into `dir`
/// (created); the paths written, the tool's own page first.
pub fn write_man_pages(command: &Command, dir: &Path) -> Result<Vec<PathBuf>, Fatal> {
    std::fs::create_dir_all(dir)
        .map_err(|e| Fatal::io(format!("cannot create {}: {e}", dir.display())))?;
    let mut command = command.clone();
    command.build();
    let bin = command.get_name().to_string();
    let mut pages = vec![(format!("{bin}.1"), man_page(&command)?)];
    for sub in command.get_subcommands() {
        if sub.is_hide_set() || sub.get_name() == "help" {
            continue;
        }
        let page = subcommand_page(&command, sub)?;
        pages.push((format!("{bin}-{}.1", sub.get_name()), page));
    }
    let mut written = Vec::new();
    for (file, text) in pages {
        let path = dir.join(file);
        std::fs::write(&path, text)
            .map_err(|e| Fatal::io(format!("cannot write {}: {e}", path.display())))?;
        written.push(path);
    }
    Ok(written)
}

/// `command` with `--completions SHELL` and `--man` (each alone on the command line,
/// so a required argument need not be given), for the tools without subcommands.
pub fn with_shell_flags(command: Command) -> Command {
    command
        .arg(
            Arg::new("completions")
                .long("completions")
                .value_name("SHELL")
                .value_parser(clap::value_parser!(Shell))
                .exclusive(true)
                .help("Print the shell completion script (bash, zsh, fish, ...) and exit"),
        )
        .arg(
            Arg::new("man")
                .long("man")
                .action(ArgAction::SetTrue)
                .exclusive(true)
                .help("Print the man page (roff) and exit"),
        )
}

/// When `--completions` or `--man` was given: print what it asks for on stdout and say
/// so (`Some`); `None` when neither was given.
pub fn run_shell_flags(matches: &ArgMatches, command: Command) -> Option<Result<(), Fatal>> {
    let bin = command.get_name().to_string();
    let output = if let Some(shell) = matches.get_one::<Shell>("completions") {
        Ok(completion_script(command, &bin, *shell))
    } else if matches.get_flag("man") {
        man_page(&command)
    } else {
        return None;
    };
    Some(output.and_then(|bytes| {
        std::io::stdout()
            .lock()
            .write_all(&bytes)
            .map_err(|e| Fatal::io(format!("cannot write to stdout: {e}")))
    }))
}

/// The command line of a tool without subcommands (gutta-vm, gutta-sim), parsed: its
/// `--completions`/`--man` answered, or its `Cli`. Err is the exit code after the answer
/// or after a usage error printed as `--message-format` (or one of `json_flags`) asks.
pub fn parse_tool_args<C: clap::Parser>(
    tool: &str,
    args: &[std::ffi::OsString],
    json_flags: &[&str],
) -> Result<C, std::process::ExitCode> {
    let format = crate::fatal::MessageFormat::from_raw_args(args, json_flags);
    let command = with_shell_flags(C::command());
    let mut matches = command
        .clone()
        .try_get_matches_from(args)
        .map_err(|e| crate::fatal::report_clap_error(e, tool, format))?;
    if let Some(done) = run_shell_flags(&matches, command) {
        return Err(done.map_or_else(
            |e| e.report(tool, format),
            |()| std::process::ExitCode::SUCCESS,
        ));
    }
    C::from_arg_matches_mut(&mut matches)
        .map_err(|e| crate::fatal::report_clap_error(e, tool, format))
}
