//! Tokens of the .lad language (logos). Lexing never fails: characters that start no
//! token become `Tok::Error` tokens, which the parser reports once. Keywords and
//! mnemonics are plain words here; the parser compares them case-insensitively.

use logos::Logos;

use crate::source::Span;

#[derive(Logos, Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[logos(skip r"[ \t\f]+")]
pub enum Tok {
    #[regex(r"\r?\n")]
    Newline,
    #[regex(r"//[^\r\n]*", allow_greedy = true)]
    Comment,
    /// `TITLE=free text` up to the end of the line.
    #[regex(r"[Tt][Ii][Tt][Ll][Ee][ \t]*=[^\r\n]*", allow_greedy = true)]
    Title,
    /// Names, keywords, mnemonics and direct addresses (`I0.0` is one word).
    #[regex(r"[\p{L}_][\p{L}\p{N}_]*(\.[0-9]+)?")]
    Word,
    #[regex(r"[0-9][0-9_]*")]
    Int,
    /// `16#0E01`, `2#1010`, `8#17`.
    #[regex(r"[0-9]+#[0-9A-Za-z_]*")]
    Based,
    #[regex(r"[0-9][0-9_]*\.[0-9]+([eE][+-]?[0-9]+)?")]
    Real,
    #[regex(r#""([^"\\\r\n]|\\[^\r\n])*""#)]
    Str,
    /// A string with no closing quote on its line.
    #[regex(r#""([^"\\\r\n]|\\[^\r\n])*"#)]
    UnterminatedStr,
    #[token("+")]
    Plus,
    #[token("-")]
    Minus,
    #[token("*")]
    Star,
    #[token("/")]
    Slash,
    #[token("=")]
    Eq,
    #[token("<>")]
    Ne,
    #[token("<")]
    Lt,
    #[token("<=")]
    Le,
    #[token(">")]
    Gt,
    #[token(">=")]
    Ge,
    #[token("&")]
    Amp,
    #[token("#")]
    Hash,
    #[token(",")]
    Comma,
    #[token(":")]
    Colon,
    #[token(":=")]
    Assign,
    #[token(";")]
    Semi,
    #[token(".")]
    Dot,
    #[token("(")]
    LParen,
    #[token(")")]
    RParen,
    /// Anything else (one character).
    Error,
}

impl Tok {
    /// How the token is named in "expected ..." messages.
    pub fn describe(self) -> &'static str {
        match self {
            Tok::Newline => "end of line",
            Tok::Comment => "comment",
            Tok::Title => "TITLE=",
            Tok::Word => "name",
            Tok::Int | Tok::Based | Tok::Real => "number",
            Tok::Str => "string",
            Tok::UnterminatedStr => "unterminated string",
            Tok::Plus => "`+`",
            Tok::Minus => "`-`",
            Tok::Star => "`*`",
            Tok::Slash => "`/`",
            Tok::Eq => "`=`",
            Tok::Ne => "`<>`",
            Tok::Lt => "`<`",
            Tok::Le => "`<=`",
            Tok::Gt => "`>`",
            Tok::Ge => "`>=`",
            Tok::Amp => "`&`",
            Tok::Hash => "`#`",
            Tok::Comma => "`,`",
            Tok::Colon => "`:`",
            Tok::Assign => "`:=`",
            Tok::Semi => "`;`",
            Tok::Dot => "`.`",
            Tok::LParen => "`(`",
            Tok::RParen => "`)`",
            Tok::Error => "unknown character",
        }
    }
}

impl std::fmt::Display for Tok {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.describe())
    }
}

/// A token and where it is.
pub type Spanned = (Tok, Span);

/// Lex a whole text into tokens (comments included, as the parser needs them for
/// titles). Never fails.
pub fn lex(text: &str) -> Vec<Spanned> {
    let mut out = Vec::with_capacity(text.len() / 4);
    let mut lexer = Tok::lexer(text);
    while let Some(tok) = lexer.next() {
        let r = lexer.span();
        out.push((tok.unwrap_or(Tok::Error), Span::new(r.start, r.end)));
    }
    out
}

/// Streaming lexer, line by line: fills `buf` with the tokens of the next line (without
/// its newline) and returns false at the end of the text.
#[derive(Debug)]
pub struct LineLexer<'a> {
    inner: logos::Lexer<'a, Tok>,
    done: bool,
}

impl<'a> LineLexer<'a> {
    pub fn new(text: &'a str) -> Self {
        LineLexer {
            inner: Tok::lexer(text),
            done: false,
        }
    }

    pub fn next_line(&mut self, buf: &mut Vec<Spanned>) -> bool {
        buf.clear();
        if self.done {
            return false;
        }
        loop {
            match self.inner.next() {
                None => {
                    self.done = true;
                    return true;
                }
                Some(tok) => {
                    let r = self.inner.span();
                    let tok = tok.unwrap_or(Tok::Error);
                    if tok == Tok::Newline {
                        return true;
                    }
                    buf.push((tok, Span::new(r.start, r.end)));
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(text: &str) -> Vec<Tok> {
        lex(text).into_iter().map(|(t, _)| t).collect()
    }

    #[test]
    fn addresses_mnemonics_and_numbers() {
        assert_eq!(kinds("LD I0.0"), [Tok::Word, Tok::Word]);
        assert_eq!(
            kinds("LDW>= T4, +2"),
            [
                Tok::Word,
                Tok::Ge,
                Tok::Word,
                Tok::Comma,
                Tok::Plus,
                Tok::Int
            ]
        );
        assert_eq!(
            kinds("MOVW 16#0E01, *MD4"),
            [Tok::Word, Tok::Based, Tok::Comma, Tok::Star, Tok::Word]
        );
        assert_eq!(
            kinds("+R 1.5e3, MD0"),
            [Tok::Plus, Tok::Word, Tok::Real, Tok::Comma, Tok::Word]
        );
        assert_eq!(
            kinds("PORT0.BAUD = 38400"),
            [Tok::Word, Tok::Dot, Tok::Word, Tok::Eq, Tok::Int]
        );
    }

    #[test]
    fn titles_comments_and_errors() {
        assert_eq!(kinds("TITLE=r := a + b // x\n"), [Tok::Title, Tok::Newline]);
        assert_eq!(
            kinds("Network 1 // latch"),
            [Tok::Word, Tok::Int, Tok::Comment]
        );
        assert_eq!(kinds("LD ?"), [Tok::Word, Tok::Error]);
        assert_eq!(kinds("\"abc"), [Tok::UnterminatedStr]);
    }

    #[test]
    fn line_lexer_splits_lines() {
        let mut l = LineLexer::new("LD I0.0\r\n\n= Q0.0");
        let mut buf = Vec::new();
        let mut lines = Vec::new();
        while l.next_line(&mut buf) {
            lines.push(buf.len());
        }
        assert_eq!(lines, [2, 0, 2]);
    }
}
