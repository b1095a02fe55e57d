//! Checks of one packed operand against what may stand in its place: an instruction's
//! operand spec, a CALL argument's parameter, a local's type, a data item. The word is
//! taken apart by `PackedOperand::decode` only; the rules are `gutta_catalog::rules`
//! (the checker applies the same). Only reads the target and the set of program units
//! in the image; never panics on any operand.

use std::collections::BTreeSet;

use gutta_catalog::rules::{self, AreaRule, DataRules, IndirectRefusal, LiteralRefusal};
use gutta_catalog::{Address, Area, OperandKind, OperandSpec, Target, Width};

use super::error::{Location, VerifyError};
use crate::{Operand, OperandError, PackedOperand, UnitRef, Use};

/// Which operand a check is about, for messages.
#[derive(Debug, Clone, Copy)]
pub(super) enum Site<'a> {
    /// Operand `index` of an instruction, named `name` in its spec.
    Operand {
        mnemonic: &'a str,
        name: &'a str,
        index: usize,
    },
    /// Operand `index` of a CALL, passed to the callee's local `local`.
    Argument {
        callee: UnitRef,
        index: usize,
        local: usize,
    },
    Local {
        index: usize,
    },
    DataItem {
        index: usize,
    },
}

impl Site<'_> {
    pub(super) fn describe(&self) -> String {
        match *self {
            Site::Operand {
                mnemonic,
                name,
                index,
            } => format!("{name} (operand {index}) of {mnemonic}"),
            Site::Argument {
                callee,
                index,
                local,
            } => format!("operand {index} of CALL {callee} (its local {local})"),
            Site::Local { index } => format!("local {index}"),
            Site::DataItem { index } => format!("data item {index}"),
        }
    }
}

/// What an operand that met its spec names, for the unit's records.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Checked {
    Data,
    Label(u16),
    Literal(u16),
    /// A unit of the image, and its page.
    Unit(UnitRef, u8),
}

/// The operand checker of one image on one target.
pub(super) struct OperandChecker<'a> {
    pub target: &'a Target,
    /// Page numbers of the program units the image has.
    pub unit_pages: &'a BTreeSet<u8>,
}

impl OperandChecker<'_> {
    /// Check an operand against an instruction's operand spec.
    pub(super) fn check_spec(
        &self,
        at: Location,
        site: Site<'_>,
        op: PackedOperand,
        spec: &OperandSpec,
    ) -> Result<Checked, VerifyError> {
        match spec.kind {
            OperandKind::Data => {
                self.check_data(at, site, op, DataRules::from_spec(spec))?;
                Ok(Checked::Data)
            }
            OperandKind::Label => match special(at, site, op, Use::Label)? {
                Operand::Label(label) => {
                    let range = rules::label_range(spec);
                    in_range(at, site, label, *range.start(), *range.end())?;
                    Ok(Checked::Label(label))
                }
                _ => Err(use_not_allowed(at, site, op)),
            },
            OperandKind::Literal => match special(at, site, op, Use::Literal)? {
                Operand::Literal(value) => {
                    self.literal(at, site, value, spec)?;
                    Ok(Checked::Literal(value))
                }
                _ => Err(use_not_allowed(at, site, op)),
            },
            OperandKind::Block => match special(at, site, op, Use::Unit)? {
                Operand::Unit(unit) => {
                    let page = self.check_unit(at, site, unit, spec)?;
                    Ok(Checked::Unit(unit, page))
                }
                _ => Err(use_not_allowed(at, site, op)),
            },
        }
    }

    /// A literal in its range on this target (`PORT`, `EVNT` narrowed).
    fn literal(
        &self,
        at: Location,
        site: Site<'_>,
        value: u16,
        spec: &OperandSpec,
    ) -> Result<(), VerifyError> {
        match rules::check_literal(spec, &self.target.memory, i64::from(value)) {
            Ok(()) => Ok(()),
            Err(LiteralRefusal::NoSuchEvent) => Err(VerifyError::UnknownEvent {
                at,
                operand: site.describe(),
                event: value,
            }),
            Err(LiteralRefusal::OutOfRange { min, max }) => in_range(at, site, value, min, max),
        }
    }

    /// A unit of the kind the spec names, which the image has; returns its page.
    fn check_unit(
        &self,
        at: Location,
        site: Site<'_>,
        unit: UnitRef,
        spec: &OperandSpec,
    ) -> Result<u8, VerifyError> {
        if !rules::unit_operand_accepts(spec, unit.kind, u32::from(unit.number)) {
            return Err(VerifyError::BlockKindMismatch {
                at,
                operand: site.describe(),
                expected: rules::unit_operand_kind(spec),
                found: unit.kind,
                number: unit.number,
            });
        }
        match unit.page(&self.target.plc) {
            Some(page) if self.unit_pages.contains(&page) => Ok(page),
            _ => Err(VerifyError::NoSuchUnit {
                at,
                operand: site.describe(),
                kind: unit.kind,
                number: unit.number,
            }),
        }
    }

    /// A memory operand: value (USE 0), address-of (USE 1) or pointer (USE 2).
    pub(super) fn check_data(
        &self,
        at: Location,
        site: Site<'_>,
        op: PackedOperand,
        rules: DataRules<'_>,
    ) -> Result<(), VerifyError> {
        let operand = op.decode().map_err(|error| match error {
            OperandError::Width(found) => VerifyError::WidthMismatch {
                at,
                operand: site.describe(),
                expected: rules.width,
                found,
            },
            OperandError::Bit { bit } => VerifyError::BitOffset {
                at,
                operand: site.describe(),
                bit,
                width: rules.width,
            },
            OperandError::Use(_) | OperandError::NotZero { .. } | OperandError::UnitSlot(_) => {
                use_not_allowed(at, site, op)
            }
        })?;
        match operand {
            Operand::Value(variable) => self.value(at, site, variable, rules),
            Operand::AddressOf { byte, width } if rules.takes_address_of() => {
                self.address_of(at, site, byte, width)
            }
            Operand::Pointer { holder, width } if rules.pointer => {
                self.pointer(at, site, holder, width, rules.width)
            }
            _ => Err(use_not_allowed(at, site, op)),
        }
    }

    fn value(
        &self,
        at: Location,
        site: Site<'_>,
        variable: Address,
        rules: DataRules<'_>,
    ) -> Result<(), VerifyError> {
        let area = self.area(at, site, variable.slot)?;
        let width = rules.width;
        width_is(at, site, variable.width, width)?;
        allows(at, site, area, width)?;
        inside(at, site, variable.offset, area, width.bytes())?;
        if !rules.accepts_area(area) {
            return Err(VerifyError::AreaNotAllowed {
                at,
                operand: site.describe(),
                area: area.name.clone(),
                allowed: self.describe_areas(rules.areas),
            });
        }
        if !rules.may_write(area) {
            return Err(VerifyError::WriteToReadOnly {
                at,
                operand: site.describe(),
                area: area.name.clone(),
            });
        }
        Ok(())
    }

    /// `&byte`, read as a DWORD pointer value.
    fn address_of(
        &self,
        at: Location,
        site: Site<'_>,
        byte: Address,
        width: Width,
    ) -> Result<(), VerifyError> {
        let area = self.area(at, site, byte.slot)?;
        width_is(at, site, width, Width::Dword)?;
        match rules::address_of_target(area, Width::Byte) {
            Ok(()) => {}
            Err(IndirectRefusal::Area) => {
                return Err(VerifyError::NotAddressOfArea {
                    at,
                    operand: site.describe(),
                    area: area.name.clone(),
                })
            }
            Err(IndirectRefusal::Width) => {
                return Err(width_not_allowed(at, site, area, Width::Byte))
            }
        }
        inside(at, site, byte.offset, area, 1)
    }

    /// `*holder`, accessed as `width` where the instruction needs `expected`.
    fn pointer(
        &self,
        at: Location,
        site: Site<'_>,
        holder: Address,
        width: Width,
        expected: Width,
    ) -> Result<(), VerifyError> {
        let area = self.area(at, site, holder.slot)?;
        width_is(at, site, width, expected)?;
        match rules::pointer_holder(area, Width::Dword) {
            Ok(()) => {}
            Err(IndirectRefusal::Area) => {
                return Err(VerifyError::NotPointerArea {
                    at,
                    operand: site.describe(),
                    area: area.name.clone(),
                })
            }
            Err(IndirectRefusal::Width) => {
                return Err(width_not_allowed(at, site, area, Width::Dword))
            }
        }
        inside(at, site, holder.offset, area, Width::Dword.bytes())
    }

    fn area(&self, at: Location, site: Site<'_>, slot: u8) -> Result<&Area, VerifyError> {
        self.target
            .memory
            .area_by_slot(slot)
            .ok_or_else(|| VerifyError::NoSuchArea {
                at,
                operand: site.describe(),
                slot,
            })
    }

    fn describe_areas(&self, rule: AreaRule<'_>) -> String {
        match rule {
            AreaRule::Any => "any area".to_string(),
            AreaRule::Listed(list) => list.join(", "),
            AreaRule::Kinds(kinds) => self
                .target
                .memory
                .areas
                .iter()
                .filter(|a| kinds.contains(&a.kind))
                .map(|a| a.name.as_str())
                .collect::<Vec<_>>()
                .join(", "),
        }
    }
}

/// A label, literal or unit operand, decoded: the word has the `expected` USE (else
/// UseNotAllowed) and no field it must not have (else MalformedOperand).
fn special(
    at: Location,
    site: Site<'_>,
    op: PackedOperand,
    expected: Use,
) -> Result<Operand, VerifyError> {
    op.decode().map_err(|error| match error {
        OperandError::NotZero { use_ } if use_ == expected => malformed(
            at,
            site,
            op,
            if use_ == Use::Unit {
                "a unit operand has WIDTH 0 and BIT_OFFSET 0"
            } else {
                "a label or literal has SLOT, WIDTH and BIT_OFFSET 0"
            },
        ),
        OperandError::UnitSlot(_) if expected == Use::Unit => malformed(
            at,
            site,
            op,
            "the SLOT of a unit operand is 0 (interrupt) or 1 (subroutine)",
        ),
        _ => use_not_allowed(at, site, op),
    })
}

fn in_range(
    at: Location,
    site: Site<'_>,
    value: u16,
    min: i64,
    max: i64,
) -> Result<(), VerifyError> {
    if (min..=max).contains(&i64::from(value)) {
        Ok(())
    } else {
        Err(VerifyError::ValueOutOfRange {
            at,
            operand: site.describe(),
            value,
            min,
            max,
        })
    }
}

fn use_not_allowed(at: Location, site: Site<'_>, op: PackedOperand) -> VerifyError {
    VerifyError::UseNotAllowed {
        at,
        operand: site.describe(),
        use_code: op.use_code(),
    }
}

pub(super) fn malformed(
    at: Location,
    site: Site<'_>,
    op: PackedOperand,
    reason: &'static str,
) -> VerifyError {
    VerifyError::MalformedOperand {
        at,
        operand: site.describe(),
        value: op,
        reason,
    }
}

/// The access width of the operand is the one the instruction uses.
fn width_is(at: Location, site: Site<'_>, found: Width, width: Width) -> Result<(), VerifyError> {
    if found == width {
        return Ok(());
    }
    Err(VerifyError::WidthMismatch {
        at,
        operand: site.describe(),
        expected: width,
        found: found as u8,
    })
}

fn allows(at: Location, site: Site<'_>, area: &Area, width: Width) -> Result<(), VerifyError> {
    if area.allows(width) {
        Ok(())
    } else {
        Err(width_not_allowed(at, site, area, width))
    }
}

fn width_not_allowed(at: Location, site: Site<'_>, area: &Area, width: Width) -> VerifyError {
    VerifyError::WidthNotAllowed {
        at,
        operand: site.describe(),
        area: area.name.clone(),
        width,
    }
}

/// `bytes` bytes at `offset` lie inside the area, at a whole unit.
fn inside(
    at: Location,
    site: Site<'_>,
    offset: u32,
    area: &Area,
    bytes: u32,
) -> Result<(), VerifyError> {
    // Decoded offsets come from the 16-bit OFFSET field.
    let shown = u16::try_from(offset).unwrap_or(u16::MAX);
    if offset + bytes > area.size {
        return Err(VerifyError::OutOfArea {
            at,
            operand: site.describe(),
            area: area.name.clone(),
            offset: shown,
            bytes,
            size: area.size,
        });
    }
    if !offset.is_multiple_of(area.unit.bytes()) {
        return Err(VerifyError::Misaligned {
            at,
            operand: site.describe(),
            area: area.name.clone(),
            offset: shown,
            unit: area.unit,
        });
    }
    Ok(())
}
