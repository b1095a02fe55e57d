//! The one read of an update: STATUS_VAR_READ answers the 4 bytes from the first byte of
//! each address, so operands that lie within 4 bytes of one another share an address
//! (`I0.0` to `I3.7` are one window, `MW10` and `MW12` another). The windows go into as
//! few requests as ExchPackSize allows, usually one. Plans and unpacks; sends nothing.

use gutta_catalog::{Address, Width};

/// Where each operand's bytes are: the windows to read and, per operand, its window and
/// byte position in it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct ReadPlan {
    /// The first byte of each 4-byte window (slot and offset; read as a DWORD).
    pub windows: Vec<Address>,
    /// For each operand in the caller's order: (window index, byte offset in it).
    places: Vec<(usize, usize)>,
    operands: Vec<Address>,
}

fn size(w: Width) -> u32 {
    match w {
        Width::Bit | Width::Byte => 1,
        Width::Word => 2,
        Width::Dword => 4,
    }
}

impl ReadPlan {
    pub fn new(operands: &[Address]) -> ReadPlan {
        let mut order: Vec<usize> = (0..operands.len()).collect();
        order.sort_by_key(|&i| {
            (
                operands[i].slot,
                operands[i].offset,
                size(operands[i].width),
            )
        });
        let mut windows: Vec<Address> = Vec::new();
        let mut places = vec![(0, 0); operands.len()];
        for i in order {
            let a = operands[i];
            let end = a.offset + size(a.width);
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
            operands: operands.to_vec(),
        }
    }

    /// Each operand's raw value (cut to its width; a bit 0 or 1) from the windows' bytes.
    pub fn values(&self, windows: &[[u8; 4]]) -> Vec<u32> {
        self.operands
            .iter()
            .zip(&self.places)
            .map(|(a, &(w, at))| {
                let bytes = &windows[w][at..];
                let mut le = [0u8; 4];
                le[..bytes.len()].copy_from_slice(bytes);
                let raw = u32::from_le_bytes(le);
                match a.width {
                    Width::Bit => (raw >> a.bit) & 1,
                    Width::Byte => raw & 0xFF,
                    Width::Word => raw & 0xFFFF,
                    Width::Dword => raw,
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use gutta_catalog::stdlib;

    #[test]
    fn near_operands_share_a_window_and_unpack_to_their_values() {
        let target = stdlib::shared(stdlib::DEFAULT).expect("target");
        let parse = |t: &str| target.memory.parse_address(t).expect("address");
        let ops: Vec<Address> = ["MW12", "I0.0", "I3.7", "MW10", "I4.0", "MD13", "Q0.1"]
            .iter()
            .map(|t| parse(t))
            .collect();
        let plan = ReadPlan::new(&ops);
        let shown: Vec<String> = plan
            .windows
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
}
