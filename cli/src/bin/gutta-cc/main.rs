//! `gutta-cc`: the command line. It parses (args.rs), fills in what a project gives
//! (project.rs) and dispatches each command to its module; it does no command's work
//! itself. Exit status: 0 clean (warnings allowed), 1 errors in the program, 2 usage or
//! I/O errors.

use std::ffi::OsString;
use std::process::ExitCode;

use clap::FromArgMatches;
use gutta_cli::fatal::{report_clap_error, Fatal, MessageFormat};

use crate::args::{Cli, Command};

mod args;
mod client;
mod compile;
mod debug;
mod explain;
mod fx;
mod inspect;
mod login;
mod monitor;
mod project;
mod serve;
mod studio;
mod test;
mod watch;

mod completions;
mod help;
mod ladder;
mod typo;

/// The name errors start with and JSON errors carry.
const TOOL: &str = "gutta-cc";

/// Parse (typos first, then clap), run, and print a fatal error as --message-format
/// asks: human on stderr, one JSON object on stdout (docs/cli.md); exit 2.
fn main() -> ExitCode {
    let args: Vec<OsString> = std::env::args_os().collect();
    let format = MessageFormat::from_raw_args(&args, &[]);
    let command = args::cli_command().color(gutta_cli::color::clap_color(
        gutta_cli::color::from_raw_args(&args),
    ));
    if let Err(e) = typo::check_first_word(&command, &args) {
        return e.report(TOOL, format);
    }
    let args = typo::subcommand_first(&command, &args);
    let matches = match command.try_get_matches_from(&args) {
        Ok(m) => m,
        Err(e) => return report_clap_error(e, TOOL, format),
    };
    let mut cli = match Cli::from_arg_matches(&matches) {
        Ok(cli) => cli,
        Err(e) => return report_clap_error(e, TOOL, format),
    };
    let format = cli.message_format;
    match project::apply(&mut cli, &matches).and_then(|()| run(&cli)) {
        Ok(code) => code,
        Err(e) => e.report(TOOL, format),
    }
}

/// Each command to the module that does it.
fn run(cli: &Cli) -> Result<ExitCode, Fatal> {
    let online = args::online(cli);
    let Some(command) = &cli.command else {
        return compile::files(cli);
    };
    match command {
        Command::New { name } => project::new(name, &cli.target),
        Command::Build { output } => {
            let project = project::required(cli.project.as_ref(), "build")?;
            project::build(cli, &project, output.as_deref(), &cli.symbols)
        }
        Command::Test {
            paths,
            filter,
            exact,
            junit,
            vcd,
            jobs,
        } => {
            let args = test::TestArgs {
                paths: paths.clone(),
                filter: filter.clone(),
                exact: *exact,
                junit: junit.clone(),
                vcd: vcd.clone(),
                jobs: *jobs,
            };
            test::test(cli, &args)
        }
        Command::Ladder {
            input,
            output,
            draw,
        } => ladder::ladder(cli, input, output, draw),
        Command::Studio(args) => studio::studio(cli, args),
        Command::Modbus { variable } => inspect::modbus(&cli.target, variable),
        Command::Explain { code } => explain::run(code),
        Command::Dis { image, format } => inspect::dis(&cli.target, image, *format),
        Command::Download { image: None, link } => {
            let project = cli.project.as_ref().ok_or_else(|| {
                Fatal::usage("download needs an IMAGE directory (or run it inside a project: `gutta-cc new NAME`)")
            })?;
            match project::build_for_download(cli, project)? {
                Some(image) => client::download(&online, &image, link),
                None => Ok(ExitCode::from(1)),
            }
        }
        Command::Download {
            image: Some(image),
            link,
        } => client::download(&online, image, link),
        Command::Status { link } => client::status(&online, link),
        Command::Upload { output, link } => client::upload(&online, output, link),
        Command::Run { link } => client::run_stop(&online, link, true),
        Command::Stop { link } => client::run_stop(&online, link, false),
        Command::Read { vars, link } => client::read(&online, vars, link),
        Command::Fx { action } => fx::run(action),
        Command::Write { assignments, link } => client::write(&online, assignments, link, false),
        Command::Unforce { vars, link } => client::unforce(&online, vars, link),
        Command::Debug {
            action,
            image,
            watch,
            link,
        } => debug::debug(&online, action, image.as_deref(), watch, link),
        Command::Force { assignments, link } => client::write(&online, assignments, link, true),
        Command::Watch {
            vars,
            interval,
            once,
            json,
            link,
        } => {
            let options = watch::Options {
                interval_ms: *interval,
                once: *once,
                json: *json || online.json,
            };
            watch::watch(&online, vars, &options, link)
        }
        Command::Monitor {
            program,
            http,
            interval,
            once,
            link,
        } => {
            let options = monitor::Options {
                program: program.clone(),
                http: http.clone(),
                interval_ms: *interval,
                once: *once,
            };
            monitor::monitor(cli, &options, link)
        }
        Command::Completions { shell } => completions::completions(*shell),
        Command::Man { command, output } => completions::man(command.as_deref(), output.as_deref()),
        Command::ListTargets => inspect::list_targets(),
    }
}
