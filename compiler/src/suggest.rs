//! "Did you mean" suggestions: the closest candidate by edit distance. Below the
//! parser and the checker (both use it), so the parser never imports the checker.

/// Edit distance on ASCII-uppercased text: names and mnemonics are case-insensitive.
fn distance(a: &str, b: &str) -> usize {
    gutta_catalog::edit_distance(&a.to_ascii_uppercase(), &b.to_ascii_uppercase())
}

/// The closest candidate within a third of the word's length (at least 1, at most 3 edits).
pub fn closest<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let len = word.chars().count();
    let limit = (len / 3).clamp(1, 3);
    candidates
        .into_iter()
        // The distance is at least the difference in length: skip those without the
        // table (unknown mnemonics met ~200 full tables each).
        .filter(|c| c.chars().count().abs_diff(len) <= limit)
        .map(|c| (distance(word, c), c))
        .filter(|(d, _)| *d <= limit)
        .min_by(|x, y| x.0.cmp(&y.0).then_with(|| x.1.cmp(y.1)))
        .map(|(_, c)| c)
}

#[cfg(test)]
mod tests {
    #[test]
    fn suggestions() {
        let c = ["MOVW", "MOVB", "MOVD", "LD", "LDN"];
        assert_eq!(super::closest("MOWV", c), Some("MOVW"));
        assert_eq!(super::closest("movx", c), Some("MOVB"));
        assert_eq!(super::closest("LDD", c), Some("LD"));
        assert_eq!(super::closest("XYZZY", c), None);
        assert_eq!(super::closest("MOVWXYZ", c), None);
        assert_eq!(super::closest("MOVWX", c), Some("MOVW"));
    }
}
