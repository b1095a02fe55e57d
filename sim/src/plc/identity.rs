//! Login and identity: PLC_CLEAR, PLC_ATTACH (with the password lockout), PLC_DETACH,
//! GET_PLC_NAME, GET_PLC_INFOR. Only `Plc::dispatch` calls these, after the registry's
//! conditions; they do not check the login themselves.

use super::window::{ConnectionId, DownloadWindow};
use super::{Plc, Refusal, FACTORY_PASSWORD};

/// Login failures and the lockout after them.
#[derive(Debug, Clone, Default)]
pub(super) struct LoginGuard {
    failures: u32,
    locked_until_ms: u64,
}

impl LoginGuard {
    const FREE_FAILURES: u32 = 2;
    const MAX_LOCKOUT_MS: u64 = 60_000;

    fn fail(&mut self, now_ms: u64) {
        self.failures += 1;
        if self.failures > Self::FREE_FAILURES {
            let doublings = (self.failures - Self::FREE_FAILURES - 1).min(6);
            let lockout = (1000u64 << doublings).min(Self::MAX_LOCKOUT_MS);
            self.locked_until_ms = now_ms + lockout;
        }
    }
}

impl Plc {
    /// PLC_CLEAR: erase the pages and the password, stop, and open a download window
    /// owned by `from` (only it writes pages until its STATUS_RESET).
    pub(super) fn clear(&mut self, from: ConnectionId, now_ms: u64) {
        self.pages.clear();
        self.password = FACTORY_PASSWORD;
        // The station and the serial lines revert to their defaults (UM4001).
        self.active_ports.clear();
        self.window = Some(DownloadWindow::open(from, now_ms));
        self.image_error = false;
        self.flash_fault = None;
        self.vm.set_running(false);
    }

    /// PLC_ATTACH: log in, unless locked out or the password is wrong.
    pub(super) fn attach(&mut self, password: [u8; 16], now_ms: u64) -> Result<(), Refusal> {
        if now_ms < self.guard.locked_until_ms {
            return Err(Refusal::LockedOut {
                until_ms: self.guard.locked_until_ms,
            });
        }
        if password != self.password {
            self.guard.fail(now_ms);
            return Err(Refusal::WrongPassword);
        }
        self.guard = LoginGuard::default();
        self.attached = true;
        self.vm.set_attached(true);
        Ok(())
    }

    /// PLC_DETACH: log out.
    pub(super) fn detach(&mut self) {
        self.attached = false;
        self.vm.set_attached(false);
    }

    /// GET_PLC_NAME: the PLC type's name.
    pub(super) fn name(&self) -> [u8; 16] {
        padded(self.target.name())
    }

    /// GET_PLC_INFOR: the PLC type's information text.
    pub(super) fn information(&self) -> [u8; 64] {
        padded(&self.target.plc.information)
    }
}

/// A name or information text as the fixed-size answer field: cut to N bytes, or
/// padded with zeros (which also terminates it).
fn padded<const N: usize>(text: &str) -> [u8; N] {
    let mut out = [0u8; N];
    let bytes = text.as_bytes();
    let n = bytes.len().min(N);
    out[..n].copy_from_slice(&bytes[..n]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lockout_doubles_after_two_free_failures() {
        let mut g = LoginGuard::default();
        g.fail(0);
        g.fail(0);
        assert_eq!(g.locked_until_ms, 0);
        g.fail(10);
        assert_eq!(g.locked_until_ms, 1010);
        g.fail(2000);
        assert_eq!(g.locked_until_ms, 4000);
        for _ in 0..20 {
            g.fail(5000);
        }
        assert_eq!(g.locked_until_ms, 65_000);
    }
}
