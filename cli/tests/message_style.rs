//! Counts agree with their nouns in every message the workspace can print: no
//! `byte(s)`-style plural in a string literal of any package's code; counts go through
//! `gutta_catalog::plural` (`1 byte`, `2 bytes`). Reads the sources, runs nothing.

use std::path::{Path, PathBuf};

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        let name = entry.file_name();
        if path.is_dir() {
            if name != "target" && name != ".git" && name != "corpus" && name != "artifacts" {
                rust_files(&path, out);
            }
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The `word(s)` plurals inside string literals of one line (a rough reading of
/// literals: the text between double quotes).
fn vague_plurals(line: &str) -> Vec<String> {
    let mut found = Vec::new();
    let mut inside = false;
    let chars: Vec<char> = line.chars().collect();
    for (i, c) in chars.iter().enumerate() {
        if *c == '"' && (i == 0 || chars[i - 1] != '\\') {
            inside = !inside;
        }
        let vague = inside
            && *c == '('
            && chars.get(i + 1) == Some(&'s')
            && chars.get(i + 2) == Some(&')')
            && i > 0
            && chars[i - 1].is_ascii_alphabetic();
        if vague {
            let start = chars[..i]
                .iter()
                .rposition(|c| !c.is_ascii_alphabetic())
                .map_or(0, |p| p + 1);
            found.push(chars[start..i + 3].iter().collect());
        }
    }
    found
}

#[test]
fn the_rule_finds_a_vague_plural_in_a_literal_only() {
    assert_eq!(
        vague_plurals(r#"format!("{n} byte(s) left") // page(s)"#),
        ["byte(s)"]
    );
    assert!(vague_plurals("// a comment on page(s)").is_empty());
    assert!(vague_plurals(r#"let s = "(s)";"#).is_empty());
}

#[test]
fn no_message_says_word_s() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("workspace root");
    let mut files = Vec::new();
    rust_files(root, &mut files);
    files.sort();
    assert!(files.len() > 100, "found the sources: {}", files.len());
    let this = Path::new(file!()).file_name().expect("name");
    let mut offenders = Vec::new();
    for file in files.iter().filter(|f| f.file_name() != Some(this)) {
        let text = std::fs::read_to_string(file).expect("read");
        for (n, line) in text.lines().enumerate() {
            for word in vague_plurals(line) {
                offenders.push(format!(
                    "{}:{}: {word}",
                    file.strip_prefix(root).unwrap_or(file).display(),
                    n + 1
                ));
            }
        }
    }
    assert!(
        offenders.is_empty(),
        "say the count with its noun (gutta_catalog::plural::count), not `word(s)`:\n{}",
        offenders.join("\n")
    );
}
