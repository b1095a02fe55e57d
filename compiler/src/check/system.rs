//! The system block: serial port settings per port of the target and the password,
//! with the ranges the vendor's editor allows.

use std::collections::HashMap;

use super::{Checker, Parity, PortConfig, SystemConfig};
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;
use crate::syntax::ast::SystemValue;

const PORT_KEYS: [&str; 8] = [
    "PROTOCOL",
    "ADDRESS",
    "BAUD",
    "DATA_BITS",
    "PARITY",
    "STOP_BITS",
    "TIMEOUT",
    "FRAME_GAP",
];
const BAUDS: [i64; 5] = [9600, 19200, 38400, 57600, 115200];

impl Checker<'_> {
    pub(super) fn system_block(&mut self) -> Option<SystemConfig> {
        let ast = self.ast;
        let first = ast.system_blocks.first()?;
        for extra in &ast.system_blocks[1..] {
            self.report(
                Diagnostic::new(
                    Code::DuplicateSystemBlock,
                    extra.span,
                    "a program has one SYSTEM_BLOCK",
                )
                .with_secondary(first.span, "first one here"),
            );
        }
        let ports = self.target.memory.serial_ports;
        let mut config = SystemConfig {
            ports: (0..ports).map(PortConfig::editor_default).collect(),
            password: None,
        };
        let mut seen: HashMap<String, Span> = HashMap::new();
        for e in ast.system_blocks.iter().flat_map(|b| &b.entries) {
            let key = self.slice(e.key).to_ascii_uppercase().replace(' ', "");
            if let Some(prev) = seen.get(&key) {
                let prev = *prev;
                self.report(
                    Diagnostic::new(
                        Code::DuplicateSystemKey,
                        e.key,
                        format!("`{key}` is set twice"),
                    )
                    .with_secondary(prev, "first set here"),
                );
                continue;
            }
            seen.insert(key.clone(), e.key);
            if e.value == SystemValue::Error {
                continue;
            }
            if key == "PASSWORD" {
                match &e.value {
                    SystemValue::Str(s, span) if s.is_ascii() && s.len() <= 16 && !s.is_empty() => {
                        let _ = span;
                        config.password = Some(s.clone());
                    }
                    SystemValue::Str(_, span) => self.report(Diagnostic::new(
                        Code::SystemValue,
                        *span,
                        "PASSWORD must be 1..16 ASCII characters",
                    )),
                    _ => self.report(
                        Diagnostic::new(Code::SystemValue, e.span, "PASSWORD is a quoted string")
                            .help("for example `PASSWORD = \"1234\"`"),
                    ),
                }
                continue;
            }
            let Some((port, field)) = key
                .strip_prefix("PORT")
                .and_then(|r| r.split_once('.'))
                .and_then(|(n, f)| Some((n.parse::<u8>().ok()?, f)))
            else {
                let mut all: Vec<String> = PORT_KEYS.iter().map(|k| format!("PORT0.{k}")).collect();
                all.push("PASSWORD".into());
                let hint = super::suggest::closest(&key, all.iter().map(String::as_str))
                    .map(|s| format!("did you mean `{s}`?"));
                self.report(
                    Diagnostic::new(
                        Code::UnknownSystemKey,
                        e.key,
                        format!("unknown system block key `{key}`"),
                    )
                    .maybe_help(hint),
                );
                continue;
            };
            if !PORT_KEYS.contains(&field) {
                let hint = super::suggest::closest(field, PORT_KEYS)
                    .map(|s| format!("did you mean `PORT{port}.{s}`?"));
                self.report(
                    Diagnostic::new(
                        Code::UnknownSystemKey,
                        e.key,
                        format!("unknown port setting `{field}`"),
                    )
                    .maybe_help(hint),
                );
                continue;
            }
            if port >= ports {
                self.report(Diagnostic::new(
                    Code::NoSuchPort,
                    e.key,
                    format!(
                        "{} has {ports} serial port{}: PORT0{}",
                        self.target.name(),
                        if ports == 1 { "" } else { "s" },
                        if ports > 1 {
                            format!("..PORT{}", ports - 1)
                        } else {
                            String::new()
                        }
                    ),
                ));
                continue;
            }
            let p = &mut config.ports[port as usize];
            let int = match e.value {
                SystemValue::Integer(v, _) => Some(v),
                _ => None,
            };
            let word = match e.value {
                SystemValue::Word(w) => {
                    Some(self.text.get(w.range()).unwrap_or("").to_ascii_uppercase())
                }
                _ => None,
            };
            let value_span = match &e.value {
                SystemValue::Integer(_, s) | SystemValue::Word(s) | SystemValue::Str(_, s) => *s,
                SystemValue::Error => e.span,
            };
            let bad = |why: String| Diagnostic::new(Code::SystemValue, value_span, why);
            let in_range = |v: Option<i64>, lo: i64, hi: i64| v.filter(|v| (lo..=hi).contains(v));
            match field {
                "PROTOCOL" => {
                    if word.as_deref() != Some("MODBUS") {
                        self.report(bad(
                            "PROTOCOL must be MODBUS (free port is not implemented on EC20/EC30)"
                                .into(),
                        ));
                    }
                }
                "ADDRESS" => match in_range(int, 0, 255) {
                    Some(v) => p.address = v as u8,
                    None => self.report(bad("ADDRESS is the station number 0..255".into())),
                },
                "BAUD" => match int.filter(|v| BAUDS.contains(v)) {
                    Some(v) => p.baud = v as u32,
                    None => self.report(bad(
                        "BAUD must be 9600, 19200, 38400, 57600 or 115200".into()
                    )),
                },
                "DATA_BITS" => {
                    if int != Some(8) {
                        self.report(bad(
                            "DATA_BITS must be 8 (RTU; 7-bit ASCII is not implemented)".into(),
                        ));
                    }
                }
                "PARITY" => match word.as_deref() {
                    Some("NONE") => p.parity = Parity::None,
                    Some("EVEN") => p.parity = Parity::Even,
                    Some("ODD") => p.parity = Parity::Odd,
                    _ => self.report(bad("PARITY must be NONE, EVEN or ODD".into())),
                },
                "STOP_BITS" => match in_range(int, 1, 2) {
                    Some(v) => p.stop_bits = v as u8,
                    None => self.report(bad("STOP_BITS must be 1 or 2".into())),
                },
                "TIMEOUT" => match in_range(int, 1, 255) {
                    Some(v) => p.timeout = v as u8,
                    None => self.report(bad("TIMEOUT is 1..255 (x 100 ms)".into())),
                },
                _ => match in_range(int, 1, 255) {
                    Some(v) => p.frame_gap = v as u8,
                    None => self.report(bad("FRAME_GAP is 1..255 (x 1 ms)".into())),
                },
            }
        }
        Some(config)
    }
}
