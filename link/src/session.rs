//! A PLC session: the one way the tools talk to a PLC. It is built from an endpoint
//! ([`LinkConfig`]: a project's `[connection]` or the command line's flags, made plain
//! by the caller), credentials ([`Credentials`]: the password lookup, with the prompt
//! injected) and, once known, the target (its ExchPackSize); it reads and writes typed
//! variables, batching and width-masking inside (`plan.rs`). Callers never see packed
//! variable addresses. It prints nothing and reads no environment: the caller passes
//! `GUTTA_PASSWORD`'s value and a prompt.

use gutta_catalog::{Address, Target};
use gutta_format::{LineSettings, PackedOperand, Parity};
use gutta_io::{Connection, Endpoint};

use gutta_protocol::transfer::PackSize;

use crate::plan::{packed, ReadPlan};
use crate::transport::{rtu_over_tcp, serial, TcpTransport};
use crate::var::Var;
use crate::{Client, LinkError, Transport, FACTORY_PASSWORD};

/// The environment variable that holds the PLC's password (an empty value means
/// unset). The library does not read it: callers pass its value to
/// [`Credentials::lookup`].
pub const PASSWORD_ENV: &str = "GUTTA_PASSWORD";

/// The PLC_ATTACH function code: a `Refused` from it is a wrong password.
const PLC_ATTACH: u16 = 0x0110;

/// How to reach a PLC: the endpoint and the line's settings.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LinkConfig {
    pub endpoint: Endpoint,
    /// The station address requests go to.
    pub station: u8,
    /// Milliseconds to wait for each answer.
    pub timeout_ms: u64,
    /// Attempts after the first when an answer does not come.
    pub retries: u32,
    /// Baud rate and parity of a serial line (8 data bits, 1 stop bit).
    pub line: LineSettings,
}

impl LinkConfig {
    /// The station a PLC answers at when nothing says otherwise.
    pub const STATION: u8 = 1;
    /// The answer timeout when nothing says otherwise.
    pub const TIMEOUT_MS: u64 = 1000;
    /// The retries when nothing says otherwise.
    pub const RETRIES: u32 = 2;

    /// A project's `[connection]`, the defaults where a key is absent (those of
    /// gutta-cc's flags); `None` when it names no PLC.
    pub fn from_connection(c: &Connection) -> Option<LinkConfig> {
        Some(LinkConfig {
            endpoint: c.endpoint.clone()?,
            station: c.station.unwrap_or(LinkConfig::STATION),
            timeout_ms: c.timeout_ms.unwrap_or(LinkConfig::TIMEOUT_MS),
            retries: c.retries.unwrap_or(LinkConfig::RETRIES),
            line: serial_line(c.baud, c.parity),
        })
    }

    /// How the user named the PLC: the address or the device.
    pub fn address(&self) -> &str {
        match &self.endpoint {
            Endpoint::Tcp(a) | Endpoint::RtuTcp(a) | Endpoint::Serial(a) => a,
        }
    }

    /// `tcp 127.0.0.1:502`, for messages.
    pub fn describe(&self) -> String {
        match &self.endpoint {
            Endpoint::Tcp(a) => format!("tcp {a}"),
            Endpoint::RtuTcp(a) => format!("rtu-tcp {a}"),
            Endpoint::Serial(d) => format!("serial {d}"),
        }
    }

    /// Open the transport the endpoint names.
    pub fn transport(&self) -> Result<Box<dyn Transport>, LinkError> {
        let (timeout, retries) = (self.timeout_ms, self.retries);
        Ok(match &self.endpoint {
            Endpoint::Tcp(a) => Box::new(TcpTransport::connect(a, timeout, retries)?),
            Endpoint::RtuTcp(a) => Box::new(rtu_over_tcp(a, timeout, retries)?),
            Endpoint::Serial(d) => Box::new(serial(d, self.line, timeout, retries)?),
        })
    }

    /// A client on a fresh transport, not logged in.
    pub fn connect(&self) -> Result<Client, LinkError> {
        Ok(Client::new(self.transport()?, self.station))
    }
}

/// A serial line of `baud` (19200 when absent) and `parity` (even when absent), 8 data
/// bits and 1 stop bit: the PLC's port 0 without a system block.
pub fn serial_line(baud: Option<u32>, parity: Option<Parity>) -> LineSettings {
    let default = LineSettings::DEFAULT;
    LineSettings {
        baud: baud.unwrap_or(default.baud),
        parity: parity.map_or(default.parity, Parity::code),
        ..default
    }
}

/// A line's parity code as the parity a serial port gets: a code other than 0..2 is
/// even, as [`crate::transport::configure`] sets it.
pub fn line_parity(line: &LineSettings) -> Parity {
    Parity::from_code(line.parity).unwrap_or(Parity::Even)
}

/// Where the password a login tries first comes from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PasswordSource {
    /// The command line's `--password`.
    Flag(String),
    /// `GUTTA_PASSWORD`.
    Environment(String),
    /// Neither: the factory password, then the prompt if the PLC refuses it.
    Factory,
}

/// The password lookup: the flag, else `GUTTA_PASSWORD`, else the factory password,
/// and only when the factory password is refused, the prompt.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Credentials {
    pub source: PasswordSource,
}

impl Credentials {
    /// `flag` (a command line's `--password`), else `environment` (the value of
    /// [`PASSWORD_ENV`]; empty counts as unset), else the factory password.
    pub fn lookup(flag: Option<&str>, environment: Option<&str>) -> Credentials {
        let source = match (flag, environment) {
            (Some(p), _) => PasswordSource::Flag(p.to_string()),
            (None, Some(p)) if !p.is_empty() => PasswordSource::Environment(p.to_string()),
            _ => PasswordSource::Factory,
        };
        Credentials { source }
    }

    /// The 16 bytes of the first login.
    pub fn password(&self) -> [u8; 16] {
        match &self.source {
            PasswordSource::Flag(p) | PasswordSource::Environment(p) => {
                gutta_format::password_bytes(Some(p))
            }
            PasswordSource::Factory => FACTORY_PASSWORD,
        }
    }
}

/// Asks the user for the password when the factory password was refused.
pub trait PasswordPrompt {
    /// The password typed for the PLC at `endpoint`; `Ok(None)` when nobody can be
    /// asked (no terminal); `Err` when asking failed.
    fn ask(&mut self, endpoint: &str) -> Result<Option<String>, String>;
}

/// Nobody to ask (a language server, a test): a refused factory password stays refused.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoPrompt;

impl PasswordPrompt for NoPrompt {
    fn ask(&mut self, _endpoint: &str) -> Result<Option<String>, String> {
        Ok(None)
    }
}

impl<F: FnMut(&str) -> Result<Option<String>, String>> PasswordPrompt for F {
    fn ask(&mut self, endpoint: &str) -> Result<Option<String>, String> {
        self(endpoint)
    }
}

/// Why a session could not start.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LoginError {
    /// Connecting or the login failed: [`is_wrong_password`] tells a refused password.
    Link(LinkError),
    /// The factory password was refused and nobody can be asked for another: the
    /// PLC's refusal.
    PasswordNeeded(LinkError),
    /// Asking for the password failed.
    Prompt(String),
}

impl From<LinkError> for LoginError {
    fn from(e: LinkError) -> LoginError {
        LoginError::Link(e)
    }
}

impl std::fmt::Display for LoginError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LoginError::Link(e) | LoginError::PasswordNeeded(e) => write!(f, "{e}"),
            LoginError::Prompt(e) => write!(f, "cannot read the password: {e}"),
        }
    }
}

impl std::error::Error for LoginError {}

/// Whether `e` is the PLC refusing a password (PLC_ATTACH refused).
pub fn is_wrong_password(e: &LinkError) -> bool {
    matches!(e, LinkError::Refused { function, .. } if *function == PLC_ATTACH)
}

/// A logged-in PLC: typed variables in, values out.
#[derive(Debug)]
pub struct Session {
    client: Client,
    password: [u8; 16],
    /// The target's ExchPackSize: the bytes a request may carry.
    pack: usize,
    var_reads: u64,
}

impl Session {
    /// Connect as `config` says and log in.
    pub fn open(
        config: &LinkConfig,
        credentials: &Credentials,
        prompt: &mut dyn PasswordPrompt,
    ) -> Result<Session, LoginError> {
        Session::log_in(config.connect()?, config.address(), credentials, prompt)
    }

    /// Log `client` in: the password of `credentials`; when that is the factory
    /// password and the PLC refuses it, the one `prompt` gives for the PLC at
    /// `endpoint`.
    pub fn log_in(
        mut client: Client,
        endpoint: &str,
        credentials: &Credentials,
        prompt: &mut dyn PasswordPrompt,
    ) -> Result<Session, LoginError> {
        let password = credentials.password();
        match client.attach(&password) {
            Ok(()) => Ok(Session::logged_in(client, password)),
            Err(e) if is_wrong_password(&e) && credentials.source == PasswordSource::Factory => {
                let Some(typed) = prompt.ask(endpoint).map_err(LoginError::Prompt)? else {
                    return Err(LoginError::PasswordNeeded(e));
                };
                let password = gutta_format::password_bytes(Some(&typed));
                client.attach(&password)?;
                Ok(Session::logged_in(client, password))
            }
            Err(e) => Err(e.into()),
        }
    }

    /// Log `client` in again with a password that worked before (a new connection
    /// after a failure).
    pub fn reattach(mut client: Client, password: [u8; 16]) -> Result<Session, LinkError> {
        client.attach(&password)?;
        Ok(Session::logged_in(client, password))
    }

    fn logged_in(client: Client, password: [u8; 16]) -> Session {
        Session {
            client,
            password,
            pack: usize::from(PackSize::MIN),
            var_reads: 0,
        }
    }

    /// Batch by `target`'s ExchPackSize from now on (until then, by the smallest a
    /// PLC may have).
    pub fn set_target(&mut self, target: &Target) {
        self.set_exch_pack_size(target.plc.exch_pack_size);
    }

    /// Batch by an ExchPackSize known without the target (a project's).
    pub fn set_exch_pack_size(&mut self, exch_pack_size: u32) {
        self.pack = exch_pack_size as usize;
    }

    /// The target's ExchPackSize (the packet size of downloads and uploads).
    pub fn pack_size(&self) -> usize {
        self.pack
    }

    /// The password the login used (download and upload log in again with it).
    pub fn password(&self) -> [u8; 16] {
        self.password
    }

    /// The client, for the operations that are not about variables (status, run,
    /// pages, the debugger).
    pub fn client(&mut self) -> &mut Client {
        &mut self.client
    }

    /// STATUS_VAR_READ requests sent so far.
    pub fn var_reads(&self) -> u64 {
        self.var_reads
    }

    /// The values of `vars`, each cut to its width, in as few STATUS_VAR_READ
    /// requests as the packet size allows.
    pub fn read(&mut self, vars: &[Var]) -> Result<Vec<u32>, LinkError> {
        let addresses: Vec<Address> = vars.iter().map(|v| v.address).collect();
        self.read_plan(&ReadPlan::new(&addresses))
    }

    /// The values of the variables `plan` was made for (a plan made once for reads
    /// repeated many times: the monitor, the language server's live values).
    pub fn read_plan(&mut self, plan: &ReadPlan) -> Result<Vec<u32>, LinkError> {
        let mut windows = Vec::with_capacity(plan.windows().len());
        for request in plan.requests(self.pack / 4) {
            self.var_reads += 1;
            windows.extend(self.client.read_vars(&words(&request))?);
        }
        Ok(plan.values(&windows))
    }

    /// The force values of `addresses` (STATUS_VAR_FORCE_READ; 0 where nothing is
    /// forced), each cut to its width.
    pub fn read_forces(&mut self, addresses: &[Address]) -> Result<Vec<u32>, LinkError> {
        let plan = ReadPlan::new(addresses);
        let mut windows = Vec::with_capacity(plan.windows().len());
        for request in plan.requests(self.pack / 4) {
            windows.extend(self.client.read_forces(&words(&request))?);
        }
        Ok(plan.values(&windows))
    }

    /// STATUS_VAR_WRITE of each variable's raw value (`Var::parse` makes one).
    pub fn write(&mut self, values: &[(Var, u32)]) -> Result<(), LinkError> {
        self.write_pairs(values, false)
    }

    /// STATUS_VAR_FORCE_WRITE of each variable's raw value (only I and Q can be
    /// forced).
    pub fn force(&mut self, values: &[(Var, u32)]) -> Result<(), LinkError> {
        self.write_pairs(values, true)
    }

    /// Release the forces of `vars`: STATUS_VAR_FORCE_WRITE with USE = 15, which
    /// gutta-sim reads as "release" (UM4001 has no unforce). The value sent is the
    /// variable's current value, read first and returned, so a PLC that ignores USE
    /// keeps it where it is rather than jumping.
    pub fn unforce(&mut self, vars: &[Var]) -> Result<Vec<u32>, LinkError> {
        let current = self.read(vars)?;
        let pairs: Vec<(PackedOperand, u32)> = vars
            .iter()
            .zip(&current)
            .map(|(v, raw)| (PackedOperand::force_release(v.address), *raw))
            .collect();
        self.send_pairs(&pairs, true)?;
        Ok(current)
    }

    fn write_pairs(&mut self, values: &[(Var, u32)], force: bool) -> Result<(), LinkError> {
        let pairs: Vec<(PackedOperand, u32)> = values
            .iter()
            .map(|(v, raw)| (packed(v.address), *raw))
            .collect();
        self.send_pairs(&pairs, force)
    }

    /// The pairs in requests of as many as the packet size holds (8 bytes each).
    fn send_pairs(&mut self, pairs: &[(PackedOperand, u32)], force: bool) -> Result<(), LinkError> {
        for chunk in pairs.chunks((self.pack / 8).max(1)) {
            let pairs: Vec<(u32, u32)> = chunk.iter().map(|(a, v)| (a.0, *v)).collect();
            self.client.write_vars(&pairs, force)?;
        }
        Ok(())
    }
}

/// The words of packed addresses, as `Client` sends them.
fn words(addresses: &[PackedOperand]) -> Vec<u32> {
    addresses.iter().map(|a| a.0).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_flag_wins_then_the_environment_then_the_factory_password() {
        let source = |flag, env| Credentials::lookup(flag, env).source;
        assert_eq!(
            source(Some("a"), Some("b")),
            PasswordSource::Flag("a".into())
        );
        assert_eq!(
            source(None, Some("b")),
            PasswordSource::Environment("b".into())
        );
        assert_eq!(source(None, Some("")), PasswordSource::Factory);
        assert_eq!(source(None, None), PasswordSource::Factory);
        assert_eq!(Credentials::lookup(None, None).password(), FACTORY_PASSWORD);
        assert_eq!(
            Credentials::lookup(Some("1234"), None).password(),
            gutta_format::password_bytes(Some("1234"))
        );
    }

    #[test]
    fn a_connection_without_keys_takes_the_flags_defaults() {
        let c = Connection {
            endpoint: Some(Endpoint::Serial("/dev/ttyUSB0".into())),
            ..Connection::default()
        };
        let config = LinkConfig::from_connection(&c).expect("an endpoint");
        assert_eq!(
            (config.station, config.timeout_ms, config.retries),
            (1, 1000, 2)
        );
        assert_eq!(config.line, LineSettings::DEFAULT);
        assert_eq!(config.describe(), "serial /dev/ttyUSB0");
        let odd = serial_line(Some(9600), Some(Parity::Odd));
        assert_eq!((odd.baud, line_parity(&odd)), (9600, Parity::Odd));
        assert!(LinkConfig::from_connection(&Connection::default()).is_none());
    }
}
