//! Sequence control relays (docs/microwin.md, "Sequence control relays"). Before the
//! checker: where the S area lives ([`convention`]: `[microwin] s_area`, `--s-area`, else
//! the last 32 bytes of M). After it: each segment from `LSCR` to `SCRE` becomes ordinary
//! code on labels the block does not use ([`rewrite`]):
//!
//! ```text
//! LSCR S0.1   ->  LDN S0.1 ; JMP e ; NOT      (skip the segment unless S0.1; leave 1)
//! SCRT S0.2   ->  S S0.2, 1 ; R S0.1, 1       (under power flow)
//! CSCRE       ->  JMP e                       (under power flow)
//! SCRE        ->  LBL e
//! ```
//!
//! and what cannot be compiled so (segments that nest or do not end, jumps across a
//! segment's border, `END` in a segment, program uses of the S bytes) is E0224.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::fmt;
use std::str::FromStr;

use gutta_catalog::s7200::S_AREA_BYTES;
use gutta_catalog::{Address, AreaKind, InstrId, Target, Width};

use crate::check::{
    BitLines, CheckedInstruction, CheckedOperand, CheckedUnit, ConstValue, ScrLine, ScrOp,
    SequenceConvention, SequenceLines, Use,
};
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;

/// Where SB0 goes, as chosen (`MB96`): an area name and a byte. Checked against the
/// target when the program is checked (`convention`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SAreaBase {
    area: String,
    pub byte: u32,
}

impl SAreaBase {
    /// The area's name (`M`).
    pub fn area(&self) -> &str {
        &self.area
    }
}

impl fmt::Display for SAreaBase {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}B{}", self.area(), self.byte)
    }
}

impl FromStr for SAreaBase {
    type Err = String;

    /// A byte address: an area name, `B`, a byte number (`MB96`, `VB200`).
    fn from_str(text: &str) -> Result<SAreaBase, String> {
        let bad = || format!("`{text}` is not a byte address such as MB96 or VB200");
        let upper = text.trim().to_ascii_uppercase();
        let letters = upper.bytes().take_while(u8::is_ascii_alphabetic).count();
        let (name, digits) = upper.split_at(letters);
        let area = name.strip_suffix('B').filter(|a| !a.is_empty());
        let (Some(area), false) = (area, digits.is_empty()) else {
            return Err(bad());
        };
        let byte = digits.parse().map_err(|_| bad())?;
        Ok(SAreaBase {
            area: area.to_string(),
            byte,
        })
    }
}

/// Where the S area goes on `target`: the chosen base, else the last 32 bytes of M.
pub fn convention(target: &Target, chosen: Option<SAreaBase>) -> SequenceConvention {
    let base = chosen.map_or_else(
        || {
            let m = target.memory.area("M");
            let byte = m.map_or(0, |m| m.size.saturating_sub(S_AREA_BYTES));
            format!("MB{byte}").parse()
        },
        Ok,
    );
    let area = base.and_then(|base| {
        let name = base.area();
        let Some(area) = target.memory.area(name) else {
            return Err(format!("{} has no memory area {name}", target.name()));
        };
        if !area.writable || !area.widths.contains(&Width::Bit) || area.kind == AreaKind::Local {
            return Err(format!(
                "area {name} is not a writable, bit-addressable global area"
            ));
        }
        if base.byte >= area.size {
            return Err(format!(
                "{base} is outside area {name} ({} bytes)",
                area.size
            ));
        }
        let address = Address {
            slot: area.slot,
            width: Width::Byte,
            offset: base.byte,
            bit: 0,
        };
        Ok((address, (area.size - base.byte).min(S_AREA_BYTES)))
    });
    SequenceConvention { area }
}

/// Where the S bits went: the S bytes used, SB0's address, and whether it was chosen.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SAreaPlacement {
    pub first: u32,
    pub last: u32,
    pub base: Address,
    pub chosen: bool,
}

/// The note: `S area: S0.0-S3.7 in MB96-MB99 (SB0 = MB96; the default: the last 32 bytes
/// of M)`; None when the program uses no S operand.
pub fn s_area_summary(placement: Option<&SAreaPlacement>, target: &Target) -> Option<String> {
    let p = placement?;
    let byte = |n: u32| {
        target.memory.format_address(&Address {
            offset: p.base.offset + n,
            ..p.base
        })
    };
    let why = if p.chosen {
        "as chosen"
    } else {
        "the default: the last 32 bytes of M"
    };
    let bytes = if p.first == p.last {
        byte(p.first)
    } else {
        format!("{}-{}", byte(p.first), byte(p.last))
    };
    Some(format!(
        "S area: S{}.0-S{}.7 in {bytes} (SB0 = {}; {why})",
        p.first,
        p.last,
        byte(0),
    ))
}

/// What the pass did: its diagnostics and where the S bits went.
pub struct Report {
    pub diagnostics: Vec<Diagnostic>,
    pub placement: Option<SAreaPlacement>,
}

/// The instructions the generated code uses.
struct Ids {
    ldn: InstrId,
    jmp: InstrId,
    not: InstrId,
    set: InstrId,
    reset: InstrId,
    lbl: InstrId,
    end: Option<InstrId>,
    for_: Option<InstrId>,
    next: Option<InstrId>,
}

impl Ids {
    fn of(target: &Target) -> Option<Ids> {
        let set = &target.instructions;
        let id = |m: &str| set.lookup(m);
        Some(Ids {
            ldn: id("LDN")?,
            jmp: id("JMP")?,
            not: id("NOT")?,
            set: id("S")?,
            reset: id("R")?,
            lbl: set.label_definition()?,
            end: id("END"),
            for_: set.by_loop_role(gutta_catalog::LoopRole::Start),
            next: set.by_loop_role(gutta_catalog::LoopRole::End),
        })
    }
}

/// One segment of a block: its `LSCR` and `SCRE` lines (indices into the block's lines).
struct Segment {
    load: usize,
    end: usize,
}

/// The pass: every block's segments to ordinary code, the timer-bit records moved with
/// the instructions they point at; nothing changes when anything is refused.
pub fn rewrite(
    units: &mut [CheckedUnit],
    sequence: &SequenceLines,
    bit_lines: &mut BitLines,
    target: &Target,
    chosen: bool,
) -> Report {
    let mut diagnostics = collisions(sequence, target);
    let placement = placement(sequence, chosen);
    if sequence.lines.is_empty() {
        return Report {
            diagnostics,
            placement,
        };
    }
    let Some(ids) = Ids::of(target) else {
        return Report {
            diagnostics,
            placement,
        };
    };
    let mut by_unit: BTreeMap<usize, Vec<&ScrLine>> = BTreeMap::new();
    for l in &sequence.lines {
        by_unit.entry(l.unit).or_default().push(l);
    }
    let mut plans = Vec::new();
    for (&ui, lines) in &by_unit {
        let Some(unit) = units.get(ui) else { continue };
        let before = diagnostics.len();
        let segments = segments(lines, &mut diagnostics);
        borders(unit, lines, &segments, &ids, &mut diagnostics);
        if diagnostics.len() == before {
            match code(unit, lines, &segments, &ids) {
                Ok(plan) => plans.push((ui, plan)),
                Err(d) => diagnostics.push(*d),
            }
        }
    }
    if diagnostics
        .iter()
        .any(|d| d.severity == crate::diagnostics::Severity::Error)
    {
        return Report {
            diagnostics,
            placement,
        };
    }
    for (ui, plan) in plans {
        apply(&mut units[ui], ui, plan, bit_lines);
    }
    Report {
        diagnostics,
        placement,
    }
}

fn placement(sequence: &SequenceLines, chosen: bool) -> Option<SAreaPlacement> {
    let first = sequence.s_operands.iter().map(|s| s.bytes.start).min()?;
    let last = sequence.s_operands.iter().map(|s| s.bytes.end - 1).max()?;
    let s = sequence.s_operands.first()?;
    let base = Address {
        width: Width::Byte,
        bit: 0,
        offset: s.address.offset - s.bytes.start,
        ..s.address
    };
    Some(SAreaPlacement {
        first,
        last,
        base,
        chosen,
    })
}

/// The bytes an address covers in its area.
fn bytes(a: &Address) -> std::ops::Range<u32> {
    a.offset..a.offset + a.width.bits().div_ceil(8)
}

/// E0224 for each program operand that uses a byte an S operand went to (the first such
/// S operand labelled too).
fn collisions(sequence: &SequenceLines, target: &Target) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    let mut seen = BTreeSet::new();
    for &(span, address) in &sequence.memory_uses {
        let used = bytes(&address);
        let Some(s) = sequence.s_operands.iter().find(|s| {
            let b = bytes(&s.address);
            s.address.slot == address.slot && b.start < used.end && used.start < b.end
        }) else {
            continue;
        };
        if !seen.insert(span) {
            continue;
        }
        let mapped = target.memory.format_address(&s.address);
        let own = target.memory.format_address(&address);
        out.push(
            Diagnostic::new(
                Code::S7200Sequence,
                span,
                format!(
                    "this program uses {own} itself, where the S area went ({} is {mapped} here)",
                    s.name
                ),
            )
            .label(format!("this program uses {own} itself"))
            .with_secondary(s.span, format!("{} is {mapped} here", s.name))
            .help(free_range_help(sequence, target, s.address.slot)),
        );
    }
    out
}

/// The help of a collision: how to move the S area, with a free range when one is found
/// in the same area.
fn free_range_help(sequence: &SequenceLines, target: &Target, slot: u8) -> String {
    let mut text = "move the S area: `[microwin] s_area = \"MBn\"` in gutta.toml or `--s-area MBn`"
        .to_string();
    let Some(area) = target.memory.area_by_slot(slot) else {
        return text;
    };
    let used: Vec<std::ops::Range<u32>> = sequence
        .memory_uses
        .iter()
        .filter(|(_, a)| a.slot == slot)
        .map(|(_, a)| bytes(a))
        .collect();
    let start = (0..area.size.saturating_sub(S_AREA_BYTES - 1))
        .rev()
        .find(|&b| {
            used.iter()
                .all(|u| u.end <= b || b + S_AREA_BYTES <= u.start)
        });
    if let Some(b) = start {
        text.push_str(&format!(
            "; {}B{b}-{}B{} is free",
            area.name,
            area.name,
            b + S_AREA_BYTES - 1
        ));
    }
    text
}

/// The block's segments, or E0224 for lines outside one, nesting and a missing `SCRE`.
fn segments(lines: &[&ScrLine], diagnostics: &mut Vec<Diagnostic>) -> Vec<Segment> {
    let mut out = Vec::new();
    let mut open: Option<usize> = None;
    for (i, l) in lines.iter().enumerate() {
        match (l.op, open) {
            (ScrOp::Load, Some(o)) => diagnostics.push(
                Diagnostic::new(Code::S7200Sequence, l.mnemonic, "`LSCR` inside a segment")
                    .label("segments do not nest")
                    .with_secondary(lines[o].mnemonic, "the segment started here")
                    .help("end the segment above with `SCRE` first"),
            ),
            (ScrOp::Load, None) => open = Some(i),
            (ScrOp::End, Some(o)) => {
                out.push(Segment { load: o, end: i });
                open = None;
            }
            (op, None) => diagnostics.push(
                Diagnostic::new(
                    Code::S7200Sequence,
                    l.mnemonic,
                    format!("`{}` outside a segment", op.mnemonic()),
                )
                .label("no `LSCR` before it in this block")
                .help("SCRT, CSCRE and SCRE stand between `LSCR Sx.y` and its `SCRE`"),
            ),
            (_, Some(_)) => {}
        }
    }
    if let Some(o) = open {
        diagnostics.push(
            Diagnostic::new(
                Code::S7200Sequence,
                lines[o].mnemonic,
                "segment without `SCRE`",
            )
            .label("not ended in its block")
            .help("end the segment with a network holding `SCRE`"),
        );
    }
    out
}

/// A position in a block: (network, instruction).
type Pos = (usize, usize);

fn pos(l: &ScrLine) -> Pos {
    (l.network, l.index)
}

/// E0224 for jumps across a segment's border, `END` in a segment and FOR/NEXT across
/// one.
fn borders(
    unit: &CheckedUnit,
    lines: &[&ScrLine],
    segments: &[Segment],
    ids: &Ids,
    diagnostics: &mut Vec<Diagnostic>,
) {
    let segment_of = |p: Pos| {
        segments
            .iter()
            .position(|s| pos(lines[s.load]) <= p && p <= pos(lines[s.end]))
    };
    let mut labels: HashMap<u16, (Pos, Span)> = HashMap::new();
    let mut instructions = Vec::new();
    for (n, net) in unit.networks.iter().enumerate() {
        for (i, ins) in net.instructions.iter().enumerate() {
            if ins.id == ids.lbl {
                if let Some(CheckedOperand::Label(l)) = ins.operands.first() {
                    labels.insert(*l, ((n, i), ins.span));
                }
            }
            instructions.push(((n, i), ins));
        }
    }
    let mut loops: Vec<(Pos, Span)> = Vec::new();
    for (p, ins) in instructions {
        let here = segment_of(p);
        if ins.id == ids.jmp {
            let Some(CheckedOperand::Label(l)) = ins.operands.first() else {
                continue;
            };
            let Some(&(lp, lspan)) = labels.get(l) else {
                continue;
            };
            let there = segment_of(lp);
            if here != there {
                let what = if here.is_some() { "out of" } else { "into" };
                diagnostics.push(
                    Diagnostic::new(
                        Code::S7200Sequence,
                        ins.span,
                        format!("`JMP` {what} a segment"),
                    )
                    .label(format!("jumps {what} the segment"))
                    .with_secondary(lspan, format!("label {l} is here"))
                    .help("jump within one segment, or around whole segments"),
                );
            }
        } else if Some(ins.id) == ids.end && here.is_some() {
            diagnostics.push(
                Diagnostic::new(Code::S7200Sequence, ins.span, "`END` inside a segment")
                    .label("the segment would never reach its `SCRE`")
                    .help("end the scan outside the segments"),
            );
        } else if Some(ins.id) == ids.for_ {
            loops.push((p, ins.span));
        } else if Some(ins.id) == ids.next {
            let Some((fp, fspan)) = loops.pop() else {
                continue;
            };
            if segment_of(fp) != here {
                diagnostics.push(
                    Diagnostic::new(
                        Code::S7200Sequence,
                        ins.span,
                        "`FOR`/`NEXT` across a segment's border",
                    )
                    .label("this NEXT")
                    .with_secondary(fspan, "and its FOR are not in the same segment")
                    .help("keep the loop inside one segment, or put the segment inside no loop"),
                );
            }
        }
    }
}

/// The instructions each SCR line becomes, by (network, index) of its placeholder.
type Plan = BTreeMap<Pos, Vec<CheckedInstruction>>;

fn code(
    unit: &CheckedUnit,
    lines: &[&ScrLine],
    segments: &[Segment],
    ids: &Ids,
) -> Result<Plan, Box<Diagnostic>> {
    let used: BTreeSet<u16> = unit
        .networks
        .iter()
        .flat_map(|n| &n.instructions)
        .flat_map(|i| &i.operands)
        .filter_map(|o| match o {
            CheckedOperand::Label(l) => Some(*l),
            _ => None,
        })
        .collect();
    let mut free = (0..=255u16).rev().filter(|l| !used.contains(l));
    let mut plan = Plan::new();
    for s in segments {
        let load = lines[s.load];
        let Some(label) = free.next() else {
            return Err(Box::new(
                Diagnostic::new(
                    Code::S7200Sequence,
                    load.mnemonic,
                    "no free label for this segment",
                )
                .label("every label 0-255 of this block is used")
                .help("a segment needs one label the block does not use; free one"),
            ));
        };
        let Some(bit) = load.bit else { continue };
        let at = |id, operands, span| CheckedInstruction { id, operands, span };
        let memory = |address| CheckedOperand::Memory {
            address,
            use_: Use::Value,
            width: Width::Bit,
        };
        let one = CheckedOperand::Constant {
            value: ConstValue::Integer(1),
            width: Width::Byte,
        };
        plan.insert(
            pos(load),
            vec![
                at(ids.ldn, vec![memory(bit)], load.span),
                at(ids.jmp, vec![CheckedOperand::Label(label)], load.span),
                at(ids.not, vec![], load.span),
            ],
        );
        for l in &lines[s.load + 1..=s.end] {
            let code = match l.op {
                ScrOp::Transition => {
                    let Some(next) = l.bit else { continue };
                    vec![
                        at(ids.set, vec![memory(next), one], l.span),
                        at(ids.reset, vec![memory(bit), one], l.span),
                    ]
                }
                ScrOp::ConditionalEnd => {
                    vec![at(ids.jmp, vec![CheckedOperand::Label(label)], l.span)]
                }
                ScrOp::End => vec![at(ids.lbl, vec![CheckedOperand::Label(label)], l.span)],
                ScrOp::Load => continue,
            };
            plan.insert(pos(l), code);
        }
    }
    Ok(plan)
}

/// The plan into the block, back to front in each network so that the indices still
/// hold; the timer-bit records of the block move with their instructions.
fn apply(unit: &mut CheckedUnit, ui: usize, plan: Plan, bit_lines: &mut BitLines) {
    let shift = |network: usize, index: usize| -> usize {
        plan.range((network, 0)..(network, index))
            .map(|(_, code)| code.len() - 1)
            .sum()
    };
    for u in bit_lines.uses.iter_mut().filter(|u| u.unit == ui) {
        u.index += shift(u.network, u.index);
    }
    for b in bit_lines.boxes.iter_mut().filter(|b| b.unit == ui) {
        b.index += shift(b.network, b.index);
    }
    for ((network, index), code) in plan.into_iter().rev() {
        if let Some(net) = unit.networks.get_mut(network) {
            if index < net.instructions.len() {
                net.instructions.splice(index..=index, code);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::source::SourceFile;

    fn target() -> std::sync::Arc<Target> {
        gutta_catalog::stdlib::shared(gutta_catalog::stdlib::DEFAULT).unwrap()
    }

    /// The mnemonics and operands of MAIN after the pass, one line each.
    fn main_code(text: &str) -> Vec<String> {
        let checked = crate::check_source(SourceFile::new("main.awl", text), None);
        let errors: Vec<_> = checked
            .diagnostics()
            .iter()
            .map(|d| d.message.clone())
            .collect();
        let program = checked
            .output
            .program
            .as_ref()
            .unwrap_or_else(|| panic!("{errors:?}"));
        let set = &checked.target.instructions;
        program.units[0]
            .networks
            .iter()
            .flat_map(|n| &n.instructions)
            .map(|i| {
                let ops: Vec<String> = i
                    .operands
                    .iter()
                    .map(|o| match o {
                        CheckedOperand::Memory { address, .. } => {
                            checked.target.memory.format_address(address)
                        }
                        CheckedOperand::Label(l) => l.to_string(),
                        CheckedOperand::Constant {
                            value: ConstValue::Integer(n),
                            ..
                        } => n.to_string(),
                        other => format!("{other:?}"),
                    })
                    .collect();
                format!("{} {}", set.get(i.id).mnemonic, ops.join(", "))
                    .trim()
                    .to_string()
            })
            .collect()
    }

    #[test]
    fn a_byte_address_parses_and_prints() {
        let b: SAreaBase = "mb96".parse().unwrap();
        assert_eq!(
            (b.area(), b.byte, b.to_string()),
            ("M", 96, "MB96".to_string())
        );
        assert_eq!("VB200".parse::<SAreaBase>().unwrap().area(), "V");
        for bad in ["M96", "MB", "B96", "MW96", "M96.0", ""] {
            assert!(bad.parse::<SAreaBase>().is_err(), "{bad}");
        }
    }

    #[test]
    fn the_default_is_the_last_32_bytes_of_m_and_a_bad_base_says_why() {
        let t = target();
        let m = t.memory.area("M").unwrap();
        let (base, room) = convention(&t, None).area.unwrap();
        assert_eq!((base.slot, base.offset, room), (m.slot, m.size - 32, 32));
        let near_end = format!("MB{}", m.size - 4).parse().ok();
        assert_eq!(convention(&t, near_end).area.unwrap().1, 4);
        let input = convention(&t, "IB0".parse().ok()).area.unwrap_err();
        assert!(input.contains("not a writable"), "{input}");
        let outside = convention(&t, format!("MB{}", m.size).parse().ok());
        assert!(outside.area.unwrap_err().contains("outside area M"));
        let none = convention(&t, "XB0".parse().ok()).area.unwrap_err();
        assert!(none.contains("no memory area X"), "{none}");
    }

    #[test]
    fn segments_become_skips_sets_and_resets_on_free_labels() {
        let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\nLSCR S0.0\nNetwork 2\n\
LD I0.0\nJMP 255\nLD I0.1\nCSCRE\nNetwork 3\nLBL 255\nLD SM0.0\nSCRT S0.1\nNetwork 4\nSCRE\n\
Network 5\nLSCR S0.1\nNetwork 6\nLD T5\nTON T5, 10\nNetwork 7\nSCRE\nEND_ORGANIZATION_BLOCK\n";
        let code = main_code(text);
        let expected = [
            "LDN M96.0",
            "JMP 254",
            "NOT", // LSCR S0.0: label 255 is the program's
            "LD I0.0",
            "JMP 255",
            "LD I0.1",
            "JMP 254", // CSCRE
            "LBL 255",
            "LD SM0.0",
            "S M96.1, 1",
            "R M96.0, 1", // SCRT S0.1
            "LBL 254",    // SCRE
            "LDN M96.1",
            "JMP 253",
            "NOT",
        ];
        assert_eq!(code[..expected.len()], expected, "{code:#?}");
        // The timer bit line after the segment's start still gets its compare.
        assert!(code[expected.len()].starts_with("LDW>= T5"), "{code:#?}");
        assert_eq!(code.last().map(String::as_str), Some("LBL 253"));
    }
}
