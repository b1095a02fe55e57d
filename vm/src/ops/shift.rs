//! Shifts and rotates (SRx, SLx, RRx, RLx, SHRB).

use super::Handler;

pub fn lookup(_mnemonic: &str) -> Option<Handler> {
    None
}
