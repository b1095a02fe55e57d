//! Sequence control relays, where an earlier stage asks for them
//! (`Conventions::sequence`: in a Micro/WIN export). The S7-200's S area (`S0.1`, `SB2`)
//! resolves to the byte range of the target the convention names; the four SCR lines
//! (`LSCR`, `SCRT`, `SCRE`, `CSCRE`) have no instruction of their own here: the checker
//! checks their operand and logic stack, leaves a placeholder where each stood and
//! records it ([`ScrLine`]). The stage's pass after checking (`crate::microwin`,
//! "Sequence control relays") gives each placeholder its instructions and reports what
//! cannot be compiled (segments, jumps, collisions with the S bytes).

use gutta_catalog::{s7200, Address, Width};

use super::Checker;
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;
use crate::syntax::ast::{Operand, OperandKind, Prefix};

/// Where the S area lives ([`Conventions::sequence`](super::Conventions::sequence)).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SequenceConvention {
    /// SB0's byte in the target (a byte address), and how many S bytes fit from there;
    /// or why the chosen place cannot hold the S area (reported at the first S operand).
    pub area: Result<(Address, u32), String>,
}

/// One of the four SCR lines.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScrOp {
    /// `LSCR Sx.y`: a segment starts.
    Load,
    /// `SCRT Sx.y`: under power flow, the next step.
    Transition,
    /// `SCRE`: the segment ends.
    End,
    /// `CSCRE`: under power flow, the rest of the segment does not run.
    ConditionalEnd,
}

impl ScrOp {
    pub fn from_mnemonic(text: &str) -> Option<ScrOp> {
        match text.to_ascii_uppercase().as_str() {
            "LSCR" => Some(ScrOp::Load),
            "SCRT" => Some(ScrOp::Transition),
            "SCRE" => Some(ScrOp::End),
            "CSCRE" => Some(ScrOp::ConditionalEnd),
            _ => None,
        }
    }

    pub fn mnemonic(self) -> &'static str {
        match self {
            ScrOp::Load => "LSCR",
            ScrOp::Transition => "SCRT",
            ScrOp::End => "SCRE",
            ScrOp::ConditionalEnd => "CSCRE",
        }
    }

    /// Logic stack levels it needs, and what it adds.
    fn stack(self) -> (i32, i32) {
        match self {
            ScrOp::Load => (0, 1),
            ScrOp::Transition | ScrOp::ConditionalEnd => (1, 0),
            ScrOp::End => (0, 0),
        }
    }
}

/// An SCR line; its placeholder is at `units[unit].networks[network].instructions[index]`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ScrLine {
    pub unit: usize,
    pub network: usize,
    pub index: usize,
    pub op: ScrOp,
    /// The S bit of `LSCR`/`SCRT`, as its target address.
    pub bit: Option<Address>,
    pub mnemonic: Span,
    pub span: Span,
}

/// An operand in the S area: the name as written and the target address it went to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SOperand {
    pub span: Span,
    pub name: String,
    pub address: Address,
    /// The S bytes it covers.
    pub bytes: std::ops::Range<u32>,
}

/// What the checker recorded for the pass after checking.
#[derive(Debug, Clone, Default)]
pub struct SequenceLines {
    pub lines: Vec<ScrLine>,
    pub s_operands: Vec<SOperand>,
    /// Every other memory operand of the program with the address it resolved to
    /// (symbols, system symbols and direct addresses), to find uses of the S bytes.
    pub memory_uses: Vec<(Span, Address)>,
    /// Upper-case names of the symbols declared at an S address (`Step1 : S0.1`).
    pub s_symbols: std::collections::HashSet<String>,
}

impl SequenceLines {
    pub(super) fn renumber_units(&mut self, position: &[usize]) {
        for l in &mut self.lines {
            l.unit = position[l.unit];
        }
    }
}

impl Checker<'_> {
    /// `S0.1`, `SB2`, ... as the target address the convention places it at; None when
    /// no convention asks for the S area or the name is no S operand. A reported
    /// problem is `Some(None)`.
    pub(super) fn s_operand(&mut self, name: Span) -> Option<Option<Address>> {
        let convention = self.conventions.sequence.as_ref()?;
        let text = self.slice(name);
        let (width, byte, bit) = s7200::s_operand(text)?;
        let len = width.bits().div_ceil(8);
        let end = byte + len;
        let refuse = |message: String, label: String| {
            Diagnostic::new(Code::S7200Sequence, name, message).label(label)
        };
        let d = match &convention.area {
            Err(why) => refuse(format!("the S area cannot be placed: {why}"), "an S operand".into())
                .help("choose a byte address of M or V with room for the S bytes: `[microwin] s_area = \"MB96\"` in gutta.toml or `--s-area MB96`"),
            Ok(_) if end > s7200::S_AREA_BYTES => refuse(
                format!("`{text}` is outside the S7-200's S area (S0.0-S31.7)"),
                "no such S address".into(),
            ),
            Ok((base, room)) if end > *room => refuse(
                format!("`{text}` does not fit: the S area at {} has room for {room} bytes", self.target.memory.format_address(base)),
                "outside the room left".into(),
            )
            .help("move the S area with `[microwin] s_area` in gutta.toml or `--s-area` to where 32 bytes are free"),
            Ok((base, _)) => {
                let address = Address {
                    slot: base.slot,
                    width,
                    offset: base.offset + byte,
                    bit,
                };
                self.out.addresses.push((name, address));
                self.sequence.s_operands.push(SOperand {
                    span: name,
                    name: text.to_ascii_uppercase(),
                    address,
                    bytes: byte..end,
                });
                return Some(Some(address));
            }
        };
        self.report(d);
        Some(None)
    }

    /// A memory operand that resolved (for the collision check), when the S area is used.
    pub(super) fn memory_use(&mut self, name: Span, address: Address) {
        if self.conventions.sequence.is_some() {
            self.sequence.memory_uses.push((name, address));
        }
    }

    /// The line as an SCR line, when the conventions ask for them and its mnemonic is
    /// one; `stack` is the network's logic stack (depth, known), updated. Its operand is
    /// checked here (a line whose operand is refused has no `bit`: the program has an
    /// error); everything about segments is the pass's.
    pub(super) fn scr_line(
        &mut self,
        at: (usize, usize, usize),
        mnemonic: Span,
        ops: &[Operand],
        span: Span,
        stack: (&mut i32, &mut bool),
    ) -> Option<ScrLine> {
        self.conventions.sequence.as_ref()?;
        let op = ScrOp::from_mnemonic(self.slice(mnemonic))?;
        let (depth, known) = stack;
        let (needs, delta) = op.stack();
        if *known {
            if *depth < needs {
                self.report(
                    Diagnostic::new(
                        Code::StackUnderflow,
                        mnemonic,
                        format!("`{}` needs power flow, but nothing is loaded in this network", op.mnemonic()),
                    )
                    .help("start the logic with a load such as `LD I0.0` (or `LD SM0.0` to run always)"),
                );
                *known = false;
            } else {
                *depth += delta;
            }
        }
        let wants_bit = matches!(op, ScrOp::Load | ScrOp::Transition);
        let bit = match (wants_bit, ops) {
            (false, []) => None,
            (true, [o]) => self.scr_bit(op, o),
            _ => {
                let n = if wants_bit { "one S bit" } else { "no operand" };
                self.report(Diagnostic::new(
                    Code::OperandCount,
                    span,
                    format!("`{}` takes {n}", op.mnemonic()),
                ));
                None
            }
        };
        let (unit, network, index) = at;
        Some(ScrLine {
            unit,
            network,
            index,
            op,
            bit,
            mnemonic,
            span,
        })
    }

    /// The S bit of `LSCR`/`SCRT`; None (reported) when it is no S bit. The line is
    /// recorded all the same, so that its segment is known.
    fn scr_bit(&mut self, op: ScrOp, o: &Operand) -> Option<Address> {
        if let OperandKind::Name {
            prefix: Prefix::None,
            local: false,
            name,
        } = o.kind
        {
            let text = self.slice(name);
            if s7200::s_operand(text).is_some_and(|(w, _, _)| w == Width::Bit) {
                return self.s_operand(name).flatten();
            }
            // A symbol of an S bit.
            if let Some(&(address, def)) = self.symbols.get(&text.to_ascii_uppercase()) {
                if address.width == Width::Bit
                    && self
                        .sequence
                        .s_operands
                        .iter()
                        .any(|s| s.address == address)
                {
                    self.reference(name, def);
                    return Some(address);
                }
            }
        }
        self.report(
            Diagnostic::new(
                Code::S7200Sequence,
                o.span,
                format!("`{}` takes an S bit", op.mnemonic()),
            )
            .label("not an S bit (S0.0-S31.7)")
            .help(format!("write the step's bit: `{} S0.1`", op.mnemonic())),
        );
        None
    }
}
