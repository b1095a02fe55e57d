//! GUTTA projects: a folder with `gutta.toml` (docs/projects.md). Finding one by walking
//! up from a folder, reading and validating its manifest, and the paths it names made
//! absolute. It does not compile, connect or create projects (gutta-cc does).

use std::ops::Range;
use std::path::{Path, PathBuf};

use serde::Deserialize;
use toml::Spanned;

/// The manifest's file name.
pub const MANIFEST: &str = "gutta.toml";

/// Where `gutta-cc build` writes the image unless `[build] output` says otherwise.
pub const DEFAULT_OUTPUT: &str = "target/image";

/// A loaded, validated project. Every path is absolute (joined to `root`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Project {
    /// The folder holding gutta.toml.
    pub root: PathBuf,
    /// The manifest itself (`root/gutta.toml`).
    pub manifest: PathBuf,
    /// `[program] name`, else the folder's name.
    pub name: String,
    /// Which PLC the program is for: `[program] plc` or `target`, or neither (then the
    /// sources' PLC_TYPE or the stdlib default decides).
    pub plc: ProjectTarget,
    /// `[program] sources`: the files of the one program, in order.
    pub sources: Vec<PathBuf>,
    /// `[program] symbols`: symbol tables.
    pub symbols: Vec<PathBuf>,
    /// `[build] output`: the image directory.
    pub output: PathBuf,
    /// `[build] scale-timer-presets`: `gutta-cc build --scale-timer-presets` (Micro/WIN
    /// exports keep their S7-200 timer timing; docs/microwin.md).
    pub scale_timer_presets: bool,
    /// `[microwin] s_area`: where a Micro/WIN export's S area starts, a byte address
    /// such as `MB96` (`gutta-cc --s-area`; docs/microwin.md, "Sequence control relays").
    pub s_area: Option<String>,
    pub connection: Connection,
}

/// `[program] plc` or `[program] target`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ProjectTarget {
    Unspecified,
    Stdlib(String),
    Folder(PathBuf),
}

/// `[connection]`: each key that is absent stays `None` (the command line's default).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Connection {
    pub endpoint: Option<Endpoint>,
    pub baud: Option<u32>,
    pub parity: Option<Parity>,
    pub station: Option<u8>,
    pub timeout_ms: Option<u64>,
    pub retries: Option<u32>,
}

/// How the PLC is reached: the three mutually exclusive keys of `[connection]`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Endpoint {
    Tcp(String),
    RtuTcp(String),
    Serial(String),
}

/// `parity`: gutta-format's, the one type of a serial line's parity.
pub use gutta_format::Parity;

/// Every key a section may hold, for the unknown-key error and its did-you-mean.
const SECTIONS: &[(&str, &[&str])] = &[
    ("", &["program", "connection", "build", "microwin"]),
    ("program", &["name", "plc", "target", "sources", "symbols"]),
    (
        "connection",
        &[
            "tcp", "rtu-tcp", "serial", "baud", "parity", "station", "timeout", "retries",
        ],
    ),
    ("build", &["output", "scale-timer-presets"]),
    ("microwin", &["s_area"]),
];

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Manifest {
    program: ProgramSection,
    connection: Option<ConnectionSection>,
    build: Option<BuildSection>,
    microwin: Option<MicrowinSection>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MicrowinSection {
    s_area: Option<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ProgramSection {
    name: Option<Spanned<String>>,
    plc: Option<Spanned<String>>,
    target: Option<Spanned<String>>,
    sources: Spanned<Vec<Spanned<String>>>,
    #[serde(default)]
    symbols: Vec<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
struct ConnectionSection {
    tcp: Option<Spanned<String>>,
    rtu_tcp: Option<Spanned<String>>,
    serial: Option<Spanned<String>>,
    baud: Option<Spanned<u32>>,
    parity: Option<Spanned<String>>,
    station: Option<Spanned<i64>>,
    timeout: Option<u64>,
    retries: Option<u32>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
struct BuildSection {
    output: Option<String>,
    #[serde(default)]
    scale_timer_presets: bool,
}

impl Project {
    /// The project `start` is in: the first folder holding gutta.toml from `start` up
    /// to the filesystem root, loaded; `None` when there is none.
    pub fn find(start: &Path) -> Result<Option<Project>, String> {
        match find_manifest(start) {
            Some(manifest) => Project::load(&manifest).map(Some),
            None => Ok(None),
        }
    }

    /// Read and validate the manifest at `manifest` (a gutta.toml). Every error names
    /// its path, and its line and column when a key or value is at fault.
    pub fn load(manifest: &Path) -> Result<Project, String> {
        let text = std::fs::read_to_string(manifest)
            .map_err(|e| format!("cannot read {}: {e}", manifest.display()))?;
        let root = manifest.parent().map(Path::to_path_buf).unwrap_or_default();
        Project::parse(&root, manifest, &text)
    }

    /// Parse and validate `text`, the manifest `manifest` of the folder `root` (the files
    /// it names must exist).
    pub fn parse(root: &Path, manifest: &Path, text: &str) -> Result<Project, String> {
        let at = |span: Range<usize>, message: String| {
            let (line, column) = line_column(text, span.start);
            format!("{}:{line}:{column}: {message}", manifest.display())
        };
        let parsed: Manifest = toml::from_str(text).map_err(|e| {
            let span = e.span().unwrap_or(0..0);
            let message = unknown_key(text, span.clone(), e.message())
                .unwrap_or_else(|| explained(text, span.start, e.message()));
            at(span, message)
        })?;
        let program = parsed.program;
        let plc = match (program.plc, program.target) {
            (Some(p), Some(t)) => {
                return Err(at(
                    t.span(),
                    format!(
                        "[program] has both plc = \"{}\" and target: give one",
                        p.get_ref()
                    ),
                ))
            }
            (Some(p), None) if p.get_ref().trim().is_empty() => {
                return Err(at(p.span(), "[program] plc is empty".into()))
            }
            (Some(p), None) => ProjectTarget::Stdlib(p.into_inner()),
            (None, Some(t)) => ProjectTarget::Folder(root.join(t.get_ref())),
            (None, None) => ProjectTarget::Unspecified,
        };
        if program.sources.get_ref().is_empty() {
            return Err(at(
                program.sources.span(),
                "[program] sources is empty: list the program's .lad files, e.g. sources = [\"src/main.lad\"]".into(),
            ));
        }
        let files = |list: Vec<Spanned<String>>, key: &str| {
            list.into_iter()
                .map(|file| {
                    let path = root.join(file.get_ref());
                    if path.is_file() {
                        Ok(path)
                    } else {
                        Err(at(
                            file.span(),
                            format!(
                                "[program] {key}: {} does not exist (paths are relative to the project folder {})",
                                path.display(),
                                root.display()
                            ),
                        ))
                    }
                })
                .collect::<Result<Vec<_>, _>>()
        };
        let sources = files(program.sources.into_inner(), "sources")?;
        let symbols = files(program.symbols, "symbols")?;
        let name = match program.name {
            Some(n) if n.get_ref().trim().is_empty() => {
                return Err(at(n.span(), "[program] name is empty".into()))
            }
            Some(n) => n.into_inner(),
            None => root
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_else(|| "program".into()),
        };
        let connection = match parsed.connection {
            Some(c) => connection(c, &at)?,
            None => Connection::default(),
        };
        let (output, scale_timer_presets) = match parsed.build {
            Some(b) => (b.output, b.scale_timer_presets),
            None => (None, false),
        };
        let output = output.unwrap_or_else(|| DEFAULT_OUTPUT.to_string());
        let s_area = match parsed.microwin.and_then(|m| m.s_area) {
            Some(s) if !is_byte_address(s.get_ref()) => {
                return Err(at(
                    s.span(),
                    format!(
                        "[microwin] s_area `{}` is not a byte address such as \"MB96\"",
                        s.get_ref()
                    ),
                ))
            }
            s => s.map(Spanned::into_inner),
        };
        Ok(Project {
            root: root.to_path_buf(),
            manifest: manifest.to_path_buf(),
            name,
            plc,
            sources,
            symbols,
            output: root.join(output),
            scale_timer_presets,
            s_area,
            connection,
        })
    }
}

/// Whether `text` has the shape of a byte address: an area name, `B`, digits (`MB96`).
fn is_byte_address(text: &str) -> bool {
    let letters = text.bytes().take_while(u8::is_ascii_alphabetic).count();
    let (name, digits) = text.split_at(letters);
    name.len() >= 2
        && name.to_ascii_uppercase().ends_with('B')
        && !digits.is_empty()
        && digits.bytes().all(|b| b.is_ascii_digit())
}

/// The first `gutta.toml` in `start` or a folder above it.
pub fn find_manifest(start: &Path) -> Option<PathBuf> {
    start
        .ancestors()
        .map(|dir| dir.join(MANIFEST))
        .find(|candidate| candidate.is_file())
}

/// `[connection]` validated: one endpoint at most, line settings only with a serial
/// line, a station a PLC can have.
fn connection(
    c: ConnectionSection,
    at: &impl Fn(Range<usize>, String) -> String,
) -> Result<Connection, String> {
    let endpoints: Vec<(&str, Spanned<String>)> =
        [("tcp", c.tcp), ("rtu-tcp", c.rtu_tcp), ("serial", c.serial)]
            .into_iter()
            .filter_map(|(key, value)| value.map(|v| (key, v)))
            .collect();
    if let [(first, _), (second, value), ..] = endpoints.as_slice() {
        return Err(at(
            value.span(),
            format!("[connection] has both {first} and {second}: give one way to reach the PLC"),
        ));
    }
    let endpoint = endpoints.into_iter().next().map(|(key, value)| {
        let value = value.into_inner();
        match key {
            "tcp" => Endpoint::Tcp(value),
            "rtu-tcp" => Endpoint::RtuTcp(value),
            _ => Endpoint::Serial(value),
        }
    });
    let serial = matches!(endpoint, Some(Endpoint::Serial(_)));
    for (key, span) in [
        ("baud", c.baud.as_ref().map(Spanned::span)),
        ("parity", c.parity.as_ref().map(Spanned::span)),
    ] {
        if let (Some(span), false) = (span, serial) {
            return Err(at(
                span,
                format!(
                    "[connection] {key} applies only to a serial line (serial = \"/dev/ttyUSB0\")"
                ),
            ));
        }
    }
    let parity = match c.parity {
        None => None,
        Some(p) => Some(match p.get_ref().to_ascii_lowercase().as_str() {
            "none" => Parity::None,
            "even" => Parity::Even,
            "odd" => Parity::Odd,
            other => {
                return Err(at(
                    p.span(),
                    format!(
                        "[connection] parity = \"{other}\": expected \"none\", \"even\" or \"odd\""
                    ),
                ))
            }
        }),
    };
    let station = match c.station {
        None => None,
        Some(s) => Some(
            u8::try_from(*s.get_ref())
                .ok()
                .filter(|n| (1..=247).contains(n))
                .ok_or_else(|| {
                    at(
                        s.span(),
                        format!(
                            "[connection] station = {}: a Modbus station is 1 to 247",
                            s.get_ref()
                        ),
                    )
                })?,
        ),
    };
    Ok(Connection {
        endpoint,
        baud: c.baud.map(Spanned::into_inner),
        parity,
        station,
        timeout_ms: c.timeout,
        retries: c.retries,
    })
}

/// toml's "unknown field" error rewritten: the key, its section and the keys close to it.
fn unknown_key(text: &str, span: Range<usize>, message: &str) -> Option<String> {
    if !message.starts_with("unknown field") {
        return None;
    }
    let key = text
        .get(span.clone())?
        .trim()
        .trim_matches(|c| c == '"' || c == '\'');
    let section = table_of_key(text, span.start);
    let section = section.as_str();
    let known = SECTIONS.iter().find(|(name, _)| *name == section)?.1;
    let heading = if section.is_empty() {
        "at the top level".to_string()
    } else {
        format!("in [{section}]")
    };
    let mut message = format!("unknown key `{key}` {heading}");
    match closest(key, known) {
        Some(close) => message.push_str(&format!("; did you mean `{close}`?")),
        None => message.push_str(&format!("; expected one of: {}", known.join(", "))),
    }
    Some(message)
}

/// Any other error of toml's, said in gutta.toml's terms: which section lacks which
/// key, or which key's value is wrong.
fn explained(text: &str, offset: usize, message: &str) -> String {
    let message = message.trim_end();
    if let Some(key) = message
        .strip_prefix("missing field `")
        .and_then(|m| m.strip_suffix('`'))
    {
        return match key {
            "program" => {
                "no [program] section: a project needs one, with sources = [\"src/main.lad\"]"
                    .into()
            }
            "sources" => {
                "[program] needs sources = [\"src/main.lad\", ...]: the program's files".into()
            }
            other => format!("missing key `{other}`"),
        };
    }
    let line_start = text[..offset.min(text.len())]
        .rfind('\n')
        .map_or(0, |i| i + 1);
    let line = text[line_start..].lines().next().unwrap_or("");
    match line.split_once('=') {
        Some((key, _)) if !line.trim_start().starts_with('[') => {
            let section = section_at(text, offset);
            let key = key.trim();
            if section.is_empty() {
                format!("`{key}`: {message}")
            } else {
                format!("[{section}] {key}: {message}")
            }
        }
        _ => message.to_string(),
    }
}

/// The table (dotted path) the key at byte `offset` belongs to: the last `[section]`
/// heading before its line, then any dotted prefix on the line itself (`program.plcc = 1`,
/// `[program.sub]`).
fn table_of_key(text: &str, offset: usize) -> String {
    let offset = offset.min(text.len());
    let line_start = text[..offset].rfind('\n').map_or(0, |i| i + 1);
    let prefix = text[line_start..offset].trim();
    let (base, dotted) = match prefix.strip_prefix('[') {
        Some(heading) => ("", heading.trim_start_matches('[')),
        None => (section_at(text, line_start), prefix),
    };
    let dotted = dotted.trim_end_matches('.').trim();
    match (base.is_empty(), dotted.is_empty()) {
        (_, true) => base.to_string(),
        (true, false) => dotted.to_string(),
        (false, false) => format!("{base}.{dotted}"),
    }
}

/// The `[section]` whose table holds byte `offset` ("" before the first heading).
fn section_at(text: &str, offset: usize) -> &str {
    text[..offset.min(text.len())]
        .lines()
        .rev()
        .filter_map(|line| {
            let line = line.trim();
            let inner = line.strip_prefix('[')?;
            Some(inner.split(']').next()?.trim())
        })
        .next()
        .unwrap_or("")
}

/// 1-based line and column (in characters) of byte `offset`.
pub(crate) fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let start = before.rfind('\n').map_or(0, |i| i + 1);
    (line, before[start..].chars().count() + 1)
}

/// The known key closest to `key` (edit distance at most 2, or one a third its length).
pub(crate) fn closest<'a>(key: &str, known: &[&'a str]) -> Option<&'a str> {
    known
        .iter()
        .map(|k| {
            (
                gutta_catalog::edit_distance(&key.to_ascii_lowercase(), k),
                *k,
            )
        })
        .filter(|(d, k)| *d <= 2.max(k.len() / 3))
        .min()
        .map(|(_, k)| k)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A folder of this test holding src/main.lad, and its gutta.toml's path.
    fn folder(tag: &str) -> (PathBuf, PathBuf) {
        let root =
            std::env::temp_dir().join(format!("gutta-io-project-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        std::fs::create_dir_all(root.join("src")).expect("mkdir");
        std::fs::write(root.join("src/main.lad"), "").expect("writes");
        let manifest = root.join(MANIFEST);
        (root, manifest)
    }

    #[test]
    fn paths_join_the_project_folder_and_absent_keys_take_their_defaults() {
        let (root, manifest) = folder("defaults");
        let p = Project::parse(
            &root,
            &manifest,
            "[program]\nsources = [\"src/main.lad\"]\n",
        )
        .expect("valid");
        assert_eq!(p.sources, vec![root.join("src/main.lad")]);
        assert!(p.symbols.is_empty());
        assert_eq!(p.output, root.join(DEFAULT_OUTPUT));
        assert_eq!(p.plc, ProjectTarget::Unspecified);
        assert_eq!(p.connection, Connection::default());
        assert_eq!(
            Some(p.name.as_str()),
            root.file_name().and_then(|n| n.to_str())
        );
    }

    #[test]
    fn find_walks_up_to_the_first_manifest() {
        let (root, manifest) = folder("find");
        std::fs::write(&manifest, "[program]\nsources = [\"src/main.lad\"]\n[connection]\nrtu-tcp = \"h:1\"\nstation = 9\n")
            .expect("writes");
        let deep = root.join("src/a/b");
        std::fs::create_dir_all(&deep).expect("mkdir");
        let p = Project::find(&deep).expect("valid").expect("found");
        assert_eq!(p.root, root);
        assert_eq!(p.connection.endpoint, Some(Endpoint::RtuTcp("h:1".into())));
        assert_eq!(p.connection.station, Some(9));
    }

    #[test]
    fn close_keys_are_suggested_and_far_ones_are_not() {
        assert_eq!(closest("sorces", &["plc", "sources"]), Some("sources"));
        assert_eq!(closest("SOURCES", &["plc", "sources"]), Some("sources"));
        assert_eq!(closest("whatever", &["plc", "sources"]), None);
        assert_eq!(line_column("ab\ncdé f", 8), (2, 5));
        assert_eq!(table_of_key("[a]\nb.c = 1", 6), "a.b");
    }
}
