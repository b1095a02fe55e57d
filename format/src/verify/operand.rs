//! Checks of one packed operand against what may stand in its place: an instruction's
//! operand spec, a CALL argument's parameter, a local's type, a data item. Only reads
//! the target and the set of program units in the image; never panics on any operand.

use std::collections::BTreeSet;

use gutta_catalog::rules::{self, IndirectRefusal, LiteralRefusal};
pub(super) use gutta_catalog::rules::{AreaRule, DataRules};
use gutta_catalog::{Area, BlockKind, OperandKind, OperandSpec, Target, Width};

use super::error::{unit_name, Location, VerifyError};
use crate::{PackedOperand, Use};

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
        callee: (BlockKind, u8),
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
            } => format!(
                "operand {index} of CALL {} (its local {local})",
                unit_name(callee.0, callee.1 as u16)
            ),
            Site::Local { index } => format!("local {index}"),
            Site::DataItem { index } => format!("data item {index}"),
        }
    }
}

/// The operand checker of one image on one target.
pub(super) struct OperandChecker<'a> {
    pub target: &'a Target,
    /// Page numbers of the program units the image has.
    pub unit_pages: &'a BTreeSet<u8>,
}

impl OperandChecker<'_> {
    /// The page of a unit, if the target can have it.
    pub(super) fn unit_page(&self, kind: BlockKind, number: u16) -> Option<u8> {
        let plc = &self.target.plc;
        let number = u32::from(number);
        if !rules::unit_exists(plc, kind, number) {
            return None;
        }
        let page = match kind {
            BlockKind::Interrupt => number,
            BlockKind::Subroutine => plc.program_block_page_int_size.checked_add(number)?,
        };
        u8::try_from(page).ok()
    }

    /// Check an operand against an instruction's operand spec. For a unit operand,
    /// returns the unit's page.
    pub(super) fn check_spec(
        &self,
        at: Location,
        site: Site<'_>,
        op: PackedOperand,
        spec: &OperandSpec,
    ) -> Result<Option<u8>, VerifyError> {
        match spec.kind {
            OperandKind::Data => self.check_data(at, site, op, DataRules::from_spec(spec))?,
            OperandKind::Label => {
                self.special(at, site, op, Use::Label)?;
                let range = rules::label_range(spec);
                self.range(at, site, op, *range.start(), *range.end())?;
            }
            OperandKind::Literal => {
                self.special(at, site, op, Use::Literal)?;
                let value = op.offset();
                match rules::check_literal(spec, &self.target.memory, i64::from(value)) {
                    Ok(()) => {}
                    Err(LiteralRefusal::NoSuchEvent) => {
                        return Err(VerifyError::UnknownEvent {
                            at,
                            operand: site.describe(),
                            event: value,
                        })
                    }
                    Err(LiteralRefusal::OutOfRange { min, max }) => {
                        return Err(VerifyError::ValueOutOfRange {
                            at,
                            operand: site.describe(),
                            value,
                            min,
                            max,
                        })
                    }
                }
            }
            OperandKind::Block => return self.check_unit(at, site, op, spec).map(Some),
        }
        Ok(None)
    }

    fn check_unit(
        &self,
        at: Location,
        site: Site<'_>,
        op: PackedOperand,
        spec: &OperandSpec,
    ) -> Result<u8, VerifyError> {
        if op.use_code() != Use::Unit as u8 {
            return Err(use_not_allowed(at, site, op));
        }
        if op.width_code() != 0 || op.bit() != 0 {
            return Err(malformed(
                at,
                site,
                op,
                "a unit operand has WIDTH 0 and BIT_OFFSET 0",
            ));
        }
        let found = match op.slot() {
            0 => BlockKind::Interrupt,
            1 => BlockKind::Subroutine,
            _ => {
                return Err(malformed(
                    at,
                    site,
                    op,
                    "the SLOT of a unit operand is 0 (interrupt) or 1 (subroutine)",
                ))
            }
        };
        let expected = rules::unit_operand_kind(spec);
        let number = op.offset();
        if !rules::unit_operand_accepts(spec, found, u32::from(number)) {
            return Err(VerifyError::BlockKindMismatch {
                at,
                operand: site.describe(),
                expected,
                found,
                number,
            });
        }
        match self.unit_page(found, number) {
            Some(page) if self.unit_pages.contains(&page) => Ok(page),
            _ => Err(VerifyError::NoSuchUnit {
                at,
                operand: site.describe(),
                kind: found,
                number,
            }),
        }
    }

    /// A label or literal: the right USE, and SLOT, WIDTH, BIT_OFFSET 0.
    fn special(
        &self,
        at: Location,
        site: Site<'_>,
        op: PackedOperand,
        use_: Use,
    ) -> Result<(), VerifyError> {
        if op.use_code() != use_ as u8 {
            return Err(use_not_allowed(at, site, op));
        }
        if op.slot() != 0 || op.width_code() != 0 || op.bit() != 0 {
            return Err(malformed(
                at,
                site,
                op,
                "a label or literal has SLOT, WIDTH and BIT_OFFSET 0",
            ));
        }
        Ok(())
    }

    fn range(
        &self,
        at: Location,
        site: Site<'_>,
        op: PackedOperand,
        min: i64,
        max: i64,
    ) -> Result<(), VerifyError> {
        let value = op.offset();
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

    /// A memory operand: value (USE 0), address-of (USE 1) or pointer (USE 2).
    pub(super) fn check_data(
        &self,
        at: Location,
        site: Site<'_>,
        op: PackedOperand,
        rules: DataRules<'_>,
    ) -> Result<(), VerifyError> {
        match op.use_() {
            Some(Use::Value) => self.value(at, site, op, rules),
            Some(Use::AddressOf) if rules.takes_address_of() => self.address_of(at, site, op),
            Some(Use::Pointer) if rules.pointer => self.pointer(at, site, op, rules.width),
            _ => Err(use_not_allowed(at, site, op)),
        }
    }

    fn value(
        &self,
        at: Location,
        site: Site<'_>,
        op: PackedOperand,
        rules: DataRules<'_>,
    ) -> Result<(), VerifyError> {
        let area = self.area(at, site, op)?;
        let width = rules.width;
        width_is(at, site, op, width)?;
        allows(at, site, area, width)?;
        bit(at, site, op, width)?;
        inside(at, site, op, area, width.bytes())?;
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

    fn address_of(
        &self,
        at: Location,
        site: Site<'_>,
        op: PackedOperand,
    ) -> Result<(), VerifyError> {
        let area = self.area(at, site, op)?;
        width_is(at, site, op, Width::Dword)?;
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
        bit(at, site, op, Width::Byte)?;
        inside(at, site, op, area, 1)
    }

    fn pointer(
        &self,
        at: Location,
        site: Site<'_>,
        op: PackedOperand,
        width: Width,
    ) -> Result<(), VerifyError> {
        let area = self.area(at, site, op)?;
        width_is(at, site, op, width)?;
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
        bit(at, site, op, width)?;
        inside(at, site, op, area, Width::Dword.bytes())
    }

    fn area(&self, at: Location, site: Site<'_>, op: PackedOperand) -> Result<&Area, VerifyError> {
        self.target
            .memory
            .area_by_slot(op.slot())
            .ok_or_else(|| VerifyError::NoSuchArea {
                at,
                operand: site.describe(),
                slot: op.slot(),
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

/// The operand's WIDTH field is the one the instruction accesses with.
fn width_is(
    at: Location,
    site: Site<'_>,
    op: PackedOperand,
    width: Width,
) -> Result<(), VerifyError> {
    if op.width_code() == width as u8 {
        return Ok(());
    }
    Err(VerifyError::WidthMismatch {
        at,
        operand: site.describe(),
        expected: width,
        found: op.width_code(),
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

/// BIT_OFFSET is 0..7 for a bit, 0 otherwise.
fn bit(at: Location, site: Site<'_>, op: PackedOperand, width: Width) -> Result<(), VerifyError> {
    let ok = if width == Width::Bit {
        op.bit() <= 7
    } else {
        op.bit() == 0
    };
    if ok {
        Ok(())
    } else {
        Err(VerifyError::BitOffset {
            at,
            operand: site.describe(),
            bit: op.bit(),
            width,
        })
    }
}

/// `bytes` bytes at the operand's offset lie inside the area, at a whole unit.
fn inside(
    at: Location,
    site: Site<'_>,
    op: PackedOperand,
    area: &Area,
    bytes: u32,
) -> Result<(), VerifyError> {
    let offset = op.offset();
    if u32::from(offset) + bytes > area.size {
        return Err(VerifyError::OutOfArea {
            at,
            operand: site.describe(),
            area: area.name.clone(),
            offset,
            bytes,
            size: area.size,
        });
    }
    if u32::from(offset) % area.unit.bytes() != 0 {
        return Err(VerifyError::Misaligned {
            at,
            operand: site.describe(),
            area: area.name.clone(),
            offset,
            unit: area.unit,
        });
    }
    Ok(())
}
