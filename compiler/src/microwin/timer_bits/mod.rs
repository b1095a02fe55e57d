//! S7-200 timer and counter bits (docs/microwin.md, "Timer and counter bits" and "Timer
//! resolutions"): the dialect's pass over the checked code. GUTTA's T and C areas hold
//! only current values, so a line that uses a timer's or counter's bit the S7-200 way
//! (`LD T37`, `AN C0`, `R T37, 1`), which the checker left as a placeholder
//! (`check::BitUse`), becomes GUTTA instructions with the same effect: a read compares
//! the current value with the preset of the instruction that drives the number
//! (`LDW>= T37, 100` after `TON T37, 100`), a reset writes the current value. A TOF's
//! bit is "the current value is below the preset", which holds from the first scan on
//! because MAIN starts with a network that sets such a timer's current value to its
//! preset on the first scan. A timer box followed by an instruction that reads the top
//! of the logic stack is wrapped in `LPS`/`LPP`, since on an S7-200 a timer leaves the
//! stack as it was and on GUTTA it leaves its done state. Timer numbers whose S7-200
//! resolution differs from the target's get W0207, and with `--scale-timer-presets`
//! their constant presets are scaled.
//!
//! It runs once the checker has checked every unit, since a bit may be read before (or
//! in another block than) the instruction that gives it its meaning, and it needs the
//! resolved operands (addresses, constant presets) only the checker has. Here: the bit
//! uses and the drivers that give them a meaning; `stack.rs` (LPS/LPP around boxes),
//! `first_scan.rs` (the TOF first-scan network), `resolutions.rs` (W0207, scaling).

use std::collections::{BTreeMap, HashMap, HashSet};

use gutta_catalog::{
    Address, AreaKind, CompareOp, DataType, InstrId, Instruction, Join, LadderClass, Target,
    TimerCounterKind, Width,
};

use crate::check::{
    BitLines, BitOp, BitUse, CheckedInstruction, CheckedOperand, CheckedUnit, ConstValue, TimerBox,
    Use,
};
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;
use crate::CompileOptions;

mod first_scan;
mod resolutions;
mod stack;

/// The instructions whose lines use a timer's or counter's bit when their first operand
/// is a timer or counter, and what each does (`check::Conventions::timer_bit_lines`).
pub(super) fn bit_lines(target: &Target) -> HashMap<InstrId, BitOp> {
    let set = &target.instructions;
    set.names()
        .filter_map(|(_, id)| Some((id, bit_op(set.get(id))?)))
        .collect()
}

/// What a line of this instruction does with a timer's or counter's bit: the plain
/// (not immediate) contacts read it, the plain set and reset coils write it (the count of
/// `R` and `S` is the line's, filled in by the checker). The catalog says which is which.
fn bit_op(spec: &Instruction) -> Option<BitOp> {
    if spec.immediate {
        return None;
    }
    Some(match spec.ladder {
        LadderClass::Contact | LadderClass::ClosedContact => BitOp::Read {
            join: spec.join()?,
            negated: spec.ladder == LadderClass::ClosedContact,
        },
        LadderClass::ResetCoil => BitOp::Reset { count: 0 },
        LadderClass::SetCoil => BitOp::Set { count: 0 },
        _ => return None,
    })
}

/// What a timer or counter number's bit means, by the kind of instruction driving it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// TON, TONR: on when the current value reaches the preset.
    OnDelay,
    /// TOF: on while the current value is below the preset (see the module comment).
    OffDelay,
    /// CTU, CTUD: on when the count reaches the preset.
    CountUp,
    /// CTD: on when the count is down to 0.
    CountDown,
}

impl Kind {
    /// The meaning of the bit of the timer or counter an instruction drives (the
    /// catalog's `Kind`); None for any other instruction.
    fn of(spec: &Instruction) -> Option<Kind> {
        Some(match spec.kind? {
            TimerCounterKind::OnDelay | TimerCounterKind::RetentiveOnDelay => Kind::OnDelay,
            TimerCounterKind::OffDelay => Kind::OffDelay,
            TimerCounterKind::CountUp | TimerCounterKind::CountUpDown => Kind::CountUp,
            TimerCounterKind::CountDown => Kind::CountDown,
        })
    }

    /// The compare that is 1 when the bit is on, and the one when it is off.
    fn compares(self) -> (CompareOp, CompareOp) {
        match self {
            Kind::OnDelay | Kind::CountUp => (CompareOp::Ge, CompareOp::Lt),
            Kind::OffDelay => (CompareOp::Lt, CompareOp::Ge),
            Kind::CountDown => (CompareOp::Le, CompareOp::Gt),
        }
    }
}

/// One instruction driving a number, as checked.
#[derive(Debug, Clone)]
struct Driver {
    kind: Kind,
    mnemonic: String,
    timer: CheckedOperand,
    preset: CheckedOperand,
    /// The preset operand as written, and the whole instruction.
    preset_span: Span,
    span: Span,
}

/// The largest current value: an off-delay timer whose preset is in memory starts
/// there (it is then not below any preset).
const CURRENT_MAX: i64 = 32767;

/// The pass's view: what it reads, what it reports and the hover notes it writes.
struct TimerBitPass<'a> {
    text: &'a str,
    target: &'a Target,
    options: CompileOptions,
    diags: Vec<Diagnostic>,
    /// S7-200 timer and counter bit operands (`T37` of `LD T37`) and what they compile
    /// to, one Markdown line each (for hover).
    notes: Vec<(Span, String)>,
}

/// What the pass gives back: its diagnostics and the hover notes of the bit operands.
#[derive(Debug, Clone, Default)]
pub(super) struct TimerBitReport {
    pub diagnostics: Vec<Diagnostic>,
    pub notes: Vec<(Span, String)>,
}

/// Give every recorded bit use its instructions in `units` (the checked program's), scale
/// or warn about timer resolutions, keep the S7-200 logic stack around timer boxes
/// (`keep_stack`) and start MAIN with the off-delay timers' first-scan network.
pub(super) fn rewrite(
    units: &mut [CheckedUnit],
    lines: &BitLines,
    text: &str,
    target: &Target,
    options: CompileOptions,
    keep_stack: bool,
) -> TimerBitReport {
    let mut pass = TimerBitPass {
        text,
        target,
        options,
        diags: Vec::new(),
        notes: Vec::new(),
    };
    pass.timer_bits(units, &lines.uses, &lines.boxes, keep_stack);
    TimerBitReport {
        diagnostics: pass.diags,
        notes: pass.notes,
    }
}

impl TimerBitPass<'_> {
    fn slice(&self, s: Span) -> &str {
        self.text.get(s.range()).unwrap_or("")
    }

    fn report(&mut self, d: Diagnostic) {
        self.diags.push(d);
    }

    /// [`rewrite`]'s work: `checked` is the checked program's units, in its order.
    fn timer_bits(
        &mut self,
        checked: &mut [CheckedUnit],
        uses: &[BitUse],
        boxes: &[TimerBox],
        keep_stack: bool,
    ) {
        let scaled = self.timer_resolutions(checked, boxes);
        let drivers = self.drivers(checked, boxes);
        let mut edits: BTreeMap<(usize, usize, usize), Vec<CheckedInstruction>> = BTreeMap::new();
        let mut first_scan: Vec<(CheckedOperand, CheckedOperand, Span)> = Vec::new();
        let mut initialised: HashSet<(u8, u32)> = HashSet::new();
        for u in uses {
            let Some(replacement) =
                self.bit_use(u, &drivers, &scaled, &mut first_scan, &mut initialised)
            else {
                continue;
            };
            edits.insert((u.unit, u.network, u.index), replacement);
        }
        if keep_stack {
            self.keep_stack_around_boxes(checked, boxes, &mut edits);
        }
        for ((unit, network, index), replacement) in edits.into_iter().rev() {
            let list = &mut checked[unit].networks[network].instructions;
            list.splice(index..=index, replacement);
        }
        if !first_scan.is_empty() {
            self.first_scan_network(checked, &first_scan);
        }
    }

    /// Every checked timer and counter instruction of the dialect, by number.
    fn drivers(
        &self,
        checked: &[CheckedUnit],
        boxes: &[TimerBox],
    ) -> HashMap<(u8, u32), Vec<Driver>> {
        let mut map: HashMap<(u8, u32), Vec<Driver>> = HashMap::new();
        for b in boxes {
            let ins = &checked[b.unit].networks[b.network].instructions[b.index];
            let spec = self.target.instructions.get(ins.id);
            let Some(kind) = Kind::of(spec) else {
                continue;
            };
            let (Some(&timer), Some(&preset)) = (ins.operands.first(), ins.operands.get(1)) else {
                continue;
            };
            let CheckedOperand::Memory { address, .. } = timer else {
                continue;
            };
            map.entry((address.slot, address.offset))
                .or_default()
                .push(Driver {
                    kind,
                    mnemonic: spec.mnemonic.clone(),
                    timer,
                    preset,
                    preset_span: b.preset,
                    span: b.span,
                });
        }
        map
    }

    /// The instructions for one bit use, or None (reported).
    fn bit_use(
        &mut self,
        u: &BitUse,
        drivers: &HashMap<(u8, u32), Vec<Driver>>,
        scaled: &HashSet<Span>,
        first_scan: &mut Vec<(CheckedOperand, CheckedOperand, Span)>,
        initialised: &mut HashSet<(u8, u32)>,
    ) -> Option<Vec<CheckedInstruction>> {
        match u.op {
            BitOp::Read { join, negated } => {
                let key = (u.address.slot, u.address.offset);
                let driver = self.one_meaning(u, drivers.get(&key).map(Vec::as_slice))?;
                let (on, off) = driver.kind.compares();
                let relation = if negated { off } else { on };
                let id = self.compare_id(join, relation, u.span)?;
                let mnemonic = &self.target.instructions.get(id).mnemonic;
                let right = match driver.kind {
                    Kind::CountDown => word_constant(0),
                    _ => driver.preset,
                };
                if driver.kind == Kind::OffDelay && initialised.insert(key) {
                    first_scan.push((off_delay_start(&driver.preset), driver.timer, driver.span));
                }
                let name = self.slice(u.operand);
                let written = self.slice(driver.preset_span);
                let (shown, extra) = match (driver.kind, driver.preset) {
                    (Kind::CountDown, _) => ("0".to_string(), String::new()),
                    (
                        _,
                        CheckedOperand::Constant {
                            value: ConstValue::Integer(v),
                            ..
                        },
                    ) if scaled.contains(&driver.preset_span) => {
                        (v.to_string(), format!(" (its preset {written}, scaled)"))
                    }
                    _ => (written.to_string(), String::new()),
                };
                let what = match driver.kind {
                    Kind::CountUp | Kind::CountDown => "counter",
                    Kind::OnDelay | Kind::OffDelay => "timer",
                };
                let note = format!(
                    "S7-200 {what} bit: compiled as `{mnemonic} {name}, {shown}`, the bit of `{}`{extra}",
                    self.slice(driver.span)
                );
                self.notes.push((u.operand, note));
                Some(vec![CheckedInstruction {
                    id,
                    operands: vec![driver.timer, right],
                    span: u.span,
                }])
            }
            BitOp::Set { .. } => {
                self.report(
                    Diagnostic::new(
                        Code::S7200TimerBit,
                        u.operand,
                        format!(
                            "`S {}` sets an S7-200 timer or counter bit; GUTTA has no such bits",
                            self.slice(u.name)
                        ),
                    )
                    .label("no counterpart on GUTTA")
                    .help("keep the state in an M bit (`S M10.0, 1`) and read that bit"),
                );
                None
            }
            BitOp::Reset { count } => {
                if !self.reset_fits(u, count) {
                    return None;
                }
                let movw = self.instruction_id("MOVW", u.span)?;
                let mut out = Vec::new();
                if count > 1 {
                    let fill = self.instruction_id("FILL", u.span)?;
                    out.push(CheckedInstruction {
                        id: fill,
                        operands: vec![
                            word_constant(0),
                            word_operand(u.address),
                            CheckedOperand::Constant {
                                value: ConstValue::Integer(i64::from(count)),
                                width: Width::Byte,
                            },
                        ],
                        span: u.span,
                    });
                }
                for n in 0..count {
                    let address = Address {
                        offset: u.address.offset + 2 * n,
                        ..u.address
                    };
                    let key = (address.slot, address.offset);
                    let list = drivers.get(&key).map(Vec::as_slice).unwrap_or_default();
                    let off_delay = list.iter().any(|d| d.kind == Kind::OffDelay);
                    if !off_delay {
                        if count == 1 {
                            out.push(CheckedInstruction {
                                id: movw,
                                operands: vec![word_constant(0), word_operand(address)],
                                span: u.span,
                            });
                        }
                        continue;
                    }
                    // An off-delay timer is reset to "not below its preset": off, and
                    // disarmed on its next execution.
                    let driver = self.one_meaning(u, Some(list))?;
                    if initialised.insert(key) {
                        first_scan.push((
                            off_delay_start(&driver.preset),
                            driver.timer,
                            driver.span,
                        ));
                    }
                    out.push(CheckedInstruction {
                        id: movw,
                        operands: vec![off_delay_start(&driver.preset), driver.timer],
                        span: u.span,
                    });
                }
                Some(out)
            }
        }
    }

    /// Whether `R T37, count` resets numbers of the area only; if not, reported.
    fn reset_fits(&mut self, u: &BitUse, count: u32) -> bool {
        let end = u.address.offset + 2 * count;
        let size = self
            .target
            .memory
            .area_by_slot(u.address.slot)
            .map_or(0, |a| a.size);
        if end <= size {
            return true;
        }
        self.report(
            Diagnostic::new(
                Code::AddressOutOfTarget,
                u.operands,
                format!(
                    "`R {}, {count}` resets numbers up to {}, past the end of {}'s area ({} numbers)",
                    self.slice(u.name),
                    end / 2 - 1,
                    self.target.name(),
                    size / 2
                ),
            )
            .label("out of the area"),
        );
        false
    }

    /// The one instruction kind and preset that give a number's bit its meaning, or an
    /// E0222 at the use.
    fn one_meaning<'d>(&mut self, u: &BitUse, list: Option<&'d [Driver]>) -> Option<&'d Driver> {
        let name = self.slice(u.operand).to_string();
        let counter = self
            .target
            .memory
            .area_by_slot(u.address.slot)
            .is_some_and(|a| a.kind == AreaKind::Counter);
        let Some(first) = list.and_then(<[Driver]>::first) else {
            let (what, which) = if counter {
                ("counter", "CTU, CTD or CTUD")
            } else {
                ("timer", "TON, TONR or TOF")
            };
            self.report(
                Diagnostic::new(
                    Code::S7200TimerBit,
                    u.operand,
                    format!("`{name}` is read as a {what} bit, but no {which} drives it"),
                )
                .label("its bit has no preset to compare with")
                .help(format!(
                    "drive it with a {what} instruction, or read its current value with a compare (`LDW>= {name}, 10`)"
                )),
            );
            return None;
        };
        let list = list.unwrap_or_default();
        if let Some(other) = list.iter().find(|d| d.kind != first.kind) {
            self.report(
                Diagnostic::new(
                    Code::S7200TimerBit,
                    u.operand,
                    format!(
                        "`{name}`'s bit has no one meaning: both {} and {} drive it",
                        first.mnemonic, other.mnemonic
                    ),
                )
                .with_secondary(first.span, format!("{} here", first.mnemonic))
                .with_secondary(other.span, format!("{} here", other.mnemonic))
                .help("drive each number with one kind of instruction"),
            );
            return None;
        }
        if let Some(other) = list.iter().find(|d| d.preset != first.preset) {
            self.report(
                Diagnostic::new(
                    Code::S7200TimerBit,
                    u.operand,
                    format!("`{name}`'s bit has no one meaning: its instructions have different presets"),
                )
                .with_secondary(first.span, "one preset here")
                .with_secondary(other.span, "another here")
                .help("give every instruction on this number the same preset"),
            );
            return None;
        }
        Some(first)
    }

    /// The target's word compare contact (`LDW>=`, `AW<`, ...) the dialect emits for a
    /// bit read, or an error naming the compare it lacks.
    fn compare_id(&mut self, join: Join, relation: CompareOp, at: Span) -> Option<InstrId> {
        let id = self
            .target
            .instructions
            .compare(join, relation, DataType::Int);
        if id.is_none() {
            let prefix = match join {
                Join::Load => "LD",
                Join::And => "A",
                Join::Or => "O",
            };
            self.missing(&format!("{prefix}W{}", relation.symbol()), at);
        }
        id
    }

    /// The target's instruction for a mnemonic the dialect emits, or an error.
    fn instruction_id(&mut self, mnemonic: &str, at: Span) -> Option<InstrId> {
        let id = self.target.instructions.lookup(mnemonic);
        if id.is_none() {
            self.missing(mnemonic, at);
        }
        id
    }

    /// The error for an instruction the target lacks and a timer or counter bit needs.
    fn missing(&mut self, mnemonic: &str, at: Span) {
        self.report(Diagnostic::new(
            Code::S7200TimerBit,
            at,
            format!(
                "{} has no `{mnemonic}`, which this S7-200 timer or counter bit needs",
                self.target.name()
            ),
        ));
    }
}

/// A WORD constant operand.
fn word_constant(v: i64) -> CheckedOperand {
    CheckedOperand::Constant {
        value: ConstValue::Integer(v),
        width: Width::Word,
    }
}

/// A timer or counter's current value as an operand.
fn word_operand(address: Address) -> CheckedOperand {
    CheckedOperand::Memory {
        address: Address {
            width: Width::Word,
            bit: 0,
            ..address
        },
        use_: Use::Value,
        width: Width::Word,
    }
}

/// Where an off-delay timer starts, and goes on reset: at its preset when that is a
/// constant, else at the largest current value (not below any preset either).
fn off_delay_start(preset: &CheckedOperand) -> CheckedOperand {
    match preset {
        CheckedOperand::Constant { .. } => *preset,
        _ => word_constant(CURRENT_MAX),
    }
}
