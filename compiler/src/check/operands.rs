//! Operands against their instruction's operand spec: direct addresses, symbols,
//! locals, `&` and `*`, constants, labels, blocks and literals. Every rule comes from
//! the target's description (area widths, permissions, operand types and areas).

use std::sync::OnceLock;

use gutta_catalog::{
    stdlib, Address, AddressError, BlockKind, DataType, MemoryMap, OperandKind as SpecKind,
    OperandSpec, Width,
};

use super::{CheckedOperand, Checker, ConstValue, Use};
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;
use crate::syntax::ast::{Operand, OperandKind, Prefix};

/// A variable before its use is applied: where it is, and its declared type if any.
struct Variable {
    address: Address,
    ty: Option<DataType>,
}

/// The memory map of every stdlib target (`None` if it does not load), in
/// `stdlib::names()` order. Loaded once per process: loading them for every unknown-area
/// error cost milliseconds per diagnostic.
pub(super) fn stdlib_memory_maps() -> &'static [(&'static str, Option<MemoryMap>)] {
    static MAPS: OnceLock<Vec<(&'static str, Option<MemoryMap>)>> = OnceLock::new();
    MAPS.get_or_init(|| {
        stdlib::names()
            .map(|n| (n, stdlib::load(n).ok().map(|t| t.memory)))
            .collect()
    })
}

fn types_text(types: &[DataType]) -> String {
    types
        .iter()
        .map(|t| t.keyword())
        .collect::<Vec<_>>()
        .join(", ")
}

impl Checker<'_> {
    /// Parse a direct address, reporting why it is not one on this target. `span` is the
    /// address text; `context` says what it is for (symbol, data row).
    pub(super) fn direct_address(&mut self, span: Span, context: Option<&str>) -> Option<Address> {
        let text = self.slice(span);
        match self.target.memory.parse_address(text) {
            Ok(a) => Some(a),
            Err(e) => {
                self.address_error(span, text, e, context);
                None
            }
        }
    }

    fn address_error(&mut self, span: Span, text: &str, e: AddressError, context: Option<&str>) {
        let plc = self.target.name().to_string();
        let d = match &e {
            AddressError::NotAnAddress => Diagnostic::new(Code::MalformedAddress, span, format!("`{text}` is not an address"))
                .help(context.map(|c| format!("{c} needs a direct address such as I0.0, MW10 or T5")).unwrap_or_default()),
            AddressError::UnknownArea { prefix } => {
                let elsewhere: Vec<&str> = stdlib_memory_maps()
                    .iter()
                    .filter(|(n, _)| !n.eq_ignore_ascii_case(&plc))
                    .filter(|(_, m)| m.as_ref().is_some_and(|m| m.area(prefix).is_some()))
                    .map(|(n, _)| *n)
                    .collect();
                let d = Diagnostic::new(Code::AddressOutOfTarget, span, format!("{plc} has no memory area {prefix}")).label("unknown area");
                if elsewhere.is_empty() {
                    let names: Vec<&str> = self.target.memory.areas.iter().map(|a| a.name.as_str()).collect();
                    d.help(format!("the areas of {plc} are {}", names.join(", ")))
                } else {
                    d.help(format!("area {prefix} exists on {}; select it with --plc or PLC_TYPE", elsewhere.join(", ")))
                }
            }
            AddressError::OutOfRange { area, size, last, .. } => {
                Diagnostic::new(Code::AddressOutOfTarget, span, format!("`{text}` is outside area {area} of {plc}"))
                    .label(format!("{area} has {size} bytes; the last {} is {last}", if last.contains('.') { "bit" } else { "such address" }))
            }
            AddressError::WidthNotAllowed { area, width, allowed } => {
                let list: Vec<&str> = allowed.iter().map(|w| w.keyword()).collect();
                Diagnostic::new(Code::AreaNotAllowed, span, format!("area {area} has no {} access", width.keyword().to_ascii_lowercase()))
                    .label(format!("{area} allows {}", list.join(", ")))
            }
            AddressError::LetterNotAllowed { example, .. } | AddressError::MissingWidth { area: example } if matches!(e, AddressError::LetterNotAllowed { .. }) => {
                Diagnostic::new(Code::MalformedAddress, span, e.to_string()).help(format!("write `{example}`"))
            }
            AddressError::MissingWidth { area } => Diagnostic::new(Code::MalformedAddress, span, e.to_string())
                .help(format!("for example `{area}B0` (byte), `{area}W0` (word), `{area}D0` (dword) or `{area}0.0` (bit)")),
            AddressError::BitOutOfRange { .. } | AddressError::LetterNotAllowed { .. } => Diagnostic::new(Code::MalformedAddress, span, e.to_string()),
        };
        let d = if d.help.as_deref() == Some("") {
            Diagnostic { help: None, ..d }
        } else {
            d
        };
        self.report(d);
    }

    /// Resolve a name operand (without prefix) to a variable: local, symbol or address.
    fn variable(&mut self, unit: usize, local: bool, name: Span) -> Option<Variable> {
        let text = self.slice(name);
        if local {
            let key = text.to_ascii_uppercase();
            if let Some(i) = self.units[unit]
                .locals
                .iter()
                .position(|l| l.name.eq_ignore_ascii_case(&key))
            {
                let l = &self.units[unit].locals[i];
                let (address, ty, def) = (l.address, l.ty, self.units[unit].local_defs[i]);
                self.reference(name, def);
                return Some(Variable {
                    address,
                    ty: Some(ty),
                });
            }
            let other = self
                .units
                .iter()
                .find(|u| u.locals.iter().any(|l| l.name.eq_ignore_ascii_case(&key)))
                .map(|u| u.name.clone());
            let d = match other {
                Some(owner) => Diagnostic::new(
                    Code::LocalOutsideBlock,
                    name,
                    format!("`#{text}` is a local of {owner}, not of this block"),
                )
                .help("locals belong to their block; pass the value as a CALL argument"),
                None => {
                    let cands: Vec<String> = self.units[unit]
                        .locals
                        .iter()
                        .map(|l| l.name.clone())
                        .collect();
                    let hint = super::suggest::closest(text, cands.iter().map(String::as_str))
                        .map(|s| format!("did you mean `#{s}`?"));
                    Diagnostic::new(
                        Code::UndefinedLocal,
                        name,
                        format!("this block declares no local `{text}`"),
                    )
                    .maybe_help(hint)
                }
            };
            self.report(d);
            return None;
        }
        let key = text.to_ascii_uppercase();
        if let Some(&(address, def)) = self.symbols.get(&key) {
            self.reference(name, def);
            return Some(Variable { address, ty: None });
        }
        if self.looks_like_address(text) {
            let a = self.direct_address(name, None)?;
            self.out.addresses.push((name, a));
            return Some(Variable {
                address: a,
                ty: None,
            });
        }
        if let Some(&u) = self.unit_names.get(&key) {
            let what = if self.units[u].kind == BlockKind::Subroutine {
                "a subroutine"
            } else {
                "an interrupt routine"
            };
            self.report(Diagnostic::new(
                Code::WrongOperandKind,
                name,
                format!("`{text}` is {what}, not a variable"),
            ));
            return None;
        }
        let mut cands: Vec<&str> = Vec::new();
        let keys: Vec<String> = self.symbols.keys().cloned().collect();
        let names: Vec<String> = keys
            .iter()
            .filter_map(|k| {
                self.symbols
                    .get(k)
                    .map(|(_, d)| self.out.definitions[*d].name.clone())
            })
            .collect();
        cands.extend(names.iter().map(String::as_str));
        let hint = super::suggest::closest(text, cands).map(|s| format!("did you mean `{s}`?"));
        self.report(
            Diagnostic::new(
                Code::UndefinedSymbol,
                name,
                format!("undefined symbol `{text}`"),
            )
            .label("not a symbol, local or address")
            .help(hint.unwrap_or_else(|| "declare it in SYMBOLS: `Name : ADDRESS`".to_string())),
        );
        None
    }

    /// Resolve one operand against its spec. `mnemonic` names the instruction in messages.
    pub(super) fn operand(
        &mut self,
        unit: usize,
        op: &Operand,
        spec: &OperandSpec,
        mnemonic: &str,
    ) -> Option<CheckedOperand> {
        match (spec.kind, op.kind) {
            (_, OperandKind::Error) => None,
            (SpecKind::Label, OperandKind::Integer(n)) if (0..=255).contains(&n) => {
                Some(CheckedOperand::Label(n as u16))
            }
            (SpecKind::Label, _) => {
                self.report(
                    Diagnostic::new(
                        Code::WrongOperandKind,
                        op.span,
                        format!("{mnemonic} needs a label number 0..255"),
                    )
                    .help(format!(
                        "for example `{mnemonic} 3` with `LBL 3` in the same block"
                    )),
                );
                None
            }
            (
                SpecKind::Block,
                OperandKind::Name {
                    prefix: Prefix::None,
                    local: false,
                    name,
                },
            ) => self.block_operand(name, spec, mnemonic),
            (SpecKind::Block, _) => {
                let what = if spec.block == Some(gutta_catalog::BlockKind::Interrupt) {
                    "an interrupt routine"
                } else {
                    "a subroutine"
                };
                self.report(Diagnostic::new(
                    Code::WrongOperandKind,
                    op.span,
                    format!("{mnemonic} needs {what} name here"),
                ));
                None
            }
            (SpecKind::Literal, OperandKind::Integer(n)) => {
                let (lo, mut hi) = (spec.min.unwrap_or(i64::MIN), spec.max.unwrap_or(i64::MAX));
                // Literals the target narrows: serial ports it has, events it raises.
                if spec.name == "PORT" {
                    hi = hi.min(self.target.memory.serial_ports as i64 - 1);
                }
                if spec.name == "EVNT"
                    && !self
                        .target
                        .memory
                        .events
                        .iter()
                        .any(|e| e.number as i64 == n)
                {
                    let list: Vec<String> = self
                        .target
                        .memory
                        .events
                        .iter()
                        .map(|e| format!("{} {}", e.number, e.name))
                        .collect();
                    self.report(
                        Diagnostic::new(
                            Code::ConstantOutOfRange,
                            op.span,
                            format!("{} raises no interrupt event {n}", self.target.name()),
                        )
                        .help(format!("events: {}", list.join(", "))),
                    );
                    return None;
                }
                if (lo..=hi).contains(&n) {
                    Some(CheckedOperand::Literal(n))
                } else {
                    self.report(
                        Diagnostic::new(
                            Code::ConstantOutOfRange,
                            op.span,
                            format!("{} of {mnemonic} must be {lo}..{hi}", spec.name),
                        )
                        .label(format!("{n} is out of range")),
                    );
                    None
                }
            }
            (SpecKind::Literal, _) => {
                self.report(
                    Diagnostic::new(
                        Code::ConstantNotAllowed,
                        op.span,
                        format!("{} of {mnemonic} must be a literal number", spec.name),
                    )
                    .label("a number is required here"),
                );
                None
            }
            (SpecKind::Data, OperandKind::Integer(v)) => {
                self.integer_constant(op.span, v, spec, mnemonic)
            }
            (SpecKind::Data, OperandKind::Real(v)) => {
                if !self.constant_allowed(op.span, spec, mnemonic) {
                    return None;
                }
                if spec.types.contains(&DataType::Real) {
                    Some(CheckedOperand::Constant {
                        value: ConstValue::Real(v as f32),
                        width: Width::Dword,
                    })
                } else {
                    self.report(
                        Diagnostic::new(
                            Code::RealNotAllowed,
                            op.span,
                            format!(
                                "{} of {mnemonic} takes {}, not a REAL constant",
                                spec.name,
                                types_text(&spec.types)
                            ),
                        )
                        .label("has a fraction or exponent"),
                    );
                    None
                }
            }
            (
                SpecKind::Data,
                OperandKind::Name {
                    prefix,
                    local,
                    name,
                },
            ) => self.variable_operand(unit, op.span, prefix, local, name, spec, mnemonic),
        }
    }

    fn block_operand(
        &mut self,
        name: Span,
        spec: &OperandSpec,
        mnemonic: &str,
    ) -> Option<CheckedOperand> {
        let text = self.slice(name);
        let key = text.to_ascii_uppercase();
        if !self.unit_names.contains_key(&key)
            && (self.looks_like_address(text) || self.symbols.contains_key(&key))
        {
            self.report(
                Diagnostic::new(
                    Code::WrongOperandKind,
                    name,
                    format!("{mnemonic} needs a block name; `{text}` is a variable"),
                )
                .help(format!(
                    "for example `{mnemonic} ADD3` or `{mnemonic} SBR0`"
                )),
            );
            return None;
        }
        let Some(&u) = self.unit_names.get(&key) else {
            let cands: Vec<String> = self.units.iter().map(|u| u.name.clone()).collect();
            let hint = super::suggest::closest(text, cands.iter().map(String::as_str))
                .map(|s| format!("did you mean `{s}`?"));
            self.report(
                Diagnostic::new(
                    Code::UndefinedBlock,
                    name,
                    format!("no block named `{text}`"),
                )
                .maybe_help(hint),
            );
            return None;
        };
        let want = match spec.block {
            Some(gutta_catalog::BlockKind::Interrupt) => BlockKind::Interrupt,
            _ => BlockKind::Subroutine,
        };
        let (kind, number, def) = (
            self.units[u].kind,
            self.units[u].number,
            self.units[u].definition,
        );
        self.reference(name, def);
        if kind != want || (want == BlockKind::Interrupt && number == 0) {
            let msg = match want {
                BlockKind::Subroutine => {
                    format!("{mnemonic} calls subroutines; `{text}` is an interrupt routine")
                }
                BlockKind::Interrupt => {
                    format!("{mnemonic} takes an interrupt routine (not MAIN); `{text}` is not one")
                }
            };
            self.report(Diagnostic::new(Code::WrongOperandKind, name, msg));
            return None;
        }
        Some(CheckedOperand::Unit { kind, number })
    }

    fn constant_allowed(&mut self, span: Span, spec: &OperandSpec, mnemonic: &str) -> bool {
        if spec.constant {
            return true;
        }
        if spec.role.writes() {
            self.report(
                Diagnostic::new(
                    Code::WriteToReadOnly,
                    span,
                    format!(
                        "{mnemonic} writes {}; a constant cannot be written",
                        spec.name
                    ),
                )
                .label("constant")
                .help("S7-200 operand order: the destination comes last (`MOVW 5, MW0`)"),
            );
        } else {
            self.report(
                Diagnostic::new(
                    Code::ConstantNotAllowed,
                    span,
                    format!(
                        "{} of {mnemonic} must be a variable, not a constant",
                        spec.name
                    ),
                )
                .label("constant"),
            );
        }
        false
    }

    fn integer_constant(
        &mut self,
        span: Span,
        v: i64,
        spec: &OperandSpec,
        mnemonic: &str,
    ) -> Option<CheckedOperand> {
        if !self.constant_allowed(span, spec, mnemonic) {
            return None;
        }
        let width = spec
            .types
            .first()
            .map(|t| t.width())
            .unwrap_or(Width::Dword);
        if spec.types.contains(&DataType::Real) {
            return Some(CheckedOperand::Constant {
                value: ConstValue::Real(v as f32),
                width: Width::Dword,
            });
        }
        let (lo, hi) = match (spec.min, spec.max) {
            (Some(lo), Some(hi)) => (lo, hi),
            _ => DataType::union_range(&spec.types).unwrap_or((i64::MAX, i64::MIN)),
        };
        if !(lo..=hi).contains(&v) {
            self.report(
                Diagnostic::new(
                    Code::ConstantOutOfRange,
                    span,
                    format!(
                        "{v} does not fit {} of {mnemonic} ({})",
                        spec.name,
                        types_text(&spec.types)
                    ),
                )
                .label(format!("allowed: {lo}..{hi}")),
            );
            return None;
        }
        Some(CheckedOperand::Constant {
            value: ConstValue::Integer(v),
            width,
        })
    }

    #[allow(clippy::too_many_arguments)]
    fn variable_operand(
        &mut self,
        unit: usize,
        span: Span,
        prefix: Prefix,
        local: bool,
        name: Span,
        spec: &OperandSpec,
        mnemonic: &str,
    ) -> Option<CheckedOperand> {
        let var = self.variable(unit, local, name)?;
        // Borrowed from the target, not from `self` (no clone per operand).
        let target = self.target;
        let area = target.memory.area_by_slot(var.address.slot)?;
        let want = spec
            .types
            .first()
            .map(|t| t.width())
            .unwrap_or(Width::Dword);
        let shown = self.slice(name);
        let shown = if local {
            format!("#{shown}")
        } else {
            shown.to_string()
        };
        match prefix {
            Prefix::AddressOf => {
                if !spec.address_of {
                    self.report(
                        Diagnostic::new(Code::UseNotAllowed, span, format!("{} of {mnemonic} does not take an address (`&`)", spec.name))
                            .help("`&` is accepted where a pointer value is expected, as in `MOVD &MB24, MD4`"),
                    );
                    return None;
                }
                if !area.address_of || var.address.width != Width::Byte {
                    let why = if !area.address_of {
                        format!("area {} does not allow taking addresses", area.name)
                    } else {
                        format!(
                            "`{shown}` is a {}, and only BYTE variables have addresses",
                            var.address.width
                        )
                    };
                    self.report(
                        Diagnostic::new(
                            Code::UseNotAllowed,
                            span,
                            format!("cannot take the address of `{shown}`"),
                        )
                        .label(why)
                        .help("take the address of a byte in M, V, SM or L: `&MB24`"),
                    );
                    return None;
                }
                Some(CheckedOperand::Memory {
                    address: var.address,
                    use_: Use::AddressOf,
                    width: Width::Dword,
                })
            }
            Prefix::Pointer => {
                if !spec.pointer {
                    self.report(Diagnostic::new(
                        Code::UseNotAllowed,
                        span,
                        format!(
                            "{} of {mnemonic} cannot be accessed through a pointer (`*`)",
                            spec.name
                        ),
                    ));
                    return None;
                }
                if !area.holds_pointer || var.address.width != Width::Dword {
                    let why = if !area.holds_pointer {
                        format!("area {} cannot hold pointers", area.name)
                    } else {
                        format!("`{shown}` is a {}; a pointer is a DWORD", var.address.width)
                    };
                    self.report(
                        Diagnostic::new(
                            Code::UseNotAllowed,
                            span,
                            format!("`{shown}` cannot hold a pointer"),
                        )
                        .label(why)
                        .help("a pointer lives in a DWORD of M, V or L: `*MD4`"),
                    );
                    return None;
                }
                Some(CheckedOperand::Memory {
                    address: var.address,
                    use_: Use::Pointer,
                    width: want,
                })
            }
            Prefix::None => {
                if !spec.allows_area(&area.name) {
                    let list = spec.areas.as_deref().unwrap_or_default().join(", ");
                    self.report(
                        Diagnostic::new(
                            Code::AreaNotAllowed,
                            name,
                            format!("{} of {mnemonic} must be in area {list}", spec.name),
                        )
                        .label(format!("`{shown}` is in area {}", area.name)),
                    );
                    return None;
                }
                if var.address.width != want {
                    if want == Width::Bit && !area.allows(Width::Bit) {
                        let help = if area.kind == gutta_catalog::AreaKind::Timer
                            || area.kind == gutta_catalog::AreaKind::Counter
                        {
                            format!("{} holds only words; test it with a compare such as `LDW>= {shown}, 10`", area.name)
                        } else {
                            format!(
                                "{} allows {}",
                                area.name,
                                area.widths
                                    .iter()
                                    .map(|w| w.keyword())
                                    .collect::<Vec<_>>()
                                    .join(", ")
                            )
                        };
                        self.report(
                            Diagnostic::new(
                                Code::AreaNotAllowed,
                                name,
                                format!(
                                    "{mnemonic} needs a bit, and area {} has no bit access",
                                    area.name
                                ),
                            )
                            .label("not a bit")
                            .help(help),
                        );
                    } else {
                        self.report(
                            Diagnostic::new(
                                Code::WidthMismatch,
                                name,
                                format!(
                                    "{} of {mnemonic} is {}; `{shown}` is a {}",
                                    spec.name,
                                    want_text(want, &spec.types),
                                    var.address.width
                                ),
                            )
                            .label(format!(
                                "{} bits, expected {}",
                                var.address.width.bits(),
                                want.bits()
                            )),
                        );
                    }
                    return None;
                }
                if let Some(ty) = var.ty {
                    if !ty.accepted_by(&spec.types) {
                        self.report(
                            Diagnostic::new(
                                Code::TypeMismatch,
                                name,
                                format!(
                                    "{} of {mnemonic} takes {}; `{shown}` is {ty}",
                                    spec.name,
                                    types_text(&spec.types)
                                ),
                            )
                            .label(format!("declared {ty}")),
                        );
                        return None;
                    }
                }
                if spec.role.writes() && !area.writable {
                    self.report(
                        Diagnostic::new(
                            Code::WriteToReadOnly,
                            name,
                            format!(
                                "{mnemonic} writes {}, but area {} is read-only for programs",
                                spec.name, area.name
                            ),
                        )
                        .label(format!("`{shown}` cannot be written"))
                        .help(match area.kind {
                            gutta_catalog::AreaKind::Constant => {
                                "K holds the program's constants".to_string()
                            }
                            _ => {
                                format!("{} is refreshed from the terminals every scan", area.name)
                            }
                        }),
                    );
                    return None;
                }
                Some(CheckedOperand::Memory {
                    address: var.address,
                    use_: Use::Value,
                    width: want,
                })
            }
        }
    }
}

fn want_text(w: Width, types: &[DataType]) -> String {
    match w {
        Width::Bit => "a BOOL".to_string(),
        _ => format!("a {} ({})", w.keyword(), types_text(types)),
    }
}
