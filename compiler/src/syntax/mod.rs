//! Source text to syntax tree: lexer (logos), line grammars (chumsky) and the block
//! parser that drives them; symbol tables (table.rs). Parsing never fails: it returns a
//! tree and diagnostics.

pub mod ast;
mod blocks;
pub mod data_block_tab;
pub mod lexer;
mod lines;
pub mod numbers;
pub mod table;

pub use blocks::{parse, parse_files, parse_microwin_files, ParseOutput};

/// Whether a word is reserved (a block keyword), so it cannot name a symbol.
pub fn is_reserved(word: &str) -> bool {
    blocks::is_keyword(word)
}
