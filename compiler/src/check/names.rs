//! Names in operands resolved to variables: `#local` of the unit, a symbol, or a
//! direct address; with a diagnostic (and a suggestion) for a name that is none of
//! them. Records references for navigation. Knows no operand specs or prefixes.

use gutta_catalog::{Address, BlockKind, DataType};

use super::Checker;
use gutta_catalog::s7200::{S7200AreaKind, S7200Name};

use crate::diagnostics::{Code, Diagnostic, Label, Suggestion};
use crate::source::Span;

/// A variable before its use is applied: where it is, its declared type if any, and
/// the definition of the symbol or local it was named by (None for a direct address).
pub(super) struct Variable {
    pub address: Address,
    pub ty: Option<DataType>,
    pub declared: Option<usize>,
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
                declared: Some(def),
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
                let hint = crate::suggest::closest(text, cands.iter().map(String::as_str))
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
            if !self.sequence.s_symbols.contains(&key) {
                self.memory_use(name, address);
            }
            return Some(Variable {
                address,
                ty: None,
                declared: Some(def),
            });
        }
        if let Some(a) = self.predefined_name(text) {
            self.out.addresses.push((name, a));
            self.memory_use(name, a);
            return Some(Variable {
                address: a,
                ty: None,
                declared: None,
            });
        }
        if let Some(a) = self.l_temporary(name) {
            self.out.addresses.push((name, a));
            return Some(Variable {
                address: a,
                ty: None,
                declared: None,
            });
        }
        if self.looks_like_address(text) {
            let a = self.direct_address(name, None)?;
            self.out.addresses.push((name, a));
            self.memory_use(name, a);
            return Some(Variable {
                address: a,
                ty: None,
                declared: None,
            });
        }
        if let Some(s) = self.s_operand(name) {
            return s.map(|address| Variable {
                address,
                ty: None,
                declared: None,
            });
        }
        self.not_a_variable(name);
        None
    }

    /// A predefined name (`Conventions`: in a Micro/WIN export, Micro/WIN's system
    /// symbols such as `Always_On`) as its address; user symbols win.
    fn predefined_name(&self, text: &str) -> Option<Address> {
        *self.predefined.get(&text.to_ascii_uppercase())?
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
        if let Some(uses) = self.unknown_names.get_mut(&key) {
            uses.later.push(name);
            return;
        }
        let d = match gutta_catalog::s7200::s7200_name(text) {
            Some(s7) => s7200_name_diagnostic(name, text, s7, self.target),
            None => self.undefined_symbol(name, text),
        };
        self.unknown_names.insert(
            key,
            UnknownName {
                diagnostic: self.diags.len(),
                later: Vec::new(),
            },
        );
        self.report(d);
    }

    /// E0202 for a name that is nothing, with the closest symbol as a suggestion.
    fn undefined_symbol(&self, name: Span, text: &str) -> Diagnostic {
        let mut names: Vec<String> = self
            .symbols
            .values()
            .map(|(_, d)| self.out.definitions[*d].name.clone())
            .collect();
        // Predefined names are names too (in a Micro/WIN export `Alway_On` -> `Always_On`).
        names.extend(
            self.conventions
                .predefined_names
                .iter()
                .map(|p| p.name.clone()),
        );
        let hint = crate::suggest::closest(text, names.iter().map(String::as_str));
        let d = Diagnostic::new(
            Code::UndefinedSymbol,
            name,
            format!("undefined symbol `{text}`"),
        )
        .label("not a symbol, local or address");
        match hint {
            Some(s) => d.suggest(Suggestion::new(name, s)),
            None => d.help("declare it in SYMBOLS: `Name : ADDRESS`"),
        }
    }

    /// After the code is checked: each unknown name's one diagnostic counts and labels
    /// its other uses (the first [`MAX_USE_LABELS`]).
    pub(super) fn list_later_uses(&mut self) {
        for uses in self.unknown_names.values() {
            let Some(d) = self.diags.get_mut(uses.diagnostic) else {
                continue;
            };
            let n = uses.later.len();
            if n == 0 {
                continue;
            }
            d.message.push_str(&format!(
                " (also used {n} more time{}{})",
                if n == 1 { "" } else { "s" },
                if n > MAX_USE_LABELS {
                    format!(", the first {MAX_USE_LABELS} labelled")
                } else {
                    String::new()
                }
            ));
            for &span in uses.later.iter().take(MAX_USE_LABELS) {
                d.secondary.push(Label {
                    span,
                    message: Some("also used here".into()),
                });
            }
        }
    }
}

/// How many later uses of an unknown name get a label of their own.
pub(super) const MAX_USE_LABELS: usize = 5;

/// An unknown name's one diagnostic (index into the checker's list) and its later uses.
#[derive(Debug, Clone)]
pub(crate) struct UnknownName {
    pub diagnostic: usize,
    pub later: Vec<Span>,
}

/// E0221: an S7-200 area or Micro/WIN system symbol this target does not have.
fn s7200_name_diagnostic(
    name: Span,
    text: &str,
    s7: S7200Name,
    on: &gutta_catalog::Target,
) -> Diagnostic {
    let target = on.name();
    match s7 {
        S7200Name::Area(S7200AreaKind::SequenceRelay) => Diagnostic::new(
            Code::S7200Area,
            name,
            format!("`{text}` is in the S7-200's S area (sequence control relays); {target} has no area S"),
        )
        .label("no area S on this target")
        .help("keep step bits in M (`M10.0`) and set them with `S`/`R`"),
        S7200Name::Area(S7200AreaKind::Accumulator) => Diagnostic::new(
            Code::S7200Area,
            name,
            format!("`{text}` is an S7-200 accumulator; {target} has no accumulators"),
        )
        .label("no accumulators on this target")
        .help("use a word of M or V, or a local variable (`#tmp`) of the block"),
        S7200Name::SystemSymbol(s) => {
            // The target's own data says which bit the name stands for (its
            // ManagerVar.xml `MicroWin` attribute), as the Micro/WIN dialect reads it.
            // Else the S7-200 table's GUTTA address, where the target has it (the scan
            // times: the target names SMW4 `Last_Scan_Time`, Micro/WIN `Scan_Time`).
            let named = on
                .memory
                .microwin_system_bit(s.name)
                .map(|b| b.address.clone());
            let named_here = named.is_some();
            let here = named.or_else(|| {
                let a = s.gutta_address?;
                on.memory.parse_address(a).ok().map(|_| a.to_string())
            });
            let lacks = if here.is_some() { "name" } else { "register" };
            let d = Diagnostic::new(
                Code::S7200Area,
                name,
                format!(
                    "`{text}` is Micro/WIN's system symbol for the S7-200's {} ({}); {target} has no such {lacks}",
                    s.s7200_address, s.what
                ),
            );
            match here {
                Some(a) if !named_here => d
                    .label(format!("{a} on this target"))
                    .help(format!(
                        "declare it in SYMBOLS (`{} : {a}`): {target} keeps the same value there",
                        s.name
                    )),
                Some(a) => d.label(format!("{a} on this target")).help(format!(
                    "declare it in SYMBOLS (`{} : {a}`), or read the file as a Micro/WIN export \
                     (first line `// dialect: microwin`, or name it .awl), where Micro/WIN's \
                     system names are known",
                    s.name
                )),
                None => d
                    .label("no equivalent on this target")
                    .help(format!("{target} has no counterpart of the S7-200's {}", s.s7200_address)),
            }
        }
        S7200Name::SmartIo(io) => smart_io_diagnostic(name, text, io, on),
    }
}

/// E0221 for MicroWIN SMART's default I/O name (`CPU_Input0`) where it does not resolve:
/// outside the dialect, or past the target's I or Q area (docs/microwin.md, "MicroWIN
/// SMART's I/O symbols").
fn smart_io_diagnostic(
    name: Span,
    text: &str,
    io: gutta_catalog::s7200_io::SmartIoName,
    on: &gutta_catalog::Target,
) -> Diagnostic {
    let target = on.name();
    let what = io.pattern.what;
    let point = io.point;
    match io.address(&on.memory) {
        Ok(a) => {
            let here = on.memory.format_address(&a);
            Diagnostic::new(
                Code::S7200Area,
                name,
                format!("`{text}` is MicroWIN SMART's default symbol for {what} {point} ({here}); {target} has no such name"),
            )
            .label(format!("{here} on this target"))
            .help(format!(
                "declare it in SYMBOLS (`{text} : {here}`), or read the file as a Micro/WIN export \
                 (first line `// dialect: microwin`, or name it .awl), where SMART's I/O names are known"
            ))
        }
        Err(Some((area, size))) => {
            let at = io.address_text(&area);
            Diagnostic::new(
                Code::S7200Area,
                name,
                format!(
                    "`{text}` is MicroWIN SMART's default symbol for {what} {point}, {at}; {target}'s area {area} has {size} bytes, {area}0.0..{area}{}.7 ({what}s 0..{})",
                    size.saturating_sub(1),
                    (size * 8).saturating_sub(1)
                ),
            )
            .label(format!("past {area}{}.7", size.saturating_sub(1)))
            .help(format!("use an {what} {target} has, or select a PLC type with more with --plc or PLC_TYPE"))
        }
        Err(None) => Diagnostic::new(
            Code::S7200Area,
            name,
            format!("`{text}` is MicroWIN SMART's default symbol for {what} {point}; {target} has no {what}s"),
        )
        .label(format!("no {what}s on this target")),
    }
}
