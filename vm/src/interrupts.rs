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
    /// The watched bytes that hold an attached edge event's input, each once: a scan
    /// compares each with its previous value under the masks of its rising and
    /// falling events, and looks at `edges` only when one of them may have occurred.
    edge_bytes: Vec<EdgeByte>,
    /// Nothing above: a scan only records the watched bytes.
    quiet: bool,
}

/// A watched byte with attached edge events on it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct EdgeByte {
    /// Index into `Sources::watched` (and `Interrupts::last_bytes`), and its flat index.
    byte: usize,
    at: usize,
    /// The bits of its attached rising and falling edge events.
    rising: u8,
    falling: u8,
}

/// The events below this number have their routine in a table (`Interrupts::pages`),
/// looked up at every routine start; ATCH's event is a byte on every target.
const PAGED_EVENTS: usize = 256;

/// Interrupt state.
#[derive(Debug, Default, Clone, PartialEq, Eq)]
pub(crate) struct Interrupts {
    /// Event number -> the page of its interrupt routine (`attach`, `detach`).
    attached: BTreeMap<u32, u8>,
    /// The same for the events below `PAGED_EVENTS`, indexed by event (as long as the
    /// highest attached one): what a routine start looks up.
    pages: Vec<Option<u8>>,
    /// Events that occurred while interrupts were disabled (one kept per event).
    pub pending: BTreeSet<u32>,
    /// The target's events, parsed at the first scan after a reset.
    sources: Option<Arc<Sources>>,
    /// `plan` no longer follows `attached` (or the sources are new).
    stale: bool,
    /// The sources are known, the plan is current, the watched bytes are recorded and
    /// no edge event is read through `Memory::read`: `after_main`'s own way is open.
    ready: bool,
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
        if let Some(k) = usize::try_from(event).ok().filter(|&k| k < PAGED_EVENTS) {
            if self.pages.len() <= k {
                self.pages.resize(k + 1, None);
            }
            self.pages[k] = Some(page);
        }
        if self.attached.insert(event, page).is_none() {
            self.stale = true;
            self.ready = false;
        }
    }

    /// DTCH: event `event` runs nothing any more (its pending occurrence is the
    /// caller's to drop).
    pub fn detach(&mut self, event: u32) {
        if let Some(slot) = self.pages.get_mut(event as usize) {
            *slot = None;
        }
        if self.attached.remove(&event).is_some() {
            self.stale = true;
            self.ready = false;
        }
    }

    /// The page of the routine `event` runs, if attached.
    #[inline]
    pub fn routine(&self, event: u32) -> Option<u8> {
        match self.pages.get(event as usize) {
            Some(&page) => page,
            None => self.attached.get(&event).copied(),
        }
    }

    /// After MAIN: advance the attached timed events by the scan's virtual time, compare
    /// the edge events' inputs with the previous scan's, and put the events whose
    /// routines run now into `queue` (empty), in order (pending ones first); while
    /// interrupts are disabled, one occurrence per event is kept pending and none run.
    /// True when `queue` has events.
    ///
    /// Most scans: with `ready`, nothing attached that can occur and nothing pending,
    /// inline, the watched bytes recorded and nothing else; with events attached, out
    /// of line (`attached_scan`) each timed one adds the scan's time and compares it
    /// with its period, each watched byte with an attached edge event is compared with
    /// its previous value under two masks, and only an occurrence or a pending event
    /// goes further (`release`). The first scan after a reset or an attachment change,
    /// and targets with edge events read through `Memory::read`, take
    /// `occurred_events`.
    #[inline(always)]
    pub fn after_main(
        &mut self,
        target: &Target,
        memory: &Memory,
        scan_ms: u32,
        queue: &mut VecDeque<u32>,
    ) -> bool {
        if self.ready && self.plan.quiet && self.pending.is_empty() {
            if let Some(sources) = &self.sources {
                for (last, &at) in self.last_bytes.iter_mut().zip(&sources.watched) {
                    *last = memory.bytes.get(at).copied().unwrap_or(0);
                }
            }
            return false;
        }
        self.attached_scan(target, memory, scan_ms, queue)
    }

    /// `after_main` with events attached or pending, or not `ready`.
    #[inline(never)]
    fn attached_scan(
        &mut self,
        target: &Target,
        memory: &Memory,
        scan_ms: u32,
        queue: &mut VecDeque<u32>,
    ) -> bool {
        let Interrupts {
            pending,
            sources: Some(sources),
            ready: true,
            plan,
            elapsed,
            last_bytes,
            occurred,
            ..
        } = self
        else {
            return self.occurred_events(target, memory, scan_ms, queue);
        };
        let bytes = &memory.bytes;
        let byte = |at: usize| bytes.get(at).copied().unwrap_or(0);
        for &(event, acc, period) in &plan.timed {
            advance(
                event,
                elapsed.get_mut(acc),
                period.read(bytes),
                scan_ms,
                occurred,
            );
        }
        for eb in &plan.edge_bytes {
            let now = byte(eb.at);
            let before = last_bytes.get(eb.byte).copied().unwrap_or(0);
            if (now ^ before) & ((now & eb.rising) | (!now & eb.falling)) != 0 {
                edges_of(&plan.edges, eb.byte, before, now, occurred);
            }
        }
        for (last, &at) in last_bytes.iter_mut().zip(&sources.watched) {
            *last = byte(at);
        }
        if occurred.is_empty() && pending.is_empty() {
            return false;
        }
        self.release(memory, queue)
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
        let mut edge_bytes: Vec<EdgeByte> = Vec::new();
        for e in &edges {
            let k = match edge_bytes.iter().position(|b| b.byte == e.byte) {
                Some(k) => k,
                None => {
                    edge_bytes.push(EdgeByte {
                        byte: e.byte,
                        at: e.at,
                        rising: 0,
                        falling: 0,
                    });
                    edge_bytes.len() - 1
                }
            };
            if e.rising {
                edge_bytes[k].rising |= e.mask;
            } else {
                edge_bytes[k].falling |= e.mask;
            }
        }
        self.plan = Plan {
            quiet: timed.is_empty() && edge_bytes.is_empty(),
            timed,
            edges,
            edge_bytes,
        };
        self.stale = false;
    }

    /// `after_main` in general: the sources parsed if new, the plan rebuilt if stale,
    /// the first scan's watched bytes recorded, edge events read through
    /// `Memory::read`.
    #[inline(never)]
    fn occurred_events(
        &mut self,
        target: &Target,
        memory: &Memory,
        scan_ms: u32,
        queue: &mut VecDeque<u32>,
    ) -> bool {
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
            ready,
            elapsed,
            last_bytes,
            last_input,
            occurred,
            ..
        } = self
        else {
            return false;
        };
        let sources: &Sources = sources;
        occurred.clear();
        for &(event, acc, period) in &plan.timed {
            advance(
                event,
                elapsed.get_mut(acc),
                period.read(bytes),
                scan_ms,
                occurred,
            );
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
        // From the next scan on, `attached_scan` does this (the plan current, the
        // watched bytes recorded) unless edge events are read through `Memory::read`.
        *ready = sources.other_edges.is_empty();
        if occurred.is_empty() && pending.is_empty() {
            return false;
        }
        self.release(memory, queue)
    }

    /// Events occurred or pending: into `queue` in order (pending ones first, then this
    /// scan's by number) when interrupts are enabled, else kept pending (one occurrence
    /// per event). True when `queue` has events. `occurred` is left empty.
    #[inline(never)]
    fn release(&mut self, memory: &Memory, queue: &mut VecDeque<u32>) -> bool {
        let Interrupts {
            pending, occurred, ..
        } = self;
        if occurred.len() > 1 {
            occurred.sort_unstable();
        }
        // ENI/DISI: the enable byte in the flat memory (off when the PLC enters RUN).
        if !memory.interrupts_enabled() {
            pending.extend(occurred.drain(..));
            return false;
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
        !queue.is_empty()
    }
}

/// A timed event's scan: `acc` (its accumulator) adds `scan_ms` and each whole
/// `period_ms` in it is an occurrence; a period of 0 stops the event.
#[inline]
fn advance(
    event: u32,
    acc: Option<&mut u32>,
    period_ms: u32,
    scan_ms: u32,
    occurred: &mut Vec<u32>,
) {
    let Some(acc) = acc.filter(|_| period_ms != 0) else {
        return;
    };
    *acc += scan_ms;
    while *acc >= period_ms {
        *acc -= period_ms;
        occurred.push(event);
    }
}

/// The attached edge events on watched byte `byte` that occurred between `before` and
/// `now` (out of line: most scans see no change).
#[inline(never)]
fn edges_of(edges: &[Edge], byte: usize, before: u8, now: u8, occurred: &mut Vec<u32>) {
    for e in edges.iter().filter(|e| e.byte == byte) {
        if is_edge(e.rising, before & e.mask != 0, now & e.mask != 0) {
            occurred.push(e.event);
        }
    }
}
