//! `gutta-sim`: a simulated GUTTA PLC on the network. It loads an image directory (or
//! starts empty), runs the VM in real time, and serves Modbus TCP (`--tcp`) and Modbus
//! RTU over TCP (`--rtu-tcp`): standard Modbus 01-06/15/16 and the GUTTA protocol in
//! function 13. All I/O is here, including the PLC's serial ports for EXCH (`ports.rs`);
//! the protocol logic is the library's (gutta-sim).

mod device;
mod flash;
mod fx;
mod listen;
mod plant;
mod plant_ports;
mod ports;
#[cfg(test)]
mod ports_tests;
mod relay;
mod scan;

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use clap::Parser;
use gutta_cli::fatal::{Fatal, MessageFormat};
use gutta_cli::target::TargetArgs;
use gutta_format::LineSettings;
use gutta_sim::plc::{ConnectionId, Plc};
use gutta_sim::session::{Framing, Session};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio_serial::SerialPortBuilderExt;

#[derive(Debug, Parser)]
#[command(
    name = "gutta-sim",
    version,
    about = "A simulated GUTTA PLC: the reference VM behind Modbus and the GUTTA protocol",
    after_help = "Each listener prints `gutta-sim: LISTENER on ADDRESS` once it listens \
                  (port 0 picks a free port). Ctrl-C (SIGINT) or SIGTERM stops the simulator \
                  cleanly: it says so and exits 0.

Examples:
  gutta-sim --tcp 127.0.0.1:5020                        # an empty CPU-EC20
  gutta-sim image/ --tcp 127.0.0.1:5020 --rtu-tcp 127.0.0.1:5021
  gutta-sim image/ --serial /dev/pts/3 --baud 9600
  gutta-sim --plant plant.toml --stats-every 5 --trace-ports   # a plant's devices

--completions SHELL prints a completion script, --man the man page.
Exit status: 0 after a clean stop (Ctrl-C included), 2 for usage, image or network errors.",
    mut_arg("plc", |a| a.help("PLC type from the stdlib (default: the image's, else the stdlib default)"))
)]
struct Cli {
    /// An image directory written by `gutta-cc -o` (the PLC starts empty without one).
    image: Option<PathBuf>,
    /// The device to simulate (docs/devices.md): the GUTTA PLC, the FX-style programming
    /// port (raw frames on --tcp, 7E1 on --serial) or the Modbus-TCP relay board (--tcp).
    #[arg(long, value_enum, default_value_t = Device::Plc)]
    device: Device,
    #[command(flatten)]
    target: TargetArgs,
    /// Serve Modbus TCP on this address (repeatable).
    #[arg(long = "tcp", value_name = "HOST:PORT")]
    tcp: Vec<String>,
    /// Serve Modbus RTU frames over TCP on this address (repeatable).
    #[arg(long = "rtu-tcp", value_name = "HOST:PORT")]
    rtu_tcp: Vec<String>,
    /// Serve Modbus RTU on a serial device (repeatable), e.g. /dev/ttyUSB0 or one end of
    /// a socat pty pair.
    #[arg(long = "serial", value_name = "DEVICE")]
    serial: Vec<PathBuf>,
    /// Hold --serial devices at this baud rate. Without it the n-th device follows the
    /// PLC's port n: the system page's settings after a reset, 19200 8E1 without one
    /// and after PLC_CLEAR.
    #[arg(long, value_name = "BAUD")]
    baud: Option<u32>,
    /// Real time per scan, in milliseconds (also the VM's virtual time per scan).
    #[arg(long, value_name = "MS", default_value_t = 10)]
    scan_ms: u32,
    /// Where the PLC's serial port 0 leads, for EXCH: tcp-connect:HOST:PORT (RTU frames
    /// to another simulator's --rtu-tcp), serial:DEVICE or pty:PATH, or
    /// modbus-tcp:HOST:PORT (through a Modbus RTU <-> TCP gateway to a Modbus TCP
    /// device, such as another simulator's --tcp).
    #[arg(long, value_name = "SPEC")]
    port0: Option<String>,
    /// Where serial port 1 leads (as --port0).
    #[arg(long, value_name = "SPEC")]
    port1: Option<String>,
    /// Every SECS seconds print the scans of that interval and their longest period
    /// (`gutta-sim: stats: 100 scans in 1.00 s, period max 10.4 ms`).
    #[arg(long, value_name = "SECS")]
    stats_every: Option<f64>,
    /// Run every device of a plant file in this process (docs/simulator.md, "Plants"):
    /// PLCs, relay boards and fx ports, each on its own listeners, EXCH between them in
    /// process. The devices' options are the file's.
    #[arg(long, value_name = "PLANT.toml", conflicts_with_all = [
        "image", "device", "plc", "target", "tcp", "rtu_tcp", "serial", "baud", "scan_ms",
        "port0", "port1", "flash",
    ])]
    plant: Option<PathBuf>,
    /// Print every EXCH request and answer of every serial port, as hex
    /// (`gutta-sim: [NAME: ]port0 > 01 02 00 04 00 04 38 08`, `port0 < ...`).
    #[arg(long)]
    trace_ports: bool,
    /// Keep the PLC's user flash (program, system page and password, RUN/STOP) in DIR
    /// across restarts, created if missing. An image is loaded into a DIR that holds
    /// no flash yet; a DIR with a flash keeps it.
    #[arg(long, value_name = "DIR")]
    flash: Option<PathBuf>,
    /// `json`: a start-up error is one JSON error object on stdout (docs/cli.md); the
    /// listener lines stay text.
    #[arg(long, value_name = "FORMAT", value_enum, default_value_t = MessageFormat::Human)]
    message_format: MessageFormat,
}

/// What `gutta-sim` simulates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Device {
    /// The GUTTA PLC (Modbus TCP, RTU over TCP, serial RTU).
    Plc,
    /// The FX-style programming port (docs/devices.md).
    Fx,
    /// The 32-channel Modbus-TCP relay board (--tcp only; docs/devices.md).
    RelayBoard,
}

/// A line on stdout; a closed stdout is not an error of the simulator.
fn say(line: &str) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    let _ = writeln!(out, "{line}");
    let _ = out.flush();
}

/// The identity of the next connection or serial line: the PLC grants a download
/// window to the connection whose PLC_CLEAR opened it (docs/simulator.md, the download
/// safety rule), so every connection gets its own number for the life of the process.
pub(crate) fn next_connection() -> ConnectionId {
    static NEXT: AtomicU64 = AtomicU64::new(1);
    ConnectionId(NEXT.fetch_add(1, Ordering::Relaxed))
}

/// The name errors start with and JSON errors carry.
const TOOL: &str = "gutta-sim";

/// Parse (`--completions`/`--man` stand alone), run until Ctrl-C, and print a start-up
/// failure as --message-format asks; exit 2.
fn main() -> ExitCode {
    let args: Vec<std::ffi::OsString> = std::env::args_os().collect();
    let cli: Cli = match gutta_cli::shell::parse_tool_args(TOOL, &args, &[]) {
        Ok(cli) => cli,
        Err(code) => return code,
    };
    let format = cli.message_format;
    let runtime = match tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
    {
        Ok(r) => r,
        Err(e) => return Fatal::io(format!("cannot start the runtime: {e}")).report(TOOL, format),
    };
    match runtime.block_on(run(cli)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => e.report(TOOL, format),
    }
}

/// Ctrl-C (SIGINT) or SIGTERM (a service manager's or container's stop) on Unix, their
/// handlers installed now (before the listeners announce themselves, so a signal sent
/// after that line is never the default, fatal one); the future says which came.
#[cfg(unix)]
fn interrupted() -> Result<impl std::future::Future<Output = listen::StoppedBy>, Fatal> {
    use tokio::signal::unix::{signal, SignalKind};
    let mut sigint = signal(SignalKind::interrupt())
        .map_err(|e| Fatal::io(format!("cannot handle Ctrl-C: {e}")))?;
    let mut sigterm = signal(SignalKind::terminate())
        .map_err(|e| Fatal::io(format!("cannot handle SIGTERM: {e}")))?;
    Ok(async move {
        tokio::select! {
            _ = sigint.recv() => listen::StoppedBy::CtrlC,
            _ = sigterm.recv() => listen::StoppedBy::Sigterm,
        }
    })
}

/// Ctrl-C: the console's Ctrl-C event elsewhere.
#[cfg(not(unix))]
fn interrupted() -> Result<impl std::future::Future<Output = listen::StoppedBy>, Fatal> {
    Ok(async {
        let _ = tokio::signal::ctrl_c().await;
        listen::StoppedBy::CtrlC
    })
}

async fn run(cli: Cli) -> Result<(), Fatal> {
    ports::TRACE_PORTS.store(cli.trace_ports, std::sync::atomic::Ordering::Relaxed);
    if let Some(file) = &cli.plant {
        return plant::run(file, cli.stats_every, interrupted()?).await;
    }
    match cli.device {
        Device::Plc | Device::Fx => run_plc(cli).await,
        Device::RelayBoard => run_relay_board(cli).await,
    }
}

/// The relay board takes --tcp listeners and nothing of the PLC's.
async fn run_relay_board(cli: Cli) -> Result<(), Fatal> {
    if cli.tcp.is_empty() {
        return Err(Fatal::usage("--device relay-board: give --tcp HOST:PORT"));
    }
    if cli.image.is_some()
        || cli.flash.is_some()
        || !cli.rtu_tcp.is_empty()
        || !cli.serial.is_empty()
        || cli.port0.is_some()
        || cli.port1.is_some()
    {
        return Err(Fatal::usage(
            "--device relay-board serves Modbus TCP only: no image, --flash, --rtu-tcp, --serial or --port0/--port1",
        ));
    }
    relay::run(&cli.tcp, interrupted()?).await
}

/// Serve the GUTTA protocol over RTU on each --serial device, its line following the
/// PLC's port settings.
fn open_serial_lines(cli: &Cli, plc: &Arc<Mutex<Plc>>, start: Instant) -> Result<(), Fatal> {
    for (n, device) in cli.serial.iter().enumerate() {
        let path = device.display().to_string();
        let follow = Follow {
            port: n,
            path: path.clone(),
            fixed_baud: cli.baud,
            line: LineSettings::DEFAULT,
            apply: |port, line| gutta_link::transport::configure(port, line),
        };
        let line = match plc.lock() {
            Ok(plc) => follow.wanted(&plc),
            Err(_) => return Err(Fatal("the PLC state was poisoned by a panic".into())),
        };
        let mut port = tokio_serial::new(&path, line.baud)
            .open_native_async()
            .map_err(|e| Fatal::io(format!("cannot open {path}: {e}")))?;
        gutta_link::transport::configure(&mut port, line)
            .map_err(|e| Fatal::io(format!("{path}: {e}")))?;
        say(&format!("gutta-sim: rtu-serial on {path} ({line})"));
        let plc = Arc::clone(plc);
        tokio::spawn(serve(
            port,
            Framing::Rtu,
            plc,
            start,
            Some(Follow { line, ..follow }),
        ));
    }
    Ok(())
}

async fn run_plc(cli: Cli) -> Result<(), Fatal> {
    if cli.tcp.is_empty() && cli.rtu_tcp.is_empty() && cli.serial.is_empty() {
        return Err(Fatal::usage(
            "nothing to serve: give --tcp HOST:PORT, --rtu-tcp HOST:PORT and/or --serial DEVICE",
        ));
    }
    let ctrl_c = interrupted()?;
    tokio::pin!(ctrl_c);
    if cli.device == Device::Fx {
        return run_fx(&cli, ctrl_c).await;
    }
    let plc = Arc::new(Mutex::new(device::load_plc(&device::PlcSpec {
        name: None,
        image: cli.image.clone(),
        target: cli.target.clone(),
        flash: cli.flash.clone(),
        scan_ms: cli.scan_ms,
        ports: [cli.port0.clone(), cli.port1.clone()],
    })?));
    let start = Instant::now();

    let mut listeners = Vec::new();
    for (framing, addresses) in [(Framing::Tcp, &cli.tcp), (Framing::Rtu, &cli.rtu_tcp)] {
        let kind = match framing {
            Framing::Tcp => "modbus-tcp",
            Framing::Rtu => "rtu-over-tcp",
        };
        for address in addresses {
            listeners.push((framing, listen::bind(address, kind).await?));
        }
    }
    for (framing, listener) in listeners {
        let plc = Arc::clone(&plc);
        listen::accept_forever(listener, move |stream| {
            serve(stream, framing, Arc::clone(&plc), start, None)
        });
    }

    open_serial_lines(&cli, &plc, start)?;

    // The scan cycle, in real time, on a thread of its own (scan.rs).
    let scans = scan::Scans::start(
        vec![scan::ScanDevice {
            name: None,
            plc: Arc::clone(&plc),
            scan_ms: cli.scan_ms,
        }],
        cli.stats_every,
    )
    .map_err(|e| Fatal::io(format!("cannot start the scan thread: {e}")))?;
    let by = ctrl_c.await;
    scans.stop();
    listen::stopped(by)
}

/// `--device fx`: the options that mean something to it, the others refused.
async fn run_fx(
    cli: &Cli,
    ctrl_c: impl std::future::Future<Output = listen::StoppedBy>,
) -> Result<(), Fatal> {
    let plc_only = cli.image.is_some()
        || cli.flash.is_some()
        || cli.target.plc.is_some()
        || cli.target.target.is_some()
        || !cli.rtu_tcp.is_empty()
        || cli.port0.is_some()
        || cli.port1.is_some();
    if plc_only {
        return Err(Fatal::usage(
            "--device fx takes --tcp, --serial and --baud only (no image, --flash, --plc, \
             --target, --rtu-tcp or --portN)",
        ));
    }
    let options = fx::FxOptions {
        tcp: &cli.tcp,
        serial: &cli.serial,
        baud: cli.baud,
    };
    fx::run(options, ctrl_c).await
}

/// One connection or serial line under a new connection identity: read, answer, until
/// the client closes or sends garbage; then a download window it left open ends.
pub(crate) async fn serve<S>(
    stream: S,
    framing: Framing,
    plc: Arc<Mutex<Plc>>,
    start: Instant,
    follow: Option<Follow<S>>,
) where
    S: tokio::io::AsyncRead + tokio::io::AsyncWrite + Unpin,
{
    let connection = next_connection();
    serve_until_closed(
        stream,
        Session::new(framing, connection),
        &plc,
        start,
        follow,
    )
    .await;
    if let Ok(mut plc) = plc.lock() {
        plc.disconnect(connection);
    }
}

async fn serve_until_closed<S>(
    mut stream: S,
    mut session: Session,
    plc: &Mutex<Plc>,
    start: Instant,
    mut follow: Option<Follow<S>>,
) where
    S: tokio::io::AsyncRead + tokio::io::AsyncWrite + Unpin,
{
    let mut buf = vec![0u8; 4096];
    loop {
        let n = match stream.read(&mut buf).await {
            Ok(0) | Err(_) => return,
            Ok(n) => n,
        };
        let now_ms = start.elapsed().as_millis() as u64;
        let answer = match plc.lock() {
            Ok(mut plc) => {
                let refused_before = session.busy;
                let answer = session.on_bytes(&mut plc, &buf[..n], now_ms);
                if let (true, Some(window)) = (session.busy > refused_before, plc.download_window())
                {
                    eprintln!(
                        "gutta-sim: busy: refused {} a change while {} downloads \
                         (its window opened {:.1} s ago)",
                        session.connection(),
                        window.owner,
                        now_ms.saturating_sub(window.opened_ms) as f64 / 1e3
                    );
                }
                answer
            }
            Err(_) => return,
        };
        match answer {
            Ok(bytes) if bytes.is_empty() => {}
            Ok(bytes) => {
                if stream.write_all(&bytes).await.is_err() {
                    return;
                }
                if let Some(follow) = follow.as_mut() {
                    let next = match plc.lock() {
                        Ok(plc) => follow.wanted(&plc),
                        Err(_) => return,
                    };
                    if next != follow.line {
                        // The answer leaves at the old settings (a reset or PLC_CLEAR
                        // is answered before it takes effect), then the line switches.
                        let (path, apply) = (follow.path.clone(), follow.apply);
                        switch_line(
                            &mut stream,
                            apply,
                            "rtu-serial",
                            &path,
                            bytes.len(),
                            follow.line,
                            next,
                        )
                        .await;
                        follow.line = next;
                    }
                }
            }
            Err(e) => {
                eprintln!("gutta-sim: closing a connection: {e}");
                return;
            }
        }
    }
}

/// A serial line that follows the PLC's port settings.
struct Follow<S> {
    /// The PLC port it is (the n-th --serial device).
    port: usize,
    path: String,
    /// --baud: the baud rate stays this.
    fixed_baud: Option<u32>,
    /// The settings the line has now.
    line: LineSettings,
    apply: fn(&mut S, LineSettings) -> Result<(), String>,
}

impl<S> Follow<S> {
    fn wanted(&self, plc: &Plc) -> LineSettings {
        let line = plc.line(self.port);
        LineSettings {
            baud: self.fixed_baud.unwrap_or(line.baud),
            ..line
        }
    }
}

/// How long `bytes` take on a line (start, data, parity and stop bits).
/// After an answer of `answer_len` bytes sent at `old`, switch a serial line to `next`
/// (waiting until the answer has left at the old rate) and say so on stdout; a failure
/// to switch is said on stderr and the line is taken as switched, as a device would.
async fn switch_line<S>(
    stream: &mut S,
    apply: fn(&mut S, LineSettings) -> Result<(), String>,
    kind: &str,
    path: &str,
    answer_len: usize,
    old: LineSettings,
    next: LineSettings,
) {
    tokio::time::sleep(wire_time(answer_len, old)).await;
    match apply(stream, next) {
        Ok(()) => say(&format!("gutta-sim: {kind} on {path} now {next}")),
        Err(e) => eprintln!("gutta-sim: {path}: cannot switch the line to {next}: {e}"),
    }
}

fn wire_time(bytes: usize, line: LineSettings) -> Duration {
    let bits =
        1 + u32::from(line.data_bits) + u32::from(line.parity != 0) + u32::from(line.stop_bits);
    Duration::from_secs_f64(bytes as f64 * f64::from(bits) / f64::from(line.baud.max(1)))
}
