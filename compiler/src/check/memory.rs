//! Variables in data operands, by prefix: `&byte` (address-of), `*holder` (through a
//! pointer) and the plain variable (area, width, declared type, writability). The
//! rules are `gutta_catalog::rules` (the verifier applies the same); this file only
//! says, in diagnostics, why a variable is refused. Names are resolved in `names.rs`.

use gutta_catalog::rules::{self, DataRules, IndirectRefusal};
use gutta_catalog::{Address, Area, AreaKind, DataType, OperandSpec, Width};

use super::names::Variable;
use super::operands::types_text;
use super::{CheckedOperand, Checker, Use};
use crate::diagnostics::{Code, Diagnostic, Fix};
use crate::source::Span;
use crate::syntax::ast::Prefix;

/// What a variable operand is checked against, for the per-prefix checks.
struct VariableSite<'s> {
    /// The whole operand (with its prefix).
    span: Span,
    /// The name without prefix.
    name: Span,
    /// The name as written, `#` included for a local.
    shown: String,
    spec: &'s OperandSpec,
    rules: DataRules<'s>,
    mnemonic: &'s str,
}

impl Checker<'_> {
    /// A variable operand: resolve the name, then check it for its prefix.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn variable_operand(
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
        let text = self.slice(name);
        let site = VariableSite {
            span,
            name,
            shown: if local {
                format!("#{text}")
            } else {
                text.to_string()
            },
            spec,
            rules: DataRules::from_spec(spec),
            mnemonic,
        };
        match prefix {
            Prefix::AddressOf => self.address_of_operand(&site, &var, area),
            Prefix::Pointer => self.pointer_operand(&site, &var, area),
            Prefix::None => self.value_operand(&site, &var, area),
        }
    }

    /// `&MB24`: the pointer value of a byte, where the operand reads a DWORD.
    fn address_of_operand(
        &mut self,
        site: &VariableSite<'_>,
        var: &Variable,
        area: &Area,
    ) -> Option<CheckedOperand> {
        let (spec, mnemonic, shown) = (site.spec, site.mnemonic, &site.shown);
        if !site.rules.takes_address_of() {
            self.report(
                Diagnostic::new(
                    Code::UseNotAllowed,
                    site.span,
                    format!("{} of {mnemonic} does not take an address (`&`)", spec.name),
                )
                .help("`&` is accepted where a pointer value is expected, as in `MOVD &MB24, MD4`"),
            );
            return None;
        }
        if let Err(refusal) = rules::address_of_target(area, var.address.width) {
            let why = match refusal {
                IndirectRefusal::Area => {
                    format!("area {} does not allow taking addresses", area.name)
                }
                IndirectRefusal::Width => format!(
                    "`{shown}` is a {}, and only BYTE variables have addresses",
                    var.address.width
                ),
            };
            self.report(
                Diagnostic::new(
                    Code::UseNotAllowed,
                    site.span,
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

    /// `*MD4`: the variable the pointer held in a DWORD points to.
    fn pointer_operand(
        &mut self,
        site: &VariableSite<'_>,
        var: &Variable,
        area: &Area,
    ) -> Option<CheckedOperand> {
        let (spec, mnemonic, shown) = (site.spec, site.mnemonic, &site.shown);
        if !site.rules.pointer {
            self.report(Diagnostic::new(
                Code::UseNotAllowed,
                site.span,
                format!(
                    "{} of {mnemonic} cannot be accessed through a pointer (`*`)",
                    spec.name
                ),
            ));
            return None;
        }
        if let Err(refusal) = rules::pointer_holder(area, var.address.width) {
            let why = match refusal {
                IndirectRefusal::Area => format!("area {} cannot hold pointers", area.name),
                IndirectRefusal::Width => {
                    format!("`{shown}` is a {}; a pointer is a DWORD", var.address.width)
                }
            };
            self.report(
                Diagnostic::new(
                    Code::UseNotAllowed,
                    site.span,
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
            width: site.rules.width,
        })
    }

    /// A plain variable: an area the operand accepts, the access width, a declared
    /// type the operand takes, and writable where the instruction writes.
    fn value_operand(
        &mut self,
        site: &VariableSite<'_>,
        var: &Variable,
        area: &Area,
    ) -> Option<CheckedOperand> {
        let accepted = self.area_accepted(site, area)
            && self.width_matches(site, var, area)
            && self.type_accepted(site, var)
            && self.writable(site, area);
        accepted.then_some(CheckedOperand::Memory {
            address: var.address,
            use_: Use::Value,
            width: site.rules.width,
        })
    }

    fn area_accepted(&mut self, site: &VariableSite<'_>, area: &Area) -> bool {
        if site.rules.accepts_area(area) {
            return true;
        }
        let list = site.spec.areas.as_deref().unwrap_or_default().join(", ");
        self.report(
            Diagnostic::new(
                Code::AreaNotAllowed,
                site.name,
                format!(
                    "{} of {} must be in area {list}",
                    site.spec.name, site.mnemonic
                ),
            )
            .label(format!("`{}` is in area {}", site.shown, area.name)),
        );
        false
    }

    fn width_matches(&mut self, site: &VariableSite<'_>, var: &Variable, area: &Area) -> bool {
        let want = site.rules.width;
        let (spec, mnemonic, shown) = (site.spec, site.mnemonic, &site.shown);
        if var.address.width == want {
            return true;
        }
        if want == Width::Bit && !area.allows(Width::Bit) {
            let help = if area.kind == AreaKind::Timer || area.kind == AreaKind::Counter {
                format!(
                    "{} holds only words; test it with a compare such as `LDW>= {shown}, 10`",
                    area.name
                )
            } else {
                let widths: Vec<&str> = area.widths.iter().map(|w| w.keyword()).collect();
                format!("{} allows {}", area.name, widths.join(", "))
            };
            self.report(
                Diagnostic::new(
                    Code::AreaNotAllowed,
                    site.name,
                    format!(
                        "{mnemonic} needs a bit, and area {} has no bit access",
                        area.name
                    ),
                )
                .label("not a bit")
                .help(help),
            );
        } else {
            let have = var.address.width.bits();
            let mut d = Diagnostic::new(
                Code::WidthMismatch,
                site.name,
                format!(
                    "{} of {mnemonic} is {}; `{shown}` is a {}",
                    spec.name,
                    want_text(want, &spec.types),
                    var.address.width
                ),
            )
            .label(format!(
                "{}, expected {}",
                gutta_catalog::plural::count(have, "bit"),
                want.bits()
            ))
            .help(self.width_help(site, want));
            if let Some(def) = var.declared {
                d = d.with_secondary(self.out.definitions[def].span, self.declared_as(shown, var));
            } else if let Some(fix) = self.same_byte_fix(site, var, area, want) {
                d = d.fix(fix);
            }
            self.report(d);
        }
        false
    }

    /// E0302's fix, where there is exactly one: a direct byte, word or double word
    /// address (not a symbol, a local or a bit) of an area that has the wanted width
    /// becomes the address of that width at the same byte (`MB4` -> `MW4` for MOVW),
    /// when that address exists on the target. A bit gets none: which byte or word
    /// was meant is not known.
    fn same_byte_fix(
        &self,
        site: &VariableSite<'_>,
        var: &Variable,
        area: &Area,
        want: Width,
    ) -> Option<Fix> {
        if want == Width::Bit || var.address.width == Width::Bit || !area.allows(want) {
            return None;
        }
        let memory = &self.target.memory;
        // Only an address written as the target writes it (not a symbol, and not one
        // a dialect renamed).
        if memory.parse_address(self.slice(site.name)).ok() != Some(var.address) {
            return None;
        }
        let wanted = Address {
            width: want,
            bit: 0,
            ..var.address
        };
        let text = memory.format_address(&wanted);
        // The address must exist (the area is long enough) and read back the same.
        if memory.parse_address(&text).ok() != Some(wanted) {
            return None;
        }
        Some(Fix {
            title: format!(
                "Replace `{}` with `{text}` (the {} at the same byte)",
                site.shown,
                width_words(want).trim_start_matches("a ")
            ),
            edits: vec![(site.name, text)],
        })
    }

    /// E0302's help: what the operand must be, as the addresses of the areas the
    /// operand accepts at that width (`OUT of INCW takes a word: QW, MW, SMW, LW, T, C,
    /// or a symbol declared as one`). K is left out: constants are written as numbers.
    fn width_help(&self, site: &VariableSite<'_>, want: Width) -> String {
        let places: Vec<String> = self
            .target
            .memory
            .areas
            .iter()
            .filter(|a| {
                a.kind != AreaKind::Constant
                    && a.allows(want)
                    && site.rules.accepts_area(a)
                    && site.rules.may_write(a)
            })
            .map(|a| match (a.fixed_width(), want.letter()) {
                (None, Some(letter)) => format!("{}{letter}", a.name),
                _ => a.name.clone(),
            })
            .collect();
        let sep = if want == Width::Bit { " of" } else { ":" };
        format!(
            "{} of {} takes {}{sep} {}, or a symbol declared as one",
            site.spec.name,
            site.mnemonic,
            width_words(want),
            places.join(", ")
        )
    }

    /// An address the operand accepts at `width`, for help lines: in M when it may be
    /// (`MW0`, `M0.0`), else in the first area it accepts (`T0`); never in K.
    pub(super) fn example_place(&self, rules: &DataRules<'_>, width: Width) -> Option<String> {
        let fits = |a: &&Area| {
            a.kind != AreaKind::Constant
                && a.allows(width)
                && rules.accepts_area(a)
                && rules.may_write(a)
        };
        let areas = &self.target.memory.areas;
        let area = areas
            .iter()
            .filter(fits)
            .find(|a| a.kind == AreaKind::Memory)
            .or_else(|| areas.iter().find(fits))?;
        Some(match (width, area.fixed_width()) {
            (Width::Bit, _) => format!("{}0.0", area.name),
            (_, Some(_)) => format!("{}0", area.name),
            (w, None) => format!("{}{}0", area.name, w.letter().unwrap_or('?')),
        })
    }

    /// The label at a symbol's or local's declaration: what it was declared as
    /// (`` `Running` is declared here as M0.0 ``, `` `#n` is declared here as BYTE ``).
    fn declared_as(&self, shown: &str, var: &Variable) -> String {
        let what = match var.ty {
            Some(ty) => ty.to_string(),
            None => self.target.memory.format_address(&var.address),
        };
        format!("`{shown}` is declared here as {what}")
    }

    fn type_accepted(&mut self, site: &VariableSite<'_>, var: &Variable) -> bool {
        let Some(ty) = var.ty else { return true };
        if ty.accepted_by(&site.spec.types) {
            return true;
        }
        self.report(
            Diagnostic::new(
                Code::TypeMismatch,
                site.name,
                format!(
                    "{} of {} takes {}; `{}` is {ty}",
                    site.spec.name,
                    site.mnemonic,
                    types_text(&site.spec.types),
                    site.shown
                ),
            )
            .label(format!("declared {ty}")),
        );
        false
    }

    fn writable(&mut self, site: &VariableSite<'_>, area: &Area) -> bool {
        if site.rules.may_write(area) {
            return true;
        }
        self.report(
            Diagnostic::new(
                Code::WriteToReadOnly,
                site.name,
                format!(
                    "{} writes {}, but area {} is read-only for programs",
                    site.mnemonic, site.spec.name, area.name
                ),
            )
            .label(format!("`{}` cannot be written", site.shown))
            .help(match area.kind {
                AreaKind::Constant => "K holds the program's constants".to_string(),
                _ => format!("{} is refreshed from the terminals every scan", area.name),
            }),
        );
        false
    }
}

fn want_text(w: Width, types: &[DataType]) -> String {
    match w {
        Width::Bit => "a BOOL".to_string(),
        _ => format!("a {} ({})", w.keyword(), types_text(types)),
    }
}

/// A width in words for help lines: `a bit`, `a byte`, `a word`, `a double word`.
pub(super) fn width_words(w: Width) -> &'static str {
    match w {
        Width::Bit => "a bit",
        Width::Byte => "a byte",
        Width::Word => "a word",
        Width::Dword => "a double word",
    }
}
