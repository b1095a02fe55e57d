//! `gutta-cc fx`: a client of the FX-style programming port (seed 001; docs/devices.md)
//! over raw TCP (`--tcp`, e.g. `gutta-sim --device fx`) or a serial line at 7E1
//! (`--serial`). The frames are gutta_protocol::fx's, the retries on NAK or silence
//! gutta_protocol::fx_client's, the line gutta-link's `transport::fx`; here are only the
//! arguments, the progress bar, the hints and the output.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use clap::{Args, Subcommand};
use gutta_cli::fatal::Fatal;
use gutta_cli::plural::count;
use gutta_link::transport::{
    self,
    fx::{FxLink, FxLinkError},
};
use gutta_protocol::fx::{
    BaudRate, FxRequest, CONFIG_START, MAX_DATA, PROGRAM_SIZE, PROGRAM_START,
};
use indicatif::{ProgressBar, ProgressStyle};

/// Where the FX-style port is.
#[derive(Debug, Clone, Args)]
pub(crate) struct FxEndpoint {
    /// Raw FX frames over TCP, e.g. gutta-sim --device fx --tcp.
    #[arg(long, value_name = "HOST:PORT", group = "fx_endpoint")]
    tcp: Option<String>,
    /// A serial device, 7 data bits, even parity, 1 stop bit.
    #[arg(long, value_name = "DEVICE", group = "fx_endpoint")]
    serial: Option<String>,
    /// Baud rate for --serial.
    #[arg(long, value_name = "BAUD", default_value_t = 9600)]
    baud: u32,
    /// Milliseconds to wait for each answer.
    #[arg(long, value_name = "MS", default_value_t = 1000)]
    timeout: u64,
    /// Attempts after the first when the answer is NAK or does not come.
    #[arg(long, value_name = "N", default_value_t = 2)]
    retries: u32,
}

/// The `fx` subcommands.
#[derive(Debug, Clone, Subcommand)]
pub(crate) enum FxAction {
    /// Read LEN bytes of the data area from ADDR (`30`): `read 0E02 2`.
    Read {
        /// Address, hex (0E02, 0x0E02).
        #[arg(value_parser = parse_u16)]
        address: u16,
        /// Bytes, 1..255 (decimal, or hex with 0x).
        #[arg(value_parser = parse_len)]
        len: u8,
        #[command(flatten)]
        endpoint: FxEndpoint,
    },
    /// Write bytes into the data area at ADDR (`31`): `write 0E02 11 22`.
    Write {
        #[arg(value_parser = parse_u16)]
        address: u16,
        /// The bytes as hex, separately or run together (11 22, 1122).
        #[arg(required = true)]
        bytes: Vec<String>,
        #[command(flatten)]
        endpoint: FxEndpoint,
    },
    /// Force a bit on (`37`); ADDR is a bit address, hex.
    ForceOn {
        #[arg(value_parser = parse_u16)]
        address: u16,
        #[command(flatten)]
        endpoint: FxEndpoint,
    },
    /// Force a bit off (`38`); ADDR is a bit address, hex.
    ForceOff {
        #[arg(value_parser = parse_u16)]
        address: u16,
        #[command(flatten)]
        endpoint: FxEndpoint,
    },
    /// Switch the device's line rate (`41`): 9600, 19200, 38400, 57600 or 115200.
    Baud {
        rate: u32,
        #[command(flatten)]
        endpoint: FxEndpoint,
    },
    /// Print the configuration block (`E00 8000 FE`) as a hex dump.
    Config {
        #[command(flatten)]
        endpoint: FxEndpoint,
    },
    /// Read program memory from 805C into FILE (`E01`, 0xFE bytes a frame).
    UploadProgram {
        /// The file to write (raw bytes).
        #[arg(short, long, value_name = "FILE")]
        output: PathBuf,
        /// Bytes to read [default: all of program memory, 805C-FFFF].
        #[arg(long, value_name = "BYTES")]
        size: Option<usize>,
        #[command(flatten)]
        endpoint: FxEndpoint,
    },
    /// Write FILE into program memory from 805C (`E11`), read it back and compare
    /// (`E01`), then end the write (`E87`).
    DownloadProgram {
        /// The program's raw bytes.
        file: PathBuf,
        #[command(flatten)]
        endpoint: FxEndpoint,
    },
}

fn parse_u16(text: &str) -> Result<u16, String> {
    let digits = text.trim_start_matches("0x").trim_start_matches("0X");
    u16::from_str_radix(digits, 16).map_err(|_| format!("`{text}` is not a hex address 0000-FFFF"))
}

fn parse_len(text: &str) -> Result<u8, String> {
    let value = match text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
        Some(hex) => u8::from_str_radix(hex, 16),
        None => text.parse(),
    };
    match value {
        Ok(0) | Err(_) => Err(format!("`{text}` is not a length 1..255")),
        Ok(n) => Ok(n),
    }
}

fn parse_bytes(words: &[String]) -> Result<Vec<u8>, Fatal> {
    let text: String = words.concat();
    let bad = || {
        Fatal::usage(format!(
            "`{}` is not bytes in hex (11 22 or 1122)",
            words.join(" ")
        ))
    };
    if text.is_empty() || !text.len().is_multiple_of(2) {
        return Err(bad());
    }
    (0..text.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(text.get(i..i + 2).ok_or_else(bad)?, 16).map_err(|_| bad()))
        .collect()
}

/// Open the port `endpoint` names.
fn connect(endpoint: &FxEndpoint) -> Result<FxLink, Fatal> {
    let to = match (&endpoint.tcp, &endpoint.serial) {
        (Some(address), _) => transport::fx::FxEndpoint::Tcp(address.clone()),
        (None, Some(device)) => transport::fx::FxEndpoint::Serial {
            device: device.clone(),
            baud: endpoint.baud,
        },
        (None, None) => return Err(Fatal::usage("give --tcp HOST:PORT or --serial DEVICE")),
    };
    FxLink::connect(&to, endpoint.timeout, endpoint.retries).map_err(|e| match (&e, &to) {
        (FxLinkError::Connect { refused: true, .. }, transport::fx::FxEndpoint::Tcp(address)) => {
            Fatal::link(e.to_string()).with_hint(format!(
                "is an FX-style port or gutta-sim listening at {address}? Check the address, or start a simulated one there: `gutta-sim --device fx --tcp {address}`"
            ))
        }
        _ => fatal(e),
    })
}

/// A failed exchange as the user reads it, with what to check.
fn fatal(e: FxLinkError) -> Fatal {
    match e {
        FxLinkError::BadRequest(message) => Fatal::usage(message),
        FxLinkError::Failed(failure) => {
            let fatal = Fatal::link(failure.to_string());
            if failure.all_nak() {
                fatal.with_hint(
                    "the device refuses the request: check the address range (docs/devices.md)",
                )
            } else if failure.all_silent() {
                fatal.with_hint("check the endpoint, the baud rate and --timeout")
            } else {
                fatal
            }
        }
        e => Fatal::link(e.to_string()),
    }
}

/// `ADDR: XX XX ...`, 16 bytes a line.
fn dump(start: u16, data: &[u8]) -> String {
    let mut out = String::new();
    for (n, row) in data.chunks(16).enumerate() {
        let address = usize::from(start) + 16 * n;
        let hex: Vec<String> = row.iter().map(|b| format!("{b:02X}")).collect();
        out.push_str(&format!("{address:04X}: {}\n", hex.join(" ")));
    }
    out
}

fn progress(total: usize, prefix: &'static str) -> Result<ProgressBar, Fatal> {
    if !std::io::stderr().is_terminal() {
        return Ok(ProgressBar::hidden());
    }
    let style = ProgressStyle::with_template("{prefix} [{bar:32}] {pos}/{len} bytes")
        .map_err(|e| Fatal::io(format!("progress bar: {e}")))?
        .progress_chars("=> ");
    Ok(ProgressBar::new(total as u64)
        .with_style(style)
        .with_prefix(prefix))
}

/// Runs one `gutta-cc fx` subcommand; prints its result on stdout.
pub(crate) fn run(action: &FxAction) -> Result<std::process::ExitCode, Fatal> {
    let out = match action {
        FxAction::Read {
            address,
            len,
            endpoint,
        } => {
            let mut client = connect(endpoint)?;
            let request = FxRequest::Read {
                address: *address,
                len: *len,
            };
            dump(
                *address,
                &client
                    .expect_data(&request, usize::from(*len))
                    .map_err(fatal)?,
            )
        }
        FxAction::Write {
            address,
            bytes,
            endpoint,
        } => {
            let data = parse_bytes(bytes)?;
            if data.len() > MAX_DATA {
                return Err(Fatal::usage(format!(
                    "{}: a write carries at most {MAX_DATA}",
                    count(data.len(), "byte")
                )));
            }
            let mut client = connect(endpoint)?;
            let n = data.len();
            client
                .expect_ack(&FxRequest::Write {
                    address: *address,
                    data,
                })
                .map_err(fatal)?;
            format!("wrote {} at {address:04X}\n", count(n, "byte"))
        }
        FxAction::ForceOn { address, endpoint } => {
            connect(endpoint)?
                .expect_ack(&FxRequest::ForceOn { bit: *address })
                .map_err(fatal)?;
            format!("forced bit {address:04X} on\n")
        }
        FxAction::ForceOff { address, endpoint } => {
            connect(endpoint)?
                .expect_ack(&FxRequest::ForceOff { bit: *address })
                .map_err(fatal)?;
            format!("forced bit {address:04X} off\n")
        }
        FxAction::Baud { rate, endpoint } => {
            let rate = BaudRate::from_bits_per_second(*rate).ok_or_else(|| {
                Fatal::usage(format!(
                    "{rate} baud: the port runs at 9600, 19200, 38400, 57600 or 115200"
                ))
            })?;
            connect(endpoint)?
                .expect_ack(&FxRequest::Baud(rate))
                .map_err(fatal)?;
            format!("the device now runs at {rate} baud (give --baud {rate} from now on)\n")
        }
        FxAction::Config { endpoint } => {
            let request = FxRequest::ReadConfig {
                address: CONFIG_START,
                len: 0xFE,
            };
            let data = connect(endpoint)?
                .expect_data(&request, 0xFE)
                .map_err(fatal)?;
            dump(CONFIG_START, &data)
        }
        FxAction::UploadProgram {
            output,
            size,
            endpoint,
        } => upload(output, size.unwrap_or(PROGRAM_SIZE), endpoint)?,
        FxAction::DownloadProgram { file, endpoint } => download(file, endpoint)?,
    };
    print!("{out}");
    Ok(std::process::ExitCode::SUCCESS)
}

fn upload(output: &Path, size: usize, endpoint: &FxEndpoint) -> Result<String, Fatal> {
    if size == 0 || size > PROGRAM_SIZE {
        return Err(Fatal::usage(format!(
            "--size {size}: program memory holds 1..{PROGRAM_SIZE} bytes"
        )));
    }
    let mut client = connect(endpoint)?;
    let bar = progress(size, "uploading")?;
    let program = client
        .upload_program(size, &mut |n| bar.inc(n as u64))
        .map_err(|e| {
            bar.abandon();
            fatal(e)
        })?;
    bar.finish_and_clear();
    gutta_io::write_file_atomically(output, &program)
        .map_err(|e| Fatal::io(format!("cannot write {}: {e}", output.display())))?;
    Ok(format!(
        "uploaded {} of program memory (805C-{:04X}) to {}\n",
        count(size, "byte"),
        usize::from(PROGRAM_START) + size - 1,
        output.display()
    ))
}

fn download(file: &Path, endpoint: &FxEndpoint) -> Result<String, Fatal> {
    let program = std::fs::read(file)
        .map_err(|e| Fatal::io(format!("cannot read {}: {e}", file.display())))?;
    if program.is_empty() || program.len() > PROGRAM_SIZE {
        return Err(Fatal::usage(format!(
            "{}: {}; program memory holds 1..{PROGRAM_SIZE}",
            file.display(),
            count(program.len(), "byte")
        )));
    }
    let mut client = connect(endpoint)?;
    // Every byte is written, then read back: the bar counts both.
    let bar = progress(2 * program.len(), "downloading")?;
    client
        .download_program(&program, &mut |n| bar.inc(n as u64))
        .map_err(|e| {
            bar.abandon();
            fatal(e)
        })?;
    bar.finish_and_clear();
    Ok(format!(
        "downloaded {} to program memory (805C-{:04X}), read back and compared, write ended (E87)\n",
        count(program.len(), "byte"),
        usize::from(PROGRAM_START) + program.len() - 1
    ))
}
