//! `gutta-cc`: the command line. All file I/O and process exit codes live here; the
//! library does the work. Exit status: 0 clean (warnings allowed), 1 errors in the
//! program, 2 usage or I/O errors.

use std::ffi::OsString;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{ArgMatches, CommandFactory, FromArgMatches, Parser, Subcommand, ValueEnum};
use gutta_catalog::stdlib;
use gutta_cli::color::ColorChoice;
use gutta_cli::fatal::{report_clap_error, Fatal, MessageFormat};
use gutta_cli::plural::count;
use gutta_cli::shell::Shell;
use gutta_compiler::diagnostics::json;
use gutta_compiler::diagnostics::render::{render, RenderStyle};
use gutta_compiler::encode::{listing, summary};
use gutta_compiler::source::{SourceEncoding, SourceFile};
use gutta_compiler::{check_program, compile_program, ExplicitTarget, ProgramSources};

#[derive(Debug, Clone, Parser)]
#[command(
    name = "gutta-cc",
    version,
    about = "Compiler and PLC client for GUTTA PLC ladder/STL programs",
    args_conflicts_with_subcommands = true,
    after_help = "Examples:
  gutta-cc --check main.lad                       # check a program (exit 1 on errors)
  gutta-cc main.lad -o image/                     # compile it into an image directory
  gutta-cc main.lad -o image/ --emit listing      # ... and print the listing
  gutta-cc download image/ --tcp 127.0.0.1:5020   # download it into a PLC

`gutta-cc COMMAND --help` shows a command's options and examples; `gutta-cc man` its manual.
Exit status: 0 clean (warnings allowed), 1 errors in the program, 2 usage, I/O or PLC errors."
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Source files (.lad): together, one program to check or compile.
    files: Vec<PathBuf>,
    /// Check only (parse and check; write nothing).
    #[arg(long, conflicts_with = "output")]
    check: bool,
    /// Compile and write the download image into this directory.
    #[arg(short, long, value_name = "DIR")]
    output: Option<PathBuf>,
    /// Also print a listing (every source line with its page, offset and bytes) on stdout.
    #[arg(long, value_enum, conflicts_with = "check")]
    emit: Option<Emit>,
    #[command(flatten)]
    target: TargetArgs,
    /// In a STEP 7-Micro/WIN export, scale constant timer presets where the timer
    /// number's S7-200 resolution differs from the target's, so the program keeps its
    /// S7-200 timing (rounded to the nearest unit; docs/microwin.md).
    #[arg(long, global = true)]
    scale_timer_presets: bool,
    /// A symbol table (CSV `Symbol,Address,Comment`, or Micro/WIN's tab-separated rows)
    /// or a program source (.lad) whose symbols the command may use (repeatable). When
    /// compiling, a table's symbols join the program's.
    #[arg(long, global = true, value_name = "FILE")]
    symbols: Vec<PathBuf>,
    /// How to print diagnostics, errors and results: human text, or JSON (one object per
    /// line on stdout).
    #[arg(long, global = true, value_name = "FORMAT", value_enum, default_value_t = MessageFormat::Human)]
    message_format: MessageFormat,
    /// Colour in human output (auto: on a terminal, unless NO_COLOR is set and not empty).
    #[arg(long, global = true, value_name = "WHEN", value_enum, default_value_t = ColorChoice::Auto)]
    color: ColorChoice,
    /// The project (gutta.toml) found from the current directory, when the command uses
    /// one (`apply_project`).
    #[arg(skip)]
    project: Option<gutta_io::Project>,
}

#[derive(Debug, Clone, clap::Args)]
struct TargetArgs {
    /// PLC type from the stdlib (overrides PLC_TYPE in the file).
    #[arg(long, global = true, value_name = "NAME", value_parser = gutta_cli::flags::PlcName, hide_possible_values = true)]
    plc: Option<String>,
    /// A target folder holding PlcType.xml, ManagerVar.xml and ManagerFun.xml.
    #[arg(long, global = true, value_name = "DIR", conflicts_with = "plc")]
    target: Option<PathBuf>,
    /// Where --plc/--target came from when not the command line (gutta.toml), for
    /// diagnostics.
    #[arg(skip)]
    origin: Option<String>,
}

#[derive(Debug, Clone, Subcommand)]
enum Command {
    /// Create a project: NAME/ with gutta.toml, src/main.lad, symbols.csv, tests/main.gtest,
    /// .gitignore and a README (`--plc NAME` for another PLC type than the stdlib default).
    #[command(
        after_help = "Examples:\n  gutta-cc new demo && cd demo && gutta-cc build && gutta-cc test\n  gutta-cc new pump --plc EC30-EKSTM32"
    )]
    New {
        /// The project folder to create (its last part names the project).
        name: PathBuf,
    },
    /// Compile the project (gutta.toml, found from the current directory upwards) into
    /// its image directory: its sources as one program, with its symbol tables.
    #[command(
        after_help = "Examples:\n  gutta-cc new lamp && cd lamp && gutta-cc build\n  gutta-cc new mixer && cd mixer && gutta-cc build --output out/ --message-format json"
    )]
    Build {
        /// The image directory [default: gutta.toml's [build] output, else target/image].
        #[arg(short, long, value_name = "DIR")]
        output: Option<PathBuf>,
    },
    /// Run unit tests of PLC programs: .gtest files (the project's tests/ by default), on
    /// the VM in virtual time; one line per test and a summary (docs/testing-programs.md).
    /// Exit status: 0 all passed, 1 a test failed, 2 usage or file errors (no test of a
    /// file with errors runs).
    #[command(
        after_help = "Examples:\n  cd demo && gutta-cc test                        # a project's tests/ (`gutta-cc new demo`)\n  gutta-cc test demo/tests/main.gtest --filter latch\n  gutta-cc test demo/tests --junit report.xml --vcd waves/\n  gutta-cc test demo/tests --message-format json"
    )]
    Test {
        /// Test files (.gtest) or folders searched for them [default: the project's tests/].
        paths: Vec<PathBuf>,
        /// Run only the tests whose name contains this text (any case).
        #[arg(long, value_name = "NAME")]
        filter: Option<String>,
        /// Also write JUnit XML (one testsuite per file) into this file.
        #[arg(long, value_name = "FILE")]
        junit: Option<PathBuf>,
        /// Write a waveform (VCD) of each failing test into this folder: every variable the
        /// test mentions, named by its symbol, over virtual time.
        #[arg(long, value_name = "DIR")]
        vcd: Option<PathBuf>,
        /// Test files run at once [default: the machine's cores].
        #[arg(long, value_name = "N")]
        jobs: Option<usize>,
    },
    /// Draw a program's networks as ladder diagrams (LAD) into an .svg (every network) or a
    /// self-contained .html page (docs/ladder.md); a network that is not one rung is shown
    /// as STL with the reason.
    #[command(
        after_help = "Examples:\n  gutta-cc ladder main.lad -o main.svg\n  gutta-cc ladder main.lad -o main.html          # open it in a browser\n  gutta-cc ladder image/ -o image.svg              # an image: addresses, no symbols\n  cd demo && gutta-cc ladder . -o demo.html       # a project (`gutta-cc new demo`)"
    )]
    Ladder {
        /// A source file (.lad, .awl), a project (its folder or gutta.toml), or an image
        /// directory (drawn through the disassembler).
        input: PathBuf,
        /// The file to write: .svg or .html.
        #[arg(short, long, value_name = "FILE")]
        output: PathBuf,
    },
    /// Print the Modbus address of a variable (the vendor editor's Modbus query).
    #[command(
        after_help = "Examples:\n  gutta-cc modbus MW20                 # holding register 400019\n  gutta-cc modbus Q0.0 --plc CPU-EC20"
    )]
    Modbus {
        /// A direct address such as MW20, MB31, Q3.0, I0.4.
        variable: String,
    },
    /// Print an image directory as STL that compiles back to the same pages.
    #[command(
        after_help = "Examples:\n  gutta-cc dis image/\n  gutta-cc dis image/ > back.lad && gutta-cc back.lad -o again/\n  gutta-cc dis --format awl image/ > back.awl   # a STEP 7-Micro/WIN STL export (CRLF)"
    )]
    Dis {
        /// The image directory (holding manifest.json).
        image: PathBuf,
        /// The layout: stl (the toolchain's own) or awl (a STEP 7-Micro/WIN STL export);
        /// both compile back to the same pages.
        #[arg(long, value_enum, default_value = "stl")]
        format: DisFormat,
    },
    /// Explain a code the tools print: E and W (compiler diagnostics), V (image
    /// verification), T (target description files), e.g. E0302, V0040, T0003.
    #[command(
        after_help = "Examples:\n  gutta-cc explain E0302\n  gutta-cc explain V0040\n  gutta-cc explain T0003"
    )]
    Explain {
        /// The code, e.g. E0302.
        code: String,
    },
    /// Download an image directory into a PLC (the PLC type must match; the PLC is
    /// cleared, every page written and read back, then reset to run the image).
    #[command(
        after_help = "Examples:\n  gutta-cc download image/ --tcp 127.0.0.1:5020\n  gutta-cc download image/ --serial /dev/ttyUSB0 --baud 9600 --parity even\n  gutta-cc download image/ --tcp 127.0.0.1:5020 --station 1 --message-format json"
    )]
    Download {
        /// The image directory (holding manifest.json) [in a project: the project,
        /// built first].
        image: Option<PathBuf>,
        #[command(flatten)]
        link: LinkArgs,
    },
    /// Upload the PLC's program into an image directory (the pages the PLC holds).
    #[command(
        after_help = "Examples:\n  gutta-cc upload -o backup/ --tcp 127.0.0.1:5020\n  gutta-cc upload -o backup/ --tcp 127.0.0.1:5020 && gutta-cc dis backup/"
    )]
    Upload {
        /// The directory to write (created; written atomically).
        #[arg(short, long, value_name = "DIR")]
        output: PathBuf,
        #[command(flatten)]
        link: LinkArgs,
    },
    /// Print the PLC's status (RUN, RESET, ATTACH, ERROR) and PLC type.
    #[command(
        after_help = "Examples:\n  gutta-cc status --tcp 127.0.0.1:5020\n  gutta-cc status --rtu-tcp 127.0.0.1:5021 --station 2\n  gutta-cc status --tcp 127.0.0.1:5020 --message-format json"
    )]
    Status {
        #[command(flatten)]
        link: LinkArgs,
    },
    /// Put the PLC in RUN.
    #[command(
        after_help = "Examples:\n  gutta-cc run --tcp 127.0.0.1:5020\n  gutta-cc run --serial /dev/ttyUSB0"
    )]
    Run {
        #[command(flatten)]
        link: LinkArgs,
    },
    /// Put the PLC in STOP.
    #[command(
        after_help = "Examples:\n  gutta-cc stop --tcp 127.0.0.1:5020\n  gutta-cc stop --serial /dev/ttyUSB0"
    )]
    Stop {
        #[command(flatten)]
        link: LinkArgs,
    },
    /// Talk to an FX-style programming port (raw frames over --tcp, or --serial at 7E1):
    /// read, write, force bits, set the baud rate, read the configuration, upload and
    /// download the program (docs/devices.md).
    #[command(
        after_help = "Examples:\n  gutta-cc fx read 0E02 2 --tcp 127.0.0.1:5030\n  gutta-cc fx download-program prog.bin --serial /dev/ttyUSB0 --baud 9600"
    )]
    Fx {
        #[command(subcommand)]
        action: fx::FxAction,
    },
    /// Read variables: `NAME (ADDR) = VALUE` for a symbol, `ADDR = VALUE` for an address,
    /// each in its format (a symbol's type; bits 0/1, bytes unsigned, words and double
    /// words signed; a `:bool|int|uint|hex|real` suffix overrides).
    #[command(
        after_help = "Examples:\n  gutta-cc read MW24 Q0.0 --tcp 127.0.0.1:5020\n  gutta-cc read MD4 AIW0 --tcp 127.0.0.1:5020 --message-format json"
    )]
    Read {
        /// Symbols or direct addresses, each with an optional `:fmt`: Speed, MW24, Q0.0,
        /// MD4:hex, MD8:real.
        #[arg(required = true)]
        vars: Vec<String>,
        #[command(flatten)]
        link: LinkArgs,
    },
    /// Write variables (an input's terminal holds the value across scans); prints what
    /// was written as `read` does.
    #[command(
        after_help = "Examples:\n  gutta-cc write MW0=16#FF Q0.0=1 --tcp 127.0.0.1:5020\n  gutta-cc write I0.0=1 AIW0=100 --tcp 127.0.0.1:5020"
    )]
    Write {
        /// VAR=VALUE, VAR a symbol or an address with an optional `:fmt`, VALUE in its
        /// format or raw bits: MW0=16#FF, Q0.0=1, Speed=-5, MD8:real=21.5.
        #[arg(required = true)]
        assignments: Vec<String>,
        #[command(flatten)]
        link: LinkArgs,
    },
    /// Release forced variables (they follow the program and inputs again).
    #[command(
        after_help = "Examples:\n  gutta-cc unforce Q0.0 --tcp 127.0.0.1:5020\n  gutta-cc unforce Q0.0 IB0 --tcp 127.0.0.1:5020"
    )]
    Unforce {
        /// Symbols or direct addresses that were forced: Q0.0, IB0, Lamp.
        #[arg(required = true)]
        vars: Vec<String>,
        #[command(flatten)]
        link: LinkArgs,
    },
    /// Debug the running program: `break MAIN:2:0` (or `break main.lad:12` with a source
    /// map), `clear`, `stop` (single-step stop), `run`, `step in|over|out`, `reset` (reset
    /// into single-step stop), `info`.
    #[command(
        after_help = "Examples:\n  gutta-cc debug reset --tcp 127.0.0.1:5020                   # single-step stop before the first scan\n  gutta-cc debug step over --image image/ --tcp 127.0.0.1:5020\n  gutta-cc debug break main.lad:12 --image image/ --tcp 127.0.0.1:5020\n  gutta-cc debug run --tcp 127.0.0.1:5020"
    )]
    Debug {
        /// The action, then its argument (a position or FILE:LINE for `break`, in/over/out
        /// for `step`).
        #[arg(required = true, num_args = 1..=2)]
        action: Vec<String>,
        /// The image directory the PLC runs, whose source map (DIR.map.json) shows file:line
        /// and instruction text [default: `image` when image.map.json exists].
        #[arg(long, value_name = "DIR")]
        image: Option<PathBuf>,
        /// A variable whose value every report shows (repeatable): a symbol or an address
        /// with an optional `:fmt`.
        #[arg(long, value_name = "VAR")]
        watch: Vec<String>,
        #[command(flatten)]
        link: LinkArgs,
    },
    /// Force I or Q variables to values (they keep them every scan).
    #[command(
        after_help = "Examples:\n  gutta-cc force Q0.0=1 --tcp 127.0.0.1:5020\n  gutta-cc force IB0=16#0F --tcp 127.0.0.1:5020"
    )]
    Force {
        /// VAR=VALUE: Q0.0=1, IB0=16#0F, Lamp=ON.
        #[arg(required = true)]
        assignments: Vec<String>,
        #[command(flatten)]
        link: LinkArgs,
    },
    /// Watch variables live: a table (name, address, format, value, when it last
    /// changed) redrawn every --interval on a terminal, q, Esc or Ctrl-C to quit; one line
    /// per sample when stdout is not a terminal.
    #[command(
        after_help = "Examples:\n  gutta-cc watch Q0.0 MW24 --tcp 127.0.0.1:5020 --once\n  gutta-cc watch MD4:hex MD8:real --tcp 127.0.0.1:5020 --once --json\n  gutta-cc watch Q0.0 --interval 500 --tcp 127.0.0.1:5020 --once"
    )]
    Watch {
        /// Symbols or direct addresses, each with an optional `:fmt`: Lamp, MW10:hex.
        #[arg(required = true)]
        vars: Vec<String>,
        /// Milliseconds between samples.
        #[arg(long, value_name = "MS", default_value_t = 200)]
        interval: u64,
        /// Print one sample and exit.
        #[arg(long)]
        once: bool,
        /// One JSON object per sample (`{"time_ms", "values": [...]}`), as with
        /// --message-format json.
        #[arg(long)]
        json: bool,
        #[command(flatten)]
        link: LinkArgs,
    },
    /// Show a program's ladder live in the browser: energized contacts, coils and wires,
    /// box values and forced operands, read from the PLC running it (docs/ladder.md,
    /// "Live view"). The PLC is read only while a page is open.
    #[command(
        after_help = "Examples:\n  gutta-cc monitor main.lad --tcp 127.0.0.1:5020 --once          # one update as JSON\n  gutta-cc monitor main.lad --tcp 127.0.0.1:5020 --once | grep -q '\"live\":true'\n  gutta-cc monitor --tcp 192.168.1.10:502 --http 0.0.0.0:8080      # a project, for the LAN"
    )]
    Monitor {
        /// A source file (.lad), or a project folder [default: the project around the
        /// current directory].
        #[arg(value_name = "SOURCE_OR_PROJECT")]
        program: Option<PathBuf>,
        /// Where the HTTP server listens (port 0: any free port; the address is printed
        /// on stderr).
        #[arg(long, value_name = "ADDR", default_value = "127.0.0.1:8080")]
        http: String,
        /// Milliseconds between updates while a page is open.
        #[arg(long, value_name = "MS", default_value_t = 50)]
        interval: u64,
        /// Print one update (the `/state` JSON) and exit: 0 live, 1 the PLC holds no
        /// program or another one, or does not answer.
        #[arg(long)]
        once: bool,
        #[command(flatten)]
        link: LinkArgs,
    },
    /// List the stdlib PLC types.
    #[command(
        after_help = "Examples:\n  gutta-cc list-targets\n  gutta-cc list-targets | grep EC20"
    )]
    ListTargets,
    /// Print a shell completion script (bash, zsh, fish, elvish, powershell).
    #[command(
        after_help = "Examples:\n  source <(gutta-cc completions bash)                 # in ~/.bashrc\n  gutta-cc completions zsh > _gutta-cc                # into a directory of $fpath\n  gutta-cc completions fish > gutta-cc.fish           # into ~/.config/fish/completions/"
    )]
    Completions {
        /// The shell.
        #[arg(value_name = "SHELL")]
        shell: Shell,
    },
    /// Print the man page of gutta-cc or of one command, or write them all (--output).
    #[command(
        after_help = "Examples:\n  gutta-cc man | man -l -\n  gutta-cc man download > gutta-cc-download.1\n  gutta-cc man --output man/                          # gutta-cc.1, gutta-cc-download.1, ..."
    )]
    Man {
        /// The command whose page to print (default: gutta-cc's own).
        #[arg(value_name = "COMMAND", conflicts_with = "output")]
        command: Option<String>,
        /// Write gutta-cc.1 and one page per command into this directory.
        #[arg(short, long, value_name = "DIR")]
        output: Option<PathBuf>,
    },
}

/// Serial parity, as a system block's PORTn.PARITY.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Parity {
    None,
    Even,
    Odd,
}

/// How to reach a PLC.
#[derive(Debug, Clone, clap::Args)]
struct LinkArgs {
    /// Modbus TCP, e.g. 127.0.0.1:502.
    #[arg(long, value_name = "HOST:PORT", group = "endpoint")]
    tcp: Option<String>,
    /// Modbus RTU frames over TCP (a serial server, or gutta-sim --rtu-tcp).
    #[arg(long, value_name = "HOST:PORT", group = "endpoint")]
    rtu_tcp: Option<String>,
    /// Modbus RTU on a serial device (8 data bits, 1 stop bit).
    #[arg(long, value_name = "DEVICE", group = "endpoint")]
    serial: Option<String>,
    /// Baud rate for --serial: the PLC's port 0 (its system block), 19200 without one.
    #[arg(long, value_name = "BAUD", default_value_t = 19200)]
    baud: u32,
    /// Parity for --serial: the PLC's port 0 (its system block), even without one.
    #[arg(long, value_name = "PARITY", default_value = "even")]
    parity: Parity,
    /// The PLC's login password (the system block's). Visible to other users: prefer
    /// GUTTA_PASSWORD, or the prompt a terminal gets when the factory password is refused.
    #[arg(long, value_name = "TEXT")]
    password: Option<String>,
    /// The PLC's station address.
    #[arg(long, value_name = "N", default_value_t = 1)]
    station: u8,
    /// Milliseconds to wait for each answer.
    #[arg(long, value_name = "MS", default_value_t = 1000)]
    timeout: u64,
    /// Attempts after the first when an answer does not come.
    #[arg(long, value_name = "N", default_value_t = 2)]
    retries: u32,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Emit {
    Listing,
}

mod client;
mod debug;
mod explain;
mod fx;
mod login;
mod monitor;
mod project;
mod test;
mod watch;

mod completions;
mod help;
mod ladder;
mod typo;

/// The name errors start with and JSON errors carry.
const TOOL: &str = "gutta-cc";

/// The command line as the parser, the help, the completions and the man pages see it.
fn cli_command() -> clap::Command {
    help::grouped(Cli::command())
}

/// Parse (typos first, then clap), run, and print a fatal error as --message-format
/// asks: human on stderr, one JSON object on stdout (docs/cli.md); exit 2.
fn main() -> ExitCode {
    let args: Vec<OsString> = std::env::args_os().collect();
    let format = MessageFormat::from_raw_args(&args, &[]);
    let command = cli_command().color(gutta_cli::color::clap_color(
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
    match apply_project(&mut cli, &matches).and_then(|()| run(cli)) {
        Ok(code) => code,
        Err(e) => e.report(TOOL, format),
    }
}

impl Command {
    /// The link flags of a command that talks to a PLC.
    fn link_mut(&mut self) -> Option<&mut LinkArgs> {
        match self {
            Command::Download { link, .. }
            | Command::Upload { link, .. }
            | Command::Status { link }
            | Command::Run { link }
            | Command::Stop { link }
            | Command::Read { link, .. }
            | Command::Write { link, .. }
            | Command::Unforce { link, .. }
            | Command::Debug { link, .. }
            | Command::Force { link, .. }
            | Command::Watch { link, .. }
            | Command::Monitor { link, .. } => Some(link),
            Command::New { .. }
            | Command::Fx { .. }
            | Command::Build { .. }
            | Command::Test { .. }
            | Command::Ladder { .. }
            | Command::Modbus { .. }
            | Command::Dis { .. }
            | Command::Explain { .. }
            | Command::ListTargets
            | Command::Completions { .. }
            | Command::Man { .. } => None,
        }
    }
}

/// Inside a project (docs/projects.md), what the command line leaves out comes from
/// gutta.toml: the link flags not given on the command line from `[connection]`,
/// --plc/--target from `[program]`, the symbol context (--symbols) from the project's
/// sources and tables, and `debug`'s image from the build output. Compiling files, `new`,
/// `dis`, `explain` and `list-targets` do not look for a project; outside one, nothing
/// changes.
fn apply_project(cli: &mut Cli, matches: &ArgMatches) -> Result<(), Fatal> {
    let uses_project = !matches!(
        cli.command,
        None | Some(
            Command::New { .. }
                | Command::Dis { .. }
                | Command::Ladder { .. }
                | Command::Explain { .. }
                | Command::ListTargets
                | Command::Completions { .. }
                | Command::Man { .. }
        )
    );
    if !uses_project {
        return Ok(());
    }
    let Some(project) = project::find()? else {
        return Ok(());
    };
    if matches!(cli.command, Some(Command::Test { .. })) {
        // `test` takes each test file's program, target and symbols itself.
        cli.project = Some(project);
        return Ok(());
    }
    project::apply_target(&mut cli.target, &project);
    let link = cli.command.as_mut().and_then(Command::link_mut);
    if let (Some(link), Some((_, sub))) = (link, matches.subcommand()) {
        project::apply_connection(link, sub, &project.connection);
    }
    let building = matches!(cli.command, Some(Command::Build { .. }));
    if cli.symbols.is_empty() && !building {
        cli.symbols = project::context_files(&project);
    }
    if let Some(Command::Debug {
        image: image @ None,
        ..
    }) = &mut cli.command
    {
        if project.output.is_dir() {
            *image = Some(project::shown(&project.output));
        }
    }
    cli.project = Some(project);
    Ok(())
}

/// What every client command takes from the command line besides its link.
fn online(cli: &Cli) -> client::Online<'_> {
    client::Online {
        targets: &cli.target,
        symbol_files: &cli.symbols,
        json: cli.message_format == MessageFormat::Json,
    }
}

fn run(mut cli: Cli) -> Result<ExitCode, Fatal> {
    // The commands that build first or make a project; then the rest, which only read `cli`.
    match &cli.command {
        Some(Command::New { name }) => {
            if cli.target.target.is_some() {
                return Err(Fatal::usage(
                    "`gutta-cc new` takes --plc NAME; for a target folder, set [program] target in gutta.toml",
                ));
            }
            return project::new(name, cli.target.plc.as_deref());
        }
        Some(Command::Build { output }) => {
            let project = project::required(cli.project.as_ref(), "build")?;
            let output = output.clone();
            project::build_command(&mut cli, &project, output)?;
            return run(cli);
        }
        Some(Command::Download { image: None, link }) => {
            let project = cli.project.as_ref().ok_or_else(|| {
                Fatal::usage("download needs an IMAGE directory (or run it inside a project: `gutta-cc new NAME`)")
            })?;
            let Some(image) = project::build_for_download(&cli, project)? else {
                return Ok(ExitCode::from(1));
            };
            let online = online(&cli);
            return client::download(&online, &image, link);
        }
        _ => {}
    }
    let online = online(&cli);
    match &cli.command {
        Some(Command::Test {
            paths,
            filter,
            junit,
            vcd,
            jobs,
        }) => {
            let args = test::TestArgs {
                paths: paths.clone(),
                filter: filter.clone(),
                junit: junit.clone(),
                vcd: vcd.clone(),
                jobs: *jobs,
            };
            return test::test(&cli, &args);
        }
        Some(Command::Ladder { input, output }) => return ladder::ladder(&cli, input, output),
        Some(Command::Modbus { variable }) => return modbus(&cli.target, variable),
        Some(Command::Explain { code }) => return explain(code),
        Some(Command::Dis { image, format }) => return dis(&cli.target, image, *format),
        Some(Command::Download {
            image: Some(image),
            link,
        }) => return client::download(&online, image, link),
        Some(Command::Status { link }) => return client::status(&online, link),
        Some(Command::Upload { output, link }) => return client::upload(&online, output, link),
        Some(Command::Run { link }) => return client::run_stop(&online, link, true),
        Some(Command::Stop { link }) => return client::run_stop(&online, link, false),
        Some(Command::Read { vars, link }) => return client::read(&online, vars, link),
        Some(Command::Fx { action }) => return fx::run(action),
        Some(Command::Write { assignments, link }) => {
            return client::write(&online, assignments, link, false)
        }
        Some(Command::Unforce { vars, link }) => return client::unforce(&online, vars, link),
        Some(Command::Debug {
            action,
            image,
            watch,
            link,
        }) => return debug::debug(&online, action, image.as_deref(), watch, link),
        Some(Command::Force { assignments, link }) => {
            return client::write(&online, assignments, link, true)
        }
        Some(Command::Watch {
            vars,
            interval,
            once,
            json,
            link,
        }) => {
            let options = watch::Options {
                interval_ms: *interval,
                once: *once,
                json: *json || online.json,
            };
            return watch::watch(&online, vars, &options, link);
        }
        Some(Command::Monitor {
            program,
            http,
            interval,
            once,
            link,
        }) => {
            let options = monitor::Options {
                program: program.clone(),
                http: http.clone(),
                interval_ms: *interval,
                once: *once,
            };
            return monitor::monitor(&cli, &options, link);
        }
        Some(Command::Completions { shell }) => return completions::completions(*shell),
        Some(Command::Man { command, output }) => {
            return completions::man(command.as_deref(), output.as_deref())
        }
        Some(Command::ListTargets) => {
            for name in stdlib::names() {
                let t = stdlib::load(name).map_err(|e| Fatal::target(e.to_string()))?;
                // A closed pipe (`| head`) ends the listing quietly.
                if writeln!(std::io::stdout(), "{:<16} {}", name, t.plc.information).is_err() {
                    break;
                }
            }
            return Ok(ExitCode::SUCCESS);
        }
        // new, build and a project's download returned above.
        Some(
            Command::New { .. } | Command::Build { .. } | Command::Download { image: None, .. },
        )
        | None => {}
    }
    if cli.files.is_empty() {
        return Err(Fatal::usage("no input files").with_hint(
            "try `gutta-cc main.lad -o image/`, `gutta-cc --check main.lad`, or --help",
        ));
    }
    let compiling = cli.output.is_some() || cli.emit.is_some();
    let mut program = read_program(&cli.files, &cli.symbols)?;
    program.options.scale_timer_presets = cli.scale_timer_presets;
    let name = match program.sources.len() {
        1 => program.sources[0].name.clone(),
        n => count(n, "file"),
    };
    let explicit = explicit_target(&cli.target)?;
    let color = gutta_cli::color::use_color(cli.color, std::io::stderr().is_terminal());
    let style = RenderStyle {
        color,
        unicode: color,
    };
    let stdout = std::io::stdout();
    let (checked, image) = if compiling {
        let compiled = compile_program(program, explicit.as_ref());
        if let (Some(Emit::Listing), Some(lowered)) = (cli.emit, &compiled.lowered) {
            if compiled.image.is_some() {
                let mut text = listing(
                    lowered,
                    &compiled.checked.file,
                    &compiled.checked.index,
                    compiled.checked.target.name(),
                );
                if let Some(line) = compiled.checked.microwin_summary() {
                    text = format!("// {line}\n{text}");
                }
                let _ = stdout.lock().write_all(text.as_bytes());
            }
        }
        let map = compiled.source_map();
        (compiled.checked, compiled.image.zip(map))
    } else {
        (check_program(program, explicit.as_ref()), None)
    };
    let any_errors = checked.has_errors();
    if let (Some((image, map)), Some(dir)) = (&image, &cli.output) {
        gutta_io::write_image_with_map(dir, image, map).map_err(|e| Fatal::io(e.0))?;
    }
    match cli.message_format {
        MessageFormat::Json => {
            let text = json::to_json_lines(&checked.file, &checked.index, checked.diagnostics());
            let _ = stdout.lock().write_all(text.as_bytes());
        }
        MessageFormat::Human => {
            eprint!("{}", render(&checked.file, checked.diagnostics(), style));
            let errors = checked
                .diagnostics()
                .iter()
                .filter(|d| d.is_error())
                .count();
            let warnings = checked.diagnostics().len() - errors;
            if errors > 0 {
                eprintln!(
                    "{name}: {}, {}",
                    count(errors, "error"),
                    count(warnings, "warning")
                );
            } else if let (Some((image, _)), Some(dir)) = (&image, &cli.output) {
                eprintln!(
                    "{name}: wrote {} for {}: {}",
                    dir.display(),
                    image.plc_type,
                    summary(image, &checked.target)
                );
                if let Some(line) = checked.microwin_summary() {
                    eprintln!("{name}: {line}");
                }
            } else if let Some(p) = &checked.output.program {
                let instructions: usize = p
                    .units
                    .iter()
                    .flat_map(|u| &u.networks)
                    .map(|n| n.instructions.len())
                    .sum();
                eprintln!(
                    "{name}: ok on {} ({}, {}, {}{})",
                    p.target_name,
                    count(p.units.len(), "block"),
                    count(instructions, "instruction"),
                    count(p.data_blocks.len(), "data block"),
                    if warnings > 0 {
                        format!(", {}", count(warnings, "warning"))
                    } else {
                        String::new()
                    }
                );
                if let Some(line) = checked.microwin_summary() {
                    eprintln!("{name}: {line}");
                }
            }
        }
    }
    let _ = cli.check; // Without -o, checking is all there is to do.
    Ok(if any_errors {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

/// The program: every source file, and the `--symbols` files that are tables (a `.lad`
/// there is a usage error: its blocks would be half a program).
fn read_program(files: &[PathBuf], tables: &[PathBuf]) -> Result<ProgramSources, Fatal> {
    if let Some(lad) = tables
        .iter()
        .find(|p| p.extension().is_some_and(|x| x.eq_ignore_ascii_case("lad")))
    {
        return Err(Fatal::usage(format!(
            "--symbols {0}: a .lad file is a source of the program; list it with the sources instead (`gutta-cc ... {0}`)",
            lad.display()
        )));
    }
    let mut program = ProgramSources::default();
    for path in files {
        program.sources.push(read_source(path, false)?);
    }
    for path in tables {
        program.symbol_tables.push(read_source(path, true)?);
    }
    Ok(program)
}

/// A file as text (BOM dropped), named as given: UTF-8; a symbol table or a Micro/WIN
/// export (`.awl`, or the dialect's marker line) may also be GBK or Windows-1252
/// (`SourceFile::from_code_page_bytes`; a note on stderr says which).
fn read_source(path: &Path, table: bool) -> Result<SourceFile, Fatal> {
    let bytes = std::fs::read(path)
        .map_err(|e| Fatal::io(format!("cannot read {}: {e}", path.display())))?;
    let name = path.display().to_string();
    let (file, encoding) =
        SourceFile::from_program_file_bytes(&name, bytes, table).map_err(|e| {
            Fatal::io(format!(
                "{name} is not UTF-8 text (invalid byte at offset {})",
                e.offset
            ))
        })?;
    if encoding != SourceEncoding::Utf8 {
        eprintln!("note: {name} is not UTF-8; read as {}", encoding.as_str());
    }
    Ok(file)
}

fn explicit_target(args: &TargetArgs) -> Result<Option<ExplicitTarget>, Fatal> {
    if let Some(name) = &args.plc {
        let target = stdlib::shared(name).map_err(|e| Fatal::target(e.to_string()))?;
        return Ok(Some(ExplicitTarget {
            target,
            origin: args
                .origin
                .clone()
                .unwrap_or_else(|| format!("--plc {name}")),
        }));
    }
    if let Some(dir) = &args.target {
        let target = std::sync::Arc::new(gutta_io::load_target_dir(dir).map_err(Fatal::target)?);
        return Ok(Some(ExplicitTarget {
            target,
            origin: args
                .origin
                .clone()
                .unwrap_or_else(|| format!("--target {}", dir.display())),
        }));
    }
    Ok(None)
}

fn modbus(args: &TargetArgs, variable: &str) -> Result<ExitCode, Fatal> {
    let target = match explicit_target(args)? {
        Some(e) => e.target,
        None => stdlib::shared(stdlib::DEFAULT).map_err(|e| Fatal::target(e.to_string()))?,
    };
    let address = target
        .memory
        .parse_address(variable.trim())
        .map_err(|e| Fatal::usage(format!("`{variable}` on {}: {e}", target.name())))?;
    match target.memory.modbus_location(&address) {
        Some(loc) => {
            println!("{loc}");
            Ok(ExitCode::SUCCESS)
        }
        None => {
            let area = target
                .memory
                .area_by_slot(address.slot)
                .map(|a| a.name.clone())
                .unwrap_or_default();
            Err(Fatal::usage(format!(
                "`{variable}`: area {area} has no Modbus address on {}",
                target.name()
            )))
        }
    }
}

/// `explain CODE`: the registry's text; an unknown code is a usage error (exit 2).
fn explain(code: &str) -> Result<ExitCode, Fatal> {
    let text = explain::explanation(code).map_err(Fatal::usage)?;
    println!("{text}");
    Ok(ExitCode::SUCCESS)
}

/// An image directory and the target it is for: --plc/--target, else its PLC type.
fn image_and_target(
    args: &TargetArgs,
    dir: &Path,
) -> Result<(gutta_format::Image, std::sync::Arc<gutta_catalog::Target>), Fatal> {
    let image = gutta_io::read_image_dir(dir).map_err(Fatal::io)?;
    let target = match explicit_target(args)? {
        Some(e) => e.target,
        None => stdlib::shared(&image.plc_type).map_err(|e| {
            Fatal::target(format!(
                "the image is for {}: {e} (pass --target DIR for a vendor PLC type)",
                image.plc_type
            ))
        })?,
    };
    Ok((image, target))
}

/// The layouts of `gutta-cc dis --format`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum DisFormat {
    /// The toolchain's own STL.
    Stl,
    /// A STEP 7-Micro/WIN STL export.
    Awl,
}

fn dis(args: &TargetArgs, dir: &Path, format: DisFormat) -> Result<ExitCode, Fatal> {
    let (image, target) = image_and_target(args, dir)?;
    let format = match format {
        DisFormat::Stl => gutta_format::disasm::Format::Stl,
        DisFormat::Awl => gutta_format::disasm::Format::Awl,
    };
    let d = gutta_format::disasm::disassemble_as(&image, &target, format);
    let _ = std::io::stdout().lock().write_all(d.text.as_bytes());
    for e in &d.errors {
        eprintln!("gutta-cc dis: {e}");
    }
    Ok(if d.errors.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}
