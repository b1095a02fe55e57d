//! A parsed test file against the program under test: every variable to an address and
//! the type its values are read and shown in, every value to the variable's bits,
//! checked to fit (E0805, E0806, E0809). The result, a [`Plan`], is what the runner
//! executes: it holds no names to look up and no text to parse.

use gutta_catalog::s7200_io::smart_io_name;
use gutta_catalog::{stdlib, Address, ValueFormat, Width};
use gutta_compiler::diagnostics::{Code, Diagnostic};
use gutta_compiler::source::{LineIndex, SourceFile, Span};

use crate::syntax::{
    Assignment, CompareOp, Comparison, Literal, LiteralValue, StatementKind, TestFile, VarRef,
};
use crate::ProgramUnderTest;

/// A variable a test mentions.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Variable {
    /// The symbol's name as declared, when the test named a symbol.
    pub symbol: Option<String>,
    pub address: Address,
    /// The address in canonical form (`MW20`, `Q0.0`).
    pub canonical: String,
    /// How its values are compared and shown: the symbol's type, else the width's.
    pub format: ValueFormat,
}

impl Variable {
    /// `Lamp (Q0.0)` for a symbol, `MW20` for an address.
    pub fn label(&self) -> String {
        match &self.symbol {
            Some(name) => format!("{name} ({})", self.canonical),
            None => self.canonical.clone(),
        }
    }

    /// The symbol's name, else the address.
    pub fn name(&self) -> &str {
        self.symbol.as_deref().unwrap_or(&self.canonical)
    }

    /// A raw value in the variable's type.
    pub fn show(&self, raw: u32) -> String {
        self.format.show(raw, self.address.width)
    }
}

/// Index of a variable in its test's [`PlannedTest::vars`].
pub type VarId = usize;

/// A value for a variable.
#[derive(Debug, Clone, PartialEq)]
pub enum Expected {
    /// The variable's raw bits.
    Bits(u32),
    /// Consecutive bytes from the variable's byte on (a text).
    Bytes(Vec<u8>),
}

/// One resolved comparison.
#[derive(Debug, Clone)]
pub struct Check {
    pub var: VarId,
    pub op: CompareOp,
    pub expected: Expected,
    /// The expected value as the report shows it.
    pub shown: String,
}

/// What a statement does, resolved.
#[derive(Debug, Clone)]
pub enum Step {
    Set(Vec<(VarId, Expected)>),
    Force(Vec<(VarId, u32)>),
    /// Empty: every force.
    Unforce(Vec<VarId>),
    Scan(u32),
    /// Scans, as many as `ADVANCE`'s time needs at the file's scan time.
    Advance {
        ms: u32,
        scans: u32,
    },
    Expect(Vec<Check>),
    ExpectFault(u8),
    ExpectMode(bool),
    Until {
        checks: Vec<Check>,
        within: u32,
    },
    Reset,
    Run,
    Stop,
}

/// A statement of a planned test.
#[derive(Debug, Clone)]
pub struct PlannedStatement {
    pub span: Span,
    /// 1-based line in the test file.
    pub line: u32,
    pub step: Step,
}

/// A test, ready to run.
#[derive(Debug, Clone)]
pub struct PlannedTest {
    pub name: String,
    pub line: u32,
    /// Every variable the test mentions, in order of first mention.
    pub vars: Vec<Variable>,
    pub statements: Vec<PlannedStatement>,
}

/// A test file, ready to run.
#[derive(Debug, Clone)]
pub struct Plan {
    pub scan_ms: u32,
    pub watchdog: Option<u64>,
    pub tests: Vec<PlannedTest>,
    /// Warnings of the resolution (W0803: a comparison that is always true).
    pub warnings: Vec<Diagnostic>,
}

/// The scan time without `SCAN_TIME`.
pub const DEFAULT_SCAN_MS: u32 = 10;

/// Resolve `parsed` (the text of `file`) against `program`; the errors of every
/// variable or value that does not fit (no plan then). Warnings go with the plan.
pub fn plan(
    file: &SourceFile,
    parsed: &TestFile,
    program: &ProgramUnderTest,
) -> Result<Plan, Vec<Diagnostic>> {
    let index = LineIndex::new(&file.text);
    let line = |span: Span| index.line_col(&file.text, span.start as usize).line;
    let scan_ms = parsed
        .header
        .scan_time_ms
        .map_or(DEFAULT_SCAN_MS, |(ms, _)| ms);
    let mut diagnostics = Vec::new();
    let mut tests = Vec::new();
    for test in &parsed.tests {
        let mut r = Resolver {
            program,
            vars: Vec::new(),
            diagnostics: &mut diagnostics,
        };
        let mut statements = Vec::new();
        for s in &test.statements {
            if let Some(step) = r.step(&s.kind, scan_ms) {
                statements.push(PlannedStatement {
                    span: s.span,
                    line: line(s.span),
                    step,
                });
            }
        }
        tests.push(PlannedTest {
            name: test.name.clone(),
            line: line(test.span),
            vars: r.vars,
            statements,
        });
    }
    let (errors, warnings): (Vec<Diagnostic>, Vec<Diagnostic>) =
        diagnostics.into_iter().partition(Diagnostic::is_error);
    if errors.is_empty() {
        Ok(Plan {
            scan_ms,
            watchdog: parsed.header.watchdog.map(|(w, _)| w),
            tests,
            warnings,
        })
    } else {
        Err(errors)
    }
}

struct Resolver<'a> {
    program: &'a ProgramUnderTest,
    vars: Vec<Variable>,
    diagnostics: &'a mut Vec<Diagnostic>,
}

impl Resolver<'_> {
    fn step(&mut self, kind: &StatementKind, scan_ms: u32) -> Option<Step> {
        Some(match kind {
            StatementKind::Set(list) => Step::Set(self.assignments(list, false)?),
            StatementKind::Force(list) => {
                let resolved = self.assignments(list, true)?;
                let bits = resolved
                    .into_iter()
                    .filter_map(|(v, e)| match e {
                        Expected::Bits(b) => Some((v, b)),
                        Expected::Bytes(_) => None,
                    })
                    .collect();
                Step::Force(bits)
            }
            StatementKind::Unforce(vars) => {
                let ids: Vec<Option<VarId>> = vars.iter().map(|v| self.var(v)).collect();
                Step::Unforce(ids.into_iter().collect::<Option<Vec<_>>>()?)
            }
            StatementKind::Scan(n) => Step::Scan(*n),
            StatementKind::Advance(ms) => Step::Advance {
                ms: *ms,
                scans: ms.div_ceil(scan_ms),
            },
            StatementKind::Expect(list) => Step::Expect(self.checks(list)?),
            StatementKind::ExpectFault(code) => Step::ExpectFault(*code),
            StatementKind::ExpectMode(run) => Step::ExpectMode(*run),
            StatementKind::Until { conditions, within } => Step::Until {
                checks: self.checks(conditions)?,
                within: *within,
            },
            StatementKind::Reset => Step::Reset,
            StatementKind::Run => Step::Run,
            StatementKind::Stop => Step::Stop,
        })
    }

    fn assignments(&mut self, list: &[Assignment], force: bool) -> Option<Vec<(VarId, Expected)>> {
        let resolved: Vec<Option<(VarId, Expected)>> = list
            .iter()
            .map(|a| {
                let id = self.var(&a.var)?;
                let var = &self.vars[id];
                if force && !self.program.target.memory.can_force(var.address.slot) {
                    let forcing = self.forcing_areas();
                    self.diagnostics.push(
                        Diagnostic::new(
                            Code::TestValueMismatch,
                            a.var.span,
                            format!("{} cannot be forced", var.label()),
                        )
                        .help(format!(
                            "only {forcing} can be forced; SET writes any variable"
                        )),
                    );
                    return None;
                }
                let expected = self.value(id, CompareOp::Eq, &a.value)?;
                if force && matches!(expected, Expected::Bytes(_)) {
                    self.mismatch(a.value.span, "FORCE takes a number, not a text".into());
                    return None;
                }
                Some((id, expected))
            })
            .collect();
        resolved.into_iter().collect()
    }

    fn checks(&mut self, list: &[Comparison]) -> Option<Vec<Check>> {
        let resolved: Vec<Option<Check>> = list
            .iter()
            .map(|c| {
                let id = self.var(&c.var)?;
                let expected = self.value(id, c.op, &c.value)?;
                let var = &self.vars[id];
                let shown = match &expected {
                    Expected::Bits(bits) => var.show(*bits),
                    Expected::Bytes(bytes) => show_bytes(bytes),
                };
                if let Some(why) = always_true(var, c.op, &expected) {
                    self.diagnostics.push(
                        Diagnostic::new(
                            Code::ComparisonAlwaysTrue,
                            c.span,
                            format!(
                                "`{} {} {shown}` is always true: {why}",
                                var.name(),
                                c.op.as_str()
                            ),
                        )
                        .label("always true")
                        .help("compare with the value the test is about; this comparison checks nothing"),
                    );
                }
                Some(Check {
                    var: id,
                    op: c.op,
                    expected,
                    shown,
                })
            })
            .collect();
        resolved.into_iter().collect()
    }

    fn forcing_areas(&self) -> String {
        let memory = &self.program.target.memory;
        let names: Vec<String> = memory
            .forcing
            .iter()
            .filter_map(|slot| memory.areas.iter().find(|a| a.slot == *slot))
            .map(|a| a.name.clone())
            .collect();
        if names.is_empty() {
            format!("no area of {}", self.program.target.name())
        } else {
            format!("variables of {}", names.join(" and "))
        }
    }

    /// The variable `v` names, added to the test's list on first mention.
    fn var(&mut self, v: &VarRef) -> Option<VarId> {
        let variable = match self.lookup(&v.name) {
            Ok(var) => var,
            Err(d) => {
                self.diagnostics.push(d(v.span));
                return None;
            }
        };
        if let Some(i) = self
            .vars
            .iter()
            .position(|x| x.address == variable.address && x.format == variable.format)
        {
            return Some(i);
        }
        self.vars.push(variable);
        Some(self.vars.len() - 1)
    }

    #[allow(clippy::type_complexity)]
    fn lookup(&self, name: &str) -> Result<Variable, Box<dyn Fn(Span) -> Diagnostic>> {
        let target = &self.program.target;
        let memory = &target.memory;
        if let Some(symbol) = self.program.symbols.get(name) {
            if let Ok(address) = memory.parse_address(&symbol.address) {
                return Ok(Variable {
                    symbol: Some(symbol.name.clone()),
                    canonical: memory.format_address(&address),
                    format: symbol.format(address.width),
                    address,
                });
            }
        }
        let error = match memory.parse_address(name) {
            Ok(address) => {
                return Ok(Variable {
                    symbol: None,
                    canonical: memory.format_address(&address),
                    format: ValueFormat::default_for(address.width),
                    address,
                })
            }
            Err(e) => e,
        };
        if self.program.microwin {
            // Micro/WIN's system symbols, and MicroWIN SMART's default I/O names
            // (`CPU_Input0`) for the bits the target has, as the dialect reads them.
            let system = memory
                .microwin_system_bit(name)
                .and_then(|bit| memory.parse_address(&bit.address).ok());
            let io = || smart_io_name(name).and_then(|io| io.address(memory).ok());
            if let Some(address) = system.or_else(io) {
                return Ok(Variable {
                    symbol: Some(name.to_string()),
                    canonical: memory.format_address(&address),
                    format: ValueFormat::default_for(address.width),
                    address,
                });
            }
        }
        let target_name = target.name().to_string();
        let name = name.to_string();
        if gutta_catalog::is_address_shaped(&name) {
            let message = format!("`{name}` is no address on {target_name}: {error}");
            let elsewhere: Vec<&str> = stdlib::names()
                .filter(|plc| {
                    stdlib::shared(plc).is_ok_and(|t| t.memory.parse_address(&name).is_ok())
                })
                .collect();
            let help = (!elsewhere.is_empty()).then(|| {
                format!(
                    "it exists on {}; `PLC_TYPE` in the test file or the program chooses the PLC type",
                    elsewhere.join(", ")
                )
            });
            return Err(Box::new(move |span| {
                Diagnostic::new(Code::UnknownTestVariable, span, message.clone())
                    .label(format!("not on {target_name}"))
                    .maybe_help(help.clone())
            }));
        }
        let similar: Vec<String> = self
            .program
            .symbols
            .similar(&name)
            .into_iter()
            .map(|s| format!("`{s}`"))
            .collect();
        let help = if similar.is_empty() {
            format!(
                "variables are the program's symbols ({} declared) or addresses of {target_name} (MW20, Q0.0)",
                self.program.symbols.symbols.len()
            )
        } else {
            format!("did you mean {}?", similar.join(" or "))
        };
        let message = format!("`{name}` is neither a symbol of the program nor an address");
        Err(Box::new(move |span| {
            Diagnostic::new(Code::UnknownTestVariable, span, message.clone())
                .label("no such variable")
                .help(help.clone())
        }))
    }

    fn mismatch(&mut self, span: Span, message: String) {
        self.diagnostics
            .push(Diagnostic::new(Code::TestValueMismatch, span, message));
    }

    /// `literal` as a value of variable `id` for `op`.
    fn value(&mut self, id: VarId, op: CompareOp, literal: &Literal) -> Option<Expected> {
        let var = self.vars[id].clone();
        match value_bits(&var, op, &literal.value) {
            Ok(e) => Some(e),
            Err(message) => {
                self.diagnostics.push(
                    Diagnostic::new(Code::TestValueMismatch, literal.span, message)
                        .label(format!("not a value of {}", type_name(&var)))
                        .help(type_help(&var)),
                );
                None
            }
        }
    }
}

/// What values the variable takes, for the help of E0806.
fn type_help(var: &Variable) -> String {
    let width = var.address.width;
    let (low, high) = signed_range(width);
    let range = match var.format {
        ValueFormat::Bool => "0 or 1 (TRUE, FALSE)".to_string(),
        ValueFormat::Real => "a REAL such as 21.5, -3, 1e3".to_string(),
        ValueFormat::Signed => format!("an integer {low}..{high}"),
        ValueFormat::Unsigned | ValueFormat::Hex => {
            format!("an integer 0..{}", unsigned_max(width))
        }
    };
    format!("{} is {}: it takes {range}", var.label(), type_name(var))
}

/// The type a variable's values are read in: `BOOL`, `INT`, `WORD`, `REAL`...
pub fn type_name(var: &Variable) -> &'static str {
    match (var.format, var.address.width) {
        (ValueFormat::Bool, _) => "BOOL",
        (ValueFormat::Real, _) => "REAL",
        (ValueFormat::Signed, Width::Byte) => "SINT",
        (ValueFormat::Signed, Width::Word) => "INT",
        (ValueFormat::Signed, _) => "DINT",
        (_, Width::Byte) => "BYTE",
        (_, Width::Word) => "WORD",
        (_, _) => "DWORD",
    }
}

fn signed_range(width: Width) -> (i64, i64) {
    let bits = width.bits();
    if bits == 1 {
        return (0, 1);
    }
    (-(1i64 << (bits - 1)), (1i64 << (bits - 1)) - 1)
}

fn unsigned_max(width: Width) -> i64 {
    (1i64 << width.bits()) - 1
}

fn mask(width: Width) -> u32 {
    match width.bits() {
        32 => u32::MAX,
        bits => (1u32 << bits) - 1,
    }
}

/// A literal as the bits of `var`, for a comparison `op` (`=` for SET and FORCE).
/// Ordered comparisons need the value in the variable's own reading (signed or not).
pub fn value_bits(var: &Variable, op: CompareOp, value: &LiteralValue) -> Result<Expected, String> {
    let width = var.address.width;
    let ty = type_name(var);
    let label = var.label();
    match (value, var.format) {
        (LiteralValue::Text(bytes), _) => {
            if width != Width::Byte {
                return Err(format!(
                    "a text needs a byte variable (MB40), not {label} ({ty})"
                ));
            }
            if !matches!(op, CompareOp::Eq | CompareOp::Ne) {
                return Err("a text is compared with `=` or `<>` only".into());
            }
            Ok(Expected::Bytes(bytes.clone()))
        }
        (LiteralValue::Bool(b), ValueFormat::Bool) => Ok(Expected::Bits(u32::from(*b))),
        (LiteralValue::Bool(b), _) => Err(format!(
            "{} is a BOOL value; {label} is {ty}",
            if *b { "TRUE" } else { "FALSE" }
        )),
        (LiteralValue::Real(v), ValueFormat::Real) => real_bits(*v),
        (LiteralValue::Real(v), _) => Err(format!("{v} is a REAL; {label} is {ty}")),
        (LiteralValue::Integer { value, based }, ValueFormat::Real) => {
            if *based {
                u32::try_from(*value)
                    .map(Expected::Bits)
                    .map_err(|_| format!("{value} does not fit the 32 bits of {label}"))
            } else {
                real_bits(*value as f64)
            }
        }
        (LiteralValue::Integer { value, .. }, format) => {
            let (low, high) = signed_range(width);
            let umax = unsigned_max(width);
            let ordered = !matches!(op, CompareOp::Eq | CompareOp::Ne);
            let fits = match format {
                ValueFormat::Bool => (0..=1).contains(value),
                ValueFormat::Signed if ordered => (low..=high).contains(value),
                ValueFormat::Unsigned | ValueFormat::Hex if ordered => (0..=umax).contains(value),
                _ => (low..=umax).contains(value),
            };
            if fits {
                Ok(Expected::Bits((*value as u32) & mask(width)))
            } else if format == ValueFormat::Bool {
                Err(format!(
                    "{value} is not a BOOL value (0, 1, TRUE, FALSE); {label} is a bit"
                ))
            } else {
                Err(format!("{value} does not fit {label} ({ty})"))
            }
        }
    }
}

fn real_bits(v: f64) -> Result<Expected, String> {
    let single = v as f32;
    if single.is_infinite() && v.is_finite() {
        return Err(format!(
            "{v} does not fit a REAL (-3.4028235e38..3.4028235e38)"
        ));
    }
    Ok(Expected::Bits(single.to_bits()))
}

/// Why `var op expected` holds whatever value `var` has, or `None` when it can fail:
/// `>=` its type's least value or `<=` its greatest (a REAL can be NaN: never).
pub fn always_true(var: &Variable, op: CompareOp, expected: &Expected) -> Option<String> {
    let Expected::Bits(bits) = expected else {
        return None;
    };
    let width = var.address.width;
    let (least, greatest) = match var.format {
        ValueFormat::Real => return None,
        ValueFormat::Bool => (0, 1),
        ValueFormat::Signed => signed_range(width),
        ValueFormat::Unsigned | ValueFormat::Hex => (0, unsigned_max(width)),
    };
    let m = mask(width);
    let value = match var.format {
        ValueFormat::Signed => {
            let shift = 32 - width.bits();
            i64::from((((bits & m) << shift) as i32) >> shift)
        }
        _ => i64::from(bits & m),
    };
    let ty = type_name(var);
    let label = var.label();
    match op {
        CompareOp::Ge if value <= least => Some(format!(
            "{label} is {ty}, never less than {}",
            var.show(least as u32)
        )),
        CompareOp::Le if value >= greatest => Some(format!(
            "{label} is {ty}, never greater than {}",
            var.show(greatest as u32)
        )),
        _ => None,
    }
}

/// Bytes as a quoted text, others escaped.
pub fn show_bytes(bytes: &[u8]) -> String {
    let text: String = bytes.iter().map(|&b| char::from(b)).collect();
    format!("{text:?}")
}

/// Compare a variable's raw value with the expected bits in its type.
pub fn compare(var: &Variable, actual: u32, expected: u32) -> Option<std::cmp::Ordering> {
    let width = var.address.width;
    let m = mask(width);
    let (a, e) = (actual & m, expected & m);
    match var.format {
        ValueFormat::Real => f32::from_bits(a).partial_cmp(&f32::from_bits(e)),
        ValueFormat::Signed => {
            let shift = 32 - width.bits();
            let sa = ((a << shift) as i32) >> shift;
            let se = ((e << shift) as i32) >> shift;
            Some(sa.cmp(&se))
        }
        _ => Some(a.cmp(&e)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn var(address: &str, format: ValueFormat) -> Variable {
        let target = stdlib::shared(stdlib::DEFAULT).expect("default target");
        let address = target.memory.parse_address(address).expect("address");
        Variable {
            symbol: None,
            canonical: target.memory.format_address(&address),
            format,
            address,
        }
    }

    #[test]
    fn values_fit_the_variable_type() {
        let int = var("MW20", ValueFormat::Signed);
        let int_value = |v: i64, op| {
            value_bits(
                &int,
                op,
                &LiteralValue::Integer {
                    value: v,
                    based: false,
                },
            )
        };
        assert_eq!(int_value(-5, CompareOp::Eq), Ok(Expected::Bits(0xFFFB)));
        assert_eq!(int_value(65535, CompareOp::Eq), Ok(Expected::Bits(0xFFFF)));
        assert!(
            int_value(65535, CompareOp::Lt).is_err_and(|e| e.contains("does not fit MW20 (INT)"))
        );
        assert!(int_value(65536, CompareOp::Eq).is_err());
        assert!(value_bits(&int, CompareOp::Eq, &LiteralValue::Real(1.5))
            .is_err_and(|e| e.contains("REAL")));
        let real = var("MD8", ValueFormat::Real);
        assert_eq!(
            value_bits(
                &real,
                CompareOp::Eq,
                &LiteralValue::Integer {
                    value: 20,
                    based: false
                }
            ),
            Ok(Expected::Bits(20.0f32.to_bits()))
        );
        let bit = var("Q0.0", ValueFormat::Bool);
        assert!(value_bits(
            &bit,
            CompareOp::Eq,
            &LiteralValue::Integer {
                value: 2,
                based: false
            }
        )
        .is_err());
        assert!(value_bits(&bit, CompareOp::Eq, &LiteralValue::Text(b"a".to_vec())).is_err());
    }

    #[test]
    fn a_comparison_that_cannot_fail_says_why() {
        let holds = |var: &Variable, op, v: i64| {
            let literal = LiteralValue::Integer {
                value: v,
                based: false,
            };
            let expected = value_bits(var, op, &literal).expect("fits");
            always_true(var, op, &expected)
        };
        let bit = var("Q0.0", ValueFormat::Bool);
        let byte = var("MB4", ValueFormat::Unsigned);
        let int = var("MW20", ValueFormat::Signed);
        let word = var("MW20", ValueFormat::Unsigned);
        let dword = var("MD8", ValueFormat::Unsigned);
        assert_eq!(
            holds(&bit, CompareOp::Ge, 0).as_deref(),
            Some("Q0.0 is BOOL, never less than 0")
        );
        assert!(holds(&bit, CompareOp::Le, 1).is_some());
        assert!(holds(&bit, CompareOp::Ge, 1).is_none());
        assert!(holds(&bit, CompareOp::Eq, 0).is_none());
        assert!(holds(&byte, CompareOp::Ge, 0).is_some());
        assert_eq!(
            holds(&byte, CompareOp::Le, 255).as_deref(),
            Some("MB4 is BYTE, never greater than 255")
        );
        assert!(holds(&byte, CompareOp::Le, 254).is_none());
        assert!(holds(&byte, CompareOp::Gt, 0).is_none());
        assert!(holds(&int, CompareOp::Ge, 0).is_none());
        assert!(holds(&int, CompareOp::Ge, -32768).is_some());
        assert!(holds(&int, CompareOp::Le, 32767).is_some());
        assert!(holds(&word, CompareOp::Ge, 0).is_some());
        assert!(holds(&dword, CompareOp::Le, 4_294_967_295).is_some());
        let real = var("MD8", ValueFormat::Real);
        let expected =
            value_bits(&real, CompareOp::Ge, &LiteralValue::Real(-3.4e38)).expect("fits");
        assert!(always_true(&real, CompareOp::Ge, &expected).is_none());
    }

    #[test]
    fn comparisons_read_the_type() {
        let int = var("MW20", ValueFormat::Signed);
        assert_eq!(compare(&int, 0xFFFF, 1), Some(std::cmp::Ordering::Less));
        let word = var("MW20", ValueFormat::Unsigned);
        assert_eq!(compare(&word, 0xFFFF, 1), Some(std::cmp::Ordering::Greater));
        let real = var("MD8", ValueFormat::Real);
        assert_eq!(
            compare(&real, 1.5f32.to_bits(), 2.0f32.to_bits()),
            Some(std::cmp::Ordering::Less)
        );
        assert_eq!(compare(&real, f32::NAN.to_bits(), 2.0f32.to_bits()), None);
    }
}
