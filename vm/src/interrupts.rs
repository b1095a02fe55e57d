//! Interrupt state and event detection (docs/vm.md, "Interrupts"): the global enable,
//! attachments, timed-event clocks, pending occurrences and edge-event inputs. Which
//! routines run after MAIN is decided here; running them is the engine's.
//!
//! A scan does only what can happen in it: the attached events' sources are gathered
//! into a plan when the attachments change (an ATCH of an event attached already, to
//! whichever routine, changes nothing), so after MAIN the attached timed events add the scan's time
//! and compare it with their period byte, the attached edge events compare one bit with
//! the previous scan's, and the routines to run go into a queue kept between scans.

use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::sync::Arc;

use gutta_catalog::{Address, Target, Width};

use crate::memory::Memory;

/// A variable at a known place of the flat memory (found once, read at every scan).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Flat {
    at: usize,
    width: Width,
    bit: u8,
}

impl Flat {
    /// Where `a` lies, if inside its area (`Memory::read` fails otherwise).
    fn of(memory: &Memory, a: Address) -> Option<Flat> {
        memory.index_of(a).map(|at| Flat {
            at,
            width: a.width,
            bit: a.bit & 7,
        })
    }

    /// Its value, as `Memory::read` gives it.
    #[inline]
    fn read(self, bytes: &[u8]) -> u32 {
        let b = |k: usize| bytes.get(self.at + k).copied().unwrap_or(0);
        match self.width {
            Width::Bit => u32::from((b(0) >> self.bit) & 1),
            Width::Byte => u32::from(b(0)),
            Width::Word => u32::from(u16::from_le_bytes([b(0), b(1)])),
            Width::Dword => u32::from_le_bytes([b(0), b(1), b(2), b(3)]),
        }
    }
}

/// A timed event of the target.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Timed {
    event: u32,
    /// Its accumulator in `Interrupts::elapsed` (shared by entries of the same number).
    acc: usize,
    /// The period variable (None: it does not parse or lies outside its area, so it
    /// reads as 0 and the event never occurs).
    period: Option<Flat>,
}

/// A target's timed and edge events with their addresses parsed, in the target's order
/// (parsed once, not at every scan).
#[derive(Debug, Default, Clone, PartialEq, Eq)]
struct Sources {
    timed: Vec<Timed>,
    /// How many accumulators the timed events need (one per event number).
    accumulators: usize,
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
    /// The input's byte: index into `Sources::watched`, and its flat index.
    byte: usize,
    at: usize,
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
                let acc = match sources.timed.iter().find(|t| t.event == e.number) {
                    Some(t) => t.acc,
                    None => {
                        sources.accumulators += 1;
                        sources.accumulators - 1
                    }
                };
                sources.timed.push(Timed {
                    event: e.number,
                    acc,
                    period: parse(&e.period).and_then(|a| Flat::of(memory, a)),
                });
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
                        at,
                        mask: 1 << (input.bit & 7),
                    });
                }
                None => sources.other_edges.push((e.number, rising, input)),
            }
        }
        sources
    }
}

/// What the scan looks at after MAIN, from the sources and the attachments (rebuilt
/// when an attachment changes).
#[derive(Debug, Default, Clone, PartialEq, Eq)]
struct Plan {
    /// The attached timed events with a period variable, in the target's order.
    timed: Vec<(u32, usize, Flat)>,
    /// The attached edge events on bits, in the target's order.
    edges: Vec<Edge>,
    /// Nothing to do but record the watched bytes: nothing above, and no edge event
    /// read through `Memory::read` (whose input is recorded whether attached or not).
    quiet: bool,
}

/// Interrupt state.
#[derive(Debug, Default, Clone, PartialEq, Eq)]
pub(crate) struct Interrupts {
    /// Event number -> the page of its interrupt routine (`attach`, `detach`).
    attached: BTreeMap<u32, u8>,
    /// Events that occurred while interrupts were disabled (one kept per event).
    pub pending: BTreeSet<u32>,
    /// The target's events, parsed at the first scan after a reset.
    sources: Option<Arc<Sources>>,
    /// `plan` no longer follows `attached` (or the sources are new).
    stale: bool,
    plan: Plan,
    /// Timed events: milliseconds accumulated towards the next occurrence, per
    /// accumulator (`Timed::acc`); 0 for an event not attached.
    elapsed: Vec<u32>,
    /// The watched input bytes at the previous scan (empty before the first).
    last_bytes: Vec<u8>,
    /// Other edge events (by index): their input bit at the previous scan.
    last_input: Vec<Option<bool>>,
    /// The events of this scan (a buffer kept between scans).
    occurred: Vec<u32>,
}

impl Interrupts {
    /// ATCH: event `event` now runs the routine on page `page` (the plan holds events,
    /// not routines: only a newly attached event changes it).
    pub fn attach(&mut self, event: u32, page: u8) {
        if self.attached.insert(event, page).is_none() {
            self.stale = true;
        }
    }

    /// DTCH: event `event` runs nothing any more (its pending occurrence is the
    /// caller's to drop).
    pub fn detach(&mut self, event: u32) {
        if self.attached.remove(&event).is_some() {
            self.stale = true;
        }
    }

    /// The page of the routine `event` runs, if attached.
    #[inline]
    pub fn routine(&self, event: u32) -> Option<u8> {
        self.attached.get(&event).copied()
    }

    /// After MAIN, when no event can occur in this scan (nothing attached that can
    /// occur, or only timed events none of which is due; nothing pending (a safeguard:
    /// only attached events are pending, and those are in the plan), no edge event, the
    /// sources known and the plan current): advance the attached timed events by the
    /// scan's time and record the watched input bytes, as `occurred_events` does then,
    /// and return true. Otherwise nothing is done and `occurred_events` is the way
    /// (false). Most scans of most programs, a timed interrupt's scans between its
    /// runs too: a few loads and stores, inline.
    #[inline]
    pub fn quiet_scan(&mut self, memory: &Memory, scan_ms: u32) -> bool {
        let Some(watched) = self.sources.as_ref().map(|s| s.watched.len()) else {
            return false;
        };
        if self.stale || !self.pending.is_empty() || self.last_bytes.len() != watched {
            return false;
        }
        if !self.plan.quiet && !self.advance_timed_not_due(memory, scan_ms) {
            return false;
        }
        let Some(sources) = &self.sources else {
            return false;
        };
        for (last, &at) in self.last_bytes.iter_mut().zip(&sources.watched) {
            *last = memory.bytes.get(at).copied().unwrap_or(0);
        }
        true
    }

    /// `quiet_scan` when something is attached: if only timed events are (no edge
    /// event) and none is due in this scan, advance them by `scan_ms` and return true;
    /// otherwise change nothing (false). Timed events are due when their accumulator
    /// reaches their period; entries of one event number share an accumulator, so at
    /// most every entry's time reaches one: none due below that bound, else the whole
    /// check decides. Out of line: `quiet_scan` stays small for the scans with nothing
    /// attached.
    #[inline(never)]
    fn advance_timed_not_due(&mut self, memory: &Memory, scan_ms: u32) -> bool {
        let other_edges = self.sources.as_ref().map_or(0, |s| s.other_edges.len());
        if !self.plan.edges.is_empty() || other_edges != 0 {
            return false;
        }
        let bytes = &memory.bytes;
        let most = u64::from(scan_ms) * self.plan.timed.len() as u64;
        for &(_, acc, period) in &self.plan.timed {
            let period_ms = period.read(bytes);
            let elapsed = self.elapsed.get(acc).copied().unwrap_or(0);
            if period_ms != 0 && u64::from(elapsed) + most >= u64::from(period_ms) {
                return false;
            }
        }
        for &(_, acc, period) in &self.plan.timed {
            if period.read(bytes) != 0 {
                if let Some(elapsed) = self.elapsed.get_mut(acc) {
                    *elapsed += scan_ms;
                }
            }
        }
        true
    }

    /// Gather the plan from the sources and the attachments; the timed events no longer
    /// attached lose their accumulated time.
    fn replan(&mut self, sources: &Sources) {
        let attached = &self.attached;
        self.elapsed.resize(sources.accumulators, 0);
        let mut timed = Vec::new();
        for t in &sources.timed {
            if !attached.contains_key(&t.event) {
                self.elapsed[t.acc] = 0;
            } else if let Some(period) = t.period {
                timed.push((t.event, t.acc, period));
            }
        }
        let edges: Vec<Edge> = sources
            .bit_edges
            .iter()
            .filter(|e| attached.contains_key(&e.event))
            .copied()
            .collect();
        self.plan = Plan {
            quiet: timed.is_empty() && edges.is_empty() && sources.other_edges.is_empty(),
            timed,
            edges,
        };
        self.stale = false;
    }

    /// After MAIN: advance the attached timed events by the scan's virtual time, compare
    /// the edge events' inputs with the previous scan's, and put the events whose
    /// routines run now into `queue` (empty), in order (pending ones first); while
    /// interrupts are disabled, one occurrence per event is kept pending and none run.
    #[inline(never)]
    pub fn occurred_events(
        &mut self,
        target: &Target,
        memory: &Memory,
        scan_ms: u32,
        queue: &mut VecDeque<u32>,
    ) {
        if self.sources.is_none() {
            self.sources = Some(Arc::new(Sources::of(target, memory)));
            self.stale = true;
        }
        if self.stale {
            // Rare (an attachment changed): the shared sources are counted once more
            // while the plan is rebuilt from them.
            if let Some(sources) = self.sources.clone() {
                self.replan(&sources);
            }
        }
        let bytes = &memory.bytes;
        let byte = |at: usize| bytes.get(at).copied().unwrap_or(0);
        let Interrupts {
            attached,
            pending,
            sources: Some(sources),
            plan,
            elapsed,
            last_bytes,
            last_input,
            occurred,
            ..
        } = self
        else {
            return;
        };
        // Borrowed, not counted: no atomic reference count at every scan.
        let sources: &Sources = sources;
        occurred.clear();
        for &(event, acc, period) in &plan.timed {
            let period_ms = period.read(bytes);
            if period_ms == 0 {
                continue;
            }
            let acc = &mut elapsed[acc];
            *acc += scan_ms;
            while *acc >= period_ms {
                *acc -= period_ms;
                occurred.push(event);
            }
        }
        // Edge events: the input bit now against the previous scan (the first scan only
        // records it, so entering RUN raises no edge). Recorded whether attached or not,
        // so an ATCH later sees the right previous value.
        if last_bytes.len() == sources.watched.len() {
            for e in &plan.edges {
                let before = last_bytes[e.byte] & e.mask != 0;
                let now = byte(e.at) & e.mask != 0;
                if is_edge(e.rising, before, now) {
                    occurred.push(e.event);
                }
            }
            for (last, &at) in last_bytes.iter_mut().zip(&sources.watched) {
                *last = byte(at);
            }
        } else {
            last_bytes.clear();
            last_bytes.extend(sources.watched.iter().map(|&at| byte(at)));
        }
        if !sources.other_edges.is_empty() {
            last_input.resize(sources.other_edges.len(), None);
            for (&(event, rising, input), last) in
                sources.other_edges.iter().zip(last_input.iter_mut())
            {
                let now = memory.read(input).unwrap_or(0) == 1;
                if let Some(before) = last.replace(now) {
                    if is_edge(rising, before, now) && attached.contains_key(&event) {
                        occurred.push(event);
                    }
                }
            }
        }
        if occurred.is_empty() && pending.is_empty() {
            return;
        }
        occurred.sort_unstable();
        // ENI/DISI: the enable byte in the flat memory (off when the PLC enters RUN).
        if !memory.interrupts_enabled() {
            pending.extend(occurred.drain(..));
            return;
        }
        if !pending.is_empty() {
            queue.extend(pending.iter().copied());
            pending.clear();
        }
        // One by one: the events of a scan are a few, and a general `extend` sets up
        // more than it moves.
        for &event in occurred.iter() {
            queue.push_back(event);
        }
        occurred.clear();
    }
}
