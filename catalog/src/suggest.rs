//! Edit distance, the one measure behind every "did you mean" of the tools: mnemonics
//! and names in the compiler, symbols on the command line, gutta.toml keys, mistyped
//! commands. No policy here (how close is close enough is each caller's).

/// Edits from `a` to `b`, counting an insertion, a deletion, a substitution or a swap of
/// two neighbours as one (optimal string alignment), on characters as they are (callers
/// fold case first when case does not matter): `MOWV` is one edit from `MOVW`.
pub fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    let w = b.len() + 1;
    let mut d = vec![0usize; (a.len() + 1) * w];
    for (i, row) in d.chunks_mut(w).enumerate() {
        row[0] = i;
    }
    for (j, cell) in d.iter_mut().enumerate().take(w) {
        *cell = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut v = (d[(i - 1) * w + j] + 1)
                .min(d[i * w + j - 1] + 1)
                .min(d[(i - 1) * w + j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                v = v.min(d[(i - 2) * w + j - 2] + 1);
            }
            d[i * w + j] = v;
        }
    }
    d[a.len() * w + b.len()]
}

#[cfg(test)]
mod tests {
    use super::edit_distance;

    #[test]
    fn edits_count_one_each() {
        assert_eq!(edit_distance("MOWV", "MOVW"), 1);
        assert_eq!(edit_distance("donwload", "download"), 1);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(edit_distance("abc", ""), 3);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        assert_eq!(edit_distance("Lamp", "lamp"), 1);
        assert_eq!(edit_distance("启动", "启动"), 0);
        assert_eq!(edit_distance("启动", "起动"), 1);
    }
}
