//! Semantic tokens: what each word of a document is (mnemonic, address by area kind,
//! symbol, local, block, label, number, string, comment, keyword), from the checker's
//! output over the document's part of the program text. The legend (names of kinds and
//! modifiers, in order) is defined here once; the server only encodes it. No LSP types.

use std::collections::HashMap;

use gutta_catalog::{Address, AreaKind, DataType};

use crate::inlay::symbol_addresses;
use gutta_compiler::check::DefKind;
use gutta_compiler::source::{PartKind, Span};
use gutta_compiler::syntax::lexer::{lex, Tok};
use gutta_compiler::CheckedFile;

/// What a token is. The order is the legend's (`TokenKind::ALL`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TokenKind {
    /// Block keywords (`SYMBOLS`, `BEGIN`, `NETWORK`, `END_...`, `PLC_TYPE`).
    Keyword,
    /// An instruction's mnemonic.
    Mnemonic,
    /// A direct address or a symbol; its area kind is in the modifiers.
    Variable,
    /// A `#local`.
    Local,
    /// A program block or data block name.
    Block,
    Label,
    Number,
    Str,
    /// A comment or a `TITLE=` line.
    Comment,
    /// A data type keyword (`INT`, `REAL`).
    DataType,
    /// A system block key (`PORT0.BAUD`).
    Key,
}

impl TokenKind {
    pub const ALL: [TokenKind; 11] = [
        TokenKind::Keyword,
        TokenKind::Mnemonic,
        TokenKind::Variable,
        TokenKind::Local,
        TokenKind::Block,
        TokenKind::Label,
        TokenKind::Number,
        TokenKind::Str,
        TokenKind::Comment,
        TokenKind::DataType,
        TokenKind::Key,
    ];

    /// The standard LSP token type it is announced as.
    pub fn lsp_name(self) -> &'static str {
        match self {
            TokenKind::Keyword => "keyword",
            TokenKind::Mnemonic => "function",
            TokenKind::Variable => "variable",
            TokenKind::Local => "parameter",
            TokenKind::Block => "namespace",
            TokenKind::Label => "label",
            TokenKind::Number => "number",
            TokenKind::Str => "string",
            TokenKind::Comment => "comment",
            TokenKind::DataType => "type",
            TokenKind::Key => "property",
        }
    }

    /// Index in the legend.
    pub fn index(self) -> u32 {
        TokenKind::ALL.iter().position(|k| *k == self).unwrap_or(0) as u32
    }
}

/// Token modifiers, one bit each in the legend's order (`MODIFIERS`).
pub mod modifier {
    pub const DECLARATION: u32 = 1 << 0;
    /// A symbol (a name that stands for an address), not a direct address.
    pub const SYMBOLIC: u32 = 1 << 1;
    pub const INPUT: u32 = 1 << 2;
    pub const OUTPUT: u32 = 1 << 3;
    pub const ANALOG: u32 = 1 << 4;
    pub const MEMORY: u32 = 1 << 5;
    /// SM: system (special) memory.
    pub const SPECIAL: u32 = 1 << 6;
    pub const TIMER: u32 = 1 << 7;
    pub const COUNTER: u32 = 1 << 8;
    pub const HIGH_SPEED: u32 = 1 << 9;
    pub const LOCAL: u32 = 1 << 10;
    /// K: constants in the PLC.
    pub const CONSTANT: u32 = 1 << 11;
    /// Flow areas (S, J).
    pub const FLOW: u32 = 1 << 12;
}

/// The modifiers' names, bit 0 first.
pub const MODIFIERS: [&str; 13] = [
    "declaration",
    "symbolic",
    "input",
    "output",
    "analog",
    "memory",
    "special",
    "timer",
    "counter",
    "highSpeed",
    "local",
    "constant",
    "flow",
];

/// The modifiers of an area kind.
pub fn area_modifiers(kind: AreaKind) -> u32 {
    use modifier::*;
    match kind {
        AreaKind::DigitalInput => INPUT,
        AreaKind::DigitalOutput => OUTPUT,
        AreaKind::AnalogInput => INPUT | ANALOG,
        AreaKind::AnalogOutput => OUTPUT | ANALOG,
        AreaKind::Memory => MEMORY,
        AreaKind::Timer => TIMER,
        AreaKind::Counter => COUNTER,
        AreaKind::HighSpeedCounter => COUNTER | HIGH_SPEED,
        AreaKind::System => SPECIAL,
        AreaKind::Flow => FLOW,
        AreaKind::Constant => CONSTANT,
        AreaKind::Local => LOCAL,
    }
}

/// One classified token (a span of the program text).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SemanticToken {
    pub span: Span,
    pub kind: TokenKind,
    pub modifiers: u32,
}

/// The tokens of the document at `part` (its byte range in `checked.file.text`) that
/// overlap `range`, in text order, without overlaps.
pub fn semantic_tokens(checked: &CheckedFile, part: Span, range: Span) -> Vec<SemanticToken> {
    let text = &checked.file.text;
    let out = &checked.output;
    let Some(doc) = text.get(part.range()) else {
        return Vec::new();
    };
    let mnemonics: HashMap<u32, Span> = out.mnemonics.iter().map(|(s, _)| (s.start, *s)).collect();
    let addresses: HashMap<u32, &Address> =
        out.addresses.iter().map(|(s, a)| (s.start, a)).collect();
    let references: HashMap<u32, usize> = out
        .references
        .iter()
        .map(|r| (r.span.start, r.definition))
        .collect();
    let definitions: HashMap<u32, usize> = out
        .definitions
        .iter()
        .enumerate()
        .filter(|(_, d)| !d.span.is_empty())
        .map(|(i, d)| (d.span.start, i))
        .collect();
    let symbols = symbol_addresses(checked);
    // The numbered names of block headers (`SBR0` in `ADD:SBR0`).
    let ast = &checked.ast;
    let numbered: HashMap<u32, Span> = ast
        .units
        .iter()
        .map(|u| &u.header)
        .chain(ast.data_blocks.iter().map(|d| &d.header))
        .filter_map(|h| h.number.map(|(_, s)| (s.start, s)))
        .filter(|(_, s)| !definitions.contains_key(&s.start))
        .collect();
    let memory = &checked.target.memory;
    // A symbol table's rows: only names, addresses and types mean something there.
    let parts = checked.file.parts();
    let table = parts
        .get(checked.file.part_index(part.start as usize))
        .is_some_and(|p| p.kind == PartKind::SymbolTable);
    let area_of = |a: &Address| {
        memory
            .area_by_slot(a.slot)
            .map(|x| area_modifiers(x.kind))
            .unwrap_or(0)
    };
    let mut tokens = Vec::new();
    let mut covered_to = 0u32;
    let mut system_block = false;
    let mut before_eq = true;
    let mut minus: Option<Span> = None;
    for (tok, s) in lex(doc) {
        let span = Span::new(
            part.start as usize + s.start as usize,
            part.start as usize + s.end as usize,
        );
        match tok {
            Tok::Newline => before_eq = true,
            Tok::Eq => before_eq = false,
            _ => {}
        }
        let sign = std::mem::replace(&mut minus, (tok == Tok::Minus).then_some(span));
        if span.start < covered_to || span.end <= range.start || span.start >= range.end {
            continue;
        }
        let word = &text[span.range()];
        let classified = if let Some(m) = mnemonics.get(&span.start) {
            Some((*m, TokenKind::Mnemonic, 0))
        } else {
            match tok {
                Tok::Comment | Tok::Title => Some((span, TokenKind::Comment, 0)),
                Tok::Str => Some((span, TokenKind::Str, 0)),
                Tok::Int | Tok::Based | Tok::Real | Tok::Word => {
                    // Labels are numbers; every other name is a word.
                    let named = references.get(&span.start).map(|d| (*d, 0)).or_else(|| {
                        definitions
                            .get(&span.start)
                            .map(|d| (*d, modifier::DECLARATION))
                    });
                    if tok != Tok::Word && named.is_none() {
                        // `-5`: the sign belongs to the number.
                        let signed = sign
                            .filter(|m| m.end == span.start && m.start >= covered_to)
                            .map_or(span, |m| m.to(span));
                        Some((signed, TokenKind::Number, 0))
                    } else if let Some((def, decl)) = named {
                        let (kind, mods) = match out.definitions[def].kind {
                            DefKind::Symbol => (
                                TokenKind::Variable,
                                modifier::SYMBOLIC | symbols.get(&def).map(area_of).unwrap_or(0),
                            ),
                            DefKind::Local => (TokenKind::Local, 0),
                            DefKind::Unit | DefKind::DataBlock => (TokenKind::Block, 0),
                            DefKind::Label => (TokenKind::Label, 0),
                        };
                        Some((span, kind, mods | decl))
                    } else if let Some(n) = numbered.get(&span.start) {
                        Some((*n, TokenKind::Block, modifier::DECLARATION))
                    } else if let Some(a) = addresses.get(&span.start) {
                        Some((span, TokenKind::Variable, area_of(a)))
                    } else if gutta_compiler::syntax::is_reserved(word) {
                        system_block = word.eq_ignore_ascii_case("SYSTEM_BLOCK");
                        Some((span, TokenKind::Keyword, 0))
                    } else if word.eq_ignore_ascii_case("PLC_TYPE") {
                        Some((span, TokenKind::Keyword, 0))
                    } else if word.parse::<DataType>().is_ok() {
                        Some((span, TokenKind::DataType, 0))
                    } else if system_block && before_eq {
                        Some((span, TokenKind::Key, 0))
                    } else if let Ok(a) = memory.parse_address(word) {
                        Some((span, TokenKind::Variable, area_of(&a)))
                    } else {
                        None
                    }
                }
                _ => None,
            }
        };
        let classified = classified.filter(|(_, kind, _)| {
            !table || matches!(kind, TokenKind::Variable | TokenKind::DataType)
        });
        if let Some((span, kind, modifiers)) = classified {
            covered_to = span.end;
            tokens.push(SemanticToken {
                span,
                kind,
                modifiers,
            });
        }
    }
    tokens
}

#[cfg(test)]
mod tests {
    use super::*;
    use gutta_compiler::source::SourceFile;

    fn shown(text: &str) -> Vec<String> {
        let checked = gutta_compiler::check_source(SourceFile::new("t.lad", text), None);
        let all = Span::new(0, text.len());
        semantic_tokens(&checked, all, all)
            .into_iter()
            .map(|t| {
                let mods: Vec<&str> = (0..MODIFIERS.len())
                    .filter(|b| t.modifiers & (1 << b) != 0)
                    .map(|b| MODIFIERS[b])
                    .collect();
                format!(
                    "{} {} {}",
                    &text[t.span.range()],
                    t.kind.lsp_name(),
                    mods.join("+")
                )
            })
            .collect()
    }

    #[test]
    fn words_by_what_they_are() {
        let text = "SYMBOLS\n  Start : I0.0 // go\nEND_SYMBOLS\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD Start\n+I 16#10, MW2\nTON T4, 2\nEND_ORGANIZATION_BLOCK\nSYSTEM_BLOCK\n  PORT0.BAUD = 9600\nEND_SYSTEM_BLOCK\n";
        assert_eq!(
            shown(text),
            [
                "SYMBOLS keyword ",
                "Start variable declaration+symbolic+input",
                "I0.0 variable input",
                "// go comment ",
                "END_SYMBOLS keyword ",
                "ORGANIZATION_BLOCK keyword ",
                "MAIN namespace declaration",
                "OB1 namespace declaration",
                "BEGIN keyword ",
                "NETWORK keyword ",
                "1 number ",
                "LD function ",
                "Start variable symbolic+input",
                "+I function ",
                "16#10 number ",
                "MW2 variable memory",
                "TON function ",
                "T4 variable timer",
                "2 number ",
                "END_ORGANIZATION_BLOCK keyword ",
                "SYSTEM_BLOCK keyword ",
                "PORT0 property ",
                "BAUD property ",
                "9600 number ",
                "END_SYSTEM_BLOCK keyword ",
            ]
        );
    }

    #[test]
    fn a_range_keeps_the_tokens_it_overlaps() {
        let text = "ORGANIZATION_BLOCK MAIN\nBEGIN\nNETWORK 1\nLD I0.0\nEND_ORGANIZATION_BLOCK\n";
        let checked = gutta_compiler::check_source(SourceFile::new("t.lad", text), None);
        let all = Span::new(0, text.len());
        let line = Span::new(40, 47);
        let kinds: Vec<TokenKind> = semantic_tokens(&checked, all, line)
            .iter()
            .map(|t| t.kind)
            .collect();
        assert_eq!(kinds, [TokenKind::Mnemonic, TokenKind::Variable]);
    }
}
