//! How live values are read in as few STATUS_VAR_READ requests as the protocol allows:
//! one read returns the 4 bytes from the first byte of a packed address, so addresses
//! of one area that fit in the same 4-byte window share one read, and the windows go
//! into requests of as many reads as the PLC's packet size holds. Plain data: this file
//! does not talk to the PLC.

use gutta_catalog::{Address, Width};
use gutta_format::{Operand, PackedOperand};

/// One 4-byte read: the byte it starts at (a byte address of the area).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Window {
    pub start: Address,
}

/// The reads for `addresses`: windows in requests of at most `per_request` reads, and
/// for every address (in the order given) the window that holds it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReadPlan {
    pub requests: Vec<Vec<Window>>,
    /// For each address: (index of its window over all requests, its byte in it).
    pub slots: Vec<(usize, u32)>,
}

/// The packed address STATUS_VAR_READ takes for a window (only SLOT and OFFSET count).
pub fn packed(window: Window) -> u32 {
    PackedOperand::encode(Operand::Value(window.start)).0
}

/// Plan the reads of `addresses` (duplicates are fine: they share a window).
pub fn plan(addresses: &[Address], per_request: usize) -> ReadPlan {
    let mut order: Vec<usize> = (0..addresses.len()).collect();
    order.sort_by_key(|&i| (addresses[i].slot, addresses[i].offset));
    let mut windows: Vec<Window> = Vec::new();
    let mut slots = vec![(0, 0); addresses.len()];
    for i in order {
        let a = addresses[i];
        let end = a.offset + a.width.bytes();
        let fits = windows
            .last()
            .is_some_and(|w| w.start.slot == a.slot && end <= w.start.offset + 4);
        if !fits {
            windows.push(Window {
                start: Address {
                    slot: a.slot,
                    width: Width::Byte,
                    offset: a.offset,
                    bit: 0,
                },
            });
        }
        let w = windows.len() - 1;
        slots[i] = (w, a.offset - windows[w].start.offset);
    }
    let requests = windows
        .chunks(per_request.max(1))
        .map(<[Window]>::to_vec)
        .collect();
    ReadPlan { requests, slots }
}

/// The value of `address` from the 4 bytes of its window, `at` bytes into it (bytes in
/// memory order, little-endian as STATUS_VAR_READ returns them).
pub fn value_in(address: &Address, window: [u8; 4], at: u32) -> u32 {
    let raw = u32::from_le_bytes(window) >> (8 * at.min(3));
    match address.width {
        Width::Bit => (raw >> address.bit) & 1,
        Width::Byte => raw & 0xFF,
        Width::Word => raw & 0xFFFF,
        Width::Dword => raw,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn addr(slot: u8, width: Width, offset: u32, bit: u8) -> Address {
        Address {
            slot,
            width,
            offset,
            bit,
        }
    }

    #[test]
    fn neighbours_share_a_window_and_areas_do_not() {
        let q00 = addr(2, Width::Bit, 0, 0);
        let q07 = addr(2, Width::Bit, 0, 7);
        let qw2 = addr(2, Width::Word, 2, 0);
        let qw3 = addr(2, Width::Word, 3, 0);
        let m0 = addr(3, Width::Bit, 0, 1);
        let plan = plan(&[qw3, q00, m0, q07, qw2], 10);
        assert_eq!(plan.requests.len(), 1);
        let starts: Vec<(u8, u32)> = plan.requests[0]
            .iter()
            .map(|w| (w.start.slot, w.start.offset))
            .collect();
        assert_eq!(starts, [(2, 0), (2, 3), (3, 0)]);
        assert_eq!(plan.slots, [(1, 0), (0, 0), (2, 0), (0, 0), (0, 2)]);
    }

    #[test]
    fn requests_hold_at_most_per_request_windows() {
        let many: Vec<Address> = (0..10).map(|i| addr(3, Width::Dword, 4 * i, 0)).collect();
        let plan = plan(&many, 4);
        let sizes: Vec<usize> = plan.requests.iter().map(Vec::len).collect();
        assert_eq!(sizes, [4, 4, 2]);
        assert_eq!(plan.slots[9], (9, 0));
        assert_eq!(super::plan(&many, 0).requests.len(), 10);
    }

    #[test]
    fn values_come_out_of_their_window() {
        let bytes = [0b1000_0001, 0x34, 0x12, 0xFF];
        assert_eq!(value_in(&addr(2, Width::Bit, 0, 0), bytes, 0), 1);
        assert_eq!(value_in(&addr(2, Width::Bit, 0, 1), bytes, 0), 0);
        assert_eq!(value_in(&addr(2, Width::Bit, 0, 7), bytes, 0), 1);
        assert_eq!(value_in(&addr(2, Width::Word, 1, 0), bytes, 1), 0x1234);
        assert_eq!(value_in(&addr(2, Width::Byte, 3, 0), bytes, 3), 0xFF);
        assert_eq!(
            value_in(&addr(2, Width::Dword, 0, 0), bytes, 0),
            0xFF12_3481
        );
    }
}
