//! The data-driven VM corpus: every program in tests/data/run is compiled for its PLC
//! type, run for its number of scans with the pre-decoded operations and again with the
//! generic semantics, and every `// expect:` value checked after the last scan (header
//! format in docs/testing.md, "VM corpus"). Failures of all files are collected and
//! reported together. It never adjusts an expectation to what the VM does.

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]

mod common;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use gutta_catalog::{stdlib, Address, Target, Width};
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};
use gutta_format::VerifiedImage;
use gutta_vm::{Vm, VmConfig};

/// Fewer files than this means the corpus went missing, not that it passed.
const MIN_PROGRAMS: usize = 20;

/// The header keys a program may use.
const KEYS: [&str; 7] = [
    "plc", "scans", "scan-ms", "set", "expect", "fault", "watchdog",
];

/// `VAR = VALUE` from a `// set:` or `// expect:` line.
#[derive(Debug)]
struct Assignment {
    line: usize,
    var: String,
    value: i64,
}

/// What the header lines of one program ask for.
#[derive(Debug, Default)]
struct Header {
    plc: Option<String>,
    scans: Option<u32>,
    scan_ms: Option<u32>,
    watchdog: Option<u64>,
    fault: Option<u8>,
    sets: Vec<Assignment>,
    expects: Vec<Assignment>,
}

/// An assignment whose variable exists on the program's target.
#[derive(Debug)]
struct Resolved<'a> {
    source: &'a Assignment,
    address: Address,
    /// The value as the variable's unsigned bits.
    bits: u32,
}

/// A number as the harness reads it: decimal, `16#..`, `2#..`, optional sign, `_` allowed.
fn parse_number(text: &str) -> Result<i64, String> {
    let (negative, rest) = match text.strip_prefix('-') {
        Some(r) => (true, r),
        None => (false, text.strip_prefix('+').unwrap_or(text)),
    };
    let (radix, digits) = if let Some(d) = rest.strip_prefix("16#") {
        (16, d)
    } else if let Some(d) = rest.strip_prefix("2#") {
        (2, d)
    } else {
        (10, rest)
    };
    let digits: String = digits.chars().filter(|&c| c != '_').collect();
    if digits.is_empty() || !digits.chars().all(|c| c.is_digit(radix)) {
        return Err(format!(
            "`{text}` is not a number (decimal, 16#FF, 2#1010, signed)"
        ));
    }
    let magnitude =
        i64::from_str_radix(&digits, radix).map_err(|_| format!("`{text}` is too large"))?;
    Ok(if negative { -magnitude } else { magnitude })
}

/// `VAR = VALUE` (for `expect`) or `VAR=VALUE` (for `set`); spaces around `=` optional.
fn parse_assignment(line: usize, text: &str) -> Result<Assignment, String> {
    let (var, value) = text
        .split_once('=')
        .ok_or_else(|| format!("`{text}` is not VAR = VALUE"))?;
    let var = var.trim();
    if var.is_empty() || var.contains(char::is_whitespace) {
        return Err(format!("`{text}`: no single variable before `=`"));
    }
    Ok(Assignment {
        line,
        var: var.to_string(),
        value: parse_number(value.trim())?,
    })
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

/// The key and value of a directive line (`// expect: MW0 = 1`), or None for a plain
/// comment. A directive is a known key, or a lowercase word within two edits of one
/// (a misspelt key, reported as an error), right before a `:`; a trailing `// ...`
/// after the value is a comment. Other comment lines are free text.
fn directive(line: &str) -> Option<(&str, &str)> {
    let body = line.trim().strip_prefix("//")?.trim_start();
    let (key, value) = body.split_once(':')?;
    if key.is_empty() || !key.chars().all(|c| c.is_ascii_lowercase() || c == '-') {
        return None;
    }
    if !KEYS.iter().any(|k| distance(k, key) <= 2) {
        return None;
    }
    let value = value.split("//").next().unwrap_or("").trim();
    Some((key, value))
}

/// The header: the comment and blank lines before the program's first line. A
/// directive after the header is an error too (it would silently be ignored).
fn parse_header(text: &str) -> Result<Header, Vec<String>> {
    let mut header = Header::default();
    let mut errors = Vec::new();
    let mut in_header = true;
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let trimmed = raw.trim().trim_start_matches('\u{feff}');
        if in_header && !(trimmed.is_empty() || trimmed.starts_with("//")) {
            in_header = false;
        }
        let Some((key, value)) = directive(trimmed) else {
            continue;
        };
        if !in_header {
            if KEYS.contains(&key) {
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
                    .map(|n| header.scans = Some(n))
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
                value
                    .parse::<u8>()
                    .map_err(|_| format!("`{value}` is not a fault code"))
                    .map(|n| header.fault = Some(n))
            }
            "set" => parse_assignment(line, value).map(|a| header.sets.push(a)),
            "expect" => parse_assignment(line, value).map(|a| header.expects.push(a)),
            other => Err(format!(
                "unknown header key `{other}` (a misspelling? known: {})",
                KEYS.join(", ")
            )),
        };
        if let Err(e) = result {
            errors.push(format!("line {line}: {e}"));
        }
    }
    if header.expects.is_empty() && header.fault.is_none() {
        errors.push("no `// expect:` and no `// fault:` line: the program checks nothing".into());
    }
    if errors.is_empty() {
        Ok(header)
    } else {
        Err(errors)
    }
}

/// The variable's address on `target` and the value as its unsigned bits; a value
/// that fits neither the signed nor the unsigned reading of the width is an error.
fn resolve<'a>(target: &Target, a: &'a Assignment) -> Result<Resolved<'a>, String> {
    let address = target
        .memory
        .parse_address(&a.var)
        .map_err(|e| format!("line {}: `{}` is no variable here: {e:?}", a.line, a.var))?;
    let bits = address.width.bits();
    let (low, high) = if bits == 1 {
        (0, 1)
    } else {
        (-(1i64 << (bits - 1)), (1i64 << bits) - 1)
    };
    if !(low..=high).contains(&a.value) {
        return Err(format!(
            "line {}: {} does not fit {} ({bits} bits)",
            a.line, a.value, a.var
        ));
    }
    let mask = if bits == 32 {
        u32::MAX
    } else {
        (1u32 << bits) - 1
    };
    Ok(Resolved {
        source: a,
        address,
        bits: (a.value as u32) & mask,
    })
}

/// Every assignment of `list` that resolves; the others become failures.
fn resolve_all<'a>(
    target: &Target,
    list: &'a [Assignment],
    name: &str,
    failures: &mut Vec<String>,
) -> Vec<Resolved<'a>> {
    list.iter()
        .filter_map(|a| {
            resolve(target, a)
                .map_err(|e| failures.push(format!("{name}: {e}")))
                .ok()
        })
        .collect()
}

/// `123 (16#7B)`, with the hex digits of the width.
fn show(value: u32, width: Width) -> String {
    match width {
        Width::Bit => value.to_string(),
        _ => format!(
            "{value} (16#{value:0digits$X})",
            digits = width.bytes() as usize * 2
        ),
    }
}

/// A compiled, verified program with its resolved header, ready to run.
struct Prepared<'a> {
    name: &'a str,
    image: VerifiedImage,
    target: Arc<Target>,
    header: &'a Header,
    sets: Vec<Resolved<'a>>,
    expects: Vec<Resolved<'a>>,
}

/// Run one mode; every mismatch becomes a line in `failures`.
fn run_mode(p: &Prepared, mode: &str, config: VmConfig, failures: &mut Vec<String>) {
    let Prepared {
        name,
        image,
        target,
        header,
        sets,
        expects,
    } = p;
    let mut vm = match Vm::new(image.clone(), Arc::clone(target), config) {
        Ok(vm) => vm,
        Err(e) => {
            failures.push(format!("{name} [{mode}]: does not load: {e:?}"));
            return;
        }
    };
    for s in sets {
        if let Err(e) = vm.write(s.address, s.bits) {
            failures.push(format!(
                "{name}:{} [{mode}]: cannot set {}: {e:?}",
                s.source.line, s.source.var
            ));
        }
    }
    let scans = header.scans.unwrap_or(1);
    let mut fault = None;
    for n in 1..=scans {
        if let Err(f) = vm.scan() {
            fault = Some((n, f));
            break;
        }
    }
    match (header.fault, &fault) {
        (None, None) => {}
        (None, Some((n, f))) => failures.push(format!(
            "{name} [{mode}]: unexpected fault in scan {n}: {f} (code {})",
            f.code()
        )),
        (Some(code), None) => failures.push(format!(
            "{name} [{mode}]: expected fault code {code}, but {scans} scans ran without one"
        )),
        (Some(code), Some((n, f))) if f.code() != code => failures.push(format!(
            "{name} [{mode}]: expected fault code {code}, got {f} (code {}) in scan {n}",
            f.code()
        )),
        (Some(_), Some(_)) => {}
    }
    for e in expects {
        match vm.read(e.address) {
            Ok(got) if got == e.bits => {}
            Ok(got) => failures.push(format!(
                "{name}:{} [{mode}]: {} expected {}, got {}",
                e.source.line,
                e.source.var,
                show(e.bits, e.address.width),
                show(got, e.address.width)
            )),
            Err(err) => failures.push(format!(
                "{name}:{} [{mode}]: cannot read {}: {err:?}",
                e.source.line, e.source.var
            )),
        }
    }
}

/// Check one program; every problem becomes a line in `failures`.
fn run_program(path: &Path, failures: &mut Vec<String>) {
    let name = path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into(),
    );
    let bytes = match std::fs::read(path) {
        Ok(b) => b,
        Err(e) => return failures.push(format!("{name}: {e}")),
    };
    let file = match SourceFile::from_bytes(path.display().to_string(), bytes) {
        Ok(f) => f,
        Err(e) => return failures.push(format!("{name}: not UTF-8: {e:?}")),
    };
    let header = match parse_header(&file.text) {
        Ok(h) => h,
        Err(errors) => {
            failures.extend(errors.into_iter().map(|e| format!("{name}: {e}")));
            return;
        }
    };
    let explicit = match &header.plc {
        None => None,
        Some(plc) => match stdlib::shared(plc) {
            Ok(target) => Some(ExplicitTarget {
                target,
                origin: format!("--plc {plc}"),
            }),
            Err(e) => return failures.push(format!("{name}: `// plc: {plc}`: {e}")),
        },
    };
    let compiled = compile(file, explicit.as_ref());
    let checked = &compiled.checked;
    let Some(image) = &compiled.image else {
        for d in checked.diagnostics().iter().filter(|d| d.is_error()) {
            let line = checked
                .index
                .line_col(&checked.file.text, d.primary.span.start as usize)
                .line;
            failures.push(format!(
                "{name}:{line}: does not compile: {} {}",
                d.code.as_str(),
                d.message
            ));
        }
        return;
    };
    let target = Arc::clone(&checked.target);
    let verified = match gutta_format::verify(image, &target) {
        Ok(v) => v,
        Err(e) => return failures.push(format!("{name}: does not verify: {e:?}")),
    };
    let sets = resolve_all(&target, &header.sets, &name, failures);
    let expects = resolve_all(&target, &header.expects, &name, failures);
    if sets.len() != header.sets.len() || expects.len() != header.expects.len() {
        return;
    }
    let base = VmConfig {
        scan_ms: header.scan_ms.unwrap_or(VmConfig::default().scan_ms),
        watchdog: header.watchdog.unwrap_or(VmConfig::default().watchdog),
        ..VmConfig::default()
    };
    let prepared = Prepared {
        name: &name,
        image: verified,
        target,
        header: &header,
        sets,
        expects,
    };
    for (mode, fast) in [("fast", true), ("generic", false)] {
        run_mode(&prepared, mode, VmConfig { fast, ..base }, failures);
    }
}

fn corpus_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/run")
}

#[test]
fn every_program_gives_its_expected_values() {
    let dir = corpus_dir();
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "lad"))
        .collect();
    files.sort();
    let mut failures = Vec::new();
    if files.len() < MIN_PROGRAMS {
        failures.push(format!(
            "{}: {} programs, expected at least {MIN_PROGRAMS}",
            dir.display(),
            files.len()
        ));
    }
    for path in &files {
        run_program(path, &mut failures);
    }
    assert!(
        failures.is_empty(),
        "{} failure(s) in {} programs of tests/data/run:\n{}",
        failures.len(),
        files.len(),
        failures.join("\n")
    );
}

#[test]
fn header_lines_are_read_as_documented() {
    let text = "// plc: EC30-EK51\n// A plain comment: with a colon.\n// scans: 3\n\
                // later: free text\n// set: MW0=-1\n// expect: MW2 = 16#0E01  // explained here\n\
                // expect: Q0.0 = 1\n\nORGANIZATION_BLOCK MAIN\n";
    let h = parse_header(text).expect("header parses");
    assert_eq!(h.plc.as_deref(), Some("EC30-EK51"));
    assert_eq!(h.scans, Some(3));
    assert_eq!((h.sets[0].var.as_str(), h.sets[0].value), ("MW0", -1));
    assert_eq!((h.expects[0].line, h.expects[0].value), (6, 0x0E01));
    assert_eq!(h.expects[1].var, "Q0.0");
    assert_eq!(parse_number("2#1010"), Ok(10));
    assert_eq!(parse_number("-16#10"), Ok(-16));
    let target = stdlib::shared(stdlib::DEFAULT).expect("target");
    let r = resolve(&target, &h.sets[0]).expect("resolves");
    assert_eq!(r.bits, 0xFFFF, "negative values are masked to the width");
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
        ("// scans: 2\n", "checks nothing"),
        (
            "// expect: MW0 = 1\nORGANIZATION_BLOCK MAIN\n// expect: MW2 = 1\n",
            "line 3: `// expect:` after the header",
        ),
    ] {
        let errors = parse_header(text).expect_err(text);
        assert!(
            errors.iter().any(|e| e.contains(wanted)),
            "{text:?}: {errors:?}"
        );
    }
    let target = stdlib::shared(stdlib::DEFAULT).expect("target");
    let too_big = Assignment {
        line: 4,
        var: "MB0".into(),
        value: 256,
    };
    let err = resolve(&target, &too_big).expect_err("256 is no byte");
    assert!(err.starts_with("line 4"), "{err}");
}
