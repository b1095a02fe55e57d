//! The constant pool: every constant of the program stored once in K, as tightly as the
//! target allows. Constants are placed widest first (then by value), each where its
//! bytes already occur, else overlapping the pool's tail as far as possible, so a byte
//! constant can share storage with the low byte of a wider one. Deterministic.

use std::collections::HashMap;

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
    /// First offset of every 1..4-byte sequence in `bytes` (constants are 1, 2 or 4
    /// bytes long), kept up to date as bytes are appended: lookups are one hash probe.
    first: HashMap<Vec<u8>, u32>,
}

impl ConstPool {
    fn push(&mut self, tail: &[u8]) {
        for &b in tail {
            self.bytes.push(b);
            let end = self.bytes.len();
            for len in 1..=4.min(end) {
                let key = self.bytes[end - len..end].to_vec();
                self.first.entry(key).or_insert((end - len) as u32);
            }
        }
    }

    /// Build the pool for a set of constants (their bytes).
    pub fn build(constants: impl IntoIterator<Item = Vec<u8>>) -> ConstPool {
        let mut unique: Vec<Vec<u8>> = constants.into_iter().collect();
        unique.sort_by(|a, b| b.len().cmp(&a.len()).then_with(|| a.cmp(b)));
        unique.dedup();
        let mut pool = ConstPool::default();
        for c in &unique {
            if pool.first.contains_key(c) {
                continue;
            }
            // Longest suffix of the pool that is a prefix of the constant.
            let n = pool.bytes.len();
            let overlap = (1..c.len().min(n + 1))
                .rev()
                .find(|&k| pool.bytes[n - k..] == c[..k])
                .unwrap_or(0);
            pool.push(&c[overlap..]);
        }
        pool
    }

    /// Offset of a constant's bytes in K.
    pub fn offset(&self, bytes: &[u8]) -> Option<u32> {
        self.first.get(bytes).copied()
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
