//! gutta-cc's command line as clap parses it: `Cli`, its commands (`Command`), the link
//! flags (`LinkArgs`) and the value enums. It must not run a command; `main.rs`
//! dispatches them to their modules.

use std::path::PathBuf;

use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::{CommandFactory, Parser, Subcommand, ValueEnum};
use gutta_cli::color::ColorChoice;
use gutta_cli::fatal::MessageFormat;
use gutta_cli::shell::Shell;
use gutta_cli::target::TargetArgs;
use gutta_format::Parity;
use gutta_link::LinkConfig;

use crate::{client, fx, help};

/// The command line as the parser, the help, the completions and the man pages see it.
pub(crate) fn cli_command() -> clap::Command {
    help::grouped(Cli::command())
}

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
pub(crate) struct Cli {
    #[command(subcommand)]
    pub(crate) command: Option<Command>,
    /// Source files (.lad): together, one program to check or compile.
    pub(crate) files: Vec<PathBuf>,
    /// Check only (parse and check; write nothing).
    #[arg(long, conflicts_with = "output")]
    pub(crate) check: bool,
    /// Compile and write the download image into this directory.
    #[arg(short, long, value_name = "DIR")]
    pub(crate) output: Option<PathBuf>,
    /// Also print a listing (every source line with its page, offset and bytes) on stdout.
    #[arg(long, value_enum, conflicts_with = "check")]
    pub(crate) emit: Option<Emit>,
    #[command(flatten)]
    pub(crate) target: TargetArgs,
    /// In a STEP 7-Micro/WIN export, scale constant timer presets where the timer
    /// number's S7-200 resolution differs from the target's, so the program keeps its
    /// S7-200 timing (rounded to the nearest unit; docs/microwin.md).
    #[arg(long, global = true)]
    pub(crate) scale_timer_presets: bool,
    /// In a STEP 7-Micro/WIN export, where the S area (sequence control relays S0.0-S31.7)
    /// goes: the byte address of SB0, such as MB96 (default: the last 32 bytes of M;
    /// docs/microwin.md, "Sequence control relays").
    #[arg(long, global = true, value_name = "BYTE", value_parser = parse_s_area)]
    pub(crate) s_area: Option<gutta_compiler::microwin::SAreaBase>,
    /// A symbol table (CSV `Symbol,Address,Comment`, or Micro/WIN's tab-separated rows)
    /// or a program source (.lad) whose symbols the command may use (repeatable). When
    /// compiling, a table's symbols join the program's.
    #[arg(long, global = true, value_name = "FILE")]
    pub(crate) symbols: Vec<PathBuf>,
    /// How to print diagnostics, errors and results: human text, or JSON (one object per
    /// line on stdout).
    #[arg(long, global = true, value_name = "FORMAT", value_enum, default_value_t = MessageFormat::Human)]
    pub(crate) message_format: MessageFormat,
    /// Colour in human output (auto: on a terminal, unless NO_COLOR is set and not empty).
    #[arg(long, global = true, value_name = "WHEN", value_enum, default_value_t = ColorChoice::Auto)]
    pub(crate) color: ColorChoice,
    /// The project (gutta.toml) found from the current directory, when the command uses
    /// one (`project::apply`).
    #[arg(skip)]
    pub(crate) project: Option<gutta_io::Project>,
}

#[derive(Debug, Clone, Subcommand)]
pub(crate) enum Command {
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
        after_help = "Examples:\n  cd demo && gutta-cc test                        # a project's tests/ (`gutta-cc new demo`)\n  gutta-cc test demo/tests/main.gtest --filter start_latches_and_stop_releases --exact\n  gutta-cc test demo/tests --junit report.xml --vcd waves/\n  gutta-cc test demo/tests --message-format json"
    )]
    Test {
        /// Test files (.gtest) or folders searched for them [default: the project's tests/].
        paths: Vec<PathBuf>,
        /// Run only the tests whose name contains this text (any case).
        #[arg(long, value_name = "NAME")]
        filter: Option<String>,
        /// With --filter: only the test named exactly NAME (any case), as the list of
        /// failed tests re-runs one.
        #[arg(long, requires = "filter")]
        exact: bool,
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
    /// Open GUTTA Studio: the program's ladder in the browser, served by gutta-cc on
    /// loopback to the page holding the printed address and its per-run token; it reads
    /// and writes only the project's files (docs/studio.md). Ctrl-C stops it (exit 0).
    #[command(
        after_help = "Examples:\n  timeout --preserve-status -s INT 2 gutta-cc studio main.lad --no-open        # serve 2 s, then Ctrl-C\n  cd demo && timeout --preserve-status -s INT 2 gutta-cc studio --no-open     # the project (`gutta-cc new demo`)"
    )]
    Studio(StudioArgs),
    /// Draw a program's networks as ladder diagrams (LAD) into an .svg (every network) or a
    /// self-contained .html page (docs/ladder.md); a network that is not one rung is shown
    /// as STL with the reason.
    #[command(
        after_help = "Examples:\n  gutta-cc ladder main.lad -o main.svg\n  gutta-cc ladder main.lad -o main.html          # open it in a browser\n  gutta-cc ladder image/ -o image.svg              # an image: addresses, no symbols\n  cd demo && gutta-cc ladder . -o demo.html       # a project (`gutta-cc new demo`)"
    )]
    Ladder {
        /// A source file (.lad, .awl), a project (its folder or gutta.toml), an image
        /// directory (drawn through the disassembler), or a ladder model (.json).
        input: PathBuf,
        /// The file to write: .svg, .html, .json (the ladder model), or - (the model on
        /// stdout); from a ladder model: .lad (its program), or - (the program on stdout).
        #[arg(short, long, value_name = "FILE")]
        output: PathBuf,
        #[command(flatten)]
        draw: DrawArgs,
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

/// `--parity`: gutta_format's one `Parity`, by the names gutta.toml uses.
fn parity_parser() -> impl TypedValueParser<Value = Parity> {
    PossibleValuesParser::new(Parity::ALL.map(Parity::name))
        .try_map(|name| Parity::from_name(&name).ok_or("not a parity"))
}

/// How to reach a PLC.
#[derive(Debug, Clone, clap::Args)]
pub(crate) struct LinkArgs {
    /// Modbus TCP, e.g. 127.0.0.1:502.
    #[arg(long, value_name = "HOST:PORT", group = "endpoint")]
    pub(crate) tcp: Option<String>,
    /// Modbus RTU frames over TCP (a serial server, or gutta-sim --rtu-tcp).
    #[arg(long, value_name = "HOST:PORT", group = "endpoint")]
    pub(crate) rtu_tcp: Option<String>,
    /// Modbus RTU on a serial device (8 data bits, 1 stop bit).
    #[arg(long, value_name = "DEVICE", group = "endpoint")]
    pub(crate) serial: Option<String>,
    /// Baud rate for --serial: the PLC's port 0 (its system block), 19200 without one.
    #[arg(long, value_name = "BAUD", default_value_t = 19200)]
    pub(crate) baud: u32,
    /// Parity for --serial: the PLC's port 0 (its system block), even without one.
    #[arg(long, value_name = "PARITY", default_value = "even", value_parser = parity_parser())]
    pub(crate) parity: Parity,
    /// The PLC's login password (the system block's). Visible to other users: prefer
    /// GUTTA_PASSWORD, or the prompt a terminal gets when the factory password is refused.
    #[arg(long, value_name = "TEXT")]
    pub(crate) password: Option<String>,
    /// The PLC's station address.
    #[arg(long, value_name = "N", default_value_t = LinkConfig::STATION)]
    pub(crate) station: u8,
    /// Milliseconds to wait for each answer.
    #[arg(long, value_name = "MS", default_value_t = LinkConfig::TIMEOUT_MS)]
    pub(crate) timeout: u64,
    /// Attempts after the first when an answer does not come.
    #[arg(long, value_name = "N", default_value_t = LinkConfig::RETRIES)]
    pub(crate) retries: u32,
}

/// What `gutta-cc studio` serves, and where.
#[derive(Debug, Clone, clap::Args)]
pub(crate) struct StudioArgs {
    /// A project folder, or source files (.lad) of one folder [default: the project
    /// around the current directory].
    #[arg(value_name = "PROJECT_DIR | FILE.lad")]
    pub(crate) paths: Vec<PathBuf>,
    /// Where the HTTP server listens: loopback with a free port unless given (port 0:
    /// any free port); the address with the token is the first line on stdout.
    #[arg(long, value_name = "HOST:PORT", default_value = "127.0.0.1:0")]
    pub(crate) http: String,
    /// Do not open the page in the browser (the address is on stdout).
    #[arg(long)]
    pub(crate) no_open: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum Emit {
    Listing,
}

/// The layouts of `gutta-cc dis --format`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum DisFormat {
    /// The toolchain's own STL.
    Stl,
    /// A STEP 7-Micro/WIN STL export.
    Awl,
}

impl Command {
    /// The link flags of a command that talks to a PLC.
    pub(crate) fn link_mut(&mut self) -> Option<&mut LinkArgs> {
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
            | Command::Studio { .. }
            | Command::Modbus { .. }
            | Command::Dis { .. }
            | Command::Explain { .. }
            | Command::ListTargets
            | Command::Completions { .. }
            | Command::Man { .. } => None,
        }
    }
}

/// What every client command takes from the command line besides its link.
pub(crate) fn online(cli: &Cli) -> client::Online<'_> {
    client::Online {
        targets: &cli.target,
        symbol_files: &cli.symbols,
        json: cli.message_format == MessageFormat::Json,
    }
}

/// How `gutta-cc ladder` draws (docs/ladder.md, "Names" and "Symbol information").
#[derive(clap::Args, Debug, Clone, Default)]
pub(crate) struct DrawArgs {
    /// Box and compare labels: lad (Micro/WIN's LAD names: ADD_I, MOV_W, >=I) or stl
    /// (the STL mnemonics: +I, MOVW, >=W).
    #[arg(long, value_enum, default_value_t = NamesArg::Lad, value_name = "NAMES")]
    pub names: NamesArg,
    /// Under each rung, a table of the symbols its network uses (address, type,
    /// comment), as Micro/WIN's symbol information.
    #[arg(long)]
    pub symbol_info: bool,
}

#[derive(clap::ValueEnum, Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) enum NamesArg {
    #[default]
    Lad,
    Stl,
}

impl DrawArgs {
    pub(crate) fn options(&self) -> gutta_ladder::svg::DrawOptions {
        gutta_ladder::svg::DrawOptions {
            names: match self.names {
                NamesArg::Lad => gutta_ladder::svg::Names::Lad,
                NamesArg::Stl => gutta_ladder::svg::Names::Stl,
            },
            symbol_info: self.symbol_info,
        }
    }
}

/// `--s-area MB96`: a byte address (whether the target has room there is the compiler's).
fn parse_s_area(text: &str) -> Result<gutta_compiler::microwin::SAreaBase, String> {
    text.parse()
}
