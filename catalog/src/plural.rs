//! Counts with their nouns, for every count the tools and libraries print: `count(1, "network")` is
//! `1 network`, `count(3, "byte")` is `3 bytes`, never `1 pages` or `page(s)`. It only
//! knows English plurals of the nouns the tools use; a noun with another plural takes
//! `count_as`.

use std::fmt::Display;

/// `N noun`, the noun in the plural unless N is 1: `1 request`, `0 requests`,
/// `2 matches`, `3 entries`.
pub fn count<N: Display + PartialEq + From<u8>>(n: N, noun: &str) -> String {
    let noun = if n == N::from(1) {
        noun.to_string()
    } else {
        plural(noun)
    };
    format!("{n} {noun}")
}

/// `N singular`, or `N plural` unless N is 1, for a noun whose plural the rule misses.
pub fn count_as<N: Display + PartialEq + From<u8>>(n: N, singular: &str, plural: &str) -> String {
    if n == N::from(1) {
        format!("{n} {singular}")
    } else {
        format!("{n} {plural}")
    }
}

/// The noun alone, in the plural unless `n` is 1, for a count printed another way
/// (with thousands separators): `noun_for(1, "byte")` is `byte`.
pub fn noun_for(n: u64, noun: &str) -> String {
    if n == 1 {
        noun.to_string()
    } else {
        plural(noun)
    }
}

/// A noun's plural by the regular rule: `-es` after s, x, z, ch and sh, `-ies` for a
/// consonant and y, else `-s`.
pub fn plural(noun: &str) -> String {
    let vowel_before_y = noun
        .strip_suffix('y')
        .and_then(|stem| stem.chars().last())
        .is_some_and(|c| "aeiou".contains(c.to_ascii_lowercase()));
    if ["s", "x", "z", "ch", "sh"]
        .iter()
        .any(|e| noun.ends_with(e))
    {
        format!("{noun}es")
    } else if let (Some(stem), false) = (noun.strip_suffix('y'), vowel_before_y) {
        format!("{stem}ies")
    } else {
        format!("{noun}s")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_is_singular_and_every_other_count_plural() {
        assert_eq!(count(1usize, "network"), "1 network");
        assert_eq!(count(0usize, "network"), "0 networks");
        assert_eq!(count(2u64, "byte"), "2 bytes");
        assert_eq!(count(1u32, "attempt"), "1 attempt");
        assert_eq!(count(3usize, "match"), "3 matches");
        assert_eq!(count(2usize, "entry"), "2 entries");
        assert_eq!(count(2usize, "day"), "2 days");
        assert_eq!(count(2usize, "box"), "2 boxes");
        assert_eq!(count_as(1usize, "child", "children"), "1 child");
        assert_eq!(count_as(4usize, "child", "children"), "4 children");
        assert_eq!(noun_for(1, "byte"), "byte");
        assert_eq!(noun_for(1_204, "byte"), "bytes");
    }
}
