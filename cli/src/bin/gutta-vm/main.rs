//! `gutta-vm`: run an image directory on the reference VM from the command line. All
//! file I/O, printing and exit codes live here; the library only runs scans. Exit
//! status: 0 ok, 1 the program faulted, 2 usage, I/O, verification or load errors.

use std::fmt::Write as _;
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::time::{Duration, Instant};

use clap::Parser;
use gutta_catalog::{choose_target, OwnName, Target, TargetInputs};
use gutta_cli::fatal::{Fatal, MessageFormat};
use gutta_cli::target::TargetArgs;
use gutta_format::{MappedInstruction, SourceMap};
use gutta_vm::{Fault, Position, ScanEnd, TierState, Vm, VmConfig, DEFAULT_NATIVE_AFTER};

#[derive(Debug, Parser)]
#[command(
    name = "gutta-vm",
    version,
    about = "Run a GUTTA PLC image on the reference VM",
    after_help = "Variables: symbols (from IMAGE.map.json or --symbols FILE) or direct \
                  addresses such as I0.0, Q3.0, MW24, MD4, AIW0, each with an optional \
                  :bool|int|uint|hex|real (Speed, MD8:real). Values in the variable's format \
                  (-1, 21.5, ON) or raw bits (16#FF, 2#1010).

Examples:
  gutta-vm image/ --scans 100 --read Q0.0 --read MW24
  gutta-vm image/ --scans 50 --set I0.0=1 --read Q0.0 --trace
  gutta-vm image/ --scans 1000 --read Q0.0 --vcd run.vcd
  gutta-vm image/ --break MAIN:2:0 --read MW24 --message-format json

--completions SHELL prints a completion script, --man the man page.
Exit status: 0 ok, 1 the program faulted, 2 usage, I/O or verification errors.",
    mut_arg("plc", |a| a.help("PLC type from the stdlib (instead of the image's PLC type)"))
)]
struct Cli {
    /// The image directory (holding manifest.json), as written by `gutta-cc -o`.
    image: PathBuf,
    /// Number of scans to run.
    #[arg(long, value_name = "N", default_value_t = 1)]
    scans: u64,
    /// Virtual time per scan, in milliseconds (timers count it).
    #[arg(long, value_name = "MS", default_value_t = 10)]
    scan_ms: u32,
    /// Instructions one scan may execute before the watchdog fault.
    #[arg(long, value_name = "N", default_value_t = VmConfig::default().watchdog)]
    watchdog: u64,
    /// Set a variable before the first scan (repeatable): I0.0=1, AIW0=100, MW0=16#FF.
    /// An input keeps its value across scans, as a wired input does.
    #[arg(long = "set", value_name = "VAR=VALUE")]
    set: Vec<String>,
    /// Force a variable of a forcing area (I, Q) for the whole run (repeatable).
    #[arg(long = "force", value_name = "VAR=VALUE")]
    force: Vec<String>,
    /// Print a variable after the last scan (repeatable): `NAME (ADDR) = VALUE` for a
    /// symbol, `ADDR = VALUE` for an address, in its format (bits 0/1, bytes unsigned,
    /// words and double words signed, a symbol's type, or the `:fmt` suffix).
    #[arg(long = "read", value_name = "VAR")]
    read: Vec<String>,
    /// A symbol table (CSV `Symbol,Address,Comment`, or Micro/WIN's tab-separated rows)
    /// or a program source (.lad) whose symbols --set, --force and --read may use
    /// (repeatable), besides the symbols of IMAGE.map.json.
    #[arg(long, value_name = "FILE")]
    symbols: Vec<PathBuf>,
    /// `json`: print one JSON object (scans, values, status, error) instead of text; a
    /// fatal error is one JSON error object on stdout too (docs/cli.md).
    #[arg(long, value_name = "FORMAT", value_enum, default_value_t = MessageFormat::Human)]
    message_format: MessageFormat,
    /// The old spelling of `--message-format json`.
    #[arg(long, hide = true)]
    json: bool,
    /// Print, per scan, the --read variables whose value changed (`scan 3: Q0.0 0 -> 1`).
    #[arg(long, requires = "read")]
    trace: bool,
    /// Write a Value Change Dump of the --read variables, one sample per scan.
    #[arg(long, value_name = "FILE", requires = "read")]
    vcd: Option<PathBuf>,
    /// Pause before an instruction and stop the run there, printing where (with the
    /// source line when IMAGE.map.json is beside the image), the logic stack and the
    /// --read values as they are at that moment. FUNCTION is MAIN, INTn, SBRn or a page
    /// number; NETWORK the network number; STEP the 0-based instruction in the network
    /// (MAIN:2:0). With the source map: FILE:LINE, or LINE alone (main.lad:12, 12); a
    /// line without an instruction stands for the next line that has one.
    #[arg(long = "break", value_name = "FUNCTION:NETWORK:STEP|FILE:LINE")]
    breakpoint: Option<String>,
    /// How the program runs: `interpreted` (never compiled), `compiled` (compiled to
    /// native code at load), `auto` (interpreted, compiled after 100 scans).
    #[arg(long, value_name = "TIER", value_enum, default_value_t = TierChoice::Auto)]
    tier: TierChoice,
    /// After the run, print one line on stderr: scans, instructions, the seconds of
    /// scanning (not loading or compiling), ns per scan and per instruction, the tier.
    #[arg(long)]
    stats: bool,
    #[command(flatten)]
    target: TargetArgs,
}

/// `--tier`: which of the VM's tiers runs the program (docs/vm.md, "Compiled tier").
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum TierChoice {
    /// The interpreter only.
    Interpreted,
    /// Compiled to native code at load.
    Compiled,
    /// Interpreted, then compiled once 100 scans have completed.
    Auto,
}

impl TierChoice {
    /// What `VmConfig::native_after` says for it. `auto` compiles in `scan`, between two
    /// timed scans (`Vm::compile_tier`), at the scan count the VM's default would.
    fn native_after(self) -> Option<u64> {
        match self {
            TierChoice::Interpreted | TierChoice::Auto => None,
            TierChoice::Compiled => Some(0),
        }
    }

    fn name(self) -> &'static str {
        match self {
            TierChoice::Interpreted => "interpreted",
            TierChoice::Compiled => "compiled",
            TierChoice::Auto => "auto",
        }
    }
}

/// The name errors start with and JSON errors carry.
const TOOL: &str = "gutta-vm";

/// Parse (`--completions`/`--man` stand alone), run, and print a fatal error (a usage,
/// I/O, verification or load failure) as --message-format asks; exit 2.
fn main() -> ExitCode {
    let args: Vec<std::ffi::OsString> = std::env::args_os().collect();
    let mut cli: Cli = match gutta_cli::shell::parse_tool_args(TOOL, &args, &["--json"]) {
        Ok(cli) => cli,
        Err(code) => return code,
    };
    cli.json |= cli.message_format == MessageFormat::Json;
    let format = if cli.json {
        MessageFormat::Json
    } else {
        MessageFormat::Human
    };
    match run(&cli) {
        Ok(code) => code,
        Err(e) => e.report(TOOL, format),
    }
}

mod vcd;

use gutta_cli::vars::{self, Var, VarJson};

/// One change seen by --trace.
struct Change {
    scan: u64,
    var: usize,
    from: u32,
    to: u32,
}

/// The run set up: the VM with the image loaded and --set, --force and --break applied,
/// its target, the source map, and the --read variables.
struct Loaded {
    vm: Vm,
    target: Arc<Target>,
    map: Option<SourceMap>,
    reads: Vec<Var>,
}

/// What the scans did: the --read values after the last one, --trace's changes, and the
/// fault or breakpoint that ended the run early.
struct Outcome {
    values: Vec<u32>,
    changes: Vec<Change>,
    fault: Option<(u64, Fault)>,
    paused: Option<(u64, Position)>,
    /// Instructions the scans executed and the seconds spent in them (`--stats`).
    instructions: u64,
    scanning: Duration,
}

fn run(cli: &Cli) -> Result<ExitCode, Fatal> {
    let mut loaded = load(cli)?;
    let outcome = scan(cli, &mut loaded)?;
    let source = Source {
        map: loaded.map.as_ref(),
        target: &loaded.target,
    };
    if cli.json {
        let report = json_report(
            &loaded.vm,
            &loaded.reads,
            &outcome.values,
            cli.trace.then_some(outcome.changes.as_slice()),
            outcome.fault.as_ref(),
            outcome.paused,
            &source,
        );
        let _ = writeln!(std::io::stdout().lock(), "{report}");
    } else {
        print_human(&loaded, &outcome, &source);
    }
    if cli.stats {
        print_stats(cli.tier, &loaded.vm, &outcome);
    }
    Ok(if outcome.fault.is_some() {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

/// Read and verify the image on its target (--plc/--target, else the image's PLC type,
/// read once), load it, resolve the variables and apply --set, --force and --break.
fn load(cli: &Cli) -> Result<Loaded, Fatal> {
    let image = gutta_io::read_image_dir(&cli.image).map_err(Fatal::io)?;
    let chosen = choose_target(&TargetInputs {
        own: Some(OwnName::Image {
            plc: &image.plc_type,
            dir: &cli.image,
        }),
        ..cli.target.inputs()
    });
    let target = gutta_cli::target::load(&chosen)?;
    let verified = gutta_format::verify(&image, &target)
        .map_err(|e| Fatal::program(format!("{}: {e}", cli.image.display())))?;
    let map = match gutta_io::read_source_map(&cli.image, &image) {
        Ok(map) => map,
        Err(e) => {
            eprintln!("gutta-vm: warning: {e}; going on without source lines");
            None
        }
    };
    let config = VmConfig {
        scan_ms: cli.scan_ms,
        watchdog: cli.watchdog,
        native_after: cli.tier.native_after(),
        ..VmConfig::default()
    };
    let mut vm = Vm::new(verified, Arc::clone(&target), config)
        .map_err(|e| Fatal::program(format!("{}: cannot load: {e}", cli.image.display())))?;

    // The image's own symbols (its source map's), then --symbols files.
    let explicit = chosen
        .origin
        .is_command_line()
        .then(|| gutta_compiler::ExplicitTarget {
            target: Arc::clone(&target),
            origin: chosen.origin.to_string(),
        });
    let symbols = vars::symbol_context(
        &cli.symbols,
        map.iter().map(|m| m.symbols.clone()).collect(),
        explicit.as_ref(),
    )
    .map_err(Fatal::usage)?;
    let reads: Vec<Var> = cli
        .read
        .iter()
        .map(|text| {
            vars::resolve(text, &symbols, &target).map_err(|e| Fatal::usage(format!("--read {e}")))
        })
        .collect::<Result<_, _>>()?;
    let sets = parse_assignments(&target, &symbols, "--set", &cli.set)?;
    let forces = parse_assignments(&target, &symbols, "--force", &cli.force)?;
    for (var, value) in &sets {
        vm.write(var.address, *value)
            .map_err(|e| Fatal::usage(format!("--set {}: {}", var.label(), e.0)))?;
    }
    for (var, value) in &forces {
        vm.force(var.address, *value)
            .map_err(|e| Fatal::usage(format!("--force {}: {e}", var.label())))?;
    }
    if let Some(text) = &cli.breakpoint {
        let at = parse_breakpoint(&target, map.as_ref(), &cli.image, text)?;
        vm.set_breakpoint(Some(at))
            .map_err(|e| Fatal::usage(format!("--break {text}: {e}")))?;
    }
    Ok(Loaded {
        vm,
        target,
        map,
        reads,
    })
}

/// Run --scans scans (fewer after a fault, a breakpoint, or STOP when nothing samples
/// per scan), printing --trace's lines and writing the --vcd file.
fn scan(cli: &Cli, loaded: &mut Loaded) -> Result<Outcome, Fatal> {
    let Loaded { vm, reads, .. } = loaded;
    let reads: &[Var] = reads;
    // The --read variables were resolved once, in `load`; a scan only reads them, and
    // only when --trace or --vcd needs their values after every scan.
    let sample = |vm: &Vm, into: &mut [u32]| -> Result<(), Fatal> {
        for (v, value) in reads.iter().zip(into.iter_mut()) {
            *value = vm
                .read(v.address)
                .map_err(|e| Fatal::usage(format!("--read {}: {}", v.label(), e.0)))?;
        }
        Ok(())
    };
    let mut values = vec![0; reads.len()];
    sample(vm, &mut values)?;
    let mut vcd = cli.vcd.as_ref().map(|_| vcd::dump(reads, &values));
    let mut changes: Vec<Change> = Vec::new();
    let stdout = std::io::stdout();
    let mut fault: Option<(u64, Fault)> = None;
    let mut paused: Option<(u64, Position)> = None;
    let per_scan = cli.trace || vcd.is_some();
    let mut now = values.clone();
    let (mut instructions, mut scanning) = (0u64, Duration::ZERO);
    let mut started = Instant::now();
    for n in 1..=cli.scans {
        let end = vm.run_scan();
        if !matches!(end, Ok(ScanEnd::Stopped)) {
            // In STOP nothing ran: the count is the last scan's that did.
            instructions += vm.executed_last_scan();
        }
        if cli.tier == TierChoice::Auto
            && matches!(end, Ok(ScanEnd::Completed))
            && *vm.tier() == TierState::Interpreted
            && vm.scans() >= DEFAULT_NATIVE_AFTER
        {
            // Compiling is not scanning: the clock stops for it.
            scanning += started.elapsed();
            vm.compile_tier();
            started = Instant::now();
        }
        match end {
            Err(f) => fault = Some((n, f)),
            Ok(ScanEnd::Paused(at)) => paused = Some((n, at)),
            // Nothing runs in STOP: the scans left would change nothing.
            Ok(ScanEnd::Stopped) if !per_scan => break,
            Ok(_) => {}
        }
        if per_scan {
            // Sampling and printing are not scanning either.
            scanning += started.elapsed();
            sample(vm, &mut now)?;
            if let Some(dump) = vcd.as_mut() {
                dump.sample(vm.clock_ms(), &now);
            }
            if cli.trace {
                for (i, (&from, &to)) in values.iter().zip(&now).enumerate() {
                    if from == to {
                        continue;
                    }
                    if !cli.json {
                        let v = &reads[i];
                        let _ = writeln!(
                            stdout.lock(),
                            "scan {n}: {} {} -> {}",
                            v.label(),
                            v.show(from),
                            v.show(to)
                        );
                    }
                    changes.push(Change {
                        scan: n,
                        var: i,
                        from,
                        to,
                    });
                }
            }
            values.copy_from_slice(&now);
            started = Instant::now();
        }
        if fault.is_some() || paused.is_some() {
            break;
        }
    }
    scanning += started.elapsed();
    if !per_scan {
        sample(vm, &mut values)?;
    }
    if let (Some(dump), Some(path)) = (vcd, &cli.vcd) {
        // The end of the run, so the last value shows for its whole time.
        let text = dump.finish(vm.clock_ms());
        std::fs::write(path, text)
            .map_err(|e| Fatal::io(format!("cannot write {}: {e}", path.display())))?;
    }
    Ok(Outcome {
        values,
        changes,
        fault,
        paused,
        instructions,
        scanning,
    })
}

/// `--stats`: `stats: 1000 scans, 18000 instructions, 0.000620 s, 620.0 ns/scan, 34.44
/// ns/instruction, tier auto` on stderr (0 per scan or instruction when there were none).
/// The seconds are those of the scans alone: not loading, compiling (`auto` compiles
/// between two scans), nor the sampling of --trace and --vcd between scans.
fn print_stats(tier: TierChoice, vm: &Vm, outcome: &Outcome) {
    let scans = vm.scans();
    let seconds = outcome.scanning.as_secs_f64();
    let per = |n: u64| {
        if n == 0 {
            0.0
        } else {
            seconds * 1e9 / n as f64
        }
    };
    eprintln!(
        "stats: {scans} scans, {} instructions, {seconds:.6} s, {:.1} ns/scan, {:.2} ns/instruction, tier {}",
        outcome.instructions,
        per(scans),
        per(outcome.instructions),
        tier.name()
    );
    if tier != TierChoice::Interpreted {
        let why = match vm.tier() {
            TierState::Refused(why) => Some(format!("the code generator refused ({why})")),
            // No unit compiles whole and every run of compilable records is too short
            // to pay for entering it (docs/vm-jit.md, "Regions"); with regions 0, only
            // subroutines such runs call were compiled.
            TierState::NothingToCompile | TierState::Compiled { regions: 0, .. } => Some(
                "nothing in the program is worth compiling (no unit compiles whole, no run of 6 instructions)"
                    .to_string(),
            ),
            _ => None,
        };
        if let Some(why) = why {
            eprintln!(
                "gutta-vm: note: --tier {}: {why}; every scan ran interpreted",
                tier.name()
            );
        }
    }
}

/// The --read values on stdout; where the run paused or faulted on stderr.
fn print_human(loaded: &Loaded, outcome: &Outcome, source: &Source) {
    let Loaded {
        vm, target, reads, ..
    } = loaded;
    let mut out = String::new();
    for (v, value) in reads.iter().zip(&outcome.values) {
        let _ = writeln!(out, "{} = {}", v.label(), v.show(*value));
    }
    let _ = std::io::stdout().lock().write_all(out.as_bytes());
    if let Some((n, at)) = outcome.paused {
        match source.instruction(at) {
            Some(i) => eprintln!(
                "gutta-vm: paused at {} in scan {n}; values are before that instruction",
                source.describe(at, i)
            ),
            None => eprintln!(
                "gutta-vm: paused at breakpoint {} (function {}) network {} step {} in scan {n}; values are before that instruction",
                function_name(target, at.function),
                at.function,
                at.network,
                at.step
            ),
        }
        eprintln!(
            "gutta-vm: logic stack (top first): {}",
            logic_stack(vm, target)
        );
    }
    if let Some((n, f)) = &outcome.fault {
        eprintln!(
            "gutta-vm: fault in scan {n}: {f} (error code {}, {})",
            f.code(),
            fault_kind(f)
        );
        if let Some(at) = vm.fault_position() {
            let place = match source.instruction(at) {
                Some(i) => source.describe(at, i),
                None => format!(
                    "{} network {} step {}",
                    function_name(target, at.function),
                    at.network,
                    at.step
                ),
            };
            eprintln!("gutta-vm: the fault is in {place}");
        }
    }
}

/// Where instructions are in the source, when the image has its source map.
struct Source<'a> {
    map: Option<&'a SourceMap>,
    target: &'a Target,
}

impl Source<'_> {
    fn instruction(&self, at: Position) -> Option<&MappedInstruction> {
        self.map?.at_position(at.function, at.network, at.step)
    }

    /// `main.lad:12:1 (MAIN network 2 step 0): MOVW  MW10, MW20`.
    fn describe(&self, at: Position, i: &MappedInstruction) -> String {
        let file = self.map.map_or("", |m| m.file_of(i));
        format!(
            "{file}:{}:{} ({} network {} step {}): {}",
            i.line,
            i.column,
            function_name(self.target, at.function),
            at.network,
            at.step,
            i.text
        )
    }

    /// `{"file", "line", "column", "text"}` of the instruction, or null.
    fn json(&self, at: Option<Position>) -> serde_json::Value {
        match (self.map, at.and_then(|at| self.instruction(at))) {
            (Some(map), Some(i)) => serde_json::json!({
                "file": map.file_of(i),
                "line": i.line,
                "column": i.column,
                "text": i.text,
            }),
            _ => serde_json::Value::Null,
        }
    }
}

/// The logic stack as bits, top first, as deep as the target's stack.
fn logic_stack(vm: &Vm, target: &Target) -> String {
    let stack = vm.debug_state().logic_stack;
    (0..u32::from(target.instructions.logic_stack_depth).min(32))
        .map(|level| if stack >> level & 1 == 1 { '1' } else { '0' })
        .collect()
}

/// `MAIN:2:0`, `SBR0:1:3`, `INT1:1:0`, `8:1:0` (a function (unit page), network and
/// step) or, with the source map, `main.lad:12` or `12` (a note says when the line had no
/// instruction and the next one is taken).
fn parse_breakpoint(
    target: &Target,
    map: Option<&SourceMap>,
    image: &std::path::Path,
    text: &str,
) -> Result<Position, Fatal> {
    let map_name = gutta_io::source_map_path(image).display().to_string();
    let at = gutta_format::parse_breakpoint(text, &target.plc, map, &map_name)
        .map_err(|e| Fatal::usage(format!("--break {e}")))?;
    if let Some(note) = at.note {
        eprintln!("gutta-vm: note: --break {note}");
    }
    let (function, network, step) = at.position;
    Ok(Position {
        function,
        network,
        step,
    })
}

/// MAIN, INTn or SBRn for a unit page.
fn function_name(target: &Target, page: u8) -> String {
    gutta_format::function_name(page, &target.plc)
}

/// The fault's variant name (`Watchdog`), for JSON and messages.
fn fault_kind(f: &Fault) -> String {
    format!("{f:?}")
        .chars()
        .take_while(char::is_ascii_alphanumeric)
        .collect()
}

fn json_report(
    vm: &Vm,
    reads: &[Var],
    values: &[u32],
    trace: Option<&[Change]>,
    fault: Option<&(u64, Fault)>,
    paused: Option<(u64, Position)>,
    source: &Source,
) -> serde_json::Value {
    use serde_json::{json, Map, Value};
    let mut map = Map::new();
    for (v, value) in reads.iter().zip(values) {
        map.insert(v.name().to_string(), v.json_value(*value));
    }
    let error = match fault {
        Some((scan, f)) => json!({
            "kind": fault_kind(f),
            "code": f.code(),
            "message": f.to_string(),
            "scan": scan,
            "position": vm.fault_position().map(|at| at.to_string()),
            "source": source.json(vm.fault_position()),
        }),
        None => Value::Null,
    };
    let mut report = json!({
        "scans": vm.scans(),
        "clock_ms": vm.clock_ms(),
        "values": map,
        "status": {
            "run": vm.is_running() && fault.is_none(),
            "error": fault.is_some(),
            "paused": paused.is_some(),
            "byte": vm.status().byte(),
        },
        "error": error,
        "break": paused.map_or(Value::Null, |(scan, at)| json!({
            "function": at.function,
            "network": at.network,
            "step": at.step,
            "scan": scan,
            "source": source.json(Some(at)),
            "logic_stack": logic_stack(vm, source.target),
        })),
    });
    if let Some(changes) = trace {
        report["trace"] = changes
            .iter()
            .map(
                |c| {
                    let v = &reads[c.var];
                    json!({ "scan": c.scan, "var": v.name(), "from": v.json_value(c.from), "to": v.json_value(c.to) })
                },
            )
            .collect();
    }
    report
}

fn parse_assignments(
    target: &Target,
    symbols: &gutta_format::SymbolTable,
    option: &str,
    items: &[String],
) -> Result<Vec<(Var, u32)>, Fatal> {
    items
        .iter()
        .map(|item| {
            vars::resolve_assignment(item, symbols, target)
                .map_err(|e| Fatal::usage(format!("{option} {e}")))
        })
        .collect()
}
