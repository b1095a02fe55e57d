//! The FX-style programming port's transport (seed 001; docs/devices.md): raw FX frames
//! over TCP (`gutta-sim --device fx`) or a serial line at 7E1, under gutta-protocol's
//! sans-I/O `FxClient` (the retries on NAK, silence or a broken answer). Blocking, with
//! the client's timeout. Its errors are typed; the caller words the hints.

use std::io::{ErrorKind, Read, Write};
use std::net::TcpStream;
use std::time::{Duration, Instant};

use gutta_format::LineSettings;
use gutta_protocol::fx::{program_chunks, FxReply, FxRequest};
use gutta_protocol::fx_client::{FxClient, FxClientConfig, FxEvent, FxFailure};

/// Where the FX-style port is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FxEndpoint {
    /// Raw FX frames over TCP, `HOST:PORT`.
    Tcp(String),
    /// A serial device at `baud`, 7 data bits, even parity, 1 stop bit.
    Serial { device: String, baud: u32 },
}

/// Why an FX exchange failed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FxLinkError {
    /// The line could not be opened; `refused`: nothing listens at the TCP address.
    Connect { message: String, refused: bool },
    /// The request cannot be encoded.
    BadRequest(String),
    /// Writing to the line failed.
    Send(String),
    /// Every attempt missed.
    Failed(FxFailure),
    /// The device answered, but not what the request expects.
    Unexpected(String),
    /// A program byte read back differs from the one written (the write was not
    /// ended with E87).
    Mismatch { address: usize, wrote: u8, read: u8 },
}

impl std::fmt::Display for FxLinkError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FxLinkError::Connect { message, .. }
            | FxLinkError::BadRequest(message)
            | FxLinkError::Send(message)
            | FxLinkError::Unexpected(message) => f.write_str(message),
            FxLinkError::Failed(failure) => write!(f, "{failure}"),
            FxLinkError::Mismatch {
                address,
                wrote,
                read,
            } => write!(
                f,
                "read-back differs at {address:04X}: wrote {wrote:02X}, read {read:02X}; \
                 the write was not ended (no E87)"
            ),
        }
    }
}

impl std::error::Error for FxLinkError {}

/// A byte line with a settable read timeout.
trait FxLine: Read + Write {
    fn set_wait(&mut self, wait: Duration) -> std::io::Result<()>;
}

impl FxLine for TcpStream {
    fn set_wait(&mut self, wait: Duration) -> std::io::Result<()> {
        self.set_read_timeout(Some(wait.max(Duration::from_millis(1))))
    }
}

impl FxLine for Box<dyn serialport::SerialPort> {
    fn set_wait(&mut self, wait: Duration) -> std::io::Result<()> {
        self.set_timeout(wait).map_err(std::io::Error::other)
    }
}

/// An FX-style port on a line.
pub struct FxLink {
    line: Box<dyn FxLine>,
    client: FxClient,
    start: Instant,
}

impl std::fmt::Debug for FxLink {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FxLink")
            .field("client", &self.client)
            .finish()
    }
}

impl FxLink {
    /// Open the line; each answer waited for `timeout_ms`, each request tried at most
    /// 1 + `retries` times.
    pub fn connect(
        endpoint: &FxEndpoint,
        timeout_ms: u64,
        retries: u32,
    ) -> Result<FxLink, FxLinkError> {
        let line: Box<dyn FxLine> = match endpoint {
            FxEndpoint::Tcp(address) => {
                let stream = TcpStream::connect(address).map_err(|e| {
                    let refused = e.kind() == ErrorKind::ConnectionRefused;
                    FxLinkError::Connect {
                        message: if refused {
                            format!("cannot connect to {address}: connection refused")
                        } else {
                            format!("cannot connect to {address}: {e}")
                        },
                        refused,
                    }
                })?;
                let _ = stream.set_nodelay(true);
                Box::new(stream)
            }
            FxEndpoint::Serial { device, baud } => {
                let connect = |message: String| FxLinkError::Connect {
                    message,
                    refused: false,
                };
                let mut port = serialport::new(device, *baud)
                    .timeout(Duration::from_millis(timeout_ms))
                    .open()
                    .map_err(|e| connect(format!("cannot open {device}: {e}")))?;
                let settings = LineSettings {
                    baud: *baud,
                    data_bits: 7,
                    parity: 1,
                    stop_bits: 1,
                };
                super::configure(port.as_mut(), settings)
                    .map_err(|e| connect(format!("{device}: {e}")))?;
                Box::new(port)
            }
        };
        Ok(FxLink {
            line,
            client: FxClient::new(FxClientConfig {
                timeout_ms,
                retries,
            }),
            start: Instant::now(),
        })
    }

    fn now(&self) -> u64 {
        self.start.elapsed().as_millis() as u64
    }

    fn write(&mut self, bytes: &[u8]) -> Result<(), FxLinkError> {
        self.line
            .write_all(bytes)
            .and_then(|()| self.line.flush())
            .map_err(|e| FxLinkError::Send(format!("cannot send: {e}")))
    }

    /// Send `request` until the device answers ACK or data.
    pub fn exchange(&mut self, request: &FxRequest) -> Result<FxReply, FxLinkError> {
        let now = self.now();
        let wire = self
            .client
            .send(request, now)
            .map_err(|e| FxLinkError::BadRequest(format!("cannot send {request:?}: {e}")))?;
        self.write(&wire)?;
        let mut buf = [0u8; 1024];
        loop {
            let now = self.now();
            let left = self.client.deadline().unwrap_or(now).saturating_sub(now);
            // The attempt's time is up, or the line cannot wait for it: no answer.
            let event = if left == 0 || self.line.set_wait(Duration::from_millis(left)).is_err() {
                self.client.on_timeout(now)
            } else {
                match self.line.read(&mut buf) {
                    Ok(0) => self
                        .client
                        .on_line_error("the connection closed".into(), self.now()),
                    Ok(n) => {
                        let now = self.now();
                        self.client.on_bytes(&buf[..n], now)
                    }
                    Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {
                        let now = self.now();
                        self.client.on_timeout(now)
                    }
                    Err(e) => {
                        let now = self.now();
                        self.client.on_line_error(e.to_string(), now)
                    }
                }
            };
            match event {
                FxEvent::Pending => {}
                FxEvent::Reply(reply) => return Ok(reply),
                FxEvent::Retry(bytes) => self.write(&bytes)?,
                FxEvent::Failed(failure) => return Err(FxLinkError::Failed(failure)),
                FxEvent::Idle => {
                    return Err(FxLinkError::Unexpected(format!(
                        "{}: no request outstanding",
                        request.describe()
                    )))
                }
            }
        }
    }

    /// `request`, whose answer must be ACK.
    pub fn expect_ack(&mut self, request: &FxRequest) -> Result<(), FxLinkError> {
        match self.exchange(request)? {
            FxReply::Ack => Ok(()),
            other => Err(FxLinkError::Unexpected(format!(
                "{}: expected ACK, got {other:?}",
                request.describe()
            ))),
        }
    }

    /// `request`, whose answer must be `len` data bytes.
    pub fn expect_data(&mut self, request: &FxRequest, len: usize) -> Result<Vec<u8>, FxLinkError> {
        match self.exchange(request)? {
            FxReply::Data(data) if data.len() == len => Ok(data),
            other => Err(FxLinkError::Unexpected(format!(
                "{}: expected {len} data bytes, got {other:?}",
                request.describe()
            ))),
        }
    }

    /// Read `size` bytes of program memory from 805C (`E01`, 0xFE bytes a frame);
    /// `progress` is told the bytes of each frame.
    pub fn upload_program(
        &mut self,
        size: usize,
        progress: &mut dyn FnMut(usize),
    ) -> Result<Vec<u8>, FxLinkError> {
        let mut program = Vec::with_capacity(size);
        for (address, len) in program_chunks(size) {
            let request = FxRequest::ReadProgram {
                address,
                len: len as u8,
            };
            program.extend(self.expect_data(&request, len)?);
            progress(len);
        }
        Ok(program)
    }

    /// Write `program` into program memory from 805C (`E11`), read it back and
    /// compare (`E01`), then end the write (`E87`); a difference leaves the write
    /// unended. `progress` is told the bytes of each frame written and read back.
    pub fn download_program(
        &mut self,
        program: &[u8],
        progress: &mut dyn FnMut(usize),
    ) -> Result<(), FxLinkError> {
        let chunks: Vec<(u16, usize)> = program_chunks(program.len()).collect();
        let mut offset = 0;
        for &(address, len) in &chunks {
            self.expect_ack(&FxRequest::WriteProgram {
                address,
                data: program[offset..offset + len].to_vec(),
            })?;
            offset += len;
            progress(len);
        }
        offset = 0;
        for &(address, len) in &chunks {
            let request = FxRequest::ReadProgram {
                address,
                len: len as u8,
            };
            let back = self.expect_data(&request, len)?;
            if let Some(n) = (0..len).find(|&n| back[n] != program[offset + n]) {
                return Err(FxLinkError::Mismatch {
                    address: usize::from(address) + n,
                    wrote: program[offset + n],
                    read: back[n],
                });
            }
            offset += len;
            progress(len);
        }
        self.expect_ack(&FxRequest::EndProgramWrite)
    }
}
