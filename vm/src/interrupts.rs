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
    /// Edge events whose input is a bit inside its area: read from `watched`.
    bit_edges: Vec<Edge>,
    /// The flat-memory bytes holding those bits, each once.
    watched: Vec<usize>,
    /// Other edge events whose input parses (read through `Memory::read`).
    other_edges: Vec<(u32, bool, Address)>,
}

/// An edge event on a bit input.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Edge {
    event: u32,
    /// Rising (else falling).
    rising: bool,
    /// The input's byte (index into `Sources::watched`) and bit mask.
    byte: usize,
    mask: u8,
}

/// Whether an input that was `before` and is `now` makes the edge.
fn is_edge(rising: bool, before: bool, now: bool) -> bool {
    (rising && now && !before) || (!rising && !now && before)
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
            if !rising && !e.kind.eq_ignore_ascii_case("FallingEdge") {
                continue;
            }
            let Some(input) = parse(&e.input) else {
                continue;
            };
            match (input.width == Width::Bit)
                .then(|| memory.index_of(input))
                .flatten()
            {
                Some(at) => {
                    let byte = match sources.watched.iter().position(|&w| w == at) {
                        Some(k) => k,
                        None => {
                            sources.watched.push(at);
                            sources.watched.len() - 1
                        }
                    };
                    sources.bit_edges.push(Edge {
                        event: e.number,
                        rising,
                        byte,
                        mask: 1 << (input.bit & 7),
                    });
                }
                None => sources.other_edges.push((e.number, rising, input)),
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
    /// The watched input bytes at the previous scan (empty before the first).
    last_bytes: Vec<u8>,
    /// The watched input bytes now (a buffer kept between scans).
    now_bytes: Vec<u8>,
    /// Other edge events (by index): their input bit at the previous scan.
    last_input: Vec<Option<bool>>,
}

impl Interrupts {
    /// After MAIN, when no event can occur (nothing attached, nothing pending, no edge
    /// event read through `Memory::read`, the sources known): record the watched input
    /// bytes, as `occurred_events` does then, and return true. Otherwise nothing is done
    /// and `occurred_events` is the way (false). Most scans of most programs: a few
    /// loads and stores instead of the whole call.
    #[inline]
    pub fn idle_scan(&mut self, memory: &Memory) -> bool {
        let Some(sources) = &self.sources else {
            return false;
        };
        if !self.attached.is_empty()
            || !self.pending.is_empty()
            || !self.elapsed.is_empty()
            || !sources.other_edges.is_empty()
            || self.last_bytes.len() != sources.watched.len()
        {
            return false;
        }
        for (last, &at) in self.last_bytes.iter_mut().zip(&sources.watched) {
            *last = memory.bytes.get(at).copied().unwrap_or(0);
        }
        true
    }

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
            last_bytes,
            now_bytes,
            last_input,
        } = self;
        let sources: &Sources =
            sources.get_or_insert_with(|| Arc::new(Sources::of(target, memory)));
        let mut occurred: Vec<u32> = Vec::new();
        if attached.is_empty() {
            // No timed event is attached: none accumulates time.
            if !elapsed.is_empty() {
                elapsed.clear();
            }
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
        // so an ATCH later sees the right previous value: the watched bytes are kept
        // whole, and compared bit by bit only when one changed and an event is attached.
        if attached.is_empty() && last_bytes.len() == sources.watched.len() {
            // Nothing attached (most scans of most programs): only record the bytes.
            for (last, &at) in last_bytes.iter_mut().zip(&sources.watched) {
                *last = memory.bytes.get(at).copied().unwrap_or(0);
            }
        } else {
            now_bytes.clear();
            now_bytes.extend(
                sources
                    .watched
                    .iter()
                    .map(|&at| memory.bytes.get(at).copied().unwrap_or(0)),
            );
            if last_bytes.len() == now_bytes.len()
                && last_bytes != now_bytes
                && !attached.is_empty()
            {
                for e in &sources.bit_edges {
                    let before = last_bytes[e.byte] & e.mask != 0;
                    let now = now_bytes[e.byte] & e.mask != 0;
                    if is_edge(e.rising, before, now) && attached.contains_key(&e.event) {
                        occurred.push(e.event);
                    }
                }
            }
            std::mem::swap(last_bytes, now_bytes);
        }
        last_input.resize(sources.other_edges.len(), None);
        for (&(event, rising, input), last) in sources.other_edges.iter().zip(last_input.iter_mut())
        {
            let now = memory.read(input).unwrap_or(0) == 1;
            if let Some(before) = last.replace(now) {
                if is_edge(rising, before, now) && attached.contains_key(&event) {
                    occurred.push(event);
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
