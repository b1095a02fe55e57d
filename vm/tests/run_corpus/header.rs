//! The header language of the run corpus (docs/testing.md, "VM corpus"): the comment
//! lines before a program's first line, read into a `Header` of plain keys and timed
//! steps. Strict: misspelt keys, bad values and misplaced lines are errors naming
//! their line. It knows no target and never runs a VM.

use gutta_vm::VmConfig;

use crate::values::{parse_assignment, parse_value, parse_variable, Assignment, Value};

/// The plain header keys.
pub const KEYS: [&str; 7] = [
    "plc", "scans", "scan-ms", "set", "expect", "fault", "watchdog",
];

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

/// Levenshtein distance of two short ASCII words.
fn distance(a: &str, b: &str) -> usize {
    let b = b.as_bytes();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.bytes().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let next = (diagonal + usize::from(ca != cb))
                .min(row[j] + 1)
                .min(row[j + 1] + 1);
            diagonal = row[j + 1];
            row[j + 1] = next;
        }
    }
    row[b.len()]
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
                && (key == "then" || key == "after" || KEYS.iter().any(|k| distance(k, key) <= 2))
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

#[test]
fn header_lines_are_read_as_documented() {
    let text = "// plc: EC30-EK51\n// A plain comment: with a colon.\n// scans: 3\n\
                // later: free text\n// set: MW0=-1\n// expect: MW2 = 16#0E01  // explained here\n\
                // expect: Q0.0 = 1\n\nORGANIZATION_BLOCK MAIN\n";
    let h = parse_header(text).expect("header parses");
    assert_eq!(h.plc.as_deref(), Some("EC30-EK51"));
    assert_eq!(h.scans, Some((3, 3)));
    assert_eq!(h.tail_scans(), 3);
    assert_eq!(
        (h.sets[0].var.as_str(), &h.sets[0].value),
        ("MW0", &Value::Number(-1))
    );
    assert_eq!(
        (h.expects[0].line, &h.expects[0].value),
        (6, &Value::Number(0x0E01))
    );
    assert_eq!(h.expects[1].var, "Q0.0");
    assert!(h.steps.is_empty());
}

#[test]
fn steps_are_read_in_order_with_their_waits() {
    let text = "// scan-ms: 10\n// set: I0.0 = 1\n// after 61 scans: expect Q0.0 = 1 // 610 ms\n\
                // then set: I0.0 = 0\n// after 1 scan: expect Q0.0 = 0\n\
                // after 500 ms: expect MB40 = \"a // b\"\n// then force: Q0.1 = 1\n\
                // then unforce: Q0.1\n// after 2 scans: fault 3\n// then reset:\n\
                // then stop:\n// then expect: STOP\n// then run:\n// expect: MW0 = 7\n";
    let h = parse_header(text).expect("header parses");
    let waits: Vec<Wait> = h.steps.iter().map(|s| s.wait).collect();
    use Wait::{Ms, Now, Scans};
    assert_eq!(
        waits,
        [
            Scans(61),
            Now,
            Scans(1),
            Ms(500),
            Now,
            Now,
            Scans(2),
            Now,
            Now,
            Now,
            Now
        ]
    );
    assert_eq!(h.steps[0].line, 3);
    assert_eq!(h.stepped_scans(), 61 + 1 + 50 + 2);
    assert_eq!(
        h.tail_scans(),
        0,
        "without `scans:` the run ends with the steps"
    );
    assert!(matches!(&h.steps[3].action,
        Action::Expect(a) if a.value == Value::Text(b"a // b".to_vec())));
    assert!(matches!(&h.steps[5].action, Action::Unforce { var } if var == "Q0.1"));
    assert!(matches!(h.steps[6].action, Action::Fault(3)));
    assert!(matches!(h.steps[7].action, Action::Reset));
    assert!(matches!(
        h.steps[9].action,
        Action::ExpectMode { running: false }
    ));
    assert!(matches!(h.steps[10].action, Action::Run));
    assert_eq!(h.expects[0].line, 14);
    let free = parse_header(
        "// after ATT 10, 20: a comment\n// Then the sum: another\n// expect: MW0 = 1\n",
    )
    .expect("free text");
    assert!(
        free.steps.is_empty(),
        "words with capitals or commas are comments"
    );
    let only_now = parse_header("// then force: Q0.0 = 1\n// expect: Q0.0 = 1\n").expect("parses");
    assert_eq!(only_now.tail_scans(), 1, "at least one scan");
}

#[test]
fn malformed_header_lines_name_their_line() {
    for (text, wanted) in [
        ("// scans: many\n// expect: MW0 = 1\n", "line 1"),
        (
            "// expect: MW0 = 1\n// expcet: MW0 = 1\n",
            "line 2: unknown header key",
        ),
        (
            "// expect: MW0 = 1\n// scan: 2\n",
            "line 2: unknown header key",
        ),
        ("// expect: MW0 is 1\n", "line 1"),
        ("// expect: MW0 = 16#XY\n", "line 1"),
        ("// expect: MB0 = \"open\n", "line 1"),
        ("// scans: 2\n", "checks nothing"),
        (
            "// expect: MW0 = 1\nORGANIZATION_BLOCK MAIN\n// expect: MW2 = 1\n",
            "line 3: `// expect:` after the header",
        ),
        (
            "// expect: MW0 = 1\nORGANIZATION_BLOCK MAIN\n// after 2 scans: expect MW2 = 1\n",
            "line 3: `// after 2 scans:` after the header",
        ),
        (
            "// after 2 scans: expcet MW0 = 1\n",
            "line 1: unknown action",
        ),
        ("// after two scans: expect MW0 = 1\n", "line 1"),
        ("// after 0 scans: expect MW0 = 1\n", "line 1"),
        ("// after 2 s: expect MW0 = 1\n", "line 1"),
        (
            "// then sett: MW0 = 1\n// expect: MW0 = 1\n",
            "line 1: unknown action",
        ),
        ("// then: set MW0 = 1\n// expect: MW0 = 1\n", "line 1"),
        (
            "// then the sum: 3\n// expect: MW0 = 1\n",
            "line 1: `then the sum` is not",
        ),
        ("// then fault: 3\n", "line 1: a fault happens in a scan"),
        ("// after 1 scan: reset now\n// expect: MW0 = 1\n", "line 1"),
        (
            "// after 1 scan: force MB0 = \"x\"\n// expect: MW0 = 1\n",
            "line 1",
        ),
        (
            "// scan-ms: 7\n// after 50 ms: expect MW0 = 1\n",
            "line 2: 50 ms",
        ),
        (
            "// scans: 3\n// after 5 scans: expect MW0 = 1\n",
            "line 1: `scans: 3`, but the steps",
        ),
        (
            "// after 1 scan: expect MW0 = 1\n// set: MW2 = 1\n",
            "line 2: a plain `// set:` after a step",
        ),
        (
            "// expect: MW2 = 1\n// after 1 scan: expect MW0 = 1\n",
            "line 1: a plain `// expect:` before a step",
        ),
        (
            "// fault: 3\n// after 1 scan: expect MW0 = 1\n",
            "line 1: a plain `// fault:` beside steps",
        ),
    ] {
        let errors = parse_header(text).expect_err(text);
        assert!(
            errors.iter().any(|e| e.contains(wanted)),
            "{text:?}: {errors:?}"
        );
    }
}

#[test]
fn values_are_numbers_or_texts() {
    use crate::values::parse_number;
    assert_eq!(parse_number("2#1010"), Ok(10));
    assert_eq!(parse_number("-16#10"), Ok(-16));
    assert_eq!(parse_value("\"1A2f\""), Ok(Value::Text(b"1A2f".to_vec())));
    assert!(parse_value("\"\"").is_err(), "an empty text");
}
