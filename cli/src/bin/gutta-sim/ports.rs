//! The simulated PLC's own serial ports, where EXCH makes it a Modbus RTU master: a
//! `vm::exch::SerialPort` over a byte stream (a TCP connection to another simulator's
//! `--rtu-tcp`, or a serial device such as a pty), driven by gutta-protocol's master
//! (the same state machine as the download client's RTU transport). Blocking: the VM
//! serves EXCH at the end of its scan. [`PortWiring`] is the port factory `gutta-sim`
//! gives the simulator core, which opens nothing itself.
//!
//! Port specs (`gutta-sim --port0 SPEC`): `tcp-connect:HOST:PORT`, `serial:DEVICE` or
//! `pty:PATH` (a serial device with the port's line: the system page's settings, 19200
//! 8E1 without one), and `modbus-tcp:HOST:PORT`: the port leads through a Modbus RTU <->
//! TCP gateway to a Modbus TCP device ([`GatewayPort`]: the sockets; the conversion is
//! gutta-protocol's `gateway`).

use std::collections::BTreeMap;
use std::io::{ErrorKind, Read, Write};
use std::net::{TcpStream, ToSocketAddrs};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use gutta_format::LineSettings;
use gutta_protocol::gateway::{answer_to_rtu, Gateway};
use gutta_protocol::master::{Master, MasterConfig, MasterEvent};
use gutta_protocol::modbus::EXCEPTION_BIT;
use gutta_protocol::rtu::{decode_rtu, encode_rtu};
use gutta_protocol::stream::TcpSplitter;
use gutta_protocol::tcp::MAX_STANDARD_MBAP_LENGTH;
use gutta_sim::ports::PortFactory;
use gutta_vm::exch::{PortError, SerialPort};

use crate::plant_ports::InProcessLine;
use crate::say;

/// How long one read waits before the master's clock is checked.
const POLL: Duration = Duration::from_millis(5);

/// Where a port leads.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PortSpec {
    TcpConnect(String),
    Serial(String),
    /// A Modbus TCP device behind a serial-to-TCP gateway.
    ModbusTcp(String),
}

impl PortSpec {
    pub fn parse(text: &str) -> Result<PortSpec, String> {
        if let Some(a) = text.strip_prefix("tcp-connect:") {
            Ok(PortSpec::TcpConnect(a.to_string()))
        } else if let Some(a) = text.strip_prefix("modbus-tcp:") {
            Ok(PortSpec::ModbusTcp(a.to_string()))
        } else if let Some(d) = text
            .strip_prefix("serial:")
            .or_else(|| text.strip_prefix("pty:"))
        {
            Ok(PortSpec::Serial(d.to_string()))
        } else {
            Err(format!(
                "`{text}`: a port is tcp-connect:HOST:PORT, modbus-tcp:HOST:PORT, \
                 serial:DEVICE or pty:PATH"
            ))
        }
    }
}

/// `--trace-ports`: every port of every PLC of the process prints its exchanges
/// ([`TracedPort`]). Set once at start, before any PLC scans.
pub static TRACE_PORTS: AtomicBool = AtomicBool::new(false);

/// Where each serial port of the PLC leads (`--port0`, `--port1`, a plant's
/// `device:NAME`): the port factory of the simulator core. A port without a lead stays
/// unconnected.
#[derive(Debug, Default)]
pub struct PortWiring {
    /// The device's name in a plant: the prefix of its trace lines.
    pub name: Option<String>,
    leads: BTreeMap<u8, PortSpec>,
    in_process: BTreeMap<u8, InProcessLine>,
}

impl PortWiring {
    /// Lead serial port `port` to `spec`.
    pub fn lead(&mut self, port: u8, spec: PortSpec) {
        self.leads.insert(port, spec);
    }

    /// Lead serial port `port` to another device of the process (a plant's
    /// `device:NAME`).
    pub fn lead_in_process(&mut self, port: u8, line: InProcessLine) {
        self.in_process.insert(port, line);
    }
}

impl PortFactory for PortWiring {
    fn port(&mut self, port: u8, line: LineSettings) -> Option<Box<dyn SerialPort>> {
        let made: Box<dyn SerialPort> = match (self.in_process.get(&port), self.leads.get(&port)) {
            (Some(device), _) => Box::new(device.port()),
            (None, Some(PortSpec::ModbusTcp(address))) => {
                Box::new(GatewayPort::new(address.clone()))
            }
            (None, Some(spec)) => Box::new(StreamPort::new(spec.clone(), line)),
            (None, None) => return None,
        };
        if !TRACE_PORTS.load(Ordering::Relaxed) {
            return Some(made);
        }
        Some(Box::new(TracedPort {
            inner: made,
            label: format!("{}port{port}", crate::scan::prefix(self.name.as_deref())),
        }))
    }
}

/// A port that prints every exchange on stdout (`--trace-ports`): the request frame as
/// the PLC sends it (`gutta-sim: NAME: port0 > 01 02 00 04 00 04 38 08`), then the
/// answer as the PLC receives it (`port0 < ...`) or what EXCH makes of silence or a bad
/// CRC. The bytes are the line's, whatever the port leads to.
#[derive(Debug)]
pub struct TracedPort {
    inner: Box<dyn SerialPort>,
    label: String,
}

/// Bytes as `01 02 0A`.
pub fn hex(bytes: &[u8]) -> String {
    let parts: Vec<String> = bytes.iter().map(|b| format!("{b:02X}")).collect();
    parts.join(" ")
}

impl SerialPort for TracedPort {
    fn transact(&mut self, request: &[u8], timeout_ms: u32) -> Result<Vec<u8>, PortError> {
        say(&format!("{} > {}", self.label, hex(request)));
        let answer = self.inner.transact(request, timeout_ms);
        match &answer {
            Ok(bytes) if bytes.is_empty() => say(&format!("{} < (no answer expected)", self.label)),
            Ok(bytes) => say(&format!("{} < {}", self.label, hex(bytes))),
            Err(PortError::Crc) => say(&format!("{} < (bad CRC)", self.label)),
            Err(_) => say(&format!("{} < (no answer in {timeout_ms} ms)", self.label)),
        }
        answer
    }
}

/// What EXCH gets from the master's event on a port: the answer frame (a response, or
/// an exception frame as received: EXCH hands the PLC program the frame), a CRC error
/// (error 3), or silence (error 2) for any other failure; `None` while the master waits
/// (or asks for a retry, which the port sends).
pub fn exch_result(event: MasterEvent) -> Option<Result<Vec<u8>, PortError>> {
    match event {
        MasterEvent::Response(f) => Some(Ok(f.encode())),
        MasterEvent::Exception {
            station,
            function,
            code,
        } => Some(Ok(encode_rtu(station, &[function | EXCEPTION_BIT, code]))),
        MasterEvent::Failed(gutta_protocol::master::MasterError::Crc { .. }) => {
            Some(Err(PortError::Crc))
        }
        MasterEvent::Failed(_) => Some(Err(PortError::Timeout)),
        MasterEvent::Retry(_) | MasterEvent::Pending | MasterEvent::Idle => None,
    }
}

trait Stream: Read + Write + Send + std::fmt::Debug {}
impl<T: Read + Write + Send + std::fmt::Debug> Stream for T {}

/// A port: connects on first use and again after a failure.
#[derive(Debug)]
pub struct StreamPort {
    spec: PortSpec,
    line: LineSettings,
    stream: Option<Box<dyn Stream>>,
    start: Instant,
}

impl StreamPort {
    /// A port leading to `spec`; a serial device runs with `line`.
    pub fn new(spec: PortSpec, line: LineSettings) -> StreamPort {
        StreamPort {
            spec,
            line,
            stream: None,
            start: Instant::now(),
        }
    }

    fn open(&self) -> Option<Box<dyn Stream>> {
        match &self.spec {
            PortSpec::TcpConnect(a) => {
                let s = TcpStream::connect(a).ok()?;
                s.set_nodelay(true).ok()?;
                s.set_read_timeout(Some(POLL)).ok()?;
                Some(Box::new(s))
            }
            PortSpec::ModbusTcp(_) => None,
            PortSpec::Serial(d) => {
                let mut p = serialport::new(d, self.line.baud)
                    .timeout(POLL)
                    .open()
                    .ok()?;
                gutta_link::transport::configure(p.as_mut(), self.line).ok()?;
                Some(Box::new(p))
            }
        }
    }

    fn now(&self) -> u64 {
        self.start.elapsed().as_millis() as u64
    }

    fn exchange(&mut self, request: &[u8], timeout_ms: u32) -> Result<Vec<u8>, PortError> {
        if self.stream.is_none() {
            self.stream = self.open();
        }
        let frame = decode_rtu(request).map_err(|_| PortError::Timeout)?;
        let mut master = Master::new(MasterConfig {
            timeout_ms: u64::from(timeout_ms),
            retries: 0,
            ..MasterConfig::default()
        });
        let bytes = master
            .send(frame.station, &frame.pdu, self.now())
            .map_err(|_| PortError::Timeout)?;
        let broadcast = frame.station == 0 && frame.pdu.first() != Some(&0x0D);
        let start = self.now();
        let Some(stream) = self.stream.as_mut() else {
            return Err(PortError::Timeout);
        };
        if stream.write_all(&bytes).is_err() {
            self.stream = None;
            return Err(PortError::Timeout);
        }
        if broadcast {
            return Ok(Vec::new());
        }
        let mut buf = [0u8; 512];
        loop {
            let now = self.start.elapsed().as_millis() as u64;
            let Some(stream) = self.stream.as_mut() else {
                return Err(PortError::Timeout);
            };
            let event = match stream.read(&mut buf) {
                Ok(0) => {
                    self.stream = None;
                    return Err(PortError::Timeout);
                }
                Ok(n) => master.on_bytes(&buf[..n], now),
                Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {
                    master.on_tick(now).unwrap_or(MasterEvent::Pending)
                }
                Err(_) => {
                    self.stream = None;
                    return Err(PortError::Timeout);
                }
            };
            if let MasterEvent::Retry(b) = &event {
                if let Some(s) = self.stream.as_mut() {
                    let _ = s.write_all(b);
                }
            } else if let Some(result) = exch_result(event) {
                return result;
            }
            if now.saturating_sub(start) > u64::from(timeout_ms) + 1000 {
                return Err(PortError::Timeout);
            }
        }
    }
}

impl SerialPort for StreamPort {
    fn transact(&mut self, request: &[u8], timeout_ms: u32) -> Result<Vec<u8>, PortError> {
        self.exchange(request, timeout_ms)
    }
}

/// A port whose line leads through a Modbus RTU <-> TCP gateway to `address`: every
/// EXCH request frame goes out as a Modbus TCP request, the answer comes back as an RTU
/// frame. What the PLC hears as silence (EXCH error 2): a dropped request (bad CRC,
/// reserved station), a refused or lost connection, no answer in the port's timeout.
/// Connects on first use and again after a failure.
#[derive(Debug)]
pub struct GatewayPort {
    address: String,
    gateway: Gateway,
    stream: Option<TcpStream>,
    splitter: TcpSplitter,
}

impl GatewayPort {
    pub fn new(address: String) -> GatewayPort {
        GatewayPort {
            address,
            gateway: Gateway::new(),
            stream: None,
            splitter: TcpSplitter::new(MAX_STANDARD_MBAP_LENGTH),
        }
    }

    /// A connection within `timeout` (the first address that takes it).
    fn connect(&self, timeout: Duration) -> Option<TcpStream> {
        let stream = self
            .address
            .to_socket_addrs()
            .ok()?
            .find_map(|a| TcpStream::connect_timeout(&a, timeout).ok())?;
        stream.set_nodelay(true).ok()?;
        Some(stream)
    }

    fn exchange(&mut self, request: &[u8], timeout_ms: u32) -> Result<Vec<u8>, PortError> {
        let forwarded = self
            .gateway
            .forward(request)
            .map_err(|_| PortError::Timeout)?;
        let timeout = Duration::from_millis(u64::from(timeout_ms.max(1)));
        let deadline = Instant::now() + timeout;
        if self.stream.is_none() {
            self.stream = self.connect(timeout);
            self.splitter.clear();
        }
        let stream = self.stream.as_mut().ok_or(PortError::Timeout)?;
        if stream.write_all(&forwarded.tcp).is_err() {
            self.stream = None;
            return Err(PortError::Timeout);
        }
        if !forwarded.answered {
            return Ok(Vec::new());
        }
        let mut buf = [0u8; 512];
        loop {
            while let Some(frame) = self.splitter.next_frame() {
                // An answer to an earlier request (a broadcast's, one that came too late)
                // or noise is not this answer.
                if let Ok(Ok(rtu)) = frame.map(|f| answer_to_rtu(&forwarded, &f)) {
                    return Ok(rtu);
                }
            }
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Err(PortError::Timeout);
            }
            let Some(stream) = self.stream.as_mut() else {
                return Err(PortError::Timeout);
            };
            if stream.set_read_timeout(Some(left)).is_err() {
                self.stream = None;
                return Err(PortError::Timeout);
            }
            match stream.read(&mut buf) {
                Ok(0) => {
                    self.stream = None;
                    return Err(PortError::Timeout);
                }
                Ok(n) => self.splitter.push(&buf[..n]),
                Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {}
                Err(_) => {
                    self.stream = None;
                    return Err(PortError::Timeout);
                }
            }
        }
    }
}

impl SerialPort for GatewayPort {
    fn transact(&mut self, request: &[u8], timeout_ms: u32) -> Result<Vec<u8>, PortError> {
        self.exchange(request, timeout_ms)
    }
}
