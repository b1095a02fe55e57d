//! The header language of the run corpus (docs/testing.md, "VM corpus"): the comment
//! lines before a program's first line, read into a `Header` of plain keys and timed
//! steps. Strict: misspelt keys, bad values and misplaced lines are errors naming
//! their line. It knows no target and never runs a VM.

use gutta_vm::VmConfig;

use crate::values::{parse_assignment, parse_variable, Assignment, Value};

/// The plain header keys.
pub const KEYS: [&str; 8] = [
    "plc", "option", "scans", "scan-ms", "set", "expect", "fault", "watchdog",
];

/// What `// option:` may name: a compile option (`gutta_compiler::CompileOptions`).
pub const OPTIONS: [&str; 1] = ["scale-timer-presets"];

/// What a step may do (`then ACTION: ARGS`, `after N scans: ACTION ARGS`).
pub const ACTIONS: [&str; 8] = [
    "set", "expect", "force", "unforce", "fault", "reset", "run", "stop",
];

/// What a step does once its scans have run.
#[derive(Debug, Clone)]
pub enum Action {
    /// Write a variable (an input's terminal for I and AI).
    Set(Assignment),
    /// Check a variable.
    Expect(Assignment),
    /// Check RUN (true) or STOP (false): `expect RUN`, `expect STOP`.
    ExpectMode {
        running: bool,
    },
    /// Force a variable of a forcing area.
    Force(Assignment),
    Unforce {
        var: String,
    },
    /// The last scan of the step faults with this code.
    Fault(u8),
    /// Power-on reset (`Vm::reset`).
    Reset,
    /// RUN or STOP, as STATUS_WRITE does.
    Run,
    Stop,
}

/// The scans a step runs before its action.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Wait {
    /// `then`: none.
    Now,
    Scans(u32),
    /// Virtual milliseconds: whole scans of `scan-ms`.
    Ms(u32),
}

/// One timed line: wait, then act.
#[derive(Debug, Clone)]
pub struct Step {
    pub line: usize,
    pub wait: Wait,
    pub action: Action,
}

impl Step {
    /// The scans this step runs (`Ms` checked to be whole scans by `parse_header`).
    pub fn scans(&self, scan_ms: u32) -> u32 {
        match self.wait {
            Wait::Now => 0,
            Wait::Scans(n) => n,
            Wait::Ms(ms) => ms.checked_div(scan_ms).unwrap_or(0),
        }
    }
}

/// What the header lines of one program ask for.
#[derive(Debug, Default)]
pub struct Header {
    pub plc: Option<String>,
    /// `option:` lines, each one of [`OPTIONS`].
    pub options: Vec<String>,
    /// `scans:` and its line.
    pub scans: Option<(usize, u32)>,
    pub scan_ms: Option<u32>,
    pub watchdog: Option<u64>,
    pub fault: Option<u8>,
    /// Plain `set:` lines: before the first scan.
    pub sets: Vec<Assignment>,
    pub steps: Vec<Step>,
    /// Plain `expect:` lines: after the last scan.
    pub expects: Vec<Assignment>,
}

impl Header {
    pub fn scan_ms(&self) -> u32 {
        self.scan_ms.unwrap_or(VmConfig::default().scan_ms)
    }

    /// Scans the steps run.
    pub fn stepped_scans(&self) -> u32 {
        self.steps.iter().map(|s| s.scans(self.scan_ms())).sum()
    }

    /// Scans run after the steps, before the plain expectations: up to `scans:` in
    /// all, or at least one scan in all without it.
    pub fn tail_scans(&self) -> u32 {
        let stepped = self.stepped_scans();
        match self.scans {
            Some((_, total)) => total.saturating_sub(stepped),
            None => u32::from(stepped == 0),
        }
    }

    fn checks_something(&self) -> bool {
        !self.expects.is_empty()
            || self.fault.is_some()
            || self.steps.iter().any(|s| {
                matches!(
                    s.action,
                    Action::Expect(_) | Action::ExpectMode { .. } | Action::Fault(_)
                )
            })
    }
}

/// The text before a trailing `// comment`, outside double quotes.
fn strip_comment(value: &str) -> &str {
    let mut quoted = false;
    let bytes = value.as_bytes();
    for (i, &b) in bytes.iter().enumerate() {
        match b {
            b'"' => quoted = !quoted,
            b'/' if !quoted && bytes.get(i + 1) == Some(&b'/') => return value[..i].trim(),
            _ => {}
        }
    }
    value.trim()
}

/// The key and value of a directive line (`// expect: MW0 = 1`), or None for a plain
/// comment. A directive is, right before a `:`, a lowercase word that is a key or
/// within two edits of one (a misspelt key, reported as an error), or lowercase words
/// starting with `then` or `after` (a step). Other comment lines are free text.
fn directive(line: &str) -> Option<(&str, &str)> {
    let body = line.trim().strip_prefix("//")?.trim_start();
    let (key, value) = body.split_once(':')?;
    let word = |w: &str| {
        !w.is_empty()
            && w.chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-')
    };
    let is_directive = match key.split_once(' ') {
        None => {
            word(key)
                && (key == "then"
                    || key == "after"
                    || KEYS
                        .iter()
                        .any(|k| gutta_catalog::edit_distance(k, key) <= 2))
        }
        Some((first, _)) => (first == "then" || first == "after") && key.split(' ').all(word),
    };
    is_directive.then(|| (key, strip_comment(value)))
}

/// When a step key (`then set`, `after 61 scans`) acts, and the action word of a
/// `then` key.
fn step_key(key: &str) -> Result<(Wait, Option<&str>), String> {
    let words: Vec<&str> = key.split(' ').collect();
    match words.as_slice() {
        ["then", action] => Ok((Wait::Now, Some(action))),
        ["then"] => Err("`then` needs its action before the `:` (`then set: I0.0 = 0`)".into()),
        ["after", count, unit] => {
            let n: u32 = count
                .parse()
                .ok()
                .filter(|&n| n > 0)
                .ok_or_else(|| format!("`{count}` is not a positive count in `{key}`"))?;
            match *unit {
                "scan" | "scans" => Ok((Wait::Scans(n), None)),
                "ms" => Ok((Wait::Ms(n), None)),
                _ => Err(format!("`{key}`: the unit is `scans` or `ms`")),
            }
        }
        _ if words[0] == "then" => Err(format!("`{key}` is not `then ACTION`")),
        _ => Err(format!(
            "`{key}` is not `after N scans` or `after N ms` (one space between words)"
        )),
    }
}

/// An action word and its arguments.
fn action(line: usize, word: &str, args: &str) -> Result<Action, String> {
    let no_args = |a: Action| {
        if args.is_empty() {
            Ok(a)
        } else {
            Err(format!("`{word}` takes nothing, not `{args}`"))
        }
    };
    match word {
        "set" => parse_assignment(line, args).map(Action::Set),
        "expect" => match args {
            "RUN" => Ok(Action::ExpectMode { running: true }),
            "STOP" => Ok(Action::ExpectMode { running: false }),
            _ => parse_assignment(line, args).map(Action::Expect),
        },
        "force" => {
            let a = parse_assignment(line, args)?;
            match a.value {
                Value::Number(_) => Ok(Action::Force(a)),
                Value::Text(_) => Err(format!("`{args}`: a force value is a number")),
            }
        }
        "unforce" => parse_variable(args).map(|var| Action::Unforce { var }),
        "fault" => args
            .parse::<u8>()
            .map(Action::Fault)
            .map_err(|_| format!("`{args}` is not a fault code")),
        "reset" => no_args(Action::Reset),
        "run" => no_args(Action::Run),
        "stop" => no_args(Action::Stop),
        other => Err(format!(
            "unknown action `{other}` (known: {})",
            ACTIONS.join(", ")
        )),
    }
}

/// A step line: `then ACTION: ARGS` or `after N scans|ms: ACTION ARGS`.
fn step(line: usize, key: &str, value: &str) -> Result<Step, String> {
    let (wait, then_action) = step_key(key)?;
    let (word, args) = match then_action {
        Some(word) => (word, value),
        None => value
            .split_once(char::is_whitespace)
            .map_or((value, ""), |(w, a)| (w, a.trim())),
    };
    if word == "fault" && wait == Wait::Now {
        return Err("a fault happens in a scan: `after N scans: fault CODE`".into());
    }
    Ok(Step {
        line,
        wait,
        action: action(line, word, args)?,
    })
}

/// The header: the comment and blank lines before the program's first line. A
/// directive after the header is an error too (it would silently be ignored).
pub fn parse_header(text: &str) -> Result<Header, Vec<String>> {
    let mut header = Header::default();
    let mut errors = Vec::new();
    let mut in_header = true;
    let mut first_plain_expect = None;
    let mut fault_line = 0;
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let trimmed = raw.trim().trim_start_matches('\u{feff}');
        if in_header && !(trimmed.is_empty() || trimmed.starts_with("//")) {
            in_header = false;
        }
        let Some((key, value)) = directive(trimmed) else {
            continue;
        };
        let is_step = key.starts_with("then") || key.starts_with("after");
        if !in_header {
            if KEYS.contains(&key) || (is_step && step(line, key, value).is_ok()) {
                errors.push(format!(
                    "line {line}: `// {key}:` after the header (headers come before the program)"
                ));
            }
            continue;
        }
        let once = |seen: bool, errors: &mut Vec<String>| {
            if seen {
                errors.push(format!("line {line}: `// {key}:` given twice"));
            }
        };
        let result: Result<(), String> = match key {
            _ if is_step => step(line, key, value).map(|s| {
                if let Some(expect_line) = first_plain_expect.take() {
                    errors.push(format!(
                        "line {expect_line}: a plain `// expect:` before a step (it checks after \
                         the last scan: move it below the steps, or write `then expect:`)"
                    ));
                }
                header.steps.push(s);
            }),
            "plc" => {
                once(header.plc.is_some(), &mut errors);
                if value.is_empty() {
                    Err("`// plc:` needs a PLC type name".into())
                } else {
                    header.plc = Some(value.to_string());
                    Ok(())
                }
            }
            "option" => {
                if OPTIONS.contains(&value) {
                    header.options.push(value.to_string());
                    Ok(())
                } else {
                    Err(format!(
                        "`{value}` is not an option (options: {})",
                        OPTIONS.join(", ")
                    ))
                }
            }
            "scans" => {
                once(header.scans.is_some(), &mut errors);
                value
                    .parse::<u32>()
                    .map_err(|_| format!("`{value}` is not a scan count"))
                    .map(|n| header.scans = Some((line, n)))
            }
            "scan-ms" => {
                once(header.scan_ms.is_some(), &mut errors);
                value
                    .parse::<u32>()
                    .map_err(|_| format!("`{value}` is not a scan time in ms"))
                    .map(|n| header.scan_ms = Some(n))
            }
            "watchdog" => {
                once(header.watchdog.is_some(), &mut errors);
                value
                    .parse::<u64>()
                    .map_err(|_| format!("`{value}` is not an instruction count"))
                    .map(|n| header.watchdog = Some(n))
            }
            "fault" => {
                once(header.fault.is_some(), &mut errors);
                fault_line = line;
                value
                    .parse::<u8>()
                    .map_err(|_| format!("`{value}` is not a fault code"))
                    .map(|n| header.fault = Some(n))
            }
            "set" if !header.steps.is_empty() => Err(
                "a plain `// set:` after a step (it sets before the first scan: move it above \
                 the steps, or write `then set:`)"
                    .into(),
            ),
            "set" => parse_assignment(line, value).map(|a| header.sets.push(a)),
            "expect" => parse_assignment(line, value).map(|a| {
                first_plain_expect.get_or_insert(line);
                header.expects.push(a);
            }),
            other => Err(format!(
                "unknown header key `{other}` (a misspelling? known: {}, then ACTION, \
                 after N scans, after N ms)",
                KEYS.join(", ")
            )),
        };
        if let Err(e) = result {
            errors.push(format!("line {line}: {e}"));
        }
    }
    check_timeline(&header, fault_line, &mut errors);
    if !header.checks_something() {
        errors.push(
            "no `// expect:`, `// fault:` or expecting step: the program checks nothing".into(),
        );
    }
    if errors.is_empty() {
        Ok(header)
    } else {
        Err(errors)
    }
}

/// Rules between lines: `after N ms` in whole scans, `scans:` not fewer than the
/// steps run, and no plain `fault:` beside steps.
fn check_timeline(header: &Header, fault_line: usize, errors: &mut Vec<String>) {
    let scan_ms = header.scan_ms();
    for s in &header.steps {
        if let Wait::Ms(ms) = s.wait {
            if scan_ms == 0 || ms % scan_ms != 0 {
                errors.push(format!(
                    "line {}: {ms} ms is not a whole number of {scan_ms} ms scans",
                    s.line
                ));
            }
        }
    }
    if let Some((line, total)) = header.scans {
        let stepped = header.stepped_scans();
        if total < stepped {
            errors.push(format!(
                "line {line}: `scans: {total}`, but the steps already run {stepped} scans"
            ));
        }
    }
    if header.fault.is_some() && !header.steps.is_empty() {
        errors.push(format!(
            "line {fault_line}: a plain `// fault:` beside steps (write `after N scans: fault CODE` \
             at the scan that faults)"
        ));
    }
}
