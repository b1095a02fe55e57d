//! How variables are read in as few requests as the protocol allows, and the one width
//! mask of a value read. STATUS_VAR_READ (and STATUS_VAR_FORCE_READ) answer the 4 bytes
//! from the first byte of each packed address, so variables that lie within 4 bytes of
//! one another share one address, a window (`I0.0` to `I3.7` are one, `MW10` and `MW12`
//! another); the windows go into requests of as many reads as the PLC's ExchPackSize
//! holds, usually one. Plans and unpacks; sends nothing.

use gutta_catalog::{Address, Width};
use gutta_format::{Operand, PackedOperand};

/// Where each variable's bytes are: the windows to read and, per variable, its window
/// and byte position in it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReadPlan {
    /// The first byte of each 4-byte window (slot and offset; read as a DWORD).
    windows: Vec<Address>,
    /// For each variable in the caller's order: (window index, byte offset in it).
    places: Vec<(usize, usize)>,
    variables: Vec<Address>,
}

impl ReadPlan {
    /// Plan the reads of `variables` (duplicates are fine: they share a window).
    pub fn new(variables: &[Address]) -> ReadPlan {
        let mut order: Vec<usize> = (0..variables.len()).collect();
        order.sort_by_key(|&i| {
            let a = variables[i];
            (a.slot, a.offset, a.width.bytes())
        });
        let mut windows: Vec<Address> = Vec::new();
        let mut places = vec![(0, 0); variables.len()];
        for i in order {
            let a = variables[i];
            let end = a.offset + a.width.bytes();
            let fits = windows
                .last()
                .is_some_and(|w| w.slot == a.slot && a.offset >= w.offset && end <= w.offset + 4);
            if !fits {
                windows.push(Address {
                    slot: a.slot,
                    width: Width::Dword,
                    offset: a.offset,
                    bit: 0,
                });
            }
            let w = windows.len() - 1;
            places[i] = (w, (a.offset - windows[w].offset) as usize);
        }
        ReadPlan {
            windows,
            places,
            variables: variables.to_vec(),
        }
    }

    /// The windows to read, in request order.
    pub fn windows(&self) -> &[Address] {
        &self.windows
    }

    /// The packed addresses of the requests: at most `per_request` windows each.
    pub fn requests(&self, per_request: usize) -> Vec<Vec<PackedOperand>> {
        self.windows
            .chunks(per_request.max(1))
            .map(|chunk| chunk.iter().map(|w| packed(*w)).collect())
            .collect()
    }

    /// Each variable's value (cut to its width; a bit 0 or 1) from the windows' bytes,
    /// in the order the plan was made with. A window not read (a short answer) leaves
    /// its variables out.
    pub fn values(&self, windows: &[[u8; 4]]) -> Vec<u32> {
        self.variables
            .iter()
            .zip(&self.places)
            .filter_map(|(a, &(w, at))| {
                let bytes = windows.get(w)?.get(at..)?;
                let mut le = [0u8; 4];
                le[..bytes.len()].copy_from_slice(bytes);
                Some(masked(a, u32::from_le_bytes(le)))
            })
            .collect()
    }
}

/// The packed address of a variable (STATUS_VAR_WRITE and the force functions use its
/// width and bit; a read only its slot and offset).
pub fn packed(address: Address) -> PackedOperand {
    PackedOperand::encode(Operand::Value(address))
}

/// A variable's value from the 4 bytes (little-endian) that start at its first byte:
/// its bit (0 or 1), or its byte, word or double word.
pub fn masked(address: &Address, raw: u32) -> u32 {
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
    use gutta_catalog::stdlib;

    fn addr(slot: u8, width: Width, offset: u32, bit: u8) -> Address {
        Address {
            slot,
            width,
            offset,
            bit,
        }
    }

    #[test]
    fn near_variables_share_a_window_and_unpack_to_their_values() {
        let target = stdlib::shared(stdlib::DEFAULT).expect("target");
        let parse = |t: &str| target.memory.parse_address(t).expect("address");
        let ops: Vec<Address> = ["MW12", "I0.0", "I3.7", "MW10", "I4.0", "MD13", "Q0.1"]
            .iter()
            .map(|t| parse(t))
            .collect();
        let plan = ReadPlan::new(&ops);
        let shown: Vec<String> = plan
            .windows()
            .iter()
            .map(|w| target.memory.format_address(w))
            .collect();
        // I0-I3, I4-, Q0-, MB10-13, MB13-16.
        assert_eq!(shown, ["ID0", "ID4", "QD0", "MD10", "MD13"]);
        let windows = [
            [0x01, 0, 0, 0x80],
            [0x01, 0, 0, 0],
            [0x02, 0, 0, 0],
            [0x34, 0x12, 0x78, 0x56],
            [0xAA, 0xBB, 0xCC, 0xDD],
        ];
        assert_eq!(
            plan.values(&windows),
            [0x5678, 1, 1, 0x1234, 1, 0xDDCCBBAA, 1]
        );
    }

    #[test]
    fn areas_do_not_share_a_window() {
        let q00 = addr(2, Width::Bit, 0, 0);
        let q07 = addr(2, Width::Bit, 0, 7);
        let qw2 = addr(2, Width::Word, 2, 0);
        let qw3 = addr(2, Width::Word, 3, 0);
        let m0 = addr(3, Width::Bit, 0, 1);
        let plan = ReadPlan::new(&[qw3, q00, m0, q07, qw2]);
        let starts: Vec<(u8, u32)> = plan.windows().iter().map(|w| (w.slot, w.offset)).collect();
        assert_eq!(starts, [(2, 0), (2, 3), (3, 0)]);
        assert_eq!(plan.places, [(1, 0), (0, 0), (2, 0), (0, 0), (0, 2)]);
    }

    #[test]
    fn requests_hold_at_most_per_request_windows() {
        let many: Vec<Address> = (0..10).map(|i| addr(3, Width::Dword, 4 * i, 0)).collect();
        let plan = ReadPlan::new(&many);
        let sizes: Vec<usize> = plan.requests(4).iter().map(Vec::len).collect();
        assert_eq!(sizes, [4, 4, 2]);
        assert_eq!(plan.places[9], (9, 0));
        assert_eq!(plan.requests(0).len(), 10);
    }

    #[test]
    fn values_are_cut_to_their_width() {
        let raw = u32::from_le_bytes([0b1000_0001, 0x34, 0x12, 0xFF]);
        assert_eq!(masked(&addr(2, Width::Bit, 0, 0), raw), 1);
        assert_eq!(masked(&addr(2, Width::Bit, 0, 1), raw), 0);
        assert_eq!(masked(&addr(2, Width::Bit, 0, 7), raw), 1);
        assert_eq!(masked(&addr(2, Width::Byte, 0, 0), raw), 0x81);
        assert_eq!(masked(&addr(2, Width::Word, 0, 0), raw), 0x3481);
        assert_eq!(masked(&addr(2, Width::Dword, 0, 0), raw), 0xFF12_3481);
    }
}
