//! Runs one corpus program's timeline on a VM: plain sets, the steps in order, the
//! remaining scans, the plain expectations. Every mismatch becomes a failure line
//! naming the file, the header line and the scan; it never adjusts an expectation.

use std::sync::Arc;

use gutta_catalog::{Address, Target};
use gutta_format::VerifiedImage;
use gutta_vm::{Vm, VmConfig};

use crate::header::{Action, Header, Wait};
use crate::values::{address, resolve, show, show_text, Assignment, Bits, Resolved};

/// A step's action with its variables resolved on the target.
#[derive(Debug)]
enum Act {
    Set(Resolved),
    Expect(Resolved),
    ExpectMode { running: bool },
    Force(Resolved),
    Unforce(Address),
    Reset,
    Run,
    Stop,
}

/// One part of a program's timeline.
#[derive(Debug)]
enum Phase {
    /// Scans of a step; `fault`: the last of them faults with this code. `ms`: the
    /// virtual clock must advance by exactly this much.
    Scans {
        line: usize,
        count: u32,
        ms: Option<u32>,
        fault: Option<u8>,
    },
    /// The scans after the steps; a fault ends them (and must be `fault` if given).
    Tail {
        count: u32,
        fault: Option<u8>,
    },
    Do {
        line: usize,
        act: Act,
    },
}

/// A compiled, verified program with its timeline resolved, ready to run.
pub struct Prepared<'a> {
    pub name: &'a str,
    pub image: VerifiedImage,
    pub target: Arc<Target>,
    phases: Vec<Phase>,
}

/// The program's timeline on `target`, or the failures of variables that do not
/// exist there or values that do not fit them.
pub fn prepare<'a>(
    name: &'a str,
    image: VerifiedImage,
    target: Arc<Target>,
    header: &Header,
    failures: &mut Vec<String>,
) -> Option<Prepared<'a>> {
    let before = failures.len();
    let mut known = |result: Result<Act, String>| {
        result
            .map_err(|e| failures.push(format!("{name}: {e}")))
            .ok()
    };
    let resolved = |a: &Assignment| resolve(&target, a);
    let mut phases = Vec::new();
    for a in &header.sets {
        if let Some(act) = known(resolved(a).map(Act::Set)) {
            phases.push(Phase::Do { line: a.line, act });
        }
    }
    let scan_ms = header.scan_ms();
    for step in &header.steps {
        let count = step.scans(scan_ms);
        let fault = match step.action {
            Action::Fault(code) => Some(code),
            _ => None,
        };
        if count > 0 {
            let ms = match step.wait {
                Wait::Ms(ms) => Some(ms),
                _ => None,
            };
            phases.push(Phase::Scans {
                line: step.line,
                count,
                ms,
                fault,
            });
        }
        let act = match &step.action {
            Action::Set(a) => resolved(a).map(Act::Set),
            Action::Expect(a) => resolved(a).map(Act::Expect),
            Action::Force(a) => resolved(a).map(Act::Force),
            Action::ExpectMode { running } => Ok(Act::ExpectMode { running: *running }),
            Action::Unforce { var } => address(&target, step.line, var).map(Act::Unforce),
            Action::Reset => Ok(Act::Reset),
            Action::Run => Ok(Act::Run),
            Action::Stop => Ok(Act::Stop),
            Action::Fault(_) => continue,
        };
        if let Some(act) = known(act) {
            phases.push(Phase::Do {
                line: step.line,
                act,
            });
        }
    }
    phases.push(Phase::Tail {
        count: header.tail_scans(),
        fault: header.fault,
    });
    for a in &header.expects {
        if let Some(act) = known(resolved(a).map(Act::Expect)) {
            phases.push(Phase::Do { line: a.line, act });
        }
    }
    (failures.len() == before).then_some(Prepared {
        name,
        image,
        target,
        phases,
    })
}

/// A VM and where its run stands, for failure messages.
struct Run<'a, 'p> {
    vm: Vm,
    name: &'a str,
    mode: &'a str,
    /// Scans run so far in this file's timeline.
    scans: u32,
    failures: &'p mut Vec<String>,
}

impl Run<'_, '_> {
    fn fail(&mut self, line: usize, what: String) {
        let at = if line == 0 {
            String::new()
        } else {
            format!(":{line}")
        };
        self.failures.push(format!(
            "{}{at} [{}] after scan {}: {what}",
            self.name, self.mode, self.scans
        ));
    }

    /// A step's scans; false when the run cannot go on (a fault other than expected).
    fn step_scans(&mut self, line: usize, count: u32, ms: Option<u32>, fault: Option<u8>) -> bool {
        let clock = self.vm.clock_ms();
        for k in 1..=count {
            self.scans += 1;
            let last = k == count;
            match (self.vm.scan(), fault) {
                (Ok(()), Some(code)) if last => {
                    self.fail(
                        line,
                        format!("expected fault code {code}, the scan ran without one"),
                    );
                    return false;
                }
                (Ok(()), _) => {}
                (Err(f), Some(code)) if last && f.code() == code => {}
                (Err(f), Some(code)) if last => {
                    let got = f.code();
                    self.fail(
                        line,
                        format!("expected fault code {code}, got {f} (code {got})"),
                    );
                    return false;
                }
                (Err(f), _) => {
                    self.fail(line, format!("unexpected fault: {f} (code {})", f.code()));
                    return false;
                }
            }
        }
        if let (Some(ms), None) = (ms, fault) {
            let passed = self.vm.clock_ms() - clock;
            if passed != u64::from(ms) {
                self.fail(
                    line,
                    format!("the virtual clock advanced {passed} ms, not {ms}"),
                );
            }
        }
        true
    }

    /// The scans after the steps, ended by a fault (as `fault:` has always meant).
    fn tail(&mut self, count: u32, fault: Option<u8>) {
        let mut got = None;
        for _ in 0..count {
            self.scans += 1;
            if let Err(f) = self.vm.scan() {
                got = Some(f);
                break;
            }
        }
        match (fault, got) {
            (None, None) => {}
            (None, Some(f)) => self.fail(0, format!("unexpected fault: {f} (code {})", f.code())),
            (Some(code), None) => self.fail(
                0,
                format!("expected fault code {code}, but the scans ran without one"),
            ),
            (Some(code), Some(f)) if f.code() != code => self.fail(
                0,
                format!("expected fault code {code}, got {f} (code {})", f.code()),
            ),
            (Some(_), Some(_)) => {}
        }
    }

    fn act(&mut self, line: usize, act: &Act) {
        match act {
            Act::Set(r) => self.set(line, r),
            Act::Expect(r) => self.expect(line, r),
            Act::ExpectMode { running } => {
                let mode = |run: bool| if run { "RUN" } else { "STOP" };
                if self.vm.is_running() != *running {
                    let got = mode(self.vm.is_running());
                    self.fail(
                        line,
                        format!("expected {}, the PLC is in {got}", mode(*running)),
                    );
                }
            }
            Act::Force(r) => {
                if let Bits::Word(bits) = r.bits {
                    if let Err(e) = self.vm.force(r.address, bits) {
                        self.fail(line, format!("cannot force {}: {e:?}", r.var));
                    }
                }
            }
            Act::Unforce(address) => self.vm.unforce(*address),
            Act::Reset => self.vm.reset(),
            Act::Run => self.vm.set_running(true),
            Act::Stop => self.vm.set_running(false),
        }
    }

    fn set(&mut self, line: usize, r: &Resolved) {
        let result = match &r.bits {
            Bits::Word(bits) => self.vm.write(r.address, *bits),
            Bits::Bytes(bytes) => bytes
                .iter()
                .try_for_each(|&(at, b)| self.vm.write(at, u32::from(b))),
        };
        if let Err(e) = result {
            self.fail(line, format!("cannot set {}: {e:?}", r.var));
        }
    }

    fn expect(&mut self, line: usize, r: &Resolved) {
        match &r.bits {
            Bits::Word(bits) => match self.vm.read(r.address) {
                Ok(got) if got == *bits => {}
                Ok(got) => self.fail(
                    line,
                    format!(
                        "{} expected {}, got {}",
                        r.var,
                        show(*bits, r.address.width),
                        show(got, r.address.width)
                    ),
                ),
                Err(e) => self.fail(line, format!("cannot read {}: {e:?}", r.var)),
            },
            Bits::Bytes(bytes) => {
                let got: Result<Vec<u8>, _> = bytes
                    .iter()
                    .map(|&(at, _)| self.vm.read(at).map(|v| v as u8))
                    .collect();
                let want: Vec<u8> = bytes.iter().map(|&(_, b)| b).collect();
                match got {
                    Ok(got) if got == want => {}
                    Ok(got) => self.fail(
                        line,
                        format!(
                            "{} expected {}, got {}",
                            r.var,
                            show_text(&want),
                            show_text(&got)
                        ),
                    ),
                    Err(e) => self.fail(line, format!("cannot read {}: {e:?}", r.var)),
                }
            }
        }
    }
}

/// Run the timeline in one mode; every mismatch becomes a line in `failures`.
pub fn run_mode(p: &Prepared, mode: &str, config: VmConfig, failures: &mut Vec<String>) {
    let vm = match Vm::new(p.image.clone(), Arc::clone(&p.target), config) {
        Ok(vm) => vm,
        Err(e) => return failures.push(format!("{} [{mode}]: does not load: {e:?}", p.name)),
    };
    let mut run = Run {
        vm,
        name: p.name,
        mode,
        scans: 0,
        failures,
    };
    for phase in &p.phases {
        match phase {
            Phase::Scans {
                line,
                count,
                ms,
                fault,
            } => {
                if !run.step_scans(*line, *count, *ms, *fault) {
                    return;
                }
            }
            Phase::Tail { count, fault } => run.tail(*count, *fault),
            Phase::Do { line, act } => run.act(*line, act),
        }
    }
}
