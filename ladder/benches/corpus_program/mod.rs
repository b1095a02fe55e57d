//! A large program made of the repository's real networks, for the ladder model's speed
//! bench (`benches/model.rs`) and its test (`tests/corpus_program.rs`). Not generated
//! noise: every network is one a real program of examples/, tests/data/run and
//! tests/data/microwin holds, with its title and comment lines.
//!
//! How it is made:
//! - Each program is checked (on the PLC type it names, else the default); programs
//!   with errors are left out.
//! - Its symbols are renamed `P<n>_<name>` (n: the program's place in the list) and
//!   gathered in one SYMBOLS block; its subroutines become `P<n>_<name>:SBR<k>`, their
//!   variable sections and networks kept; every operand naming a symbol, and every
//!   CALL's block, is rewritten to the new name (through the parsed tree's operand
//!   spans, not text search); a Micro/WIN system symbol (`Always_On`) becomes its
//!   address. Interrupt, data and system blocks are left out.
//! - The program's MAIN networks alone (with its symbols and subroutines) are checked
//!   on the bench target (the front end's, compiler/benches/target/: program limits a
//!   1,000-network program fits in); networks with an error there (an `ATCH` of an
//!   interrupt routine left out) are dropped, and a program whose symbols or
//!   subroutines have errors is left out.
//! - MAIN then takes the kept MAIN networks of every program in turn, cycled (the
//!   whole list again and again) until the program has `networks` networks with the
//!   subroutines. Each copy's label numbers are moved up so that its `JMP`s and
//!   `LBL`s pair up as in the original. Other operands are not renumbered: the compiler
//!   accepts the same bit, word, timer or counter in many networks (with warnings of
//!   a coil or timer driven twice); the test checks that it compiles with no error.
//!
//! Reads the repository's files: a bench helper, not library code.

#![allow(
    clippy::disallowed_methods,
    reason = "the program is made from the repository's files"
)]

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use gutta_compiler::check_source;
use gutta_compiler::source::{SourceFile, Span};
use gutta_compiler::syntax::ast::{self, OperandKind};
use gutta_compiler::{CheckedFile, ExplicitTarget};

/// The corpora the program's networks come from (relative to the repository's root).
const CORPORA: [(&str, &[&str]); 3] = [
    ("examples", &["lad"]),
    ("tests/data/run", &["lad"]),
    ("tests/data/microwin", &["lad", "awl"]),
];

/// One source program's part of the made program.
struct Part {
    symbols: Vec<String>,
    subroutines: Vec<String>,
    /// The subroutines' network count.
    subroutine_networks: usize,
    /// MAIN's networks, their label numbers as `LABEL` marks (see `labelled`).
    main: Vec<String>,
    /// One more than the highest label number of MAIN's networks (0: none).
    labels: i64,
}

/// Marks a label number in a MAIN network's text: `\u{1}3\u{1}` for label 3.
const LABEL: char = '\u{1}';

/// A MAIN network's text with each label number moved up by `offset`.
fn labelled(net: &str, offset: i64) -> String {
    net.split(LABEL)
        .enumerate()
        .map(|(i, piece)| match piece.parse::<i64>() {
            Ok(n) if i % 2 == 1 => (n + offset).to_string(),
            _ => piece.to_string(),
        })
        .collect()
}

/// The program text: a SYMBOLS block, MAIN holding the corpus's MAIN networks cycled,
/// then the subroutines; at least `networks` networks in all.
pub fn generate(networks: usize, target: &ExplicitTarget) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut parts = Vec::new();
    let mut next_sbr = 0;
    for (dir, exts) in CORPORA {
        for path in files(&root.join(dir), exts) {
            let n = parts.len();
            if let Some(part) = part_of(&path, n, &mut next_sbr, target) {
                parts.push(part);
            }
        }
    }
    assert!(
        parts.iter().any(|p| !p.main.is_empty()),
        "the corpora give MAIN networks"
    );
    let in_subroutines: usize = parts.iter().map(|p| p.subroutine_networks).sum();
    let in_main = networks.saturating_sub(in_subroutines).max(1);
    // Each copy of each program's networks gets label numbers of its own.
    let labels_per_copy: i64 = parts.iter().map(|p| p.labels).sum();
    let mut main = Vec::with_capacity(in_main);
    'copies: for copy in 0.. {
        let mut offset = copy * labels_per_copy;
        for p in &parts {
            for net in &p.main {
                if main.len() == in_main {
                    break 'copies;
                }
                main.push(labelled(net, offset));
            }
            offset += p.labels;
        }
    }
    let mut text = String::from("SYMBOLS\n");
    for p in &parts {
        for s in &p.symbols {
            text.push_str(s);
        }
    }
    text.push_str("END_SYMBOLS\n\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n");
    for (i, net) in main.iter().enumerate() {
        let _ = writeln!(text, "NETWORK {}{net}", i + 1);
    }
    text.push_str("END_ORGANIZATION_BLOCK\n");
    for p in &parts {
        for s in &p.subroutines {
            text.push_str(s);
        }
    }
    text
}

/// The program files of a folder with one of `exts`, sorted.
fn files(dir: &Path, exts: &[&str]) -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    out.retain(|p| {
        p.extension()
            .is_some_and(|x| exts.iter().any(|e| x.eq_ignore_ascii_case(e)))
    });
    out.sort();
    out
}

/// The program at `path` as part `n`, or None when it does not check clean, or its
/// symbols or subroutines do not on the bench target.
fn part_of(path: &Path, n: usize, next_sbr: &mut usize, target: &ExplicitTarget) -> Option<Part> {
    let bytes = std::fs::read(path).ok()?;
    let (file, _) =
        SourceFile::from_program_file_bytes(path.display().to_string(), bytes, false).ok()?;
    let checked = check_source(file, None);
    if checked.has_errors() {
        return None;
    }
    let sbr_before = *next_sbr;
    let mut part = Renamer::new(&checked, n, next_sbr).part();
    // The part alone on the bench target: drop the MAIN networks with errors.
    let alone = check_source(SourceFile::new("part.lad", assemble(&part)), Some(target));
    if alone.has_errors() {
        let main = alone.ast.units.first()?;
        let bad: Vec<usize> = alone
            .diagnostics()
            .iter()
            .filter(|d| d.is_error())
            .map(|d| {
                main.networks
                    .iter()
                    .position(|net| net_span(net).contains(&d.primary.span.start))
            })
            .collect::<Option<Vec<usize>>>()
            .unwrap_or_else(|| vec![usize::MAX]);
        if bad.contains(&usize::MAX) {
            // An error outside MAIN's networks: leave the program out.
            *next_sbr = sbr_before;
            return None;
        }
        part.main = std::mem::take(&mut part.main)
            .into_iter()
            .enumerate()
            .filter(|(i, _)| !bad.contains(i))
            .map(|(_, net)| net)
            .collect();
        let again = check_source(SourceFile::new("part.lad", assemble(&part)), Some(target));
        if again.has_errors() {
            *next_sbr = sbr_before;
            return None;
        }
    }
    Some(part)
}

/// The byte range of a network, from its header (or first instruction) to its last
/// instruction's end.
fn net_span(net: &ast::Network) -> std::ops::Range<u32> {
    let end = net.instructions.last().map_or(net.span.end, |i| i.span.end);
    net.span.start..end.max(net.span.end)
}

/// One part as a program of its own.
fn assemble(part: &Part) -> String {
    let mut text = String::from("SYMBOLS\n");
    part.symbols.iter().for_each(|s| text.push_str(s));
    text.push_str("END_SYMBOLS\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n");
    for (i, net) in part.main.iter().enumerate() {
        let _ = writeln!(text, "NETWORK {}{}", i + 1, labelled(net, 0));
    }
    text.push_str("END_ORGANIZATION_BLOCK\n");
    part.subroutines.iter().for_each(|s| text.push_str(s));
    text
}

/// A checked program's symbols and subroutines renamed for part `n`.
struct Renamer<'a> {
    checked: &'a CheckedFile,
    /// Symbol name, upper case -> its new name.
    symbols: HashMap<String, String>,
    /// Subroutine name and numbered name, upper case -> its new name.
    subroutines: HashMap<String, String>,
    /// New subroutine headers, by unit index.
    headers: HashMap<usize, String>,
}

impl<'a> Renamer<'a> {
    fn new(checked: &'a CheckedFile, n: usize, next_sbr: &mut usize) -> Renamer<'a> {
        let text = |s: Span| checked.file.slice(s).trim().to_string();
        let symbols = checked
            .ast
            .symbols
            .iter()
            .map(|s| {
                let name = text(s.name);
                (name.to_ascii_uppercase(), format!("P{n}_{name}"))
            })
            .collect();
        let mut subroutines = HashMap::new();
        let mut headers = HashMap::new();
        for (u, unit) in checked.ast.units.iter().enumerate() {
            if keyword(checked, unit) != "SUBROUTINE_BLOCK" {
                continue;
            }
            let name = text(unit.header.name);
            let new = format!("P{n}_{name}");
            // Its numbered name (`SBR0`) as written, else as the checker numbered it.
            let numbered = unit.header.number.map(|(_, span)| text(span)).or_else(|| {
                let program = checked.output.program.as_ref()?;
                let u = program
                    .units
                    .iter()
                    .find(|u| u.name.eq_ignore_ascii_case(&name));
                u.map(|u| u.numbered_name())
            });
            if let Some(numbered) = numbered {
                subroutines.insert(numbered.to_ascii_uppercase(), new.clone());
            }
            subroutines.insert(name.to_ascii_uppercase(), new.clone());
            headers.insert(u, format!("SUBROUTINE_BLOCK {new}:SBR{next_sbr}\n"));
            *next_sbr += 1;
        }
        Renamer {
            checked,
            symbols,
            subroutines,
            headers,
        }
    }

    fn slice(&self, s: Span) -> &'a str {
        self.checked.file.slice(s)
    }

    fn part(&self) -> Part {
        let ast = &self.checked.ast;
        let symbols = ast
            .symbols
            .iter()
            .map(|s| {
                let mut row = format!(
                    "  {} : {}",
                    self.symbols[&self.slice(s.name).trim().to_ascii_uppercase()],
                    self.slice(s.address).trim()
                );
                if let Some(t) = s.data_type {
                    let _ = write!(row, " : {}", self.slice(t).trim());
                }
                if let Some(c) = s.comment {
                    let c = self.slice(c).trim().trim_matches('"').replace('\n', " ");
                    if !c.is_empty() {
                        let _ = write!(row, " // {c}");
                    }
                }
                row.push('\n');
                row
            })
            .collect();
        let mut main = Vec::new();
        let mut subroutines = Vec::new();
        let mut subroutine_networks = 0;
        let mut labels = 0;
        for (u, unit) in ast.units.iter().enumerate() {
            let main_block = keyword(self.checked, unit) == "ORGANIZATION_BLOCK";
            let networks = unit
                .networks
                .iter()
                .filter(|net| !net.instructions.is_empty())
                .map(|net| self.network(net, main_block.then_some(&mut labels)));
            match keyword(self.checked, unit).as_str() {
                "ORGANIZATION_BLOCK" => main.extend(networks),
                "SUBROUTINE_BLOCK" => {
                    let mut block = self.headers[&u].clone();
                    // TITLE=, the variable sections and BEGIN, as written.
                    let from = line_end(&self.checked.file.text, unit.header.span.end as usize);
                    let to = unit
                        .networks
                        .first()
                        .map_or(unit.header.span.end, |n| n.span.start)
                        as usize;
                    let head = self.checked.file.text.get(from..to).unwrap_or("");
                    block.push_str(head.trim_start_matches(['\r', '\n']));
                    if !block.ends_with('\n') {
                        block.push('\n');
                    }
                    for (i, net) in networks.enumerate() {
                        subroutine_networks += 1;
                        let _ = writeln!(block, "NETWORK {}{net}", i + 1);
                    }
                    block.push_str("END_SUBROUTINE_BLOCK\n");
                    subroutines.push(block);
                }
                _ => {}
            }
        }
        Part {
            symbols,
            subroutines,
            subroutine_networks,
            main,
            labels,
        }
    }

    /// A network after its `NETWORK n`: ` // title`, its comment lines and its
    /// instructions with the operands renamed, one a line. With `labels`, label numbers
    /// are marked (`LABEL`) and `labels` kept above the highest.
    fn network(&self, net: &ast::Network, mut labels: Option<&mut i64>) -> String {
        let text = &self.checked.file.text;
        let mut out = String::new();
        if let Some(title) = net.title.map(|t| self.slice(t).trim()) {
            if !title.is_empty() {
                let _ = write!(out, " // {title}");
            }
        }
        out.push('\n');
        if let (Some(header), Some(first)) = (net.header, net.instructions.first()) {
            let from = line_end(text, header.end as usize);
            let to = first.span.start as usize;
            let head = text.get(from..to.max(from)).unwrap_or("");
            for line in head.lines().map(str::trim).filter(|l| l.starts_with("//")) {
                let _ = writeln!(out, "{line}");
            }
        }
        let set = &self.checked.target.instructions;
        for ins in &net.instructions {
            let mnemonic = self.slice(ins.mnemonic).trim();
            let spec = set.lookup(mnemonic).map(|id| set.get(id));
            let calls = spec.is_some_and(|s| s.call_arguments);
            let mut operands = Vec::new();
            for (i, op) in net.operands_of(ins).iter().enumerate() {
                let label = spec
                    .and_then(|s| s.operands.get(i))
                    .is_some_and(|o| o.kind == gutta_catalog::OperandKind::Label);
                match (op.kind, labels.as_deref_mut()) {
                    (OperandKind::Integer(n), Some(highest)) if label => {
                        *highest = (*highest).max(n + 1);
                        operands.push(format!("{LABEL}{n}{LABEL}"));
                    }
                    _ => operands.push(self.operand(op, calls && i == 0)),
                }
            }
            if operands.is_empty() {
                let _ = writeln!(out, "{mnemonic}");
            } else {
                let _ = writeln!(out, "{mnemonic:<6} {}", operands.join(", "));
            }
        }
        out.pop();
        out
    }

    /// An operand as written, a symbol (or a CALL's block) renamed, a Micro/WIN system
    /// symbol replaced by its address.
    fn operand(&self, op: &ast::Operand, block: bool) -> String {
        let written = self.slice(op.span).trim();
        let OperandKind::Name {
            local: false, name, ..
        } = op.kind
        else {
            return written.to_string();
        };
        let bare = self.slice(name).trim();
        let new = if block {
            self.subroutines.get(&bare.to_ascii_uppercase())
        } else {
            self.symbols.get(&bare.to_ascii_uppercase())
        };
        if let Some(new) = new {
            return written.replacen(bare, new, 1);
        }
        // A Micro/WIN system symbol (`Always_On`) is its system bit (`SM0.0`).
        let memory = &self.checked.target.memory;
        match memory.microwin_system_bit(bare) {
            Some(bit) if self.checked.microwin.is_some() => written.replacen(bare, &bit.address, 1),
            _ => written.to_string(),
        }
    }
}

/// The block's keyword: the header line's first word, upper case.
fn keyword(checked: &CheckedFile, unit: &ast::Unit) -> String {
    checked
        .file
        .slice(unit.header.span)
        .split_whitespace()
        .next()
        .unwrap_or("")
        .to_ascii_uppercase()
}

/// Offset of the end of the line holding `offset` (after its newline).
fn line_end(text: &str, offset: usize) -> usize {
    text.get(offset..)
        .and_then(|t| t.find('\n'))
        .map_or(text.len(), |i| offset + i + 1)
}
