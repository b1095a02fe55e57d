//! Micro/WIN's LAD temporaries L60.0-L63.7, where an earlier stage asks for them
//! (`Conventions::l_temporaries`: in a Micro/WIN export). Micro/WIN uses these four
//! bytes when it converts LAD networks to STL (`= L60.0` ... `LD L60.0`); GUTTA's L is
//! smaller, so a direct operand in them that the target's L does not hold is placed at
//! [`LTemporaries::base`] (the last four bytes of L) by the same offset. L is each
//! block's own on GUTTA (the VM saves the caller's L for a CALL), so the placement is
//! checked block by block: where the block's locals or its own direct L operands take
//! those bytes, E0226 at the first use. Every other address keeps its meaning (an L
//! address past L that is no temporary stays E0306).

use gutta_catalog::{Address, AreaKind, Target};

use super::{Checker, UnitInfo};
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;

/// Where Micro/WIN's temporaries go in the target's L.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LTemporaries {
    /// The first S7-200 byte (60) and how many bytes (4).
    pub first: u32,
    pub bytes: u32,
    /// The byte of the target's L that S7-200's `first` goes to.
    pub base: u32,
    /// The L area's slot and size in bytes.
    pub slot: u8,
    pub size: u32,
}

impl LTemporaries {
    /// L60-L63 in the last four bytes of the target's L; None when the target has no L
    /// of at least four bytes, or one that holds L60-L63 itself.
    pub fn last_bytes_of_l(target: &Target) -> Option<LTemporaries> {
        let (first, bytes) = (60, 4);
        let l = target
            .memory
            .areas
            .iter()
            .find(|a| a.kind == AreaKind::Local)?;
        (l.size >= bytes && l.size < first + bytes).then_some(LTemporaries {
            first,
            bytes,
            base: l.size - bytes,
            slot: l.slot,
            size: l.size,
        })
    }

    /// `LB28-LB31`: the target bytes, as text.
    pub fn target_bytes(&self, area: &str) -> String {
        format!("{area}B{}-{area}B{}", self.base, self.base + self.bytes - 1)
    }
}

/// The temporaries of one block that fit, for the note.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LTemporaryPlacement {
    pub unit: String,
    /// `LB28-LB31`.
    pub bytes: String,
    /// The block's first use of L60-L63.
    pub first_use: Span,
}

impl Checker<'_> {
    /// A direct operand in L60-L63 the target's L does not hold, placed in the target's
    /// L; None for every other text.
    pub(super) fn l_temporary(&mut self, name: Span) -> Option<Address> {
        let temps = self.conventions.l_temporaries?;
        let text = self.slice(name);
        if self.target.memory.parse_address(text).is_ok() {
            return None;
        }
        let area = &self.target.memory.area_by_slot(temps.slot)?.name;
        let upper = text.to_ascii_uppercase();
        let rest = upper.strip_prefix(area.to_ascii_uppercase().as_str())?;
        let (letter, rest) = match rest.chars().next()? {
            c @ ('B' | 'W' | 'D') => (Some(c), &rest[1..]),
            _ => (None, rest),
        };
        let (byte, bit) = match rest.split_once('.') {
            Some((byte, bit)) if letter.is_none() => (byte, Some(bit)),
            None if letter.is_some() => (rest, None),
            _ => return None,
        };
        if byte.is_empty() || !byte.bytes().all(|b| b.is_ascii_digit()) || byte.len() > 3 {
            return None;
        }
        let offset: u32 = byte.parse().ok()?;
        let width = match letter {
            Some('W') => 2,
            Some('D') => 4,
            _ => 1,
        };
        if offset < temps.first || offset + width > temps.first + temps.bytes {
            return None;
        }
        let placed = offset - temps.first + temps.base;
        let moved = match (letter, bit) {
            (Some(l), _) => format!("{area}{l}{placed}"),
            (None, Some(bit)) => format!("{area}{placed}.{bit}"),
            (None, None) => return None,
        };
        let address = self.target.memory.parse_address(&moved).ok()?;
        self.l_temporary_uses.push(name);
        Some(address)
    }

    /// After a block's code: whether its temporaries fit (its locals and direct L
    /// operands leave the bytes free), E0226 at the first use otherwise. `addresses_from`
    /// is where the block's direct addresses start in `out.addresses`.
    pub(super) fn place_l_temporaries(&mut self, info: &UnitInfo, addresses_from: usize) {
        let uses = std::mem::take(&mut self.l_temporary_uses);
        let (Some(temps), Some(&first_use)) = (self.conventions.l_temporaries, uses.first()) else {
            return;
        };
        let Some(area) = self
            .target
            .memory
            .area_by_slot(temps.slot)
            .map(|a| a.name.clone())
        else {
            return;
        };
        let range = temps.base..temps.base + temps.bytes;
        let overlaps = |a: &Address| {
            a.slot == temps.slot && a.offset < range.end && a.offset + a.width.bytes() > range.start
        };
        let bytes = temps.target_bytes(&area);
        let what = format!(
            "`{}` is one of L60-L63, the temporaries Micro/WIN uses for LAD networks converted to STL; {} places them in {bytes}, the last 4 of its {}-byte L",
            self.slice(first_use),
            self.target.name(),
            temps.size
        );
        let locals: Vec<_> = info
            .locals
            .iter()
            .filter(|l| overlaps(&l.address))
            .collect();
        if let Some(taken) = locals.first() {
            let end = info
                .locals
                .iter()
                .map(|l| l.address.offset + l.address.width.bytes())
                .max()
                .unwrap_or(0);
            let (taken_span, name) = (taken.span, taken.name.clone());
            self.report(
                Diagnostic::new(
                    Code::S7200LTemporaries,
                    first_use,
                    format!(
                        "{what}, but {}'s locals take {area}B0-{area}B{}",
                        info.name,
                        end.saturating_sub(1)
                    ),
                )
                .label("no room for Micro/WIN's temporaries in this block")
                .with_secondary(taken_span, format!("`{name}` is in {bytes}"))
                .help(format!(
                    "declare fewer or smaller locals in {} so that {bytes} stay free, or keep the value of L60-L63 in M or V",
                    info.name
                )),
            );
            return;
        }
        let own = self.out.addresses[addresses_from..]
            .iter()
            .find(|(span, a)| overlaps(a) && !uses.contains(span))
            .map(|(span, _)| *span);
        if let Some(own) = own {
            self.report(
                Diagnostic::new(
                    Code::S7200LTemporaries,
                    first_use,
                    format!(
                        "{what}, but {} uses `{}` there itself",
                        info.name,
                        self.slice(own)
                    ),
                )
                .label("no room for Micro/WIN's temporaries in this block")
                .with_secondary(own, format!("in {bytes}"))
                .help(format!("move {}'s own use of {bytes} to M or V", info.name)),
            );
            return;
        }
        self.out.l_temporaries.push(LTemporaryPlacement {
            unit: info.name.clone(),
            bytes,
            first_use,
        });
    }
}
