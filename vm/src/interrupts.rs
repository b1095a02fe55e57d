//! Interrupt state and event detection (docs/vm.md, "Interrupts"): the global enable,
//! attachments, timed-event clocks, pending occurrences and edge-event inputs. Which
//! routines run after MAIN is decided here; running them is the engine's.

use std::collections::{BTreeMap, BTreeSet};
use std::sync::Arc;

use gutta_catalog::{Address, Target, Width};

use crate::memory::Memory;

/// A target's timed and edge events with their addresses parsed, in the target's order
/// (parsed once, not at every scan).
#[derive(Debug, Default, Clone, PartialEq, Eq)]
struct Sources {
    /// Timed events: number and period variable (None: the period does not parse).
    timed: Vec<(u32, Option<Address>)>,
    /// Edge events whose input parses, in the target's order.
    edges: Vec<Edge>,
}

/// An edge event.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Edge {
    event: u32,
    /// Rising (else falling).
    rising: bool,
    input: Address,
    /// A bit input inside its area: its byte in the flat memory and its mask.
    bit: Option<(usize, u8)>,
}

impl Edge {
    /// The input is on (a bit read straight from its byte).
    fn input_on(&self, memory: &Memory) -> bool {
        match self.bit {
            Some((at, mask)) => memory.bytes.get(at).is_some_and(|b| b & mask != 0),
            None => memory.read(self.input).unwrap_or(0) == 1,
        }
    }
}

impl Sources {
    fn of(target: &Target, memory: &Memory) -> Sources {
        let mut sources = Sources::default();
        for e in &target.memory.events {
            let parse = |text: &Option<String>| {
                text.as_ref()
                    .and_then(|t| target.memory.parse_address(t).ok())
            };
            if e.kind.eq_ignore_ascii_case("Timed") {
                sources.timed.push((e.number, parse(&e.period)));
                continue;
            }
            let rising = e.kind.eq_ignore_ascii_case("RisingEdge");
            if rising || e.kind.eq_ignore_ascii_case("FallingEdge") {
                if let Some(input) = parse(&e.input) {
                    let bit = (input.width == Width::Bit)
                        .then(|| memory.index_of(input))
                        .flatten()
                        .map(|at| (at, 1u8 << (input.bit & 7)));
                    sources.edges.push(Edge {
                        event: e.number,
                        rising,
                        input,
                        bit,
                    });
                }
            }
        }
        sources
    }
}

/// Interrupt state.
#[derive(Debug, Default, Clone, PartialEq, Eq)]
pub(crate) struct Interrupts {
    /// ENI/DISI; off when the PLC enters RUN.
    pub enabled: bool,
    /// Event number -> the page of its interrupt routine.
    pub attached: BTreeMap<u32, u8>,
    /// Timed events: milliseconds accumulated towards the next occurrence.
    elapsed: BTreeMap<u32, u32>,
    /// Events that occurred while interrupts were disabled (one kept per event).
    pub pending: BTreeSet<u32>,
    /// The target's events, parsed at the first scan after a reset.
    sources: Option<Arc<Sources>>,
    /// Edge events (by index in `sources.edges`): their input bit at the previous scan.
    last_input: Vec<Option<bool>>,
}

impl Interrupts {
    /// After MAIN: advance the timed events by the scan's virtual time, compare the
    /// edge events' inputs, and return the events whose routines run now, in order
    /// (pending ones first); while interrupts are disabled, one occurrence per event is
    /// kept pending and none run.
    pub fn occurred_events(&mut self, target: &Target, memory: &Memory, scan_ms: u32) -> Vec<u32> {
        let Interrupts {
            enabled,
            attached,
            elapsed,
            pending,
            sources,
            last_input,
        } = self;
        let sources: &Sources =
            sources.get_or_insert_with(|| Arc::new(Sources::of(target, memory)));
        let mut occurred: Vec<u32> = Vec::new();
        if attached.is_empty() {
            // No timed event is attached: none accumulates time.
            elapsed.clear();
        } else {
            for &(event, period) in &sources.timed {
                if !attached.contains_key(&event) {
                    elapsed.remove(&event);
                    continue;
                }
                let Some(addr) = period else {
                    continue;
                };
                let period_ms = memory.read(addr).unwrap_or(0);
                if period_ms == 0 {
                    continue;
                }
                let acc = elapsed.entry(event).or_insert(0);
                *acc += scan_ms;
                while *acc >= period_ms {
                    *acc -= period_ms;
                    occurred.push(event);
                }
            }
        }
        // Edge events: the input bit now against the previous scan (the first scan only
        // records it, so entering RUN raises no edge). Recorded whether attached or not,
        // so an ATCH later sees the right previous value.
        last_input.resize(sources.edges.len(), None);
        for (edge, last) in sources.edges.iter().zip(last_input.iter_mut()) {
            let now = edge.input_on(memory);
            if let Some(before) = last.replace(now) {
                let rising = edge.rising;
                if ((rising && now && !before) || (!rising && !now && before))
                    && attached.contains_key(&edge.event)
                {
                    occurred.push(edge.event);
                }
            }
        }
        if occurred.is_empty() && pending.is_empty() {
            return occurred;
        }
        occurred.sort_unstable();
        if !*enabled {
            pending.extend(occurred);
            return Vec::new();
        }
        let mut queue: Vec<u32> = std::mem::take(pending).into_iter().collect();
        queue.extend(occurred);
        queue
    }
}
