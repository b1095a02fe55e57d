//! Timers (TON, TOF, TONR) and counters (CTU, CTD, CTUD).

use super::Handler;

pub fn lookup(_mnemonic: &str) -> Option<Handler> {
    None
}
