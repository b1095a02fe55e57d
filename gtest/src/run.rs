//! Runs one planned test on a fresh VM, in virtual time: statements in order, every
//! scan counted, the first failure ends the test with what a programmer needs to see
//! (the statement, the scan and time, expected and actual values in the variables'
//! types, the other variables of the test). It never reads a clock: durations are the
//! caller's to measure.

use std::sync::Arc;

use gutta_vm::{Fault, Vm, VmConfig};

use crate::resolve::{compare, show_bytes, Check, Expected, PlannedTest, Step, Variable};
use crate::syntax::CompareOp;
use crate::{Plan, ProgramUnderTest};

/// How to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RunOptions {
    /// The VM's pre-decoded operations (true, the default) or the generic semantics.
    pub fast: bool,
    /// Keep every value of the test's variables after each change, for a waveform.
    pub record: bool,
    /// When the VM's compiled tier compiles (`VmConfig::native_after`).
    pub native_after: Option<u64>,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions {
            fast: true,
            record: false,
            native_after: VmConfig::default().native_after,
        }
    }
}

/// One comparison that did not hold.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Mismatch {
    /// `Lamp (Q0.0)`.
    pub var: String,
    pub op: CompareOp,
    pub expected: String,
    pub actual: String,
}

/// Why a test failed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FailureKind {
    /// EXPECT: the comparisons that did not hold.
    Expect(Vec<Mismatch>),
    /// UNTIL: not all held within the limit; the ones that did not at the end.
    Until {
        within: u32,
        mismatches: Vec<Mismatch>,
    },
    /// A scan faulted and the next statement is not `EXPECT FAULT`; `still`: the PLC
    /// was already in that fault (an expected one) and ran no scan.
    Fault {
        code: u8,
        message: String,
        still: bool,
    },
    /// `EXPECT FAULT`: a different fault, or none.
    FaultExpected {
        expected: u8,
        got: Option<(u8, String)>,
    },
    /// `EXPECT RUN`/`EXPECT STOP`.
    Mode { expected_run: bool },
    /// The VM refused a write, force or read.
    Access(String),
}

/// A failed test: where, when and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Failure {
    /// The failing statement (for a fault: the statement whose scan faulted).
    pub line: u32,
    pub span: gutta_compiler::source::Span,
    /// Scans the test had run when it failed, and the virtual time.
    pub scan: u64,
    pub time_ms: u64,
    pub kind: FailureKind,
    /// The test's other variables at that moment: label and value.
    pub others: Vec<(String, String)>,
}

/// An UNTIL that held: after how many scans of its own.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UntilHeld {
    pub line: u32,
    pub after_scans: u32,
    pub scan: u64,
    pub time_ms: u64,
}

/// Every value of a test's variables over virtual time, for `--vcd`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Trace {
    /// (time in ms, one raw value per variable of the test).
    pub samples: Vec<(u64, Vec<u32>)>,
}

/// What running a test gave.
#[derive(Debug, Clone, PartialEq)]
pub struct TestResult {
    pub name: String,
    pub line: u32,
    pub scans: u64,
    pub time_ms: u64,
    pub untils: Vec<UntilHeld>,
    pub failure: Option<Failure>,
    pub trace: Option<Trace>,
}

impl TestResult {
    pub fn passed(&self) -> bool {
        self.failure.is_none()
    }
}

/// A running test.
struct Run<'a> {
    vm: Vm,
    test: &'a PlannedTest,
    scan_ms: u64,
    scans: u64,
    time_ms: u64,
    /// A fault of the last scans, waiting for `EXPECT FAULT` (statement line, span).
    pending: Option<(Fault, u32, gutta_compiler::source::Span)>,
    untils: Vec<UntilHeld>,
    trace: Option<Trace>,
    /// The pending fault is one an earlier statement expected: the PLC is still in it.
    still_faulted: bool,
}

/// Run `test` of `plan` on a fresh, reset PLC loaded with the program.
pub fn run_test(
    program: &ProgramUnderTest,
    plan: &Plan,
    test: &PlannedTest,
    options: RunOptions,
) -> TestResult {
    let config = VmConfig {
        scan_ms: plan.scan_ms,
        watchdog: plan.watchdog.unwrap_or(VmConfig::default().watchdog),
        fast: options.fast,
        native_after: options.native_after,
    };
    let result = |failure: Option<Failure>, run: Option<Run>| {
        let (scans, time_ms, untils, trace) = match run {
            Some(r) => (r.scans, r.time_ms, r.untils, r.trace),
            None => (0, 0, Vec::new(), None),
        };
        TestResult {
            name: test.name.clone(),
            line: test.line,
            scans,
            time_ms,
            untils,
            failure,
            trace,
        }
    };
    let vm = match Vm::new(program.image.clone(), Arc::clone(&program.target), config) {
        Ok(vm) => vm,
        Err(e) => {
            let failure = Failure {
                line: test.line,
                span: gutta_compiler::source::Span::new(0, 0),
                scan: 0,
                time_ms: 0,
                kind: FailureKind::Access(format!("the VM does not load the program: {e:?}")),
                others: Vec::new(),
            };
            return result(Some(failure), None);
        }
    };
    let mut run = Run {
        vm,
        test,
        scan_ms: u64::from(plan.scan_ms),
        scans: 0,
        time_ms: 0,
        pending: None,
        untils: Vec::new(),
        trace: options.record.then(Trace::default),
        still_faulted: false,
    };
    run.sample();
    let failure = run.statements();
    result(failure, Some(run))
}

impl Run<'_> {
    fn statements(&mut self) -> Option<Failure> {
        for s in &self.test.statements {
            if let Some((fault, line, span)) = self.pending.take() {
                if let Step::ExpectFault(expected) = s.step {
                    if fault.code() == expected {
                        self.still_faulted = false;
                        continue;
                    }
                    let got = Some((fault.code(), fault.to_string()));
                    return Some(self.failure(
                        s.line,
                        s.span,
                        FailureKind::FaultExpected { expected, got },
                        &[],
                    ));
                }
                let kind = self.fault_kind(&fault);
                return Some(self.failure(line, span, kind, &[]));
            }
            let failed = match &s.step {
                Step::Set(list) => self.set(list),
                Step::Force(list) => self.force(list),
                Step::Unforce(list) => {
                    if list.is_empty() {
                        self.vm.unforce_all();
                    } else {
                        for &v in list {
                            self.vm.unforce(self.test.vars[v].address);
                        }
                    }
                    self.sample();
                    None
                }
                Step::Scan(n) => {
                    self.scans_of(*n, s.line, s.span);
                    None
                }
                Step::Advance { scans, .. } => {
                    self.scans_of(*scans, s.line, s.span);
                    None
                }
                Step::Expect(checks) => {
                    let mismatches = self.mismatches(checks);
                    (!mismatches.is_empty()).then_some(FailureKind::Expect(mismatches))
                }
                Step::ExpectFault(expected) => Some(FailureKind::FaultExpected {
                    expected: *expected,
                    got: None,
                }),
                Step::ExpectMode(run) => (self.vm.is_running() != *run)
                    .then_some(FailureKind::Mode { expected_run: *run }),
                Step::Until { checks, within } => self.until(checks, *within, s.line, s.span),
                Step::Reset => {
                    self.vm.reset();
                    self.sample();
                    None
                }
                Step::Run => {
                    self.vm.set_running(true);
                    None
                }
                Step::Stop => {
                    self.vm.set_running(false);
                    None
                }
            };
            if let Some(kind) = failed {
                let failing = failing_vars(&kind, self.test);
                return Some(self.failure(s.line, s.span, kind, &failing));
            }
        }
        self.pending.take().map(|(fault, line, span)| {
            let kind = self.fault_kind(&fault);
            self.failure(line, span, kind, &[])
        })
    }

    fn fault_kind(&self, fault: &Fault) -> FailureKind {
        FailureKind::Fault {
            code: fault.code(),
            message: fault.to_string(),
            still: self.still_faulted,
        }
    }

    fn failure(
        &self,
        line: u32,
        span: gutta_compiler::source::Span,
        kind: FailureKind,
        failing: &[usize],
    ) -> Failure {
        let others = self
            .test
            .vars
            .iter()
            .enumerate()
            .filter(|(i, _)| !failing.contains(i))
            .map(|(_, v)| (v.label(), self.show(v)))
            .collect();
        Failure {
            line,
            span,
            scan: self.scans,
            time_ms: self.time_ms,
            kind,
            others,
        }
    }

    fn show(&self, v: &Variable) -> String {
        match self.vm.read(v.address) {
            Ok(raw) => v.show(raw),
            Err(e) => format!("(unreadable: {e:?})"),
        }
    }

    /// Record the variables' values at the current time.
    fn sample(&mut self) {
        let Some(trace) = &mut self.trace else {
            return;
        };
        let values = self
            .test
            .vars
            .iter()
            .map(|v| self.vm.read(v.address).unwrap_or(0))
            .collect();
        trace.samples.push((self.time_ms, values));
    }

    /// One scan; false (with the fault pending) when it faulted.
    fn scan(&mut self, line: u32, span: gutta_compiler::source::Span) -> bool {
        if let Some(fault) = self.vm.fault() {
            // A faulted PLC runs no scan until a RESET: say so, not "faulted in scan n".
            self.pending = Some((fault.clone(), line, span));
            self.still_faulted = true;
            return false;
        }
        self.scans += 1;
        self.time_ms += self.scan_ms;
        let outcome = self.vm.scan();
        self.sample();
        match outcome {
            Ok(()) => true,
            Err(fault) => {
                self.pending = Some((fault, line, span));
                false
            }
        }
    }

    fn scans_of(&mut self, n: u32, line: u32, span: gutta_compiler::source::Span) {
        for _ in 0..n {
            if !self.scan(line, span) {
                return;
            }
        }
    }

    fn set(&mut self, list: &[(usize, Expected)]) -> Option<FailureKind> {
        for (v, value) in list {
            let var = &self.test.vars[*v];
            let result = match value {
                Expected::Bits(bits) => self.vm.write(var.address, *bits),
                Expected::Bytes(bytes) => bytes.iter().zip(0u32..).try_for_each(|(&b, k)| {
                    let mut at = var.address;
                    at.offset += k;
                    self.vm.write(at, u32::from(b))
                }),
            };
            if let Err(e) = result {
                return Some(FailureKind::Access(format!(
                    "cannot set {}: {e:?}",
                    var.label()
                )));
            }
        }
        self.sample();
        None
    }

    fn force(&mut self, list: &[(usize, u32)]) -> Option<FailureKind> {
        for &(v, bits) in list {
            let var = &self.test.vars[v];
            if let Err(e) = self.vm.force(var.address, bits) {
                return Some(FailureKind::Access(format!(
                    "cannot force {}: {e:?}",
                    var.label()
                )));
            }
        }
        self.sample();
        None
    }

    /// The checks that do not hold now.
    fn mismatches(&self, checks: &[Check]) -> Vec<Mismatch> {
        checks
            .iter()
            .filter_map(|c| {
                let var = &self.test.vars[c.var];
                let (holds, actual) = match &c.expected {
                    Expected::Bits(expected) => match self.vm.read(var.address) {
                        Ok(raw) => {
                            let holds = compare(var, raw, *expected).is_some_and(|o| c.op.holds(o))
                                || (c.op == CompareOp::Ne
                                    && compare(var, raw, *expected).is_none());
                            (holds, var.show(raw))
                        }
                        Err(e) => (false, format!("(unreadable: {e:?})")),
                    },
                    Expected::Bytes(expected) => {
                        let got: Result<Vec<u8>, _> = (0u32..)
                            .zip(expected)
                            .map(|(k, _)| {
                                let mut at = var.address;
                                at.offset += k;
                                self.vm.read(at).map(|b| b as u8)
                            })
                            .collect();
                        match got {
                            Ok(got) => (
                                (got == *expected) == (c.op == CompareOp::Eq),
                                show_bytes(&got),
                            ),
                            Err(e) => (false, format!("(unreadable: {e:?})")),
                        }
                    }
                };
                (!holds).then(|| Mismatch {
                    var: var.label(),
                    op: c.op,
                    expected: c.shown.clone(),
                    actual,
                })
            })
            .collect()
    }

    fn until(
        &mut self,
        checks: &[Check],
        within: u32,
        line: u32,
        span: gutta_compiler::source::Span,
    ) -> Option<FailureKind> {
        for k in 0..=within {
            if self.mismatches(checks).is_empty() {
                self.untils.push(UntilHeld {
                    line,
                    after_scans: k,
                    scan: self.scans,
                    time_ms: self.time_ms,
                });
                return None;
            }
            if k == within || !self.scan(line, span) {
                break;
            }
        }
        if self.pending.is_some() {
            // The fault is reported by the next statement (or the end of the test).
            return None;
        }
        Some(FailureKind::Until {
            within,
            mismatches: self.mismatches(checks),
        })
    }
}

/// The variables a failure is about (left out of "other variables"): those of the
/// comparisons that did not hold.
fn failing_vars(kind: &FailureKind, test: &PlannedTest) -> Vec<usize> {
    let mismatches = match kind {
        FailureKind::Expect(m) | FailureKind::Until { mismatches: m, .. } => m,
        _ => return Vec::new(),
    };
    test.vars
        .iter()
        .enumerate()
        .filter(|(_, v)| mismatches.iter().any(|m| m.var == v.label()))
        .map(|(i, _)| i)
        .collect()
}
