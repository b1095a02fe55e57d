//! `gutta-cc`: the command line. All file I/O and process exit codes live here; the
//! library does the work. Exit status: 0 clean (warnings allowed), 1 errors in the
//! program, 2 usage or I/O errors.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};
use gutta_catalog::stdlib;
use gutta_compiler::diagnostics::json;
use gutta_compiler::diagnostics::render::{render, RenderStyle};
use gutta_compiler::encode::{listing, summary};
use gutta_compiler::source::SourceFile;
use gutta_compiler::{check_program, compile_program, ExplicitTarget, ProgramSources};

#[derive(Debug, Parser)]
#[command(
    name = "gutta-cc",
    version,
    about = "Compiler for GUTTA PLC ladder/STL programs",
    args_conflicts_with_subcommands = true
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
    /// A symbol table (CSV `Symbol,Address,Comment`, or Micro/WIN's tab-separated rows)
    /// or a program source (.lad) whose symbols the command may use (repeatable). When
    /// compiling, a table's symbols join the program's.
    #[arg(long, global = true, value_name = "FILE")]
    symbols: Vec<PathBuf>,
    /// How to print diagnostics, errors and results: human text, or JSON (one object per
    /// line on stdout).
    #[arg(long, global = true, value_enum, default_value_t = MessageFormat::Human)]
    message_format: MessageFormat,
    /// Colour in human output.
    #[arg(long, global = true, value_enum, default_value_t = ColorChoice::Auto)]
    color: ColorChoice,
}

#[derive(Debug, clap::Args)]
struct TargetArgs {
    /// PLC type from the stdlib (overrides PLC_TYPE in the file).
    #[arg(long, global = true, value_name = "NAME")]
    plc: Option<String>,
    /// A target folder holding PlcType.xml, ManagerVar.xml and ManagerFun.xml.
    #[arg(long, global = true, value_name = "DIR", conflicts_with = "plc")]
    target: Option<PathBuf>,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Print the Modbus address of a variable (the vendor editor's Modbus query).
    Modbus {
        /// A direct address such as MW20, MB31, Q3.0, I0.4.
        variable: String,
    },
    /// Print an image directory as STL that compiles back to the same pages.
    Dis {
        /// The image directory (holding manifest.json).
        image: PathBuf,
    },
    /// Explain a code the tools print: E and W (compiler diagnostics), V (image
    /// verification), T (target description files), e.g. E0302, V0040, T0003.
    Explain { code: String },
    /// Download an image directory into a PLC (UM4001: the PLC type must match; the PLC
    /// is cleared, every page written and read back, then reset to run the image).
    Download {
        /// The image directory (holding manifest.json).
        image: PathBuf,
        #[command(flatten)]
        link: LinkArgs,
    },
    /// Upload the PLC's program into an image directory (the pages the PLC holds).
    Upload {
        /// The directory to write (created; written atomically).
        #[arg(short, long, value_name = "DIR")]
        output: PathBuf,
        #[command(flatten)]
        link: LinkArgs,
    },
    /// Print the PLC's status (RUN, RESET, ATTACH, ERROR) and PLC type.
    Status {
        #[command(flatten)]
        link: LinkArgs,
    },
    /// Put the PLC in RUN.
    Run {
        #[command(flatten)]
        link: LinkArgs,
    },
    /// Put the PLC in STOP.
    Stop {
        #[command(flatten)]
        link: LinkArgs,
    },
    /// Read variables (`VAR = VALUE` lines, unsigned decimal; bits 0 or 1).
    Read {
        /// Direct addresses: MW24, Q0.0, AIW0, MD4.
        #[arg(required = true)]
        vars: Vec<String>,
        #[command(flatten)]
        link: LinkArgs,
    },
    /// Write variables (an input's terminal holds the value across scans).
    Write {
        /// VAR=VALUE: MW0=16#FF, Q0.0=1, AIW0=100.
        #[arg(required = true)]
        assignments: Vec<String>,
        #[command(flatten)]
        link: LinkArgs,
    },
    /// Release forced variables (they follow the program and inputs again).
    Unforce {
        /// Direct addresses that were forced: Q0.0, IB0.
        #[arg(required = true)]
        vars: Vec<String>,
        #[command(flatten)]
        link: LinkArgs,
    },
    /// Debug the running program: `break MAIN:2:0` (or `break main.lad:12` with a source
    /// map), `clear`, `stop` (single-step stop), `run`, `step in|over|out`, `reset` (reset
    /// into single-step stop), `info`.
    Debug {
        /// The action, then its argument (a position or FILE:LINE for `break`, in/over/out
        /// for `step`).
        #[arg(required = true, num_args = 1..=2)]
        action: Vec<String>,
        /// The image directory the PLC runs, whose source map (DIR.map.json) shows file:line
        /// and instruction text [default: `image` when image.map.json exists].
        #[arg(long, value_name = "DIR")]
        image: Option<PathBuf>,
        #[command(flatten)]
        link: LinkArgs,
    },
    /// Force I or Q variables to values (they keep them every scan).
    Force {
        /// VAR=VALUE: Q0.0=1, IB0=16#0F.
        #[arg(required = true)]
        assignments: Vec<String>,
        #[command(flatten)]
        link: LinkArgs,
    },
    /// List the stdlib PLC types.
    ListTargets,
}

/// Serial parity, as a system block's PORTn.PARITY.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Parity {
    None,
    Even,
    Odd,
}

/// How to reach a PLC.
#[derive(Debug, clap::Args)]
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

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum MessageFormat {
    Human,
    Json,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum ColorChoice {
    Auto,
    Always,
    Never,
}

mod client;
mod explain;
mod login;

/// A usage or I/O failure: printed, exit 2.
struct Fatal(String);

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(code) => code,
        Err(Fatal(message)) => {
            eprintln!("gutta-cc: error: {message}");
            ExitCode::from(2)
        }
    }
}

fn run(cli: Cli) -> Result<ExitCode, Fatal> {
    match &cli.command {
        Some(Command::Modbus { variable }) => return modbus(&cli.target, variable),
        Some(Command::Explain { code }) => return explain(code),
        Some(Command::Dis { image }) => return dis(&cli.target, image),
        Some(Command::Download { image, link }) => {
            return client::download(&cli.target, image, link)
        }
        Some(Command::Status { link }) => return client::status(link),
        Some(Command::Upload { output, link }) => return client::upload(&cli.target, output, link),
        Some(Command::Run { link }) => return client::run_stop(link, true),
        Some(Command::Stop { link }) => return client::run_stop(link, false),
        Some(Command::Read { vars, link }) => return client::read(&cli.target, vars, link),
        Some(Command::Write { assignments, link }) => {
            return client::write(&cli.target, assignments, link, false)
        }
        Some(Command::Unforce { vars, link }) => return client::unforce(&cli.target, vars, link),
        Some(Command::Debug {
            action,
            image,
            link,
        }) => return client::debug(&cli.target, action, image.as_deref(), link),
        Some(Command::Force { assignments, link }) => {
            return client::write(&cli.target, assignments, link, true)
        }
        Some(Command::ListTargets) => {
            for name in stdlib::names() {
                let t = stdlib::load(name).map_err(|e| Fatal(e.to_string()))?;
                // A closed pipe (`| head`) ends the listing quietly.
                if writeln!(std::io::stdout(), "{:<16} {}", name, t.plc.information).is_err() {
                    break;
                }
            }
            return Ok(ExitCode::SUCCESS);
        }
        None => {}
    }
    if cli.files.is_empty() {
        return Err(Fatal(
            "no input files (try `gutta-cc main.lad -o image/`, `gutta-cc --check main.lad`, or --help)".into(),
        ));
    }
    let compiling = cli.output.is_some() || cli.emit.is_some();
    let program = read_program(&cli.files, &cli.symbols)?;
    let name = match program.sources.len() {
        1 => program.sources[0].name.clone(),
        n => format!("{n} files"),
    };
    let explicit = explicit_target(&cli.target)?;
    let color = match cli.color {
        ColorChoice::Always => true,
        ColorChoice::Never => false,
        ColorChoice::Auto => {
            std::io::stderr().is_terminal() && std::env::var_os("NO_COLOR").is_none()
        }
    };
    let style = RenderStyle {
        color,
        unicode: color,
    };
    let stdout = std::io::stdout();
    let (checked, image) = if compiling {
        let compiled = compile_program(program, explicit.as_ref());
        if let (Some(Emit::Listing), Some(lowered)) = (cli.emit, &compiled.lowered) {
            if compiled.image.is_some() {
                let text = listing(
                    lowered,
                    &compiled.checked.file,
                    &compiled.checked.index,
                    compiled.checked.target.name(),
                );
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
        gutta_io::write_image_with_map(dir, image, map).map_err(|e| Fatal(e.0))?;
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
                    "{name}: {errors} error{}, {warnings} warning{}",
                    plural(errors),
                    plural(warnings)
                );
            } else if let (Some((image, _)), Some(dir)) = (&image, &cli.output) {
                eprintln!(
                    "{name}: wrote {} for {}: {}",
                    dir.display(),
                    image.plc_type,
                    summary(image, &checked.target)
                );
            } else if let Some(p) = &checked.output.program {
                let instructions: usize = p
                    .units
                    .iter()
                    .flat_map(|u| &u.networks)
                    .map(|n| n.instructions.len())
                    .sum();
                eprintln!(
                    "{name}: ok on {} ({} block{}, {instructions} instruction{}, {} data block{}{})",
                    p.target_name,
                    p.units.len(),
                    plural(p.units.len()),
                    plural(instructions),
                    p.data_blocks.len(),
                    plural(p.data_blocks.len()),
                    if warnings > 0 { format!(", {warnings} warning{}", plural(warnings)) } else { String::new() }
                );
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
        return Err(Fatal(format!(
            "--symbols {0}: a .lad file is a source of the program; list it with the sources instead (`gutta-cc ... {0}`)",
            lad.display()
        )));
    }
    let mut program = ProgramSources::default();
    for path in files {
        program.sources.push(read_source(path)?);
    }
    for path in tables {
        program.symbol_tables.push(read_source(path)?);
    }
    Ok(program)
}

/// A file as UTF-8 text (BOM dropped), named as given.
fn read_source(path: &Path) -> Result<SourceFile, Fatal> {
    let bytes =
        std::fs::read(path).map_err(|e| Fatal(format!("cannot read {}: {e}", path.display())))?;
    let name = path.display().to_string();
    SourceFile::from_bytes(&name, bytes).map_err(|e| {
        Fatal(format!(
            "{name} is not UTF-8 text (invalid byte at offset {})",
            e.offset
        ))
    })
}

fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

fn explicit_target(args: &TargetArgs) -> Result<Option<ExplicitTarget>, Fatal> {
    if let Some(name) = &args.plc {
        let target = stdlib::shared(name).map_err(|e| Fatal(e.to_string()))?;
        return Ok(Some(ExplicitTarget {
            target,
            origin: format!("--plc {name}"),
        }));
    }
    if let Some(dir) = &args.target {
        let target = std::sync::Arc::new(gutta_io::load_target_dir(dir).map_err(Fatal)?);
        return Ok(Some(ExplicitTarget {
            target,
            origin: format!("--target {}", dir.display()),
        }));
    }
    Ok(None)
}

fn modbus(args: &TargetArgs, variable: &str) -> Result<ExitCode, Fatal> {
    let target = match explicit_target(args)? {
        Some(e) => e.target,
        None => stdlib::shared(stdlib::DEFAULT).map_err(|e| Fatal(e.to_string()))?,
    };
    let address = target
        .memory
        .parse_address(variable.trim())
        .map_err(|e| Fatal(format!("`{variable}` on {}: {e}", target.name())))?;
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
            Err(Fatal(format!(
                "`{variable}`: area {area} has no Modbus address on {}",
                target.name()
            )))
        }
    }
}

/// `explain CODE`: the registry's text; an unknown code is a usage error (exit 2).
fn explain(code: &str) -> Result<ExitCode, Fatal> {
    let text = explain::explanation(code).map_err(Fatal)?;
    println!("{text}");
    Ok(ExitCode::SUCCESS)
}

/// An image directory and the target it is for: --plc/--target, else its PLC type.
fn image_and_target(
    args: &TargetArgs,
    dir: &Path,
) -> Result<(gutta_format::Image, std::sync::Arc<gutta_catalog::Target>), Fatal> {
    let image = gutta_io::read_image_dir(dir).map_err(Fatal)?;
    let target = match explicit_target(args)? {
        Some(e) => e.target,
        None => stdlib::shared(&image.plc_type).map_err(|e| {
            Fatal(format!(
                "the image is for {}: {e} (pass --target DIR for a vendor PLC type)",
                image.plc_type
            ))
        })?,
    };
    Ok((image, target))
}

fn dis(args: &TargetArgs, dir: &Path) -> Result<ExitCode, Fatal> {
    let (image, target) = image_and_target(args, dir)?;
    let d = gutta_format::disasm::disassemble_with_errors(&image, &target);
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
