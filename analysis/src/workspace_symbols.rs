//! Workspace symbol search: every definition of a program whose name matches a query
//! fuzzily (the query's characters in order, case-insensitive), best matches first.
//! Plain data over `&CheckedFile`; no LSP types, no I/O.

use gutta_compiler::check::Definition;
use gutta_compiler::CheckedFile;

/// How well `name` matches `query`: `None` when it does not; lower is better (an exact
/// name 0, a prefix 1, a substring 2, then scattered characters by how spread out).
pub fn fuzzy_score(query: &str, name: &str) -> Option<u32> {
    let q: Vec<char> = query.chars().flat_map(char::to_lowercase).collect();
    let n: Vec<char> = name.chars().flat_map(char::to_lowercase).collect();
    if q.is_empty() {
        return Some(3);
    }
    if q == n {
        return Some(0);
    }
    if n.starts_with(&q) {
        return Some(1);
    }
    if n.windows(q.len()).any(|w| w == q.as_slice()) {
        return Some(2);
    }
    let mut at = 0;
    let mut gaps = 0u32;
    for c in &q {
        let found = n[at..].iter().position(|x| x == c)?;
        gaps += found as u32;
        at += found + 1;
    }
    Some(3 + gaps)
}

/// The definitions of `checked` that match `query`, best first (then by name).
pub fn search<'a>(checked: &'a CheckedFile, query: &str) -> Vec<(&'a Definition, u32)> {
    let mut found: Vec<(&Definition, u32)> = checked
        .output
        .definitions
        .iter()
        .filter(|d| !d.span.is_empty())
        .filter_map(|d| Some((d, fuzzy_score(query, &d.name)?)))
        .collect();
    found.sort_by(|a, b| a.1.cmp(&b.1).then_with(|| a.0.name.cmp(&b.0.name)));
    found
}

#[cfg(test)]
mod tests {
    use super::*;
    use gutta_compiler::source::SourceFile;

    #[test]
    fn exact_beats_prefix_beats_substring_beats_scattered() {
        assert_eq!(fuzzy_score("start", "Start"), Some(0));
        assert_eq!(fuzzy_score("sta", "Start"), Some(1));
        assert_eq!(fuzzy_score("art", "Start"), Some(2));
        assert_eq!(fuzzy_score("srt", "Start"), Some(5));
        assert_eq!(fuzzy_score("xyz", "Start"), None);
        assert_eq!(fuzzy_score("", "Start"), Some(3));
    }

    #[test]
    fn search_finds_symbols_blocks_and_locals() {
        let text = "SYMBOLS\n  MotorRun : Q0.0\n  Start : I0.0\nEND_SYMBOLS\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\nLD     Start\n=      MotorRun\nEND_ORGANIZATION_BLOCK\n";
        let c = gutta_compiler::check_source(SourceFile::new("m.lad", text), None);
        let names: Vec<&str> = search(&c, "mr")
            .iter()
            .map(|(d, _)| d.name.as_str())
            .collect();
        assert_eq!(names, ["MotorRun"]);
        let all: Vec<&str> = search(&c, "")
            .iter()
            .map(|(d, _)| d.name.as_str())
            .collect();
        assert_eq!(all, ["MAIN", "MotorRun", "Start"]);
    }
}
