//! The writer's round trip over every program we have (docs/ladder.md, "From ladder to
//! STL"): examples/, tests/data/check/ok, tests/data/run, tests/data/microwin (the
//! split program too) and the networks docs/ladder.md shows. For every network the
//! builder draws as a rung, its text is replaced by the STL `gutta_ladder::write`
//! writes, and the whole program compiled again: the image must be the same, byte for
//! byte (programs with errors have none: their rungs only); the rewritten program
//! built again must give the same rungs (source lines aside, as the written text has
//! its own, and contact mnemonics compared in their load form), and writing them again
//! the same lines. The census (`cargo test -p gutta-ladder --test round_trip --
//! --nocapture`) prints networks drawn, round-tripped and shown as STL. Networks whose
//! source is not the canonical text of their rung are listed exactly in
//! `NOT_CANONICAL`: any other failure, and any listed network that now round-trips,
//! fails the test.

#![allow(
    clippy::disallowed_methods,
    clippy::disallowed_macros,
    reason = "the round trip reads the repository's programs and prints its census"
)]

mod common;

use std::collections::BTreeSet;
use std::path::Path;

use gutta_catalog::{stdlib, InstructionSet, Join};
use gutta_compiler::source::{PartKind, SourceFile};
use gutta_compiler::{compile_program, Compiled, ExplicitTarget, ProgramSources};
use gutta_ladder::model::{Body, BoxElement, Branch, BranchEnd, Ladder, Node, Rung};

use common::{files, root};

/// Networks (`program block:network`) whose written STL is a different text for the
/// same rung, so their image differs: the canonical form is not the one their source
/// chose. Each line says which text the source wrote.
const NOT_CANONICAL: &[&str] = &[
    "tests/data/check/ok/power_flow.lad MAIN:6: another image -- the source ORs the \
     word compares as their own path (`LDW>=` `AW<=` `OW>` `OLD`); the canonical form \
     puts the single contact `OW>` in parallel at once (`OLD` before `OW>`)",
    "tests/data/check/ok/power_flow.lad MAIN:10: another image -- nine levels loaded at \
     once then `ALD` x4 and `OLD` x4; the canonical form writes `O` and `A` and one `OLD`",
    "tests/data/run/bit_logic.lad MAIN:10: another image -- `LD I0.2` `ALD` where the \
     canonical form writes `A I0.2`",
];

/// A program as the tools read it: its sources and tables, and a `// plc: NAME` first
/// line honoured.
struct Program {
    name: String,
    sources: Vec<SourceFile>,
    tables: Vec<SourceFile>,
}

impl Program {
    fn file(name: String, path: &Path) -> Program {
        let bytes = std::fs::read(path).expect("read program");
        let (file, _) =
            SourceFile::from_program_file_bytes(path.display().to_string(), bytes, false)
                .unwrap_or_else(|_| panic!("{}: not UTF-8", path.display()));
        Program {
            name,
            sources: vec![file],
            tables: Vec::new(),
        }
    }

    fn compile(&self) -> Compiled {
        let first = self.sources[0].text.lines().next().unwrap_or("").trim();
        let explicit = first.strip_prefix("// plc:").map(|name| ExplicitTarget {
            target: stdlib::shared(name.trim()).expect("stdlib target"),
            origin: format!("--plc {}", name.trim()),
        });
        let program = ProgramSources {
            sources: self.sources.clone(),
            symbol_tables: self.tables.clone(),
            options: Default::default(),
        };
        compile_program(program, explicit.as_ref())
    }
}

/// The program exported one block per file, read as one.
fn split_program() -> Program {
    let dir = root().join("tests/data/microwin/split_program");
    let read = |name: &str| {
        let bytes = std::fs::read(dir.join(name)).expect("read split program file");
        SourceFile::from_code_page_bytes(name, bytes).0
    };
    Program {
        name: "tests/data/microwin/split_program".to_string(),
        sources: ["MAIN.awl", "SBR_0.awl", "INT_0.awl"].map(read).to_vec(),
        tables: ["symbols.csv", "symbols_gbk.txt"].map(read).to_vec(),
    }
}

/// The ```` ``` ```` blocks of docs/ladder.md that hold networks, each as a subroutine.
fn docs_programs() -> Vec<Program> {
    let page = std::fs::read_to_string(root().join("docs/ladder.md")).expect("docs/ladder.md");
    let mut out = Vec::new();
    for (i, block) in page.split("```").skip(1).step_by(2).enumerate() {
        if !block.trim_start().starts_with("NETWORK") {
            continue;
        }
        // A subroutine MAIN calls, with the locals the page's networks use.
        let text = format!(
            "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\nCALL DOCS, MW0, MW2\n\
             END_ORGANIZATION_BLOCK\nSUBROUTINE_BLOCK DOCS:SBR0\n\
             VAR_INPUT\n  raw : INT;\nEND_VAR\nVAR_OUTPUT\n  permille : INT;\nEND_VAR\n\
             BEGIN\n{block}\nEND_SUBROUTINE_BLOCK\n"
        );
        out.push(Program {
            name: format!("docs/ladder.md#{i}"),
            sources: vec![SourceFile::new("ladder.md.lad", text)],
            tables: Vec::new(),
        });
    }
    out
}

/// The program with each drawn network's text replaced by its written STL (`only`: the
/// one network at these indices of block and network).
fn rewritten(
    program: &Program,
    compiled: &Compiled,
    ladder: &Ladder,
    only: Option<(usize, usize)>,
) -> Program {
    let checked = &compiled.checked;
    let set = &checked.target.instructions;
    let text = &checked.file.text;
    let newline = if text.contains("\r\n") { "\r\n" } else { "\n" };
    let mut edits: Vec<(usize, usize, String)> = Vec::new();
    for (b, (unit, block)) in checked.ast.units.iter().zip(&ladder.blocks).enumerate() {
        for (n, (net, drawn)) in unit.networks.iter().zip(&block.networks).enumerate() {
            let Body::Rung(rung) = &drawn.body else {
                continue;
            };
            if only.is_some_and(|o| o != (b, n)) {
                continue;
            }
            let lines = gutta_ladder::write::rung(set, rung).unwrap_or_else(|e| {
                panic!("{} {}:{}: {e}", program.name, block.name, drawn.number)
            });
            let (Some(first), Some(last)) = (net.instructions.first(), net.instructions.last())
            else {
                continue;
            };
            let from = text[..first.span.start as usize]
                .rfind('\n')
                .map_or(0, |i| i + 1);
            let to = text[last.span.end as usize..]
                .find('\n')
                .map_or(text.len(), |i| last.span.end as usize + i);
            let to = if text[..to].ends_with('\r') {
                to - 1
            } else {
                to
            };
            edits.push((from, to, lines.join(newline)));
        }
    }
    // Apply the edits file by file (a joined program keeps its files).
    let mut sources = Vec::new();
    let mut tables = Vec::new();
    for part in checked.file.parts() {
        let mut piece = String::new();
        let mut at = part.start;
        for (from, to, written) in edits
            .iter()
            .filter(|(from, _, _)| (part.start..part.end).contains(from))
        {
            piece.push_str(&text[at..*from]);
            piece.push_str(written);
            at = *to;
        }
        piece.push_str(&text[at..part.end]);
        let file = SourceFile::new(part.name.clone(), piece);
        match part.kind {
            PartKind::Source | PartKind::DataBlockTab => sources.push(file),
            PartKind::SymbolTable => tables.push(file),
        }
    }
    Program {
        name: program.name.clone(),
        sources,
        tables,
    }
}

/// A rung as the round trip compares it: without its source lines (the written text
/// has lines of its own), and each contact's mnemonic in its load form (the model
/// keeps the form the source wrote: `A I0.2` and `LD I0.2` ... `ALD` are one contact).
fn comparable(rung: &Rung, set: &InstructionSet) -> Rung {
    fn node(n: &mut Node, set: &InstructionSet) {
        match n {
            Node::Contact(c) => {
                c.line = 0;
                let id = set.lookup(&c.mnemonic).expect("a known contact");
                let load = set.with_join(id, Join::Load).unwrap_or(id);
                c.mnemonic = set.get(load).mnemonic.clone();
            }
            Node::Box(b) => boxed(b, set),
            Node::Series(v) | Node::Parallel(v) => v.iter_mut().for_each(|n| node(n, set)),
        }
    }
    fn boxed(b: &mut BoxElement, set: &InstructionSet) {
        b.line = 0;
        b.power_inputs.iter_mut().for_each(|(_, p)| node(p, set));
    }
    fn branch(b: &mut Branch, set: &InstructionSet) {
        b.path.iter_mut().for_each(|n| node(n, set));
        match &mut b.end {
            BranchEnd::Coil(c) => c.line = 0,
            BranchEnd::Box(x) => boxed(x, set),
            BranchEnd::Split(v) => v.iter_mut().for_each(|b| branch(b, set)),
        }
    }
    let mut r = rung.clone();
    r.input.iter_mut().for_each(|n| node(n, set));
    r.outputs.iter_mut().for_each(|b| branch(b, set));
    r
}

#[derive(Default)]
struct Census {
    drawn: usize,
    round_tripped: usize,
    /// Drawn networks of programs with errors (no image): their model round-trips.
    without_image: usize,
    stl: usize,
}

/// One program through the round trip: its census, and the networks that failed with
/// what failed.
fn round_trip(program: &Program, census: &mut Census, failures: &mut Vec<String>) {
    let compiled = program.compile();
    let ladder = gutta_ladder::build(&compiled.checked);
    let again = rewritten(program, &compiled, &ladder, None);
    let recompiled = again.compile();
    let rebuilt = gutta_ladder::build(&recompiled.checked);
    let set = &compiled.checked.target.instructions;
    if compiled.image.is_none() {
        println!("  {} has errors: no image to compare", program.name);
    }
    let same_image = compiled.image == recompiled.image;
    assert_eq!(
        compiled.image.is_some(),
        recompiled.image.is_some(),
        "{}: the rewritten program compiles as the original does: {:?}",
        program.name,
        recompiled.checked.diagnostics()
    );
    let mut image_blamed = false;
    for (b, (block, block_again)) in ladder.blocks.iter().zip(&rebuilt.blocks).enumerate() {
        assert_eq!(block.networks.len(), block_again.networks.len());
        for (n, (net, net_again)) in block.networks.iter().zip(&block_again.networks).enumerate() {
            let at = format!("{} {}:{}", program.name, block.name, net.number);
            let Body::Rung(rung) = &net.body else {
                census.stl += 1;
                continue;
            };
            census.drawn += 1;
            if compiled.image.is_none() {
                census.without_image += 1;
            }
            let Body::Rung(rung_again) = &net_again.body else {
                failures.push(format!("{at}: written STL is not a rung"));
                continue;
            };
            if comparable(rung, set) != comparable(rung_again, set) {
                failures.push(format!("{at}: another rung"));
                continue;
            }
            let written = gutta_ladder::write::rung(set, rung).expect("written once");
            let twice = gutta_ladder::write::rung(set, rung_again).expect("written twice");
            assert_eq!(written, twice, "{at}: writing is stable");
            // The image is the whole program's: when it differs, each network is
            // rewritten alone to find those that change it.
            if !same_image
                && rewritten(program, &compiled, &ladder, Some((b, n)))
                    .compile()
                    .image
                    != compiled.image
            {
                image_blamed = true;
                failures.push(format!("{at}: another image"));
                continue;
            }
            census.round_tripped += 1;
        }
    }
    let failed_here = failures
        .iter()
        .any(|f| f.starts_with(&format!("{} ", program.name)));
    assert!(
        same_image || image_blamed || failed_here,
        "{}: the image differs though every network wrote its own text",
        program.name
    );
}

#[test]
fn every_drawn_network_round_trips_through_stl() {
    let sets = common::CORPORA;
    let mut failures = Vec::new();
    let mut total = Census::default();
    let mut groups: Vec<(String, Vec<Program>)> = sets
        .iter()
        .map(|(dir, exts)| {
            let mut programs: Vec<Program> = files(dir, exts)
                .iter()
                .map(|p| {
                    let name = format!("{dir}/{}", p.file_name().unwrap().to_string_lossy());
                    Program::file(name, p)
                })
                .collect();
            if *dir == "tests/data/microwin" {
                programs.push(split_program());
            }
            (dir.to_string(), programs)
        })
        .collect();
    groups.push(("docs/ladder.md".to_string(), docs_programs()));
    for (dir, programs) in &groups {
        let mut census = Census::default();
        for program in programs {
            round_trip(program, &mut census, &mut failures);
        }
        println!(
            "{dir}: {} networks drawn, {} round-tripped ({} of programs without an image: \
             the model only), {} shown as STL",
            census.drawn, census.round_tripped, census.without_image, census.stl
        );
        total.drawn += census.drawn;
        total.without_image += census.without_image;
        total.round_tripped += census.round_tripped;
        total.stl += census.stl;
    }
    println!(
        "all: {} networks drawn, {} round-tripped ({} without an image), {} shown as STL",
        total.drawn, total.round_tripped, total.without_image, total.stl
    );
    for f in &failures {
        println!("  not round-tripped: {f}");
    }
    assert!(total.drawn > 400, "the corpora draw networks");
    // docs/ladder.md states the figures: keep them true.
    let docs = std::fs::read_to_string(root().join("docs/ladder.md")).expect("docs/ladder.md");
    let row = format!(
        "| all | {} | {} | {} |",
        total.drawn, total.round_tripped, total.stl
    );
    assert!(docs.contains(&row), "docs/ladder.md lacks the row `{row}`");
    let found: BTreeSet<&str> = failures.iter().map(String::as_str).collect();
    let listed: BTreeSet<&str> = NOT_CANONICAL
        .iter()
        .map(|l| l.split(" -- ").next().unwrap_or(l))
        .collect();
    let new: Vec<&&str> = found.difference(&listed).collect();
    let gone: Vec<&&str> = listed.difference(&found).collect();
    assert!(
        new.is_empty() && gone.is_empty(),
        "round-trip failures differ from NOT_CANONICAL: new {new:#?}, now round-tripping {gone:#?}"
    );
}
