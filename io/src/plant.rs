//! Plants: several simulated devices in one `gutta-sim --plant PLANT.toml` (docs/simulator.md,
//! "Plants"). Reading and validating the plant file: its `[[device]]` tables, the keys
//! each kind takes, unique names, `device:NAME` ports that lead to a device able to
//! answer on a line, and paths made absolute (relative to the plant file's folder).
//! Every error carries a P code and the file, line and column at fault. It does not
//! compile, load or run anything (gutta-sim does) and checks no `--port0` spec beyond
//! its prefix.

use std::ops::Range;
use std::path::{Path, PathBuf};

use serde::Deserialize;
use toml::Spanned;

use crate::project::{closest, line_column};

/// Stable codes of plant file errors (docs/simulator.md, "Plants").
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum PlantErrorCode {
    /// P0001: the file cannot be read, is not TOML, or a value has the wrong type.
    Syntax,
    /// P0002: a key the plant file does not know.
    UnknownKey,
    /// P0003: a required key is missing (`name`, `kind`), or the plant has no device.
    Missing,
    /// P0004: a value is malformed or out of range.
    Value,
    /// P0005: two devices have the same name.
    Duplicate,
    /// P0006: a key the device's kind does not take, or two keys that exclude each other.
    KindKey,
    /// P0007: a port that leads nowhere a line can reach (`device:NAME` of no device, of
    /// itself or of an fx device; a spec of no known form).
    Port,
}

impl PlantErrorCode {
    /// Every code, in number order.
    pub const ALL: &'static [PlantErrorCode] = &[
        PlantErrorCode::Syntax,
        PlantErrorCode::UnknownKey,
        PlantErrorCode::Missing,
        PlantErrorCode::Value,
        PlantErrorCode::Duplicate,
        PlantErrorCode::KindKey,
        PlantErrorCode::Port,
    ];

    pub fn as_str(self) -> &'static str {
        match self {
            PlantErrorCode::Syntax => "P0001",
            PlantErrorCode::UnknownKey => "P0002",
            PlantErrorCode::Missing => "P0003",
            PlantErrorCode::Value => "P0004",
            PlantErrorCode::Duplicate => "P0005",
            PlantErrorCode::KindKey => "P0006",
            PlantErrorCode::Port => "P0007",
        }
    }

    /// What the code means, in one line.
    pub fn summary(self) -> &'static str {
        match self {
            PlantErrorCode::Syntax => {
                "the file cannot be read, is not TOML, or a value has the wrong type"
            }
            PlantErrorCode::UnknownKey => "a key the plant file does not know",
            PlantErrorCode::Missing => "a required key is missing, or the plant has no device",
            PlantErrorCode::Value => "a value is malformed or out of range",
            PlantErrorCode::Duplicate => "two devices have the same name",
            PlantErrorCode::KindKey => {
                "a key the device's kind does not take, or two keys that exclude each other"
            }
            PlantErrorCode::Port => "a port leads to no device that can answer on a line",
        }
    }
}

/// A plant file error: its code, where it is and what was wrong.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PlantError {
    pub code: PlantErrorCode,
    /// `FILE:LINE:COLUMN`, or `FILE` when no key or value is at fault.
    pub place: String,
    pub message: String,
}

impl std::fmt::Display for PlantError {
    /// `plant.toml:3:8: [P0002] unknown key ...`: the place first, as gutta.toml's.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}: [{}] {}",
            self.place,
            self.code.as_str(),
            self.message
        )
    }
}

impl std::error::Error for PlantError {}

/// A loaded, validated plant. Every path is absolute (joined to the plant file's folder).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Plant {
    /// The plant file.
    pub file: PathBuf,
    /// The devices, in the file's order.
    pub devices: Vec<PlantDevice>,
}

/// What a device is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DeviceKind {
    Plc,
    Fx,
    RelayBoard,
}

impl DeviceKind {
    /// Its name in the plant file (`plc`, `fx`, `relay-board`).
    pub fn as_str(self) -> &'static str {
        match self {
            DeviceKind::Plc => "plc",
            DeviceKind::Fx => "fx",
            DeviceKind::RelayBoard => "relay-board",
        }
    }

    /// The keys a device of this kind takes.
    fn keys(self) -> &'static [&'static str] {
        match self {
            DeviceKind::Plc => DEVICE_KEYS,
            DeviceKind::Fx | DeviceKind::RelayBoard => &["name", "kind", "tcp"],
        }
    }
}

/// A PLC's program.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PlcProgram {
    /// Neither `image` nor `project`: the PLC starts empty (a download gives it one).
    Empty,
    /// `image`: an image directory written by `gutta-cc -o` or `gutta-cc build`.
    Image(PathBuf),
    /// `project`: a project folder (or its gutta.toml), compiled when the plant starts.
    Project(PathBuf),
}

/// Where a PLC's serial port leads.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PortLead {
    /// `device:NAME`: another device of the plant, in process.
    Device(String),
    /// Any `gutta-sim --port0` spec (`tcp-connect:`, `modbus-tcp:`, `serial:`, `pty:`).
    Spec(String),
}

/// One `[[device]]`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PlantDevice {
    pub name: String,
    pub kind: DeviceKind,
    /// `FILE:LINE:COLUMN` of its `[[device]]` heading, for errors found later (an image
    /// that does not load, a project that does not compile).
    pub place: String,
    /// `tcp`: Modbus TCP listeners (the relay board's, the fx device's raw frames).
    pub tcp: Vec<String>,
    /// `rtu-tcp`: Modbus RTU over TCP listeners (a PLC's).
    pub rtu_tcp: Vec<String>,
    pub program: PlcProgram,
    /// `plc`: the PLC type from the stdlib (else the image's or project's, else the
    /// default).
    pub plc: Option<String>,
    /// `target`: a target folder.
    pub target: Option<PathBuf>,
    /// `flash`: the PLC's flash folder (`gutta-sim --flash`).
    pub flash: Option<PathBuf>,
    /// `scan-ms`: real time per scan (10 without it).
    pub scan_ms: u32,
    /// `port0`, `port1`.
    pub ports: [Option<PortLead>; 2],
}

/// Every key of a `[[device]]`, for the unknown-key error and its did-you-mean.
const DEVICE_KEYS: &[&str] = &[
    "name", "kind", "tcp", "rtu-tcp", "image", "project", "plc", "target", "flash", "scan-ms",
    "port0", "port1",
];

/// The scan time without `scan-ms` (gutta-sim's --scan-ms default).
pub const DEFAULT_SCAN_MS: u32 = 10;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PlantFile {
    #[serde(default)]
    device: Vec<Spanned<RawDevice>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
struct RawDevice {
    name: Option<Spanned<String>>,
    kind: Option<Spanned<String>>,
    tcp: Option<Spanned<Addresses>>,
    rtu_tcp: Option<Spanned<Addresses>>,
    image: Option<Spanned<String>>,
    project: Option<Spanned<String>>,
    plc: Option<Spanned<String>>,
    target: Option<Spanned<String>>,
    flash: Option<Spanned<String>>,
    scan_ms: Option<Spanned<i64>>,
    port0: Option<Spanned<String>>,
    port1: Option<Spanned<String>>,
}

/// `tcp = "host:port"` or `tcp = ["host:port", ...]`.
#[derive(Deserialize)]
#[serde(untagged)]
enum Addresses {
    One(String),
    Many(Vec<String>),
}

impl Plant {
    /// Read and validate the plant file `file`.
    pub fn load(file: &Path) -> Result<Plant, PlantError> {
        let text = std::fs::read_to_string(file).map_err(|e| PlantError {
            code: PlantErrorCode::Syntax,
            place: file.display().to_string(),
            message: format!("cannot read the plant file: {e}"),
        })?;
        let folder = file.parent().map(Path::to_path_buf).unwrap_or_default();
        Plant::parse(&folder, file, &text)
    }

    /// Parse and validate `text`, the plant file `file` in `folder` (paths it names are
    /// joined to `folder`; whether they exist is the loader's business).
    pub fn parse(folder: &Path, file: &Path, text: &str) -> Result<Plant, PlantError> {
        let here = |span: Range<usize>| {
            let (line, column) = line_column(text, span.start);
            format!("{}:{line}:{column}", file.display())
        };
        let at = |code: PlantErrorCode, span: Range<usize>, message: String| PlantError {
            code,
            place: here(span),
            message,
        };
        let parsed: PlantFile = toml::from_str(text).map_err(|e| {
            let span = e.span().unwrap_or(0..0);
            match unknown_key(text, span.clone(), e.message()) {
                Some(message) => at(PlantErrorCode::UnknownKey, span, message),
                None => at(
                    PlantErrorCode::Syntax,
                    span,
                    e.message().trim_end().to_string(),
                ),
            }
        })?;
        if parsed.device.is_empty() {
            return Err(at(
                PlantErrorCode::Missing,
                0..0,
                "the plant has no device: add a [[device]] with name and kind".into(),
            ));
        }
        let mut devices = Vec::new();
        for raw in &parsed.device {
            let device = device(folder, raw, &here, &at)?;
            if let Some(first) = devices
                .iter()
                .find(|d: &&PlantDevice| d.name == device.name)
            {
                let name = raw
                    .get_ref()
                    .name
                    .as_ref()
                    .map_or(raw.span(), Spanned::span);
                return Err(at(
                    PlantErrorCode::Duplicate,
                    name,
                    format!(
                        "a second device named `{}` (the first is at {}): names are unique",
                        device.name, first.place
                    ),
                ));
            }
            devices.push(device);
        }
        for (raw, device) in parsed.device.iter().zip(&devices) {
            let raw = raw.get_ref();
            for (key, value) in [("port0", &raw.port0), ("port1", &raw.port1)] {
                let Some(value) = value else { continue };
                let Some(other) = value.get_ref().strip_prefix("device:") else {
                    continue;
                };
                let refuse = |why: String| {
                    Err(at(
                        PlantErrorCode::Port,
                        value.span(),
                        format!(
                            "device `{}`: {key} = \"{}\": {why}",
                            device.name,
                            value.get_ref()
                        ),
                    ))
                };
                match devices.iter().find(|d| d.name == other) {
                    None => {
                        let names: Vec<&str> = devices.iter().map(|d| d.name.as_str()).collect();
                        let hint = closest(other, &names)
                            .map_or_else(String::new, |n| format!("; did you mean `device:{n}`?"));
                        return refuse(format!("the plant has no device `{other}`{hint}"));
                    }
                    Some(d) if d.name == device.name => {
                        return refuse("a port cannot lead to its own PLC".into())
                    }
                    Some(d) if d.kind == DeviceKind::Fx => {
                        return refuse(format!(
                            "`{other}` is an fx device, which answers no Modbus RTU on a line \
                             (a port leads to a plc or a relay-board)"
                        ))
                    }
                    Some(_) => {}
                }
            }
        }
        Ok(Plant {
            file: file.to_path_buf(),
            devices,
        })
    }
}

/// One `[[device]]` validated on its own (the names it refers to are checked later).
fn device(
    folder: &Path,
    spanned: &Spanned<RawDevice>,
    here: &impl Fn(Range<usize>) -> String,
    at: &impl Fn(PlantErrorCode, Range<usize>, String) -> PlantError,
) -> Result<PlantDevice, PlantError> {
    let raw = spanned.get_ref();
    let heading = spanned.span();
    let Some(name) = &raw.name else {
        return Err(at(
            PlantErrorCode::Missing,
            heading,
            "a [[device]] needs name = \"...\"".into(),
        ));
    };
    let name_ok = {
        let mut chars = name.get_ref().chars();
        chars.next().is_some_and(|c| c.is_ascii_alphabetic())
            && chars.all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
    };
    if !name_ok {
        return Err(at(
            PlantErrorCode::Value,
            name.span(),
            format!(
                "name = \"{}\": a device name is a letter, then letters, digits, `-` or `_`",
                name.get_ref()
            ),
        ));
    }
    let name_text = name.get_ref().clone();
    let Some(kind) = &raw.kind else {
        return Err(at(
            PlantErrorCode::Missing,
            heading,
            format!("device `{name_text}` needs kind = \"plc\", \"fx\" or \"relay-board\""),
        ));
    };
    let kind_value = match kind.get_ref().as_str() {
        "plc" => DeviceKind::Plc,
        "fx" => DeviceKind::Fx,
        "relay-board" => DeviceKind::RelayBoard,
        other => {
            return Err(at(
                PlantErrorCode::Value,
                kind.span(),
                format!(
                    "device `{name_text}`: kind = \"{other}\": expected \"plc\", \"fx\" or \"relay-board\""
                ),
            ))
        }
    };
    let present: [(&str, Option<Range<usize>>); 10] = [
        ("tcp", raw.tcp.as_ref().map(Spanned::span)),
        ("rtu-tcp", raw.rtu_tcp.as_ref().map(Spanned::span)),
        ("image", raw.image.as_ref().map(Spanned::span)),
        ("project", raw.project.as_ref().map(Spanned::span)),
        ("plc", raw.plc.as_ref().map(Spanned::span)),
        ("target", raw.target.as_ref().map(Spanned::span)),
        ("flash", raw.flash.as_ref().map(Spanned::span)),
        ("scan-ms", raw.scan_ms.as_ref().map(Spanned::span)),
        ("port0", raw.port0.as_ref().map(Spanned::span)),
        ("port1", raw.port1.as_ref().map(Spanned::span)),
    ];
    for (key, span) in &present {
        if let (Some(span), false) = (span, kind_value.keys().contains(key)) {
            return Err(at(
                PlantErrorCode::KindKey,
                span.clone(),
                format!(
                    "device `{name_text}` is a {}, which takes no `{key}` (it takes {})",
                    kind_value.as_str(),
                    kind_value.keys()[2..].join(", ")
                ),
            ));
        }
    }
    for (first, second, value) in [
        (
            "image",
            "project",
            raw.image.as_ref().and(raw.project.as_ref()),
        ),
        ("plc", "target", raw.plc.as_ref().and(raw.target.as_ref())),
    ] {
        if let Some(value) = value {
            return Err(at(
                PlantErrorCode::KindKey,
                value.span(),
                format!("device `{name_text}` has both {first} and {second}: give one"),
            ));
        }
    }
    let addresses =
        |key: &str, value: &Option<Spanned<Addresses>>| -> Result<Vec<String>, PlantError> {
            let Some(value) = value else {
                return Ok(Vec::new());
            };
            let span = value.span();
            let list = match value.get_ref() {
                Addresses::One(a) => vec![a.clone()],
                Addresses::Many(list) => list.clone(),
            };
            if list.is_empty() || list.iter().any(|a| a.trim().is_empty()) {
                return Err(at(
                    PlantErrorCode::Value,
                    span,
                    format!(
                    "device `{name_text}`: {key}: an address is HOST:PORT, e.g. \"127.0.0.1:5020\""
                ),
                ));
            }
            Ok(list)
        };
    let tcp = addresses("tcp", &raw.tcp)?;
    let rtu_tcp = addresses("rtu-tcp", &raw.rtu_tcp)?;
    let path =
        |key: &str, value: &Option<Spanned<String>>| -> Result<Option<PathBuf>, PlantError> {
            match value {
                Some(v) if v.get_ref().trim().is_empty() => Err(at(
                    PlantErrorCode::Value,
                    v.span(),
                    format!("device `{name_text}`: {key} is empty"),
                )),
                Some(v) => Ok(Some(folder.join(v.get_ref()))),
                None => Ok(None),
            }
        };
    let program = match (path("image", &raw.image)?, path("project", &raw.project)?) {
        (Some(image), _) => PlcProgram::Image(image),
        (None, Some(project)) => PlcProgram::Project(project),
        (None, None) => PlcProgram::Empty,
    };
    let plc = match &raw.plc {
        Some(p) if p.get_ref().trim().is_empty() => {
            return Err(at(
                PlantErrorCode::Value,
                p.span(),
                format!("device `{name_text}`: plc is empty"),
            ))
        }
        p => p.as_ref().map(|p| p.get_ref().clone()),
    };
    let scan_ms = match &raw.scan_ms {
        None => DEFAULT_SCAN_MS,
        Some(s) => u32::try_from(*s.get_ref())
            .ok()
            .filter(|ms| (1..=60_000).contains(ms))
            .ok_or_else(|| {
                at(
                    PlantErrorCode::Value,
                    s.span(),
                    format!(
                        "device `{name_text}`: scan-ms = {}: a scan takes 1 to 60000 ms",
                        s.get_ref()
                    ),
                )
            })?,
    };
    let mut ports = [None, None];
    for (slot, (key, value)) in ports
        .iter_mut()
        .zip([("port0", &raw.port0), ("port1", &raw.port1)])
    {
        let Some(value) = value else { continue };
        let text = value.get_ref();
        *slot = Some(if let Some(other) = text.strip_prefix("device:") {
            PortLead::Device(other.to_string())
        } else if ["tcp-connect:", "modbus-tcp:", "serial:", "pty:"]
            .iter()
            .any(|p| text.starts_with(p))
        {
            PortLead::Spec(text.clone())
        } else {
            return Err(at(
                PlantErrorCode::Port,
                value.span(),
                format!(
                    "device `{name_text}`: {key} = \"{text}\": a port is device:NAME, \
                     tcp-connect:HOST:PORT, modbus-tcp:HOST:PORT, serial:DEVICE or pty:PATH"
                ),
            ));
        });
    }
    Ok(PlantDevice {
        name: name_text.clone(),
        kind: kind_value,
        place: here(heading),
        tcp,
        rtu_tcp,
        program,
        plc,
        target: path("target", &raw.target)?,
        flash: path("flash", &raw.flash)?,
        scan_ms,
        ports,
    })
}

/// toml's "unknown field" error said in the plant file's terms, with the closest key.
fn unknown_key(text: &str, span: Range<usize>, message: &str) -> Option<String> {
    if !message.starts_with("unknown field") {
        return None;
    }
    let key = text
        .get(span)?
        .trim()
        .trim_matches(|c| c == '"' || c == '\'');
    let top = message.contains("expected `device`");
    let known: &[&str] = if top { &["device"] } else { DEVICE_KEYS };
    let heading = if top {
        "at the top level"
    } else {
        "in a [[device]]"
    };
    let mut out = format!("unknown key `{key}` {heading}");
    match closest(key, known) {
        Some(close) if top => out.push_str(&format!("; did you mean `[[{close}]]`?")),
        Some(close) => out.push_str(&format!("; did you mean `{close}`?")),
        None => out.push_str(&format!("; expected one of: {}", known.join(", "))),
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Plant, PlantError> {
        Plant::parse(Path::new("/plants"), Path::new("/plants/plant.toml"), text)
    }

    fn error(text: &str) -> (PlantErrorCode, String) {
        let e = parse(text).expect_err("refused");
        let shown = e.to_string();
        (e.code, shown)
    }

    #[test]
    fn a_plant_of_every_kind_with_paths_joined_to_its_folder() {
        let plant = parse(
            "[[device]]\nname = \"master\"\nkind = \"plc\"\ntcp = \"127.0.0.1:0\"\n\
             project = \"master\"\nscan-ms = 20\nport0 = \"device:slave\"\nport1 = \"device:board\"\n\
             [[device]]\nname = \"slave\"\nkind = \"plc\"\nimage = \"img\"\nrtu-tcp = [\"a:1\", \"b:2\"]\nflash = \"f\"\n\
             [[device]]\nname = \"board\"\nkind = \"relay-board\"\n\
             [[device]]\nname = \"fx1\"\nkind = \"fx\"\ntcp = \"h:3\"\n",
        )
        .expect("valid");
        let [m, s, b, f] = plant.devices.as_slice() else {
            panic!("four devices")
        };
        assert_eq!(m.program, PlcProgram::Project("/plants/master".into()));
        assert_eq!(m.scan_ms, 20);
        assert_eq!(m.ports[0], Some(PortLead::Device("slave".into())));
        assert_eq!(m.place, "/plants/plant.toml:1:1");
        assert_eq!(s.program, PlcProgram::Image("/plants/img".into()));
        assert_eq!(s.rtu_tcp, vec!["a:1", "b:2"]);
        assert_eq!(s.flash, Some("/plants/f".into()));
        assert_eq!(s.scan_ms, DEFAULT_SCAN_MS);
        assert_eq!(b.kind, DeviceKind::RelayBoard);
        assert!(b.tcp.is_empty());
        assert_eq!(
            (f.kind, f.tcp.as_slice()),
            (DeviceKind::Fx, &["h:3".to_string()][..])
        );
    }

    #[test]
    fn bad_files_get_their_code_and_place() {
        let cases: &[(&str, PlantErrorCode, &str)] = &[
            ("", PlantErrorCode::Missing, "plant.toml:1:1: [P0003] the plant has no device"),
            (
                "[[device]]\nname = \"a\"\nkind = \"plc\"\nscan_ms = 5\n",
                PlantErrorCode::UnknownKey,
                "plant.toml:4:1: [P0002] unknown key `scan_ms` in a [[device]]; did you mean `scan-ms`?",
            ),
            (
                "[[devices]]\nname = \"a\"\n",
                PlantErrorCode::UnknownKey,
                "did you mean `[[device]]`?",
            ),
            ("[[device]]\nkind = \"plc\"\n", PlantErrorCode::Missing, ":1:1: [P0003] a [[device]] needs name"),
            (
                "[[device]]\nname = \"a\"\nkind = \"robot\"\n",
                PlantErrorCode::Value,
                ":3:8: [P0004] device `a`: kind = \"robot\"",
            ),
            (
                "[[device]]\nname = \"a\"\nkind = \"plc\"\n[[device]]\nname = \"a\"\nkind = \"fx\"\n",
                PlantErrorCode::Duplicate,
                ":5:8: [P0005] a second device named `a` (the first is at /plants/plant.toml:1:1)",
            ),
            (
                "[[device]]\nname = \"b\"\nkind = \"relay-board\"\nrtu-tcp = \"h:1\"\n",
                PlantErrorCode::KindKey,
                ":4:11: [P0006] device `b` is a relay-board, which takes no `rtu-tcp` (it takes tcp)",
            ),
            (
                "[[device]]\nname = \"a\"\nkind = \"plc\"\nimage = \"i\"\nproject = \"p\"\n",
                PlantErrorCode::KindKey,
                ":5:11: [P0006] device `a` has both image and project",
            ),
            (
                "[[device]]\nname = \"a\"\nkind = \"plc\"\nport0 = \"device:a\"\n",
                PlantErrorCode::Port,
                ":4:9: [P0007] device `a`: port0 = \"device:a\": a port cannot lead to its own PLC",
            ),
            (
                "[[device]]\nname = \"a\"\nkind = \"plc\"\nport1 = \"device:slav\"\n[[device]]\nname = \"slave\"\nkind = \"plc\"\n",
                PlantErrorCode::Port,
                "the plant has no device `slav`; did you mean `device:slave`?",
            ),
            (
                "[[device]]\nname = \"a\"\nkind = \"plc\"\nport0 = \"device:f\"\n[[device]]\nname = \"f\"\nkind = \"fx\"\n",
                PlantErrorCode::Port,
                "`f` is an fx device",
            ),
            (
                "[[device]]\nname = \"a\"\nkind = \"plc\"\nport0 = \"ttyS0\"\n",
                PlantErrorCode::Port,
                "a port is device:NAME",
            ),
            (
                "[[device]]\nname = \"a\"\nkind = \"plc\"\nscan-ms = 0\n",
                PlantErrorCode::Value,
                ":4:11: [P0004] device `a`: scan-ms = 0",
            ),
            (
                "[[device]]\nname = \"a\"\nkind = \"plc\"\ntcp = 5020\n",
                PlantErrorCode::Syntax,
                ":4:7: [P0001]",
            ),
            ("[[device]\n", PlantErrorCode::Syntax, "[P0001]"),
            (
                "[[device]]\nname = \"1a\"\nkind = \"plc\"\n",
                PlantErrorCode::Value,
                "a device name is a letter",
            ),
        ];
        for (text, code, wanted) in cases {
            let (got, shown) = error(text);
            assert_eq!(got, *code, "{text}: {shown}");
            assert!(shown.contains(wanted), "{text}: {shown} lacks {wanted}");
        }
    }

    #[test]
    fn a_missing_file_is_named() {
        let e = Plant::load(Path::new("/no/such/plant.toml")).expect_err("refused");
        assert_eq!(e.code, PlantErrorCode::Syntax);
        assert!(
            e.to_string()
                .starts_with("/no/such/plant.toml: [P0001] cannot read the plant file: "),
            "{e}"
        );
    }

    #[test]
    fn codes_are_numbered_in_order() {
        for (n, code) in PlantErrorCode::ALL.iter().enumerate() {
            assert_eq!(code.as_str(), format!("P{:04}", n + 1));
            assert!(!code.summary().is_empty());
        }
    }
}
