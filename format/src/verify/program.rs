//! Program units: argument pages (header, locals), each instruction page
//! (`code.rs`), then the call graph (no recursion, CallDepth). Works on decoded
//! pages; every index into them comes from `get` or a zip. Unit pages are
//! `UnitRef`'s: this file computes none.

use std::collections::{BTreeMap, BTreeSet};

use gutta_catalog::rules::{self, DataRules};
use gutta_catalog::{BlockKind, PlcType, Target, Width};

use super::code;
use super::error::{Location, VerifyError};
use super::operand::{OperandChecker, Site};
use super::VerifiedUnit;
use crate::{ArgumentPage, Image, LocalSection, Operand, PageId, PageKind, UnitRef};

/// The unit a program page stands for on the target, with its number as a byte (a
/// page number is a byte, so the unit's number is one too).
pub(super) fn unit_at(plc: &PlcType, page: u8) -> Option<(UnitRef, u8)> {
    let unit = UnitRef::from_page(page, plc)?;
    Some((unit, u8::try_from(unit.number).ok()?))
}

/// Decode and check every argument page, then every instruction page.
pub(super) fn verify_units(
    image: &Image,
    target: &Target,
) -> Result<BTreeMap<u8, VerifiedUnit>, VerifyError> {
    let mut arguments = BTreeMap::new();
    for (id, bytes) in image.pages.range(kind_range(PageKind::Argument)) {
        let page = verify_argument_page(*id, bytes, target)?;
        arguments.insert(id.number, page);
    }
    let unit_pages: BTreeSet<u8> = arguments.keys().copied().collect();
    let checker = OperandChecker {
        target,
        unit_pages: &unit_pages,
    };
    let mut units = BTreeMap::new();
    let mut calls: BTreeMap<u8, Vec<(u8, Location)>> = BTreeMap::new();
    for (id, bytes) in image.pages.range(kind_range(PageKind::Instruction)) {
        let (kind, number, locals) =
            match (unit_at(&target.plc, id.number), arguments.get(&id.number)) {
                (Some((unit, number)), Some(args)) => (unit.kind, number, args.locals.clone()),
                _ => continue, // Excluded by the page checks before.
            };
        let mut unit = VerifiedUnit {
            page: id.number,
            kind,
            number,
            locals,
            records: Vec::new(),
            labels: BTreeMap::new(),
            loops: BTreeMap::new(),
        };
        let edges = code::verify_code(*id, bytes, &checker, &arguments, &mut unit)?;
        calls.insert(id.number, edges);
        units.insert(id.number, unit);
    }
    verify_call_graph(target, &calls)?;
    Ok(units)
}

/// All pages of one kind in an image's page map.
pub(super) fn kind_range(kind: PageKind) -> std::ops::RangeInclusive<PageId> {
    PageId::new(kind, 0)..=PageId::new(kind, u8::MAX)
}

fn verify_argument_page(
    id: PageId,
    bytes: &[u8],
    target: &Target,
) -> Result<ArgumentPage, VerifyError> {
    let Some((UnitRef { kind, .. }, number)) = unit_at(&target.plc, id.number) else {
        return Err(VerifyError::PageNotOnTarget {
            page: id,
            count: target.plc.program_block_page_int_size + target.plc.program_block_page_sbr_size,
            limit: "ProgramBlockPageIntSize + ProgramBlockPageSbrSize",
        });
    };
    let page =
        ArgumentPage::decode(bytes).map_err(|error| VerifyError::Decode { page: id, error })?;
    let reserved =
        std::iter::once(3).chain((0..page.locals.len()).flat_map(|i| [10 + 8 * i, 11 + 8 * i]));
    for offset in reserved {
        match bytes.get(offset) {
            Some(&value) if value != 0 => {
                return Err(VerifyError::ReservedNotZero {
                    at: Location { page: id, offset },
                    value,
                })
            }
            _ => {}
        }
    }
    let found = if page.subroutine {
        BlockKind::Subroutine
    } else {
        BlockKind::Interrupt
    };
    if found != kind || page.unit_number != number {
        return Err(VerifyError::UnitHeader {
            at: Location {
                page: id,
                offset: if found != kind { 0 } else { 1 },
            },
            expected: (kind, number),
            found: (found, page.unit_number),
        });
    }
    let (max, limit) = rules::locals_limit(&target.plc, kind);
    if page.locals.len() as u64 > u64::from(max) {
        return Err(VerifyError::SizeLimit {
            page: Some(id),
            what: "locals",
            size: page.locals.len() as u64,
            limit: limit.to_string(),
            max: u64::from(max),
        });
    }
    let no_units = BTreeSet::new();
    let checker = OperandChecker {
        target,
        unit_pages: &no_units,
    };
    let mut previous = LocalSection::Input;
    for (i, local) in page.locals.iter().enumerate() {
        let at = |offset| Location {
            page: id,
            offset: 4 + 8 * i + offset,
        };
        if !rules::takes_parameters(kind) && local.section != LocalSection::Temp {
            return Err(VerifyError::InterruptParameter {
                at: at(4),
                local: i,
            });
        }
        if (local.section as u8) < previous as u8 {
            return Err(VerifyError::LocalOrder {
                at: at(4),
                local: i,
            });
        }
        previous = local.section;
        let rules = DataRules::local(local.data_type.width());
        checker.check_data(at(0), Site::Local { index: i }, local.operand, rules)?;
    }
    verify_locals_apart(id, &page)?;
    Ok(page)
}

/// No two locals share a bit of L (the checker's layout never makes them overlap; a
/// CALL passing two parameters through one variable would depend on the copy order).
/// Runs after every local has been checked to be a variable in L.
fn verify_locals_apart(id: PageId, page: &ArgumentPage) -> Result<(), VerifyError> {
    // (first bit, end bit, local index), sorted by first bit.
    let mut spans: Vec<(u64, u64, usize)> = page
        .locals
        .iter()
        .enumerate()
        .filter_map(|(i, local)| match local.operand.decode() {
            Ok(Operand::Value(a)) => {
                let first = u64::from(a.offset) * 8;
                Some(match a.width {
                    Width::Bit => (first + u64::from(a.bit), first + u64::from(a.bit) + 1, i),
                    w => (first, first + 8 * u64::from(w.bytes()), i),
                })
            }
            _ => None,
        })
        .collect();
    spans.sort_unstable();
    // The span reaching furthest so far: any later span starting before its end overlaps.
    let mut reach: Option<(u64, usize)> = None;
    for &(start, end, b) in &spans {
        if let Some((_, a)) = reach.filter(|&(furthest, _)| start < furthest) {
            let (other, local) = (a.min(b), a.max(b));
            return Err(VerifyError::OverlappingLocals {
                at: Location {
                    page: id,
                    offset: 4 + 8 * local,
                },
                local,
                other,
            });
        }
        if reach.is_none_or(|(furthest, _)| end > furthest) {
            reach = Some((end, b));
        }
    }
    Ok(())
}

/// No unit reaches itself through CALLs; from every interrupt routine, calls nest at
/// most `CallDepth` deep.
fn verify_call_graph(
    target: &Target,
    calls: &BTreeMap<u8, Vec<(u8, Location)>>,
) -> Result<(), VerifyError> {
    const NEW: u8 = 0;
    const ON_PATH: u8 = 1;
    const DONE: u8 = 2;
    let mut state = [NEW; 256];
    let mut depth = [0usize; 256];
    let edges = |u: u8| calls.get(&u).map(Vec::as_slice).unwrap_or(&[]);
    for &start in calls.keys() {
        if state[usize::from(start)] != NEW {
            continue;
        }
        state[usize::from(start)] = ON_PATH;
        let mut stack: Vec<(u8, usize)> = vec![(start, 0)];
        while let Some(top) = stack.last_mut() {
            let (node, next) = *top;
            if let Some(&(callee, at)) = edges(node).get(next) {
                top.1 += 1;
                match state[usize::from(callee)] {
                    ON_PATH => return Err(VerifyError::CallCycle { at, callee }),
                    NEW => {
                        state[usize::from(callee)] = ON_PATH;
                        stack.push((callee, 0));
                    }
                    _ => {}
                }
            } else {
                depth[usize::from(node)] = edges(node)
                    .iter()
                    .map(|(callee, _)| depth[usize::from(*callee)].saturating_add(1))
                    .max()
                    .unwrap_or(0);
                state[usize::from(node)] = DONE;
                stack.pop();
            }
        }
    }
    let max = usize::from(target.instructions.call_depth);
    for &page in calls.keys() {
        let d = depth[usize::from(page)];
        let interrupt =
            unit_at(&target.plc, page).is_some_and(|(unit, _)| unit.kind == BlockKind::Interrupt);
        if interrupt && d > max {
            return Err(VerifyError::CallDepth {
                page: PageId::new(PageKind::Instruction, page),
                depth: d,
                max,
            });
        }
    }
    Ok(())
}
