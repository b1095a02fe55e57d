//! Where the cursor stands in the grammar, read from the text around it: the block it is
//! in (by the nearest structural keyword above it, so half-written code still has a
//! place) and its position in the line (a mnemonic, the n-th operand, a system key...).
//! Completion and signature help share it. No items, no messages here.

use gutta_compiler::source::{PartKind, Span};
use gutta_compiler::CheckedFile;

/// The block the cursor's line belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Block {
    /// Outside every block.
    Top,
    Symbols,
    /// After a program block header, before `BEGIN` (VAR sections, `TITLE=`).
    UnitHead,
    /// Inside a `VAR...` section.
    Vars,
    /// After `BEGIN`: networks and instructions.
    Body,
    Data,
    System,
}

/// The cursor's position in its line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Place {
    /// In a comment, a string or a symbol table: nothing to offer.
    Comment,
    /// The first word of a line at the top level.
    TopKeyword,
    /// After `PLC_TYPE`.
    PlcTypeName,
    /// The first word of a line in a block other than code (`SYMBOLS`' names, VAR names).
    LineStart(Block),
    /// After the n-th `:` of a symbol or local declaration (1: address or type, 2: type).
    AfterColon(Block, usize),
    /// The first word of a line in code: a mnemonic, `NETWORK`, `END_...`.
    Mnemonic,
    /// The operand `index` (0-based, by commas) of the instruction `mnemonic`.
    Operand { mnemonic: Span, index: usize },
    /// A data block row: 0 address, 1 type, 2 value.
    DataField(usize),
    /// A system block key.
    SystemKey,
    /// The value of the system block key `key` (as written, upper case).
    SystemValue(String),
}

/// The cursor's context: its block, place, the unit it is in (index into `ast.units`),
/// and the word being typed (the span a completion replaces).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Cursor {
    pub block: Block,
    pub place: Place,
    pub unit: Option<usize>,
    pub word: Span,
}

/// Characters a word being typed is made of (names, addresses, mnemonics with their
/// operator characters, `#` of locals, `.` of bits and keys).
fn word_char(c: char) -> bool {
    c.is_alphanumeric() || matches!(c, '_' | '#' | '.' | '+' | '-' | '/' | '<' | '>' | '=')
}

/// The context at `offset` in the checked text.
pub fn cursor_at(checked: &CheckedFile, offset: usize) -> Cursor {
    let text = checked.file.text.as_str();
    let offset = floor_char_boundary(text, offset.min(text.len()));
    let part = checked.file.part_range(offset);
    let line_start = text[part.start..offset]
        .rfind('\n')
        .map_or(part.start, |i| part.start + i + 1);
    let before = &text[line_start..offset];
    let block = block_at(&text[part.start..line_start]);
    let word_start = before
        .char_indices()
        .rev()
        .take_while(|(_, c)| word_char(*c))
        .last()
        .map_or(offset, |(i, _)| line_start + i);
    let mut word = Span::new(word_start, offset);
    let unit = unit_at(checked, offset);
    let in_table = checked
        .file
        .parts()
        .get(checked.file.part_index(offset))
        .is_some_and(|p| p.kind == PartKind::SymbolTable);
    let place = if in_table {
        // A symbol table is CSV or tab-separated rows, not the language.
        Place::Comment
    } else {
        line_place(block, before, line_start)
    };
    if let Place::Mnemonic = place {
        // A mnemonic is the whole first word, operator characters and all.
        word = Span::new(
            line_start + (before.len() - before.trim_start().len()),
            offset,
        );
    }
    Cursor {
        block,
        place,
        unit,
        word,
    }
}

fn floor_char_boundary(text: &str, mut at: usize) -> usize {
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    at
}

/// The block that lines after `above` stand in: the nearest structural keyword above.
fn block_at(above: &str) -> Block {
    for line in above.lines().rev() {
        let first = line
            .trim_start()
            .split(|c: char| c.is_whitespace() || c == ':' || c == '/')
            .next()
            .unwrap_or("")
            .to_ascii_uppercase();
        let block = match first.as_str() {
            "SYMBOLS" => Block::Symbols,
            "ORGANIZATION_BLOCK" | "INTERRUPT_BLOCK" | "SUBROUTINE_BLOCK" | "END_VAR" => {
                Block::UnitHead
            }
            "VAR" | "VAR_TEMP" | "VAR_INPUT" | "VAR_OUTPUT" | "VAR_IN_OUT" => Block::Vars,
            "BEGIN" | "NETWORK" => Block::Body,
            "DATA_BLOCK" => Block::Data,
            "SYSTEM_BLOCK" => Block::System,
            "PLC_TYPE"
            | "END_SYMBOLS"
            | "END_ORGANIZATION_BLOCK"
            | "END_INTERRUPT_BLOCK"
            | "END_SUBROUTINE_BLOCK"
            | "END_DATA_BLOCK"
            | "END_SYSTEM_BLOCK" => Block::Top,
            _ => continue,
        };
        return block;
    }
    Block::Top
}

/// The program unit whose header is the last one before `offset`, when `offset` is
/// before its end.
fn unit_at(checked: &CheckedFile, offset: usize) -> Option<usize> {
    let units = &checked.ast.units;
    let i = units
        .partition_point(|u| u.header.span.start as usize <= offset)
        .checked_sub(1)?;
    match units[i].end {
        Some(end) if (end.start as usize) < offset => None,
        _ => Some(i),
    }
}

/// The place in a line whose text before the cursor is `before`.
fn line_place(block: Block, before: &str, line_start: usize) -> Place {
    if in_comment(before) {
        return Place::Comment;
    }
    let trimmed = before.trim_start();
    let first_word_done = trimmed.contains(|c: char| c.is_whitespace());
    match block {
        Block::Top => {
            let first = trimmed.split_whitespace().next().unwrap_or("");
            if first_word_done && first.eq_ignore_ascii_case("PLC_TYPE") {
                Place::PlcTypeName
            } else if first_word_done {
                Place::Comment
            } else {
                Place::TopKeyword
            }
        }
        Block::Symbols | Block::Vars => match trimmed.matches(':').count() {
            0 => Place::LineStart(block),
            n => Place::AfterColon(block, n),
        },
        Block::UnitHead => Place::LineStart(block),
        Block::Body => {
            if !first_word_done {
                return Place::Mnemonic;
            }
            let (mnemonic, rest) = trimmed.split_at(
                trimmed
                    .find(|c: char| c.is_whitespace())
                    .unwrap_or(trimmed.len()),
            );
            let start = line_start + before.len() - trimmed.len();
            let mnemonic = Span::new(start, start + mnemonic.len());
            Place::Operand {
                mnemonic,
                index: rest.matches(',').count(),
            }
        }
        Block::Data => Place::DataField(
            trimmed
                .split_whitespace()
                .count()
                .saturating_sub(usize::from(!before.ends_with(char::is_whitespace))),
        ),
        Block::System => match trimmed.split_once('=') {
            None => Place::SystemKey,
            Some((key, _)) => Place::SystemValue(key.trim().to_ascii_uppercase()),
        },
    }
}

/// Whether the text before the cursor ends inside a `//` comment or a string.
fn in_comment(before: &str) -> bool {
    let mut in_string = false;
    let mut chars = before.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '\\' if in_string => {
                chars.next();
            }
            '"' => in_string = !in_string,
            '/' if !in_string && chars.peek() == Some(&'/') => return true,
            _ => {}
        }
    }
    in_string
}

#[cfg(test)]
mod tests {
    use super::*;
    use gutta_compiler::source::SourceFile;

    fn at(text: &str) -> Cursor {
        let offset = text.find('|').expect("a cursor");
        let text = text.replacen('|', "", 1);
        let checked = gutta_compiler::check_source(SourceFile::new("t.lad", text), None);
        cursor_at(&checked, offset)
    }

    const UNIT: &str = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\n";

    #[test]
    fn places_in_code() {
        let c = at(&format!("{UNIT}LD|\nEND_ORGANIZATION_BLOCK\n"));
        assert_eq!(
            (c.block, c.place, c.unit),
            (Block::Body, Place::Mnemonic, Some(0))
        );
        let c = at(&format!("{UNIT}  MOVW MW0, |\nEND_ORGANIZATION_BLOCK\n"));
        let Place::Operand { index, mnemonic } = c.place else {
            panic!("{c:?}")
        };
        assert_eq!(index, 1);
        assert_eq!(mnemonic.end - mnemonic.start, 4);
        let c = at(&format!("{UNIT}MOVW #co|"));
        assert_eq!(c.word.end - c.word.start, 3);
        let c = at(&format!("{UNIT}MOVW MW0, MW2 // x|"));
        assert_eq!(c.place, Place::Comment);
    }

    #[test]
    fn places_in_blocks() {
        assert_eq!(at("SYM|").place, Place::TopKeyword);
        assert_eq!(at("PLC_TYPE CPU|").place, Place::PlcTypeName);
        assert_eq!(
            at("SYMBOLS\n  Start : I|").place,
            Place::AfterColon(Block::Symbols, 1)
        );
        assert_eq!(
            at("SUBROUTINE_BLOCK A\nVAR_INPUT\n  x : |").place,
            Place::AfterColon(Block::Vars, 1)
        );
        assert_eq!(at("SYSTEM_BLOCK\n  PORT0.BA|").place, Place::SystemKey);
        assert_eq!(
            at("SYSTEM_BLOCK\n  port0.baud = |").place,
            Place::SystemValue("PORT0.BAUD".into())
        );
        assert_eq!(at("DATA_BLOCK D\n  MW0 |").place, Place::DataField(1));
        assert_eq!(at("DATA_BLOCK D\n  MW0 UI|").place, Place::DataField(1));
        assert_eq!(at("SYMBOLS\nEND_SYMBOLS\n|").place, Place::TopKeyword);
    }

    #[test]
    fn nothing_in_a_symbol_table() {
        let program = gutta_compiler::ProgramSources {
            sources: vec![SourceFile::new(
                "a.lad",
                "ORGANIZATION_BLOCK MAIN\nEND_ORGANIZATION_BLOCK\n",
            )],
            symbol_tables: vec![SourceFile::new("t.csv", "Symbol,Address,Comment\nS")],
            ..Default::default()
        };
        let checked = gutta_compiler::check_program(program, None);
        let end = checked.file.text.len() - 1;
        assert_eq!(cursor_at(&checked, end).place, Place::Comment);
    }
}
