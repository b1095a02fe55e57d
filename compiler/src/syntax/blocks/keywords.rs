//! The reserved words of the block structure (`SYMBOLS`, `BEGIN`, `END_VAR`, ...), looked
//! up case-insensitively. Only the words: what a keyword does is the block parser's.

use crate::syntax::ast::VarSection;

/// A block-structure keyword.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Kw {
    PlcType,
    Symbols,
    EndSymbols,
    Organization,
    EndOrganization,
    Subroutine,
    EndSubroutine,
    Interrupt,
    EndInterrupt,
    Data,
    EndData,
    System,
    EndSystem,
    Begin,
    Network,
    Var(VarSection),
    EndVar,
}

const KEYWORDS: &[(&str, Kw)] = &[
    ("PLC_TYPE", Kw::PlcType),
    ("SYMBOLS", Kw::Symbols),
    ("END_SYMBOLS", Kw::EndSymbols),
    ("ORGANIZATION_BLOCK", Kw::Organization),
    ("END_ORGANIZATION_BLOCK", Kw::EndOrganization),
    ("SUBROUTINE_BLOCK", Kw::Subroutine),
    ("END_SUBROUTINE_BLOCK", Kw::EndSubroutine),
    ("INTERRUPT_BLOCK", Kw::Interrupt),
    ("END_INTERRUPT_BLOCK", Kw::EndInterrupt),
    ("DATA_BLOCK", Kw::Data),
    ("END_DATA_BLOCK", Kw::EndData),
    ("SYSTEM_BLOCK", Kw::System),
    ("END_SYSTEM_BLOCK", Kw::EndSystem),
    ("BEGIN", Kw::Begin),
    ("NETWORK", Kw::Network),
    ("VAR_INPUT", Kw::Var(VarSection::Input)),
    ("VAR_IN_OUT", Kw::Var(VarSection::InOut)),
    ("VAR_OUTPUT", Kw::Var(VarSection::Output)),
    ("VAR", Kw::Var(VarSection::Temp)),
    ("VAR_TEMP", Kw::Var(VarSection::Temp)),
    ("END_VAR", Kw::EndVar),
];

/// The `END_...` keywords, for the did-you-mean of a misspelt one.
pub(super) fn end_keywords() -> impl Iterator<Item = &'static str> {
    KEYWORDS
        .iter()
        .map(|(k, _)| *k)
        .filter(|k| k.starts_with("END_"))
}

/// Whether a word is a reserved keyword of the block structure.
pub fn is_keyword(word: &str) -> bool {
    keyword(word).is_some()
}

/// The keyword a word spells, if any.
pub(super) fn keyword(word: &str) -> Option<Kw> {
    if word.len() < 3 || word.len() > 22 {
        return None;
    }
    KEYWORDS
        .iter()
        .find(|(k, _)| k.eq_ignore_ascii_case(word))
        .map(|(_, kw)| *kw)
}
