//! What an instruction is lives in ManagerFun.xml (issue 25, point 6): outside the
//! catalog and the VM's decoders (`vm/src/decode.rs`, `vm/src/ops/`, the compiled tier's
//! `vm/src/tier.rs` and `tier_generic.rs`) no code matches an
//! instruction's mnemonic or alias to learn what it is. This test reads the workspace's
//! library and binary sources and finds every string literal naming a shipped mnemonic
//! where code compares with it: a match arm (`"TON" =>`, `"TON" |`), `==`/`!=`,
//! `lookup("..")`, `strip_prefix`/`starts_with`/`ends_with`/`eq_ignore_ascii_case`.
//! Test modules (after `#[cfg(test)]`) are not read.
//!
//! `REMAINING` lists the places still doing it, each with the catalog API that replaces
//! it; the list must be exact, so it shrinks as they go and a new match fails.

#![allow(
    clippy::disallowed_methods,
    clippy::disallowed_types,
    reason = "the test reads the workspace's sources"
)]

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use gutta_catalog::InstructionSet;

const MANAGER_FUN: &[u8] = include_bytes!("../../stdlib/ManagerFun.xml");

/// Source folders read, relative to the workspace root.
const SOURCES: &[&str] = &[
    "analysis/src",
    "cli/src",
    "compiler/src",
    "format/src",
    "gtest/src",
    "io/src",
    "jit/src",
    "ladder/src",
    "link/src",
    "lsp/src",
    "protocol/src",
    "sim/src",
    "vm/src",
];

/// The VM's decoders, which turn the catalog's instructions into operations: the
/// interpreter's (`decode.rs`, the semantics in `ops/`) and the compiled tier's
/// (`tier.rs`, `tier_generic.rs`: records into gutta-jit steps with the semantics of
/// `ops/`).
const DECODER: &[&str] = &[
    "vm/src/decode.rs",
    "vm/src/ops/",
    "vm/src/tier.rs",
    "vm/src/tier_generic.rs",
];

/// (file, mnemonics matched there, what replaces them or why they stay).
const REMAINING: &[(&str, &[&str], &str)] = &[
    (
        "compiler/src/microwin/timer_bits/first_scan.rs",
        &["MOVW"],
        "the first-scan network's word move: no catalog data says \"the plain word move\" yet",
    ),
    (
        "compiler/src/syntax/blocks/mod.rs",
        &["END"],
        "the parser tells the END instruction from the END_... block keywords by its text",
    ),
    (
        "compiler/src/syntax/blocks/code.rs",
        &["NOP"],
        "the parser drops a Micro/WIN export's `NOP 0` lines, which GUTTA has no instruction for",
    ),
    (
        "gtest/src/syntax.rs",
        &["ON"],
        "ON is a gtest boolean literal, not the mnemonic",
    ),
];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The string literals of `code` (one line) with the text just before and after each.
fn literals(code: &str) -> Vec<(&str, &str, &str)> {
    let mut out = Vec::new();
    let mut rest = code;
    let mut offset = 0;
    while let Some(start) = rest.find('"') {
        let after_quote = &rest[start + 1..];
        let Some(len) = after_quote.find('"') else {
            break;
        };
        let text = &after_quote[..len];
        let abs_start = offset + start;
        let abs_end = abs_start + len + 2;
        out.push((&code[..abs_start], text, &code[abs_end..]));
        offset = abs_end;
        rest = &code[abs_end..];
    }
    out
}

/// Whether a literal stands where code compares with it.
fn compared(before: &str, after: &str) -> bool {
    let before = before.trim_end();
    let after = after.trim_start();
    after.starts_with("=>")
        || (after.starts_with('|') && !after.starts_with("||"))
        || before.ends_with("==")
        || before.ends_with("!=")
        || before.ends_with("| ")
        || before.ends_with('|') && !before.ends_with("||")
        || [
            "lookup(",
            "strip_prefix(",
            "starts_with(",
            "ends_with(",
            "eq_ignore_ascii_case(",
        ]
        .iter()
        .any(|call| before.ends_with(call))
}

/// Every (file, mnemonic) matched outside the catalog and the decoder.
fn matches(set: &InstructionSet) -> BTreeMap<String, Vec<String>> {
    let names: std::collections::BTreeSet<&str> = set.names().map(|(n, _)| n).collect();
    let root = root();
    let mut files = Vec::new();
    for dir in SOURCES {
        rust_files(&root.join(dir), &mut files);
    }
    let mut found: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for path in files {
        let rel = path
            .strip_prefix(&root)
            .expect("under the root")
            .to_string_lossy()
            .replace('\\', "/");
        if DECODER.iter().any(|d| rel.starts_with(d)) {
            continue;
        }
        let text = std::fs::read_to_string(&path).expect("a source file reads");
        for line in text.lines().take_while(|l| l.trim() != "#[cfg(test)]") {
            let code = line.split("//").next().unwrap_or("");
            for (before, literal, after) in literals(code) {
                if names.contains(literal) && compared(before, after) {
                    let list = found.entry(rel.clone()).or_default();
                    if !list.iter().any(|m| m == literal) {
                        list.push(literal.to_string());
                    }
                }
            }
        }
    }
    found
}

#[test]
fn no_code_outside_the_catalog_matches_a_mnemonic_except_the_listed() {
    let set = InstructionSet::parse(MANAGER_FUN).expect("stdlib/ManagerFun.xml loads");
    let found = matches(&set);
    let mut problems = Vec::new();
    for (file, mnemonics) in &found {
        let listed = REMAINING.iter().find(|(f, ..)| f == file);
        for m in mnemonics {
            if !listed.is_some_and(|(_, ms, _)| ms.contains(&m.as_str())) {
                problems.push(format!(
                    "{file} matches the mnemonic `{m}`: ask the catalog what the instruction is \
                     (Instruction::kind, ladder, join(), power_inputs; docs/instruction-schema.md)"
                ));
            }
        }
    }
    for (file, mnemonics, _) in REMAINING {
        for m in *mnemonics {
            if !found.get(*file).is_some_and(|ms| ms.iter().any(|x| x == m)) {
                problems.push(format!(
                    "{file} no longer matches `{m}`: remove it from REMAINING"
                ));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_scan_finds_a_match_in_each_form() {
    // The detector itself: each way of comparing with a mnemonic is seen, and
    // producing one is not.
    for line in [
        r#"            "TON" | "TOF" => 1,"#,
        r#"            "CTU" => 2,"#,
        r#"        if spec.mnemonic == "CTU" {"#,
        r#"        let id = set.lookup("CTU");"#,
        r#"        let base = m.strip_prefix("LD")"#,
    ] {
        let hit = literals(line).into_iter().any(|(before, literal, after)| {
            ["TON", "CTU", "LD"].contains(&literal) && compared(before, after)
        });
        assert!(hit, "{line}");
    }
    for line in [
        r#"        CoilKind::Set => "S","#,
        r#"        let text = format!("{} TON", x);"#,
        r#"        if a || "TON".is_empty() {"#,
    ] {
        let hit = literals(line).into_iter().any(|(before, literal, after)| {
            ["S", "TON"].contains(&literal) && compared(before, after)
        });
        assert!(!hit, "{line}");
    }
}
