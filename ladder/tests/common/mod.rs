//! Shared helpers of the ladder tests: a program checked from text, and a compact
//! textual rendering of the model that the expectations are written in.
//!
//! The rendering: a contact is `kind(operands)` (`no(I0.0)`, `nc(Stop)`, `noI(I0.5)`
//! for immediate, `pos-edge()`, `compare>=W(MW14,-5)`); series elements are separated
//! by blanks, parallel ones are `(a | b)`; a box is `[TITLE PIN=x OUT>y R:path]` (`>`
//! an output pin, `NAME:path` an extra power input); a coil is `kind(BIT[,N])`
//! (`out(Q0.0)`, `set(Full,1)`); a rung is `INPUT -> OUTPUTS` (`|` for a rung on the
//! rail), several branches `{ b1 ; b2 }`; a refused network is `STL: reason`.

#![allow(
    dead_code,
    clippy::disallowed_methods,
    reason = "shared by several test binaries, each using part; the corpus helpers read the repository's programs"
)]

pub mod edit;
pub mod xml;

use std::path::{Path, PathBuf};

use gutta_catalog::stdlib;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{check_source, CheckedFile, ExplicitTarget};
use gutta_ladder::model::{Body, BoxElement, Branch, BranchEnd, Contact, Ladder, Network, Node};

/// The repository's root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The program corpora every whole-corpus test walks: each folder and its extensions.
pub const CORPORA: [(&str, &[&str]); 4] = [
    ("examples", &["lad"]),
    ("tests/data/check/ok", &["lad"]),
    ("tests/data/run", &["lad"]),
    ("tests/data/microwin", &["lad", "awl"]),
];

/// The files of a corpus folder (relative to the root) with one of `exts`, sorted.
pub fn files(dir: &str, exts: &[&str]) -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(root().join(dir))
        .unwrap_or_else(|e| panic!("{dir}: {e}"))
        .map(|e| e.expect("dir entry").path())
        .filter(|p| {
            p.extension()
                .is_some_and(|x| exts.iter().any(|e| x.eq_ignore_ascii_case(e)))
        })
        .collect();
    out.sort();
    out
}

/// A program file as the tools read it, with a `// plc: NAME` first line honoured.
pub fn checked_file(path: &Path) -> CheckedFile {
    let bytes = std::fs::read(path).expect("read program");
    let (file, _) = SourceFile::from_program_file_bytes(path.display().to_string(), bytes, false)
        .unwrap_or_else(|_| panic!("{}: not UTF-8", path.display()));
    let first = file.text.lines().next().unwrap_or("").trim().to_string();
    let explicit = first.strip_prefix("// plc:").map(|name| ExplicitTarget {
        target: stdlib::shared(name.trim()).expect("stdlib target"),
        origin: format!("--plc {}", name.trim()),
    });
    check_source(file, explicit.as_ref())
}

/// `text` checked on the default target.
pub fn checked(text: &str) -> CheckedFile {
    check_source(SourceFile::new("test.lad", text), None)
}

/// The networks of MAIN holding `code` (its `NETWORK` lines included).
pub fn main_with(code: &str) -> String {
    format!("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n{code}\nEND_ORGANIZATION_BLOCK\n")
}

/// The ladder of a MAIN holding `code`.
pub fn ladder(code: &str) -> Ladder {
    gutta_ladder::build(&checked(&main_with(code)))
}

/// The rendering of each network of MAIN holding `code`.
pub fn rendered(code: &str) -> Vec<String> {
    ladder(code).blocks[0].networks.iter().map(render).collect()
}

/// The rendering of the one network `code` (without its NETWORK line).
pub fn one(code: &str) -> String {
    let r = rendered(&format!("NETWORK 1\n{code}"));
    assert_eq!(r.len(), 1, "{r:?}");
    r[0].clone()
}

pub fn render(net: &Network) -> String {
    match &net.body {
        Body::Stl { reason } => format!("STL: {reason}"),
        Body::Rung(rung) => {
            let input = rung.input.as_ref().map_or("|".to_string(), node);
            format!("{input} -> {}", branches(&rung.outputs))
        }
    }
}

fn branches(list: &[Branch]) -> String {
    if let [one] = list {
        return branch(one);
    }
    let parts: Vec<String> = list.iter().map(branch).collect();
    format!("{{ {} }}", parts.join(" ; "))
}

fn branch(b: &Branch) -> String {
    let mut parts: Vec<String> = b.path.iter().map(node).collect();
    parts.push(match &b.end {
        BranchEnd::Coil(c) => {
            let mut ops = vec![c.operand.written.clone()];
            ops.extend(c.count.iter().map(|n| n.written.clone()));
            format!("{}({})", c.kind.data_kind(), ops.join(","))
        }
        BranchEnd::Box(b) => boxed(b),
        BranchEnd::Split(list) => branches(list),
    });
    parts.join(" ")
}

pub fn node(n: &Node) -> String {
    match n {
        Node::Contact(c) => contact(c),
        Node::Box(b) => boxed(b),
        Node::Series(v) => v.iter().map(node).collect::<Vec<_>>().join(" "),
        Node::Parallel(v) => format!("({})", v.iter().map(node).collect::<Vec<_>>().join(" | ")),
    }
}

fn contact(c: &Contact) -> String {
    let ops: Vec<&str> = c.operands.iter().map(|o| o.written.as_str()).collect();
    format!(
        "{}{}{}({})",
        c.kind.data_kind(),
        c.relation.as_deref().unwrap_or(""),
        if c.immediate { "I" } else { "" },
        ops.join(",")
    )
}

fn boxed(b: &BoxElement) -> String {
    let mut parts = vec![b.title.clone()];
    for p in &b.pins {
        let sep = if p.output { ">" } else { "=" };
        parts.push(format!("{}{sep}{}", p.name, p.operand.written));
    }
    for (name, path) in &b.power_inputs {
        parts.push(format!("{name}:{}", node(path)));
    }
    format!("[{}]", parts.join(" "))
}

/// Every element id of a rung in drawing order, with what it is.
pub fn ids(net: &Network) -> Vec<(u32, String)> {
    fn walk_node(n: &Node, out: &mut Vec<(u32, String)>) {
        match n {
            Node::Contact(c) => out.push((c.id, contact(c))),
            Node::Box(b) => walk_box(b, out),
            Node::Series(v) | Node::Parallel(v) => v.iter().for_each(|n| walk_node(n, out)),
        }
    }
    fn walk_box(b: &BoxElement, out: &mut Vec<(u32, String)>) {
        for (_, p) in &b.power_inputs {
            walk_node(p, out);
        }
        out.push((b.id, b.title.clone()));
    }
    fn walk_branch(b: &Branch, out: &mut Vec<(u32, String)>) {
        b.path.iter().for_each(|n| walk_node(n, out));
        match &b.end {
            BranchEnd::Coil(c) => out.push((c.id, c.operand.written.clone())),
            BranchEnd::Box(x) => walk_box(x, out),
            BranchEnd::Split(v) => v.iter().for_each(|b| walk_branch(b, out)),
        }
    }
    let mut out = Vec::new();
    if let Body::Rung(r) = &net.body {
        if let Some(i) = &r.input {
            walk_node(i, &mut out);
        }
        r.outputs.iter().for_each(|b| walk_branch(b, &mut out));
    }
    out
}
