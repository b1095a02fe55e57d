//! `gutta-sim --device fx`: the simulated FX-style programming port (gutta_sim::fx) on
//! raw TCP connections (`--tcp`, the frames as they would be on the line) and serial
//! lines at 7E1 (`--serial`). All connections share one device; each has its own
//! splitter. A `41` baud request switches a serial line once its ACK has left; the
//! rate is announced on stdout either way. No protocol logic here.

use std::future::Future;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use gutta_cli::fatal::Fatal;
use gutta_format::LineSettings;
use gutta_protocol::fx::{BaudRate, FxSplitter};
use gutta_sim::fx::FxDevice;
use tokio::io::{AsyncRead, AsyncReadExt, AsyncWrite, AsyncWriteExt};
use tokio::net::TcpListener;
use tokio_serial::SerialPortBuilderExt;

use crate::{listen, say, switch_line};

/// Where the FX device is served.
pub struct FxOptions<'a> {
    pub tcp: &'a [String],
    pub serial: &'a [PathBuf],
    /// --baud: the serial lines' starting rate (9600 without it).
    pub baud: Option<u32>,
}

/// 7 data bits, even parity, 1 stop bit at `baud`.
fn line_7e1(baud: u32) -> LineSettings {
    LineSettings {
        baud,
        data_bits: 7,
        parity: 1,
        stop_bits: 1,
    }
}

/// Serves the device until Ctrl-C.
pub async fn run(
    options: FxOptions<'_>,
    ctrl_c: impl Future<Output = listen::StoppedBy>,
) -> Result<(), Fatal> {
    let start_baud = match options.baud {
        None => BaudRate::B9600,
        Some(bps) => BaudRate::from_bits_per_second(bps).ok_or_else(|| {
            Fatal::usage(format!(
                "--baud {bps}: the FX-style port runs at 9600, 19200, 38400, 57600 or 115200"
            ))
        })?,
    };
    let device = Arc::new(Mutex::new(FxDevice::new()));
    for address in options.tcp {
        accept(listen::bind(address, "fx-tcp").await?, &device);
    }
    for device_path in options.serial {
        let path = device_path.display().to_string();
        let line = line_7e1(start_baud.bits_per_second());
        let mut port = tokio_serial::new(&path, line.baud)
            .open_native_async()
            .map_err(|e| Fatal::io(format!("cannot open {path}: {e}")))?;
        gutta_link::transport::configure(&mut port, line)
            .map_err(|e| Fatal::io(format!("{path}: {e}")))?;
        say(&format!("gutta-sim: fx-serial on {path} ({line})"));
        tokio::spawn(serve(
            port,
            Arc::clone(&device),
            Some(SerialLine { path, line }),
            |port, line| gutta_link::transport::configure(port, line),
        ));
    }
    listen::until_ctrl_c(ctrl_c).await
}

/// Serves `device` on `listener` (raw frames) for the life of the process: the
/// command line's `--tcp` and a plant's fx device.
pub fn accept(listener: TcpListener, device: &Arc<Mutex<FxDevice>>) {
    let device = Arc::clone(device);
    listen::accept_forever(listener, move |stream| {
        serve(stream, Arc::clone(&device), None, |_, _| Ok(()))
    });
}

/// A serial line and its settings now.
struct SerialLine {
    path: String,
    line: LineSettings,
}

/// One connection or line: bytes in, the device's answer out, until it closes.
async fn serve<S>(
    mut stream: S,
    device: Arc<Mutex<FxDevice>>,
    mut serial: Option<SerialLine>,
    apply: fn(&mut S, LineSettings) -> Result<(), String>,
) where
    S: AsyncRead + AsyncWrite + Unpin,
{
    let mut splitter = FxSplitter::new();
    let mut buf = vec![0u8; 4096];
    loop {
        let n = match stream.read(&mut buf).await {
            Ok(0) | Err(_) => return,
            Ok(n) => n,
        };
        let output = match device.lock() {
            Ok(mut device) => device.feed_from(&mut splitter, &buf[..n]),
            Err(_) => return,
        };
        if !output.reply.is_empty() && stream.write_all(&output.reply).await.is_err() {
            return;
        }
        let Some(rate) = output.switch_to else {
            continue;
        };
        match serial.as_mut() {
            Some(serial) => {
                // The ACK leaves at the old rate, then the line switches.
                let _ = stream.flush().await;
                let next = line_7e1(rate.bits_per_second());
                let len = output.reply.len();
                switch_line(
                    &mut stream,
                    apply,
                    "fx-serial",
                    &serial.path,
                    len,
                    serial.line,
                    next,
                )
                .await;
                serial.line = next;
            }
            None => say(&format!("gutta-sim: fx-tcp baud rate now {rate}")),
        }
    }
}
