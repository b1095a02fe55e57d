//! The constant pool: every constant of the program stored once in K, as tightly as the
//! target allows. Constants are placed widest first (then by value), each where its
//! bytes already occur, else overlapping the pool's tail as far as possible, so a byte
//! constant can share storage with the low byte of a wider one. Deterministic.

use std::collections::BTreeMap;

use gutta_catalog::Width;

use crate::check::ConstValue;

/// A constant's bytes as they sit in K (little-endian, its operand's width).
pub fn const_bytes(value: ConstValue, width: Width) -> Vec<u8> {
    let raw: u32 = match value {
        ConstValue::Integer(v) => v as u32,
        ConstValue::Real(r) => r.to_bits(),
    };
    raw.to_le_bytes()[..width.bytes() as usize].to_vec()
}

/// The pool: its bytes and where each distinct constant lives.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ConstPool {
    pub bytes: Vec<u8>,
    offsets: BTreeMap<Vec<u8>, u32>,
}

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    if needle.is_empty() {
        return Some(0);
    }
    haystack.windows(needle.len()).position(|w| w == needle)
}

impl ConstPool {
    /// Build the pool for a set of constants (their bytes).
    pub fn build(constants: impl IntoIterator<Item = Vec<u8>>) -> ConstPool {
        let mut unique: Vec<Vec<u8>> = constants.into_iter().collect();
        unique.sort_by(|a, b| b.len().cmp(&a.len()).then_with(|| a.cmp(b)));
        unique.dedup();
        let mut bytes: Vec<u8> = Vec::new();
        for c in &unique {
            if find(&bytes, c).is_some() {
                continue;
            }
            // Longest suffix of the pool that is a prefix of the constant.
            let overlap = (1..c.len().min(bytes.len() + 1))
                .rev()
                .find(|&k| bytes[bytes.len() - k..] == c[..k])
                .unwrap_or(0);
            bytes.extend_from_slice(&c[overlap..]);
        }
        let offsets = unique
            .into_iter()
            .map(|c| (find(&bytes, &c).unwrap_or(0) as u32, c))
            .map(|(o, c)| (c, o))
            .collect();
        ConstPool { bytes, offsets }
    }

    /// Offset of a constant's bytes in K.
    pub fn offset(&self, bytes: &[u8]) -> Option<u32> {
        self.offsets.get(bytes).copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constants_share_storage() {
        let pool = ConstPool::build([
            const_bytes(ConstValue::Integer(0x0E01), Width::Word),
            const_bytes(ConstValue::Integer(1), Width::Byte),
            const_bytes(ConstValue::Integer(0x0E02), Width::Word),
            const_bytes(ConstValue::Integer(2), Width::Dword),
            const_bytes(ConstValue::Integer(0x0E01), Width::Word),
        ]);
        // 02 00 00 00 | 01 0E | 02 0E: the byte 1 sits inside 0x0E01, nothing twice.
        assert_eq!(
            pool.bytes,
            vec![0x02, 0x00, 0x00, 0x00, 0x01, 0x0E, 0x02, 0x0E]
        );
        assert_eq!(pool.offset(&[0x01]), Some(4));
        assert_eq!(pool.offset(&[0x02, 0x0E]), Some(6));
    }

    #[test]
    fn tail_overlap_is_used() {
        let pool = ConstPool::build([vec![0xAA, 0xBB], vec![0xBB, 0xCC]]);
        assert_eq!(pool.bytes, vec![0xAA, 0xBB, 0xCC]);
    }
}
