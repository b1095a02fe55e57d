//! The census (docs/ladder.md, "Which networks are ladder"): every program of examples/,
//! tests/data/check/ok, tests/data/run and tests/data/microwin built into a ladder;
//! how many networks are drawn and how many are STL, with the reasons grouped
//! (`cargo test -p gutta-ladder --test census -- --nocapture` prints them). No program
//! may panic, and most networks of examples/ must be drawn.

#![allow(
    clippy::disallowed_methods,
    clippy::disallowed_macros,
    reason = "the census reads the repository's programs and prints its counts"
)]

mod common;

use std::collections::BTreeMap;
use std::path::Path;

use gutta_compiler::source::SourceFile;
use gutta_compiler::{check_program, ProgramSources};
use gutta_ladder::model::{Body, Ladder};

use common::{checked_file, files, root};

/// A program file's ladder, as the tools read the file.
fn ladder_of(path: &Path) -> Ladder {
    gutta_ladder::build(&checked_file(path))
}

/// The program exported one block per file, read as one.
fn split_program() -> Ladder {
    let dir = root().join("tests/data/microwin/split_program");
    let read = |name: &str| {
        let bytes = std::fs::read(dir.join(name)).expect("read split program file");
        SourceFile::from_code_page_bytes(name, bytes).0
    };
    let program = ProgramSources {
        sources: ["MAIN.awl", "SBR_0.awl", "INT_0.awl"].map(read).to_vec(),
        symbol_tables: ["symbols.csv", "symbols_gbk.txt"].map(read).to_vec(),
        options: Default::default(),
    };
    gutta_ladder::build(&check_program(program, None))
}

#[derive(Default)]
struct Census {
    drawn: usize,
    stl: usize,
    /// Reason with its line numbers taken out -> programs:networks.
    reasons: BTreeMap<String, Vec<String>>,
}

impl Census {
    fn add(&mut self, name: &str, ladder: &Ladder) {
        for block in &ladder.blocks {
            for net in &block.networks {
                match &net.body {
                    Body::Rung(_) => self.drawn += 1,
                    Body::Stl { reason } => {
                        self.stl += 1;
                        self.reasons
                            .entry(group(reason))
                            .or_default()
                            .push(format!("{name} {}:{}", block.name, net.number));
                    }
                }
            }
        }
    }

    fn print(&self, title: &str) {
        println!(
            "{title}: {} networks drawn, {} as STL",
            self.drawn, self.stl
        );
        for (reason, at) in &self.reasons {
            println!("  {:3} x {reason}  [{}]", at.len(), at.join(", "));
        }
    }
}

/// A reason without its instruction's operands and line, to group alike ones.
fn group(reason: &str) -> String {
    let mut out = String::new();
    let mut parts = reason.split('`');
    out.push_str(parts.next().unwrap_or(""));
    while let Some(code) = parts.next() {
        let mnemonic = code.split_whitespace().next().unwrap_or("");
        out.push_str(&format!("`{mnemonic} ..`"));
        out.push_str(parts.next().unwrap_or(""));
    }
    out.split(" at line ")
        .enumerate()
        .map(|(i, p)| {
            if i == 0 {
                p.to_string()
            } else {
                p.trim_start_matches(|c: char| c.is_ascii_digit())
                    .to_string()
            }
        })
        .collect::<Vec<_>>()
        .join(" at line N")
}

#[test]
fn census_of_every_program() {
    let mut total = Census::default();
    let sets = common::CORPORA;
    let mut examples = (0, 0);
    for (dir, exts) in sets {
        let mut census = Census::default();
        for path in files(dir, exts) {
            let name = path.file_name().unwrap().to_string_lossy().to_string();
            let ladder = ladder_of(&path);
            census.add(&name, &ladder);
            total.add(&format!("{dir}/{name}"), &ladder);
        }
        if dir == "tests/data/microwin" {
            let ladder = split_program();
            census.add("split_program", &ladder);
            total.add("tests/data/microwin/split_program", &ladder);
        }
        census.print(dir);
        if dir == "examples" {
            examples = (census.drawn, census.stl);
        }
    }
    println!("all: {} networks drawn, {} as STL", total.drawn, total.stl);
    // docs/ladder.md states the figures: keep them true.
    let docs = std::fs::read_to_string(root().join("docs/ladder.md")).expect("docs/ladder.md");
    for row in [
        format!("| examples/ | {} | {} ", examples.0, examples.1),
        format!("| all | {} | {} |", total.drawn, total.stl),
    ] {
        assert!(
            docs.contains(&row),
            "docs/ladder.md lacks the census row `{row}`"
        );
    }
    let (drawn, stl) = examples;
    assert!(
        drawn + stl > 0 && drawn * 10 >= (drawn + stl) * 8,
        "most networks of examples/ must be drawn: {drawn} drawn, {stl} as STL (want 80% or more)"
    );
    assert!(
        total.drawn * 10 >= (total.drawn + total.stl) * 8,
        "{} drawn, {} as STL over every program",
        total.drawn,
        total.stl
    );
}

#[test]
fn reasons_group_without_operands_and_lines() {
    assert_eq!(
        group("`LD I0.2` at line 14 starts a second power path"),
        "`LD ..` at line N starts a second power path"
    );
}

/// Programs with errors (tests/data/check/err) are built too: no panic, every network
/// either a rung or STL with a reason, every STL network keeping its text.
#[test]
fn programs_with_errors_build_without_panics() {
    let mut networks = 0;
    for path in files("tests/data/check/err", &["lad"]) {
        let ladder = ladder_of(&path);
        for net in ladder.blocks.iter().flat_map(|b| &b.networks) {
            networks += 1;
            if let Body::Stl { reason } = &net.body {
                assert!(
                    !reason.is_empty(),
                    "{}: network {}",
                    path.display(),
                    net.number
                );
            }
        }
    }
    assert!(networks > 0, "tests/data/check/err holds networks");
}
