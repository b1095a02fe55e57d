//! Transports of the client: one request PDU out, its answer PDU back. Modbus TCP
//! matches answers by transaction id; RTU (over TCP or a serial line) goes through
//! gutta-protocol's master (timeout, retries, CRC). Blocking, with timeouts. The one
//! home of serial line configuration ([`configure`]), for the client and `gutta-sim`.
//! The only module of the libraries that does I/O: connecting, reading and writing a
//! line is its job (the package's clippy.toml forbids I/O everywhere else).

#![allow(
    clippy::disallowed_methods,
    clippy::disallowed_types,
    reason = "a transport's job is I/O: sockets, serial lines and their clock"
)]

use std::io::{ErrorKind, Read, Write};
use std::net::TcpStream;
use std::time::{Duration, Instant};

use gutta_format::LineSettings;
use gutta_protocol::master::{Master, MasterConfig, MasterEvent};
use gutta_protocol::modbus::exception_of;
use gutta_protocol::stream::TcpSplitter;
use gutta_protocol::tcp::{decode_tcp, encode_tcp};

use crate::{ConnectFailure, LinkError};

pub mod fx;

/// A transport's answer to one request PDU: the answer PDU, or a Modbus exception.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Answer {
    Pdu(Vec<u8>),
    /// `function` is the request's function code (without the exception bit), `code`
    /// the exception code as received.
    Exception {
        function: u8,
        code: u8,
    },
}

impl Answer {
    /// An answer PDU received whole (Modbus TCP, a PLC in the same process): an
    /// exception in its exact shape (`modbus::exception_of`) is one.
    pub fn from_pdu(pdu: Vec<u8>) -> Answer {
        match exception_of(&pdu) {
            Some((function, code)) => Answer::Exception { function, code },
            None => Answer::Pdu(pdu),
        }
    }
}

/// One request, one answer.
pub trait Transport: std::fmt::Debug {
    fn exchange(&mut self, station: u8, pdu: &[u8]) -> Result<Answer, LinkError>;

    /// Switch a serial line to `line` (PLC_CLEAR and a reset change the PLC's); a
    /// transport without a line ignores it.
    fn set_line(&mut self, _line: LineSettings) -> Result<(), LinkError> {
        Ok(())
    }
}

/// The byte stream under an RTU transport, with or without a serial line to set.
pub trait Line {
    fn set_line(&mut self, line: LineSettings) -> Result<(), String>;
}

impl Line for TcpStream {
    fn set_line(&mut self, _line: LineSettings) -> Result<(), String> {
        Ok(())
    }
}

impl Line for Box<dyn serialport::SerialPort> {
    fn set_line(&mut self, line: LineSettings) -> Result<(), String> {
        configure(self.as_mut(), line)
    }
}

/// Set a serial device to `line`: baud rate, data bits, parity, stop bits. (The
/// simulator's serial lines use it too.)
pub fn configure(port: &mut dyn serialport::SerialPort, line: LineSettings) -> Result<(), String> {
    use serialport::{DataBits, Parity, StopBits};
    let data_bits = match line.data_bits {
        5 => DataBits::Five,
        6 => DataBits::Six,
        7 => DataBits::Seven,
        _ => DataBits::Eight,
    };
    let parity = match crate::session::line_parity(&line) {
        gutta_format::Parity::None => Parity::None,
        gutta_format::Parity::Odd => Parity::Odd,
        gutta_format::Parity::Even => Parity::Even,
    };
    let stop_bits = if line.stop_bits == 2 {
        StopBits::Two
    } else {
        StopBits::One
    };
    port.set_baud_rate(line.baud)
        .and_then(|()| port.set_data_bits(data_bits))
        .and_then(|()| port.set_parity(parity))
        .and_then(|()| port.set_stop_bits(stop_bits))
        .map_err(|e| e.to_string())
}

/// How long one read waits before the master's clock is checked.
const POLL: Duration = Duration::from_millis(20);

/// Modbus TCP.
#[derive(Debug)]
pub struct TcpTransport {
    stream: TcpStream,
    transaction: u16,
    timeout: Duration,
    retries: u32,
}

impl TcpTransport {
    pub fn connect(address: &str, timeout_ms: u64, retries: u32) -> Result<Self, LinkError> {
        let stream = connect_tcp(address)?;
        Ok(TcpTransport {
            stream,
            transaction: 0,
            timeout: Duration::from_millis(timeout_ms),
            retries,
        })
    }
}

impl Transport for TcpTransport {
    fn exchange(&mut self, station: u8, pdu: &[u8]) -> Result<Answer, LinkError> {
        for _ in 0..=self.retries {
            self.transaction = self.transaction.wrapping_add(1);
            let frame = encode_tcp(self.transaction, station, pdu)
                .ok_or_else(|| LinkError::Protocol("request too long for Modbus TCP".into()))?;
            self.stream
                .write_all(&frame)
                .map_err(|e| LinkError::Io(e.to_string()))?;
            let mut splitter = TcpSplitter::new(u16::MAX);
            let deadline = Instant::now() + self.timeout;
            let mut buf = [0u8; 1024];
            while Instant::now() < deadline {
                match self.stream.read(&mut buf) {
                    Ok(0) => return Err(LinkError::Io("the connection was closed".into())),
                    Ok(n) => splitter.push(&buf[..n]),
                    Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {}
                    Err(e) => return Err(LinkError::Io(e.to_string())),
                }
                while let Some(frame) = splitter.next_frame() {
                    let frame = frame.map_err(|e| LinkError::Protocol(e.to_string()))?;
                    let frame =
                        decode_tcp(&frame).map_err(|e| LinkError::Protocol(e.to_string()))?;
                    if frame.transaction == self.transaction {
                        return Ok(Answer::from_pdu(frame.pdu));
                    }
                }
            }
        }
        Err(LinkError::Timeout {
            attempts: self.retries + 1,
        })
    }
}

/// Modbus RTU over any byte stream with a short read timeout (a TCP socket, a serial
/// port), through the protocol's master.
#[derive(Debug)]
pub struct RtuTransport<S: Read + Write + std::fmt::Debug> {
    port: S,
    master: Master,
    start: Instant,
}

impl<S: Read + Write + std::fmt::Debug> RtuTransport<S> {
    pub fn new(port: S, timeout_ms: u64, retries: u32) -> Self {
        RtuTransport {
            port,
            master: Master::new(MasterConfig {
                timeout_ms,
                retries,
                ..MasterConfig::default()
            }),
            start: Instant::now(),
        }
    }

    fn now(&self) -> u64 {
        self.start.elapsed().as_millis() as u64
    }
}

/// RTU over TCP.
pub fn rtu_over_tcp(
    address: &str,
    timeout_ms: u64,
    retries: u32,
) -> Result<RtuTransport<TcpStream>, LinkError> {
    Ok(RtuTransport::new(
        connect_tcp(address)?,
        timeout_ms,
        retries,
    ))
}

/// A TCP connection for requests: no Nagle delay, reads that wake every POLL.
fn connect_tcp(address: &str) -> Result<TcpStream, LinkError> {
    let stream = TcpStream::connect(address).map_err(|e| {
        let refused = e.kind() == ErrorKind::ConnectionRefused;
        LinkError::Connect {
            message: if refused {
                format!("cannot connect to {address}: connection refused")
            } else {
                format!("cannot connect to {address}: {e}")
            },
            failure: if refused {
                ConnectFailure::Refused
            } else {
                ConnectFailure::Other
            },
        }
    })?;
    stream
        .set_nodelay(true)
        .and_then(|_| stream.set_read_timeout(Some(POLL)))
        .map_err(|e| LinkError::Io(e.to_string()))?;
    Ok(stream)
}

/// A serial line with `line`'s settings (`LineSettings::DEFAULT` is 19200 8E1, a
/// PLC's after PLC_CLEAR).
pub fn serial(
    device: &str,
    line: LineSettings,
    timeout_ms: u64,
    retries: u32,
) -> Result<RtuTransport<Box<dyn serialport::SerialPort>>, LinkError> {
    let mut port = serialport::new(device, line.baud)
        .timeout(POLL)
        .open()
        .map_err(|e| {
            let missing = matches!(
                e.kind(),
                serialport::ErrorKind::Io(ErrorKind::NotFound) | serialport::ErrorKind::NoDevice
            ) && !std::path::Path::new(device).exists();
            LinkError::Connect {
                message: if missing {
                    format!("cannot open {device}: no such device")
                } else {
                    format!("cannot open {device}: {e}")
                },
                failure: if missing {
                    ConnectFailure::NoDevice
                } else {
                    ConnectFailure::Other
                },
            }
        })?;
    Line::set_line(&mut port, line).map_err(|e| LinkError::Io(format!("{device}: {e}")))?;
    Ok(RtuTransport::new(port, timeout_ms, retries))
}

impl<S: Read + Write + Line + std::fmt::Debug> Transport for RtuTransport<S> {
    fn set_line(&mut self, line: LineSettings) -> Result<(), LinkError> {
        self.port
            .flush()
            .map_err(|e| LinkError::Io(e.to_string()))?;
        Line::set_line(&mut self.port, line).map_err(LinkError::Io)
    }

    fn exchange(&mut self, station: u8, pdu: &[u8]) -> Result<Answer, LinkError> {
        let bytes = self
            .master
            .send(station, pdu, self.now())
            .map_err(|e| LinkError::Protocol(e.to_string()))?;
        self.port
            .write_all(&bytes)
            .map_err(|e| LinkError::Io(e.to_string()))?;
        let mut buf = [0u8; 1024];
        loop {
            let event = match self.port.read(&mut buf) {
                Ok(0) => return Err(LinkError::Io("the connection was closed".into())),
                Ok(n) => {
                    let now = self.now();
                    self.master.on_bytes(&buf[..n], now)
                }
                Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {
                    let now = self.now();
                    self.master.on_tick(now).unwrap_or(MasterEvent::Pending)
                }
                Err(e) => return Err(LinkError::Io(e.to_string())),
            };
            match event {
                MasterEvent::Response(frame) => return Ok(Answer::Pdu(frame.pdu)),
                MasterEvent::Exception { function, code, .. } => {
                    return Ok(Answer::Exception { function, code })
                }
                MasterEvent::Retry(bytes) => self
                    .port
                    .write_all(&bytes)
                    .map_err(|e| LinkError::Io(e.to_string()))?,
                MasterEvent::Failed(e) => {
                    return Err(LinkError::Timeout {
                        attempts: match e {
                            gutta_protocol::master::MasterError::Timeout { attempts }
                            | gutta_protocol::master::MasterError::Crc { attempts } => attempts,
                            _ => 1,
                        },
                    })
                }
                MasterEvent::Pending | MasterEvent::Idle => {}
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Client;
    use gutta_protocol::rtu::encode_rtu;

    /// A line that delivers `answer` to the first read and then stays silent.
    #[derive(Debug, Default)]
    struct Scripted {
        answer: Vec<u8>,
    }

    impl Read for Scripted {
        fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
            if self.answer.is_empty() {
                std::thread::sleep(Duration::from_millis(1));
                return Err(ErrorKind::WouldBlock.into());
            }
            let n = self.answer.len().min(buf.len());
            buf[..n].copy_from_slice(&self.answer[..n]);
            self.answer.drain(..n);
            Ok(n)
        }
    }

    impl Write for Scripted {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            Ok(buf.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    impl Line for Scripted {
        fn set_line(&mut self, _line: LineSettings) -> Result<(), String> {
            Ok(())
        }
    }

    fn client(answer: Vec<u8>) -> Client {
        Client::new(Box::new(RtuTransport::new(Scripted { answer }, 50, 0)), 1)
    }

    #[test]
    fn an_exception_over_rtu_is_the_clients_exception() {
        let mut c = client(encode_rtu(1, &[0x83, 0x02]));
        assert_eq!(
            c.modbus(&[0x03, 0x00, 0x00, 0x00, 0x01]),
            Err(LinkError::Exception {
                function: 0x03,
                code: 0x02
            })
        );
    }

    #[test]
    fn a_long_exception_over_rtu_is_no_answer() {
        let mut c = client(encode_rtu(1, &[0x83, 0x02, 0x00, 0x00]));
        assert_eq!(
            c.modbus(&[0x03, 0x00, 0x00, 0x00, 0x01]),
            Err(LinkError::Timeout { attempts: 1 })
        );
    }
}
