//! Live values (opt-in, docs/editors.md): the values a PLC holds for the operands the
//! editor shows, for `textDocument/inlineValue` and the inlay hints. The setting
//! `gutta.liveValues` (initializationOptions `{"liveValues": true}`, or
//! workspace/didChangeConfiguration `{"gutta": {"liveValues": true}}`, or the command
//! `gutta.toggleLiveValues`) turns it on; a document of a project with `[connection]`
//! then gets a poller (poller.rs) reading the operands of the range the client last
//! asked about. This file decides which operands and what to show; it knows no
//! positions (the handler converts) and never waits for the PLC.

mod poller;

use std::collections::BTreeMap;
use std::ops::Range;
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use crossbeam_channel::Sender;
use gutta_analysis::inlay::operand_addresses;
use gutta_catalog::{Address, Width};
use gutta_compiler::source::{PartKind, Span};
use gutta_compiler::CheckedFile;
use lsp_server::{Message, Notification, Request, RequestId};
use serde_json::Value;

pub use poller::{Event, LinkSettings, PASSWORD_ENV, PERIOD};
use poller::{Notify, Poller};

/// The command that turns live values on and off.
pub const TOGGLE_COMMAND: &str = "gutta.toggleLiveValues";

/// Sends a message to the client from any thread (a clone of the connection's sender).
pub type Outbox = Arc<dyn Fn(Message) + Send + Sync>;

/// An operand whose value can be shown: where it is, how it is written, what it reads.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LiveOperand {
    /// Byte span in the program's joined text.
    pub span: Span,
    /// The operand as written: `Lamp`, `M0.0`.
    pub label: String,
    pub address: Address,
}

/// Which refresh requests the client accepts (its workspace capabilities).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Refresh {
    pub inlay_hints: bool,
    pub inline_values: bool,
}

impl Refresh {
    /// From the client's capabilities in `initialize`.
    pub fn from_capabilities(c: &lsp_types::ClientCapabilities) -> Refresh {
        let w = c.workspace.as_ref();
        Refresh {
            inlay_hints: w
                .and_then(|w| w.inlay_hint.as_ref())
                .and_then(|i| i.refresh_support)
                .unwrap_or(false),
            inline_values: w
                .and_then(|w| w.inline_value.as_ref())
                .and_then(|i| i.refresh_support)
                .unwrap_or(false),
        }
    }
}

/// `{"liveValues": b}` (initializationOptions) or `{"gutta": {"liveValues": b}}`
/// (didChangeConfiguration's settings); `None` when the setting is not there.
pub fn setting(value: &Value) -> Option<bool> {
    value
        .get("liveValues")
        .or_else(|| value.get("gutta").and_then(|g| g.get("liveValues")))
        .and_then(Value::as_bool)
}

/// The live-values state of the server: on or off, and one poller per PLC.
pub struct Live {
    enabled: bool,
    refresh: Refresh,
    outbox: Outbox,
    /// By project manifest.
    pollers: BTreeMap<PathBuf, Poller>,
    next_request: Arc<AtomicU64>,
}

impl std::fmt::Debug for Live {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Live")
            .field("enabled", &self.enabled)
            .field("refresh", &self.refresh)
            .field("pollers", &self.pollers.keys().collect::<Vec<_>>())
            .finish()
    }
}

impl Live {
    pub fn new(enabled: bool, refresh: Refresh, outbox: Outbox) -> Live {
        Live {
            enabled,
            refresh,
            outbox,
            pollers: BTreeMap::new(),
            next_request: Arc::new(AtomicU64::new(0)),
        }
    }

    /// As `initialize` asks: the setting from initializationOptions, the refresh
    /// requests the client supports, messages through `sender`.
    pub fn from_init(init: &lsp_types::InitializeParams, sender: Sender<Message>) -> Live {
        let enabled = init
            .initialization_options
            .as_ref()
            .and_then(setting)
            .unwrap_or(false);
        let outbox: Outbox = Arc::new(move |m| {
            // A closed channel means the client is gone; the server's loop ends then.
            let _ = sender.send(m);
        });
        Live::new(
            enabled,
            Refresh::from_capabilities(&init.capabilities),
            outbox,
        )
    }

    pub fn enabled(&self) -> bool {
        self.enabled
    }

    /// Turn live values on or off; off stops every poller. The client is asked to
    /// refresh what it shows when the state changed.
    pub fn set_enabled(&mut self, on: bool) {
        if on == self.enabled {
            return;
        }
        self.enabled = on;
        if !on {
            self.pollers.clear();
        }
        self.notifier()(Event::Changed);
    }

    /// The live values for the operands of the networks `range` touches (bytes of the
    /// joined text of `checked`), in a program of the project `manifest` whose PLC
    /// `settings` names. Starts the project's poller on first use and makes it read
    /// these operands from now on; never waits for it (values not read yet are `None`).
    /// Empty when live values are off or the project has no PLC.
    pub fn values(
        &mut self,
        manifest: &std::path::Path,
        settings: Option<LinkSettings>,
        checked: &CheckedFile,
        range: Range<usize>,
    ) -> Vec<(LiveOperand, Option<u32>)> {
        if !self.enabled {
            return Vec::new();
        }
        let Some(settings) = settings else {
            self.pollers.remove(manifest);
            return Vec::new();
        };
        if self
            .pollers
            .get(manifest)
            .is_some_and(|p| p.settings != settings)
        {
            self.pollers.remove(manifest);
        }
        let notify = self.notifier();
        let poller = self
            .pollers
            .entry(manifest.to_path_buf())
            .or_insert_with(|| Poller::start(settings, notify));
        let operands = operands_in(checked, networks_around(checked, range));
        let mut wanted: Vec<Address> = operands.iter().map(|o| o.address).collect();
        wanted.sort();
        wanted.dedup();
        poller.want(wanted);
        let values = poller.values();
        operands
            .into_iter()
            .map(|o| {
                let v = values.get(&o.address).copied();
                (o, v)
            })
            .collect()
    }

    /// The poller's events as LSP messages: refresh requests the client supports, one
    /// warning per outage.
    fn notifier(&self) -> Notify {
        let outbox = Arc::clone(&self.outbox);
        let refresh = self.refresh;
        let next = Arc::clone(&self.next_request);
        Arc::new(move |event| match event {
            Event::Changed => {
                let methods = [
                    (refresh.inlay_hints, "workspace/inlayHint/refresh"),
                    (refresh.inline_values, "workspace/inlineValue/refresh"),
                ];
                for (_, method) in methods.iter().filter(|(on, _)| *on) {
                    let n = next.fetch_add(1, Ordering::Relaxed);
                    let id = RequestId::from(format!("gutta-live-{n}"));
                    outbox(Message::Request(Request::new(id, method.to_string(), ())));
                }
            }
            Event::Unreachable(text) => {
                let params = lsp_types::ShowMessageParams {
                    typ: lsp_types::MessageType::WARNING,
                    message: text,
                };
                outbox(Message::Notification(Notification::new(
                    "window/showMessage".into(),
                    params,
                )));
            }
        })
    }
}

/// `range` grown to the whole networks it touches (a network runs from its NETWORK
/// line to the next one, or to its block's end): the editor shows part of a network,
/// the poller reads all of it.
pub fn networks_around(checked: &CheckedFile, range: Range<usize>) -> Range<usize> {
    let (mut start, mut end) = (range.start, range.end);
    for unit in &checked.ast.units {
        let unit_end = unit
            .end
            .map_or(checked.file.text.len(), |e| e.start as usize);
        let starts: Vec<usize> = unit
            .networks
            .iter()
            .map(|n| n.span.start as usize)
            .collect();
        for (i, &from) in starts.iter().enumerate() {
            let to = starts.get(i + 1).copied().unwrap_or(unit_end).max(from);
            if from < range.end.max(range.start + 1) && range.start < to {
                start = start.min(from);
                end = end.max(to);
            }
        }
    }
    start..end
}

/// The operands of `checked`'s source files within `range` (the networks the poller
/// reads): direct addresses and uses of symbols, in text order, as the inlay hints find
/// them (`analysis::inlay::operand_addresses`, the one home of that question).
pub fn operands_in(checked: &CheckedFile, range: Range<usize>) -> Vec<LiveOperand> {
    let text = &checked.file.text;
    let parts = checked.file.parts();
    let in_source = |s: &Span| {
        parts
            .get(checked.file.part_index(s.start as usize))
            .is_none_or(|p| p.kind == PartKind::Source)
    };
    operand_addresses(checked, Span::new(range.start, range.end))
        .into_iter()
        .filter(|(s, _)| in_source(s))
        .map(|(span, address)| LiveOperand {
            span,
            label: text.get(span.range()).unwrap_or("").to_string(),
            address,
        })
        .collect()
}

/// A value as the editor shows it: bits 0/1, bytes unsigned, words and double words
/// signed (INT, DINT); `?` when there is none (not read yet, or the PLC does not answer).
pub fn show(address: &Address, value: Option<u32>) -> String {
    let Some(v) = value else {
        return "?".into();
    };
    match address.width {
        Width::Bit | Width::Byte => v.to_string(),
        Width::Word => (v as u16 as i16).to_string(),
        Width::Dword => (v as i32).to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use gutta_compiler::source::SourceFile;

    const BLINK: &str = "PLC_TYPE CPU-EC20\nSYMBOLS\n  Lamp : Q0.0\n  Speed : MW20\nEND_SYMBOLS\n\
        ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD     SM0.5\n=      Lamp\n\
        NETWORK 2\nLD     SM0.0\nMOVW   Speed, MW22\nEND_ORGANIZATION_BLOCK\n";

    fn checked() -> CheckedFile {
        gutta_compiler::check_source(SourceFile::new("blink.lad", BLINK), None)
    }

    #[test]
    fn operands_are_addresses_and_symbol_uses_in_the_range() {
        let c = checked();
        assert!(!c.has_errors(), "{:?}", c.diagnostics());
        let all: Vec<String> = operands_in(&c, 0..BLINK.len())
            .iter()
            .map(|o| format!("{} {:?}", o.label, o.address.width))
            .collect();
        assert_eq!(
            all,
            [
                "SM0.5 Bit",
                "Lamp Bit",
                "SM0.0 Bit",
                "Speed Word",
                "MW22 Word"
            ]
        );
        let network_2 = BLINK.find("NETWORK 2").unwrap_or(0);
        let tail: Vec<String> = operands_in(&c, network_2..BLINK.len())
            .into_iter()
            .map(|o| o.label)
            .collect();
        assert_eq!(tail, ["SM0.0", "Speed", "MW22"]);
        assert!(operands_in(&c, 0..10).is_empty());
    }

    #[test]
    fn a_range_grows_to_the_networks_it_touches() {
        let c = checked();
        let ld = BLINK.find("LD     SM0.0").unwrap_or(0);
        let grown = networks_around(&c, ld..ld + 2);
        let labels: Vec<String> = operands_in(&c, grown)
            .into_iter()
            .map(|o| o.label)
            .collect();
        assert_eq!(labels, ["SM0.0", "Speed", "MW22"]);
        assert_eq!(networks_around(&c, 0..10), 0..10, "no network there");
    }

    #[test]
    fn symbol_operands_carry_the_symbols_address() {
        let c = checked();
        let lamp = operands_in(&c, 0..BLINK.len())
            .into_iter()
            .find(|o| o.label == "Lamp")
            .map(|o| c.target.memory.format_address(&o.address));
        assert_eq!(lamp.as_deref(), Some("Q0.0"));
    }

    #[test]
    fn values_show_by_width_and_missing_ones_as_a_question_mark() {
        let a = |width| Address {
            slot: 3,
            width,
            offset: 0,
            bit: 0,
        };
        assert_eq!(show(&a(Width::Bit), Some(1)), "1");
        assert_eq!(show(&a(Width::Byte), Some(200)), "200");
        assert_eq!(show(&a(Width::Word), Some(0xFFFE)), "-2");
        assert_eq!(show(&a(Width::Dword), Some(70000)), "70000");
        assert_eq!(show(&a(Width::Word), None), "?");
    }

    #[test]
    fn the_setting_comes_from_either_shape() {
        assert_eq!(
            setting(&serde_json::json!({"liveValues": true})),
            Some(true)
        );
        assert_eq!(
            setting(&serde_json::json!({"gutta": {"liveValues": false}})),
            Some(false)
        );
        assert_eq!(setting(&serde_json::json!({"gutta": {}})), None);
        assert_eq!(setting(&Value::Null), None);
    }
}
