//! The documentation's examples are true: every ```console block of README.md,
//! ARCHITECTURE.md and docs/**/*.md runs, with gutta-cc, gutta-vm and gutta-sim on PATH,
//! and prints what it shows (the runner's rules are in docs/testing.md, "Console
//! examples in the docs"). What the docs say about the repository itself is checked by
//! `docs_consistency.rs`.

mod common;

use std::collections::BTreeMap;
use std::io::{BufRead, BufReader, Read};
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use common::docs::{markdown_files, read, relative, repo, walk};

// ---------------------------------------------------------------------------------
// Parsing the blocks

/// One `$ command` of a block and the lines it is shown to print.
#[derive(Debug, Clone)]
struct Step {
    /// 1-based line of the `$` in the Markdown file.
    line: usize,
    command: String,
    expected: Vec<String>,
}

/// A ```console block and the `<!-- console: ... -->` directives just above it.
#[derive(Debug, Clone)]
struct Block {
    /// 1-based line of the opening fence.
    line: usize,
    /// `continue`: runs in the session of the block before (same folder, working
    /// directory and servers) instead of a fresh one.
    continues: bool,
    /// `skip REASON`: not run; the reason says why it cannot.
    skip: Option<String>,
    /// `varies PATTERN`: an expected line that PATTERN matches only has to match PATTERN.
    varies: Vec<String>,
    steps: Vec<Step>,
}

const DIRECTIVE: &str = "<!-- console:";

/// The console blocks of a Markdown text. Panics on a malformed block or directive,
/// naming `file:line`.
fn console_blocks(file: &str, text: &str) -> Vec<Block> {
    let lines: Vec<&str> = text.lines().collect();
    let mut blocks = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let fence = lines[i].trim_start();
        if !fence.starts_with("```") {
            i += 1;
            continue;
        }
        let console = fence.trim_end() == "```console";
        let open = i;
        i += 1;
        let mut body = Vec::new();
        while i < lines.len() && lines[i].trim() != "```" {
            body.push((i + 1, lines[i]));
            i += 1;
        }
        assert!(
            i < lines.len(),
            "{file}:{}: the block never closes",
            open + 1
        );
        i += 1;
        if !console {
            continue;
        }
        let mut block = Block {
            line: open + 1,
            continues: false,
            skip: None,
            varies: Vec::new(),
            steps: Vec::new(),
        };
        // The directives: the comment lines right above the fence (blank lines between
        // them allowed).
        let mut j = open;
        while j > 0 {
            let above = lines[j - 1].trim();
            if above.is_empty() {
                j -= 1;
                continue;
            }
            let Some(rest) = above.strip_prefix(DIRECTIVE) else {
                break;
            };
            let directive = rest
                .strip_suffix("-->")
                .unwrap_or_else(|| panic!("{file}:{j}: a directive is one line: {above}"))
                .trim();
            let (word, arg) = directive.split_once(' ').unwrap_or((directive, ""));
            match word {
                "continue" => block.continues = true,
                "skip" => {
                    assert!(!arg.trim().is_empty(), "{file}:{j}: `skip` needs a reason");
                    block.skip = Some(arg.trim().to_string());
                }
                "varies" => {
                    assert!(
                        arg.contains("[..]"),
                        "{file}:{j}: a `varies` pattern holds `[..]`"
                    );
                    block.varies.push(arg.trim().to_string());
                }
                _ => panic!("{file}:{j}: unknown directive `{word}` (continue, skip, varies)"),
            }
            j -= 1;
        }
        for (n, line) in body {
            if let Some(command) = line.strip_prefix("$ ") {
                block.steps.push(Step {
                    line: n,
                    command: command.to_string(),
                    expected: Vec::new(),
                });
            } else {
                let step = block.steps.last_mut().unwrap_or_else(|| {
                    panic!("{file}:{n}: output before the first `$ ` command: {line}")
                });
                step.expected.push(line.to_string());
            }
        }
        assert!(
            !block.steps.is_empty(),
            "{file}:{}: a console block without a `$ ` command",
            block.line
        );
        blocks.push(block);
    }
    blocks
}

// ---------------------------------------------------------------------------------
// Comparing output

/// Whether `line` matches `pattern`, in which `[..]` stands for any text.
fn glob(pattern: &str, line: &str) -> bool {
    let parts: Vec<&str> = pattern.split("[..]").collect();
    if parts.len() == 1 {
        return pattern == line;
    }
    let (first, last) = (parts[0], parts[parts.len() - 1]);
    if !line.starts_with(first) || line.len() < first.len() + last.len() {
        return false;
    }
    if !line[first.len()..].ends_with(last) {
        return false;
    }
    let mut rest = &line[first.len()..line.len() - last.len()];
    for part in &parts[1..parts.len() - 1] {
        match rest.find(part) {
            Some(at) => rest = &rest[at + part.len()..],
            None => return false,
        }
    }
    true
}

/// Whether the actual lines match the expected ones: `...` alone on a line matches any
/// number of lines (none too), every other line matches one line (`glob`).
fn matches(expected: &[String], actual: &[String]) -> bool {
    match expected.split_first() {
        None => actual.is_empty(),
        Some((first, rest)) if first == "..." => {
            (0..=actual.len()).any(|skip| matches(rest, &actual[skip..]))
        }
        Some((first, rest)) => {
            actual.first().is_some_and(|a| glob(first, a)) && matches(rest, &actual[1..])
        }
    }
}

/// The normalisation applied to both sides: trailing blanks go (also trailing empty
/// lines), and a wall-clock time, a number with exactly two decimals before ` s`
/// (`(0.01 s)`, `in 0.12 s`), becomes `#.## s`. Virtual times have three decimals
/// (`2.510 s`) and stay.
fn normalise(lines: &[String]) -> Vec<String> {
    let mut out: Vec<String> = lines.iter().map(|l| wall_clock(l.trim_end())).collect();
    while out.last().is_some_and(|l| l.is_empty()) {
        out.pop();
    }
    out
}

fn wall_clock(line: &str) -> String {
    let b = line.as_bytes();
    let mut out = String::new();
    let mut i = 0;
    while i < b.len() {
        if b[i].is_ascii_digit() && (i == 0 || !b[i - 1].is_ascii_digit() && b[i - 1] != b'.') {
            let mut j = i;
            while j < b.len() && b[j].is_ascii_digit() {
                j += 1;
            }
            let two = b.get(j) == Some(&b'.')
                && b.get(j + 1).is_some_and(u8::is_ascii_digit)
                && b.get(j + 2).is_some_and(u8::is_ascii_digit)
                && b.get(j + 3) == Some(&b' ')
                && b.get(j + 4) == Some(&b's')
                && !b.get(j + 5).is_some_and(u8::is_ascii_alphanumeric);
            if two {
                out.push_str("#.## s");
                i = j + 5;
                continue;
            }
            out.push_str(&line[i..j]);
            i = j;
            continue;
        }
        let ch = line[i..].chars().next().expect("a char");
        out.push(ch);
        i += ch.len_utf8();
    }
    out
}

/// `text` with `127.0.0.1:FROM` (not followed by another digit) as `127.0.0.1:TO`.
fn replace_port(text: &str, from: u16, to: u16) -> String {
    let needle = format!("127.0.0.1:{from}");
    let mut out = String::new();
    let mut rest = text;
    while let Some(at) = rest.find(&needle) {
        let end = at + needle.len();
        out.push_str(&rest[..at]);
        if rest[end..].starts_with(|c: char| c.is_ascii_digit()) {
            out.push_str(&needle);
        } else {
            out.push_str(&format!("127.0.0.1:{to}"));
        }
        rest = &rest[end..];
    }
    out.push_str(rest);
    out
}

/// The ports of `127.0.0.1:PORT` in `text`, in order.
fn loopback_ports(text: &str) -> Vec<u16> {
    let mut ports = Vec::new();
    let mut rest = text;
    while let Some(at) = rest.find("127.0.0.1:") {
        rest = &rest[at + "127.0.0.1:".len()..];
        let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
        if let Ok(port) = digits.parse() {
            ports.push(port);
        }
    }
    ports
}

// ---------------------------------------------------------------------------------
// Running a session

/// A server a block started (`gutta-sim` with a listener), killed with its process
/// group when the session ends, also when the test panics.
struct Server {
    child: Child,
}

impl Drop for Server {
    fn drop(&mut self) {
        kill_group(&mut self.child);
    }
}

fn kill_group(child: &mut Child) {
    // Bash's kill: procps-ng 4.0.2's /usr/bin/kill reads `-KILL -PGID` as `kill(-9)`.
    let _ = Command::new("bash")
        .args(["-c", &format!("kill -KILL -- -{}", child.id())])
        .stderr(Stdio::null())
        .status();
    let _ = child.kill();
    let _ = child.wait();
}

/// The folder, working directory, servers and port map blocks share.
struct Session {
    dir: PathBuf,
    cwd: PathBuf,
    servers: Vec<Server>,
    /// documented port -> the port the server really listens on.
    ports: BTreeMap<u16, u16>,
}

impl Session {
    /// A fresh folder holding copies of examples/ and docs/examples/, as the repository
    /// root does; the working directory starts there.
    fn new(tag: &str) -> Session {
        let dir =
            std::env::temp_dir().join(format!("gutta-docs-console-{}-{tag}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("creates the session folder");
        for folder in ["examples", "docs/examples"] {
            copy_tree(&repo().join(folder), &dir.join(folder));
        }
        Session {
            cwd: dir.clone(),
            dir,
            servers: Vec::new(),
            ports: BTreeMap::new(),
        }
    }

    fn command(&self, script: &str) -> Command {
        let bin = Path::new(env!("CARGO_BIN_EXE_gutta-cc"))
            .parent()
            .expect("the binaries' folder");
        let path = format!(
            "{}:{}",
            bin.display(),
            std::env::var("PATH").unwrap_or_default()
        );
        let mut c = Command::new("bash");
        c.arg("-c")
            .arg(script)
            .current_dir(&self.cwd)
            .env("PATH", path)
            .env("NO_COLOR", "1")
            .env_remove("PLC_TYPE")
            .env_remove("GUTTA_PASSWORD")
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .process_group(0);
        c
    }

    /// The command as it runs: `binaries(command)` with the documented ports as the
    /// servers' real ones.
    fn real_command(&self, command: &str) -> String {
        self.to_real(&binaries(command))
    }

    /// The documented ports in `text` as the servers' real ones.
    fn to_real(&self, text: &str) -> String {
        let mut text = text.to_string();
        for (&doc, &real) in &self.ports {
            text = replace_port(&text, doc, real);
        }
        text
    }

    /// The servers' real ports in `text` as the documented ones.
    fn to_documented(&self, text: &str) -> String {
        let mut text = text.to_string();
        for (&doc, &real) in &self.ports {
            text = replace_port(&text, real, doc);
        }
        text
    }

    /// Every gutta.toml the examples wrote points at the servers' real ports.
    fn retarget_manifests(&self) {
        if self.ports.is_empty() {
            return;
        }
        walk(&self.dir, &mut |p| {
            if p.file_name().is_some_and(|n| n == "gutta.toml") {
                let text = read(p);
                let new = self.to_real(&text);
                if new != text {
                    std::fs::write(p, new).expect("rewrites gutta.toml");
                }
            }
        });
    }

    /// Runs one command to its end (at most two minutes) and returns its output,
    /// stdout and stderr interleaved as a terminal shows them.
    fn run(&mut self, command: &str) -> Result<Vec<String>, String> {
        self.retarget_manifests();
        let state = self.dir.join(".cwd");
        let script = format!(
            "exec 2>&1\ntrap 'pwd > \"{}\"' EXIT\n{}\n",
            state.display(),
            self.real_command(command)
        );
        let mut child = self.command(&script).spawn().map_err(|e| e.to_string())?;
        let mut stdout = child.stdout.take().expect("piped");
        let reader = std::thread::spawn(move || {
            let mut bytes = Vec::new();
            let _ = stdout.read_to_end(&mut bytes);
            bytes
        });
        let start = Instant::now();
        loop {
            if child.try_wait().map_err(|e| e.to_string())?.is_some() {
                break;
            }
            if start.elapsed() > Duration::from_secs(120) {
                kill_group(&mut child);
                return Err("did not end within 120 s".into());
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        let bytes = reader.join().expect("reader");
        if let Ok(cwd) = std::fs::read_to_string(&state) {
            self.cwd = PathBuf::from(cwd.trim_end());
        }
        let text = self.to_documented(&String::from_utf8_lossy(&bytes));
        Ok(text.lines().map(str::to_string).collect())
    }

    /// Starts a server in the background on free ports (each documented
    /// `127.0.0.1:PORT` becomes `127.0.0.1:0`), reads its first `lines` lines (at least
    /// one) and learns its real ports from them.
    fn start(&mut self, command: &str, lines: usize) -> Result<Vec<String>, String> {
        self.retarget_manifests();
        let documented = loopback_ports(command);
        let mut real_command = binaries(command);
        for &port in &documented {
            real_command = replace_port(&real_command, port, 0);
        }
        let script = format!("exec 2>&1\nexec {real_command}\n");
        let mut child = self.command(&script).spawn().map_err(|e| e.to_string())?;
        let stdout = child.stdout.take().expect("piped");
        self.servers.push(Server { child });
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { break };
                if tx.send(line).is_err() {
                    break;
                }
            }
        });
        let mut got = Vec::new();
        let deadline = Instant::now() + Duration::from_secs(30);
        while got.len() < lines.max(1) {
            let left = deadline.saturating_duration_since(Instant::now());
            match rx.recv_timeout(left) {
                Ok(line) => got.push(line),
                Err(_) => {
                    return Err(format!(
                        "the server printed {} within 30 s: {got:?}",
                        gutta_cli::plural::count(got.len(), "line")
                    ))
                }
            }
        }
        let real = loopback_ports(&got.join("\n"));
        for (doc, real) in documented.iter().zip(real) {
            self.ports.insert(*doc, real);
        }
        Ok(got.iter().map(|l| self.to_documented(l)).collect())
    }
}

impl Drop for Session {
    fn drop(&mut self) {
        self.servers.clear();
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

fn copy_tree(from: &Path, to: &Path) {
    let Ok(entries) = std::fs::read_dir(from) else {
        return;
    };
    std::fs::create_dir_all(to).expect("creates a folder");
    for entry in entries {
        let path = entry.expect("entry").path();
        let target = to.join(path.file_name().expect("a name"));
        if path.is_dir() {
            copy_tree(&path, &target);
        } else {
            std::fs::copy(&path, &target).expect("copies");
        }
    }
}

/// `cargo run [-q] -p gutta-cli --bin NAME -- ARGS` as the binary under test, `NAME
/// ARGS` (cargo is not run from a test).
fn binaries(command: &str) -> String {
    let mut command = command.to_string();
    for quiet in ["-q ", ""] {
        for bin in ["gutta-cc", "gutta-vm", "gutta-sim"] {
            let cargo = format!("cargo run {quiet}-p gutta-cli --bin {bin} -- ");
            command = command.replace(&cargo, &format!("{bin} "));
        }
    }
    command
}

/// A command that serves until it is stopped: `gutta-sim` with a listener.
fn is_server(command: &str) -> bool {
    let words: Vec<&str> = command.split_whitespace().collect();
    words.first() == Some(&"gutta-sim")
        && words.iter().any(|w| matches!(*w, "--tcp" | "--rtu-tcp"))
        && !words
            .iter()
            .any(|w| matches!(*w, "--help" | "-h" | "--man" | "--completions"))
}

/// Runs the console blocks of one file; returns a failure report per failing command.
fn run_file(path: &Path) -> Vec<String> {
    let file = relative(path);
    let blocks = console_blocks(&file, &read(path));
    let mut failures = Vec::new();
    let mut session: Option<Session> = None;
    for (n, block) in blocks.iter().enumerate() {
        if block.skip.is_some() {
            continue;
        }
        if block.continues && session.is_none() {
            // It continues a session that failed (reported) or a skipped block.
            continue;
        }
        if !block.continues {
            let tag = format!("{}-{n}", file.replace(['/', '.'], "_"));
            session = Some(Session::new(&tag));
        }
        let s = session.as_mut().expect("a session");
        for step in &block.steps {
            let result = if is_server(&step.command) {
                s.start(&step.command, step.expected.len())
            } else {
                s.run(&step.command)
            };
            let expected: Vec<String> = step
                .expected
                .iter()
                .map(|line| {
                    block
                        .varies
                        .iter()
                        .find(|p| glob(p, line.trim_end()))
                        .cloned()
                        .unwrap_or_else(|| line.clone())
                })
                .collect();
            let failure = match result {
                Err(e) => Some(e),
                Ok(actual) => {
                    let (e, a) = (normalise(&expected), normalise(&actual));
                    (!matches(&e, &a)).then(|| format!("actual output:\n{}", actual.join("\n")))
                }
            };
            if let Some(why) = failure {
                failures.push(format!(
                    "{file}:{}: $ {}\nexpected output:\n{}\n{why}\n",
                    step.line,
                    step.command,
                    step.expected.join("\n")
                ));
                // The commands after it depend on it: the rest of the session would
                // only repeat the failure.
                drop(session.take());
                break;
            }
        }
    }
    failures
}

#[test]
fn every_console_example_prints_what_it_shows() {
    let files = markdown_files();
    let failures: Vec<String> = std::thread::scope(|scope| {
        let handles: Vec<_> = files
            .iter()
            .map(|f| scope.spawn(move || run_file(f)))
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().expect("a file's runner"))
            .collect()
    });
    assert!(
        failures.is_empty(),
        "console examples that do not print what the docs show ({}):\n\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// The blocks the docs mark as not runnable stay few, and each says why.
#[test]
fn skipped_console_blocks_are_rare_and_explained() {
    let mut skipped = Vec::new();
    let mut total = 0;
    for path in markdown_files() {
        let file = relative(&path);
        for block in console_blocks(&file, &read(&path)) {
            total += 1;
            if let Some(why) = &block.skip {
                skipped.push(format!("{file}:{}: {why}", block.line));
            }
        }
    }
    assert!(total >= 10, "only {total} console blocks found");
    assert!(
        skipped.len() <= 3,
        "too many skipped blocks:\n{}",
        skipped.join("\n")
    );
}

// ---------------------------------------------------------------------------------
// The runner's own rules

#[test]
fn the_runner_compares_as_docs_testing_md_says() {
    let s = |v: &[&str]| v.iter().map(|l| l.to_string()).collect::<Vec<_>>();
    // `...` elides any number of lines, none included.
    assert!(matches(&s(&["a", "...", "z"]), &s(&["a", "b", "c", "z"])));
    assert!(matches(&s(&["a", "...", "z"]), &s(&["a", "z"])));
    assert!(!matches(&s(&["a", "...", "z"]), &s(&["a", "b"])));
    assert!(!matches(&s(&["a", "b"]), &s(&["a", "b", "c"])));
    // `[..]` within a line.
    assert!(glob("Lamp  Q0.0  bool  [..]", "Lamp  Q0.0  bool  1      -"));
    assert!(glob("x[..]y[..]z", "x1y2z"));
    assert!(!glob("x[..]y", "x1z"));
    assert!(!glob("ab[..]ba", "aba"));
    // Wall-clock times, not virtual ones.
    assert_eq!(
        wall_clock("in 16 requests (0.01 s); ok in 12.34 s"),
        "in 16 requests (#.## s); ok in #.## s"
    );
    assert_eq!(wall_clock("(251 scans, 2.510 s)"), "(251 scans, 2.510 s)");
    // Ports.
    assert_eq!(
        replace_port("tcp = \"127.0.0.1:5020\" 127.0.0.1:50201", 5020, 41000),
        "tcp = \"127.0.0.1:41000\" 127.0.0.1:50201"
    );
    assert_eq!(
        loopback_ports("on 127.0.0.1:5020 and 127.0.0.1:7"),
        [5020, 7]
    );
    // Directives and steps.
    let text = "<!-- console: continue -->\n<!-- console: varies a [..] -->\n```console\n$ echo a 1\na 2\n$ true\n```\n";
    let blocks = console_blocks("t.md", text);
    assert_eq!(blocks.len(), 1);
    assert!(blocks[0].continues);
    assert_eq!(blocks[0].varies, ["a [..]"]);
    assert_eq!(blocks[0].steps.len(), 2);
    assert_eq!(blocks[0].steps[0].expected, ["a 2"]);
    assert_eq!(blocks[0].steps[0].line, 4);
    assert!(is_server("gutta-sim --tcp 127.0.0.1:5020"));
    assert!(!is_server("gutta-sim --help"));
    assert!(!is_server("gutta-cc read MW24 --tcp 127.0.0.1:5020"));
    assert_eq!(
        binaries(
            "cargo run -q -p gutta-cli --bin gutta-cc -- a.lad -o i/ && cargo run -p gutta-cli --bin gutta-vm -- i/"
        ),
        "gutta-cc a.lad -o i/ && gutta-vm i/"
    );
}

/// A wrong expectation fails: the runner really compares.
#[test]
fn a_wrong_example_fails() {
    let dir = std::env::temp_dir().join(format!("gutta-docs-console-wrong-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let md = dir.join("wrong.md");
    std::fs::write(
        &md,
        "```console\n$ gutta-cc modbus MW20\nMW20 is not what it prints\n```\n",
    )
    .expect("writes");
    let failures = run_file(&md);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(failures.len(), 1, "{failures:?}");
    assert!(
        failures[0].contains("wrong.md:2: $ gutta-cc modbus MW20"),
        "{}",
        failures[0]
    );
    assert!(failures[0].contains("actual output:"), "{}", failures[0]);
}
