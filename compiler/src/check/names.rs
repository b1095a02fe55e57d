//! Names in operands resolved to variables: `#local` of the unit, a symbol, or a
//! direct address; with a diagnostic (and a suggestion) for a name that is none of
//! them. Records references for navigation. Knows no operand specs or prefixes.

use gutta_catalog::{Address, BlockKind, DataType};

use super::Checker;
use crate::diagnostics::{Code, Diagnostic, Suggestion};
use crate::source::Span;

/// A variable before its use is applied: where it is, and its declared type if any.
pub(super) struct Variable {
    pub address: Address,
    pub ty: Option<DataType>,
}

impl Checker<'_> {
    /// Resolve a name operand (without prefix) to a variable: local (`#name`, when
    /// `local`), symbol or address.
    pub(super) fn variable(&mut self, unit: usize, local: bool, name: Span) -> Option<Variable> {
        if local {
            self.local_variable(unit, name)
        } else {
            self.global_variable(name)
        }
    }

    /// `#name`: a local of this unit.
    fn local_variable(&mut self, unit: usize, name: Span) -> Option<Variable> {
        let text = self.slice(name);
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
                    .map(|s| Suggestion::new(name, s).shown_as(format!("#{s}")));
                Diagnostic::new(
                    Code::UndefinedLocal,
                    name,
                    format!("this block declares no local `{text}`"),
                )
                .maybe_suggest(hint)
            }
        };
        self.report(d);
        None
    }

    /// A symbol or a direct address.
    fn global_variable(&mut self, name: Span) -> Option<Variable> {
        let text = self.slice(name);
        let key = text.to_ascii_uppercase();
        if let Some(&(address, def)) = self.symbols.get(&key) {
            self.reference(name, def);
            return Some(Variable { address, ty: None });
        }
        if let Some(a) = self.microwin_system_name(text) {
            self.out.addresses.push((name, a));
            return Some(Variable {
                address: a,
                ty: None,
            });
        }
        if self.looks_like_address(text) {
            let a = self.direct_address(name, None)?;
            self.out.addresses.push((name, a));
            return Some(Variable {
                address: a,
                ty: None,
            });
        }
        self.not_a_variable(name);
        None
    }

    /// In the Micro/WIN dialect, Micro/WIN's system symbol `text` (`Always_On`) as the
    /// target's address for it (the target's `MicroWin` attribute); user symbols win.
    fn microwin_system_name(&self, text: &str) -> Option<Address> {
        if !self.ast.microwin {
            return None;
        }
        let bit = self.target.memory.microwin_system_bit(text)?;
        self.target.memory.parse_address(&bit.address).ok()
    }

    /// A name that is no variable: a unit's, or nothing defined.
    fn not_a_variable(&mut self, name: Span) {
        let text = self.slice(name);
        let key = text.to_ascii_uppercase();
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
            return;
        }
        let names: Vec<String> = self
            .symbols
            .values()
            .map(|(_, d)| self.out.definitions[*d].name.clone())
            .collect();
        let hint = super::suggest::closest(text, names.iter().map(String::as_str));
        let d = Diagnostic::new(
            Code::UndefinedSymbol,
            name,
            format!("undefined symbol `{text}`"),
        )
        .label("not a symbol, local or address");
        self.report(match hint {
            Some(s) => d.suggest(Suggestion::new(name, s)),
            None => d.help("declare it in SYMBOLS: `Name : ADDRESS`"),
        });
    }
}
