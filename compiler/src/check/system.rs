//! The system block: serial port settings per port of the target and the password,
//! in the ranges of `gutta_catalog::rules` (the verifier checks the system page by
//! the same) and the baud rates of `gutta_format::BAUD_RATES`.

use std::collections::HashMap;

use gutta_catalog::rules::{self, port};
use gutta_format::BAUD_RATES;

use super::{Checker, Parity, PortConfig, SystemConfig};
use crate::diagnostics::{Code, Diagnostic, Suggestion};
use crate::source::Span;
use crate::syntax::ast::{SystemEntry, SystemValue};

pub const PORT_KEYS: [&str; 8] = [
    "PROTOCOL",
    "ADDRESS",
    "BAUD",
    "DATA_BITS",
    "PARITY",
    "STOP_BITS",
    "TIMEOUT",
    "FRAME_GAP",
];

/// A port setting's value as written.
struct SettingValue {
    int: Option<i64>,
    /// A word, upper-cased (`MODBUS`, `EVEN`).
    word: Option<String>,
    span: Span,
}

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
            if let Some(&prev) = seen.get(&key) {
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
                self.password(e, &mut config);
                continue;
            }
            let Some((port, field)) = self.port_key(e, &key) else {
                continue;
            };
            let value = SettingValue {
                int: match e.value {
                    SystemValue::Integer(v, _) => Some(v),
                    _ => None,
                },
                word: match e.value {
                    SystemValue::Word(w) => {
                        Some(self.text.get(w.range()).unwrap_or("").to_ascii_uppercase())
                    }
                    _ => None,
                },
                span: match &e.value {
                    SystemValue::Integer(_, s) | SystemValue::Word(s) | SystemValue::Str(_, s) => {
                        *s
                    }
                    SystemValue::Error => e.span,
                },
            };
            self.port_setting(&mut config.ports[usize::from(port)], field, &value);
        }
        Some(config)
    }

    /// `PASSWORD = "..."`: 1..16 ASCII characters.
    fn password(&mut self, e: &SystemEntry, config: &mut SystemConfig) {
        match &e.value {
            SystemValue::Str(s, _) if rules::password_allowed(s.as_bytes()) => {
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
    }

    /// `PORTn.FIELD`: a port the target has and a known field.
    fn port_key<'k>(&mut self, e: &SystemEntry, key: &'k str) -> Option<(u8, &'k str)> {
        let Some((port, field)) = key
            .strip_prefix("PORT")
            .and_then(|r| r.split_once('.'))
            .and_then(|(n, f)| Some((n.parse::<u8>().ok()?, f)))
        else {
            let mut all: Vec<String> = PORT_KEYS.iter().map(|k| format!("PORT0.{k}")).collect();
            all.push("PASSWORD".into());
            let hint = crate::suggest::closest(key, all.iter().map(String::as_str))
                .map(|s| Suggestion::new(e.key, s));
            self.report(
                Diagnostic::new(
                    Code::UnknownSystemKey,
                    e.key,
                    format!("unknown system block key `{key}`"),
                )
                .maybe_suggest(hint),
            );
            return None;
        };
        if !PORT_KEYS.contains(&field) {
            let hint = crate::suggest::closest(field, PORT_KEYS)
                .map(|s| Suggestion::new(e.key, format!("PORT{port}.{s}")));
            self.report(
                Diagnostic::new(
                    Code::UnknownSystemKey,
                    e.key,
                    format!("unknown port setting `{field}`"),
                )
                .maybe_suggest(hint),
            );
            return None;
        }
        let ports = self.target.memory.serial_ports;
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
            return None;
        }
        Some((port, field))
    }

    /// One setting of one port, in its range.
    fn port_setting(&mut self, p: &mut PortConfig, field: &str, value: &SettingValue) {
        let bad = |why: &str| Diagnostic::new(Code::SystemValue, value.span, why.to_string());
        let byte_in = |range: std::ops::RangeInclusive<u8>| {
            value
                .int
                .and_then(|v| u8::try_from(v).ok())
                .filter(|v| range.contains(v))
        };
        let word = value.word.as_deref();
        match field {
            "PROTOCOL" => {
                if word != Some("MODBUS") {
                    self.report(bad(
                        "PROTOCOL must be MODBUS (free port is not implemented on EC20/EC30)",
                    ));
                }
            }
            "ADDRESS" => match byte_in(0..=255) {
                Some(v) => p.address = v,
                None => self.report(bad("ADDRESS is the station number 0..255")),
            },
            "BAUD" => match value
                .int
                .and_then(|v| u32::try_from(v).ok())
                .filter(|v| BAUD_RATES.contains(v))
            {
                Some(v) => p.baud = v,
                None => self.report(bad("BAUD must be 9600, 19200, 38400, 57600 or 115200")),
            },
            "DATA_BITS" => {
                if value.int != Some(i64::from(port::DATA_BITS)) {
                    self.report(bad(
                        "DATA_BITS must be 8 (RTU; 7-bit ASCII is not implemented)",
                    ));
                }
            }
            "PARITY" => match word {
                Some("NONE") => p.parity = Parity::None,
                Some("EVEN") => p.parity = Parity::Even,
                Some("ODD") => p.parity = Parity::Odd,
                _ => self.report(bad("PARITY must be NONE, EVEN or ODD")),
            },
            "STOP_BITS" => match byte_in(port::STOP_BITS) {
                Some(v) => p.stop_bits = v,
                None => self.report(bad("STOP_BITS must be 1 or 2")),
            },
            "TIMEOUT" => match byte_in(port::TIMEOUT) {
                Some(v) => p.timeout = v,
                None => self.report(bad("TIMEOUT is 1..255 (x 100 ms)")),
            },
            _ => match byte_in(port::FRAME_GAP) {
                Some(v) => p.frame_gap = v,
                None => self.report(bad("FRAME_GAP is 1..255 (x 1 ms)")),
            },
        }
    }
}
