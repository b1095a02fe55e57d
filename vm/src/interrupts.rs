//! Interrupt state and event detection (docs/vm.md, "Interrupts"): the global enable,
//! attachments, timed-event clocks, pending occurrences and edge-event inputs. Which
//! routines run after MAIN is decided here; running them is the engine's.

use std::collections::{BTreeMap, BTreeSet};

use gutta_catalog::Target;

use crate::memory::Memory;

/// Interrupt state.
#[derive(Debug, Default, Clone, PartialEq, Eq)]
pub(crate) struct Interrupts {
    /// ENI/DISI; off when the PLC enters RUN.
    pub enabled: bool,
    /// Event number -> the page of its interrupt routine.
    pub attached: BTreeMap<u32, u8>,
    /// Timed events: milliseconds accumulated towards the next occurrence.
    pub elapsed: BTreeMap<u32, u32>,
    /// Events that occurred while interrupts were disabled (one kept per event).
    pub pending: BTreeSet<u32>,
    /// Edge events: their input bit at the previous scan.
    pub last_input: BTreeMap<u32, bool>,
}

impl Interrupts {
    /// After MAIN: advance the timed events by the scan's virtual time, compare the
    /// edge events' inputs, and return the events whose routines run now, in order
    /// (pending ones first); while interrupts are disabled, one occurrence per event is
    /// kept pending and none run.
    pub fn occurred_events(&mut self, target: &Target, memory: &Memory, scan_ms: u32) -> Vec<u32> {
        let mut occurred: Vec<u32> = Vec::new();
        for e in &target.memory.events {
            if !e.kind.eq_ignore_ascii_case("Timed") {
                continue;
            }
            let event = e.number;
            if !self.attached.contains_key(&event) {
                self.elapsed.remove(&event);
                continue;
            }
            let Some(addr) = e
                .period
                .as_ref()
                .and_then(|p| target.memory.parse_address(p).ok())
            else {
                continue;
            };
            let period_ms = memory.read(addr).unwrap_or(0);
            if period_ms == 0 {
                continue;
            }
            let acc = self.elapsed.entry(event).or_insert(0);
            *acc += scan_ms;
            while *acc >= period_ms {
                *acc -= period_ms;
                occurred.push(event);
            }
        }
        // Edge events: the input bit now against the previous scan (the first scan only
        // records it, so entering RUN raises no edge).
        for e in &target.memory.events {
            let rising = e.kind.eq_ignore_ascii_case("RisingEdge");
            if !rising && !e.kind.eq_ignore_ascii_case("FallingEdge") {
                continue;
            }
            let Some(a) = e
                .input
                .as_ref()
                .and_then(|i| target.memory.parse_address(i).ok())
            else {
                continue;
            };
            let now = memory.read(a).unwrap_or(0) == 1;
            let before = self.last_input.insert(e.number, now);
            if let Some(before) = before {
                if self.attached.contains_key(&e.number)
                    && ((rising && now && !before) || (!rising && !now && before))
                {
                    occurred.push(e.number);
                }
            }
        }
        occurred.sort_unstable();
        if !self.enabled {
            self.pending.extend(occurred);
            return Vec::new();
        }
        let mut queue: Vec<u32> = std::mem::take(&mut self.pending).into_iter().collect();
        queue.extend(occurred);
        queue
    }
}
