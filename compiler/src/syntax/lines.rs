//! chumsky grammars for the content of one line: instruction operands, symbol and
//! local declarations, data rows, system entries, block and network headers. The
//! block parser (blocks/) splits the text into lines and picks the grammar; a line
//! that fails its grammar gives exactly one E0102 diagnostic.

use chumsky::input::ValueInput;
use chumsky::prelude::*;

use crate::source::Span;
use crate::syntax::ast::Prefix;
use crate::syntax::lexer::Tok;

pub type Extra<'t> = extra::Err<Rich<'t, Tok, SimpleSpan>>;

pub fn span(s: SimpleSpan) -> Span {
    Span::new(s.start, s.end)
}

/// An operand before number conversion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RawOperand {
    Name {
        prefix: Prefix,
        local: bool,
        name: Span,
        span: Span,
    },
    Number {
        negative: bool,
        digits: Span,
        span: Span,
    },
}

fn word<'t, I>() -> impl Parser<'t, I, Span, Extra<'t>> + Clone
where
    I: ValueInput<'t, Token = Tok, Span = SimpleSpan>,
{
    just(Tok::Word)
        .map_with(|_, e| span(e.span()))
        .labelled("name")
}

fn number<'t, I>() -> impl Parser<'t, I, RawOperand, Extra<'t>> + Clone
where
    I: ValueInput<'t, Token = Tok, Span = SimpleSpan>,
{
    let sign = choice((just(Tok::Plus).to(false), just(Tok::Minus).to(true))).or_not();
    let digits = select! { Tok::Int => (), Tok::Based => (), Tok::Real => () }
        .map_with(|_, e| span(e.span()));
    sign.then(digits)
        .map_with(|(sign, digits), e| RawOperand::Number {
            negative: sign == Some(true),
            digits,
            span: span(e.span()),
        })
        .labelled("number")
}

/// One operand: `MW10`, `#a`, `&MB24`, `*MD4`, `*#p`, `16#0E01`, `-3`, `1.5`.
pub fn operand<'t, I>() -> impl Parser<'t, I, RawOperand, Extra<'t>> + Clone
where
    I: ValueInput<'t, Token = Tok, Span = SimpleSpan>,
{
    let local = just(Tok::Hash).ignore_then(word()).map(|n| (true, n));
    let target = choice((local, word().map(|n| (false, n))));
    let prefix = choice((
        just(Tok::Amp).to(Prefix::AddressOf),
        just(Tok::Star).to(Prefix::Pointer),
    ))
    .or_not();
    let named = prefix
        .then(target)
        .map_with(|(prefix, (local, name)), e| RawOperand::Name {
            prefix: prefix.unwrap_or(Prefix::None),
            local,
            name,
            span: span(e.span()),
        });
    choice((number(), named)).labelled("operand")
}

/// `op, op, ...` (possibly none) to the end of the line.
pub fn operand_list<'t, I>() -> impl Parser<'t, I, Vec<RawOperand>, Extra<'t>>
where
    I: ValueInput<'t, Token = Tok, Span = SimpleSpan>,
{
    operand()
        .separated_by(just(Tok::Comma))
        .collect::<Vec<_>>()
        .then_ignore(end())
}

/// `operand_list` without chumsky for a well-formed line (nearly every instruction
/// line): the same operands, or `None` when the line needs the grammar (which then
/// also describes the error). Building chumsky's rich "expected" sets for every
/// alternative tried was a third of the front end's time on large files.
pub fn simple_operand_list(toks: &[(Tok, SimpleSpan)]) -> Option<Vec<RawOperand>> {
    let mut out = Vec::new();
    if toks.is_empty() {
        return Some(out);
    }
    let mut i = 0;
    loop {
        let start = toks[i].1.start;
        let op = match toks[i].0 {
            Tok::Plus | Tok::Minus | Tok::Int | Tok::Based | Tok::Real => {
                let negative = toks[i].0 == Tok::Minus;
                if matches!(toks[i].0, Tok::Plus | Tok::Minus) {
                    i += 1;
                }
                let &(tok, digits) = toks.get(i)?;
                if !matches!(tok, Tok::Int | Tok::Based | Tok::Real) {
                    return None;
                }
                i += 1;
                RawOperand::Number {
                    negative,
                    digits: span(digits),
                    span: Span::new(start, digits.end),
                }
            }
            Tok::Amp | Tok::Star | Tok::Hash | Tok::Word => {
                let prefix = match toks[i].0 {
                    Tok::Amp => Prefix::AddressOf,
                    Tok::Star => Prefix::Pointer,
                    _ => Prefix::None,
                };
                if prefix != Prefix::None {
                    i += 1;
                }
                let local = toks.get(i)?.0 == Tok::Hash;
                if local {
                    i += 1;
                }
                let &(tok, name) = toks.get(i)?;
                if tok != Tok::Word {
                    return None;
                }
                i += 1;
                RawOperand::Name {
                    prefix,
                    local,
                    name: span(name),
                    span: Span::new(start, name.end),
                }
            }
            _ => return None,
        };
        out.push(op);
        match toks.get(i) {
            None => return Some(out),
            Some((Tok::Comma, _)) if i + 1 < toks.len() => i += 1,
            Some(_) => return None,
        }
    }
}

/// `Name : ADDRESS` or `Name : ADDRESS : TYPE` in SYMBOLS.
pub fn symbol_decl<'t, I>() -> impl Parser<'t, I, (Span, Span, Option<Span>), Extra<'t>>
where
    I: ValueInput<'t, Token = Tok, Span = SimpleSpan>,
{
    word()
        .then_ignore(just(Tok::Colon))
        .then(word().labelled("address"))
        .then(
            just(Tok::Colon)
                .ignore_then(word().labelled("data type"))
                .or_not(),
        )
        .map(|((name, address), ty)| (name, address, ty))
        .then_ignore(just(Tok::Semi).or_not())
        .then_ignore(end())
}

/// `a, b : INT;` in a VAR section.
pub fn var_decl<'t, I>() -> impl Parser<'t, I, (Vec<Span>, Span), Extra<'t>>
where
    I: ValueInput<'t, Token = Tok, Span = SimpleSpan>,
{
    word()
        .separated_by(just(Tok::Comma))
        .at_least(1)
        .collect::<Vec<_>>()
        .then_ignore(just(Tok::Colon))
        .then(word().labelled("data type"))
        .then_ignore(just(Tok::Semi).or_not())
        .then_ignore(end())
}

/// `MW22 UINT 6` or `MW22 6` in a data block.
pub fn data_row<'t, I>() -> impl Parser<'t, I, (Span, Option<Span>, RawOperand), Extra<'t>>
where
    I: ValueInput<'t, Token = Tok, Span = SimpleSpan>,
{
    word()
        .labelled("address")
        .then(word().labelled("data type").or_not())
        .then(number().labelled("initial value"))
        .map(|((a, t), v)| (a, t, v))
        .then_ignore(just(Tok::Semi).or_not())
        .then_ignore(end())
}

/// Value of a system entry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RawValue {
    Word(Span),
    Number(RawOperand),
    Str(Span),
}

/// `PORT0.BAUD = 38400` / `PASSWORD = "1234"`: (key span, value).
pub fn system_entry<'t, I>() -> impl Parser<'t, I, (Span, RawValue), Extra<'t>>
where
    I: ValueInput<'t, Token = Tok, Span = SimpleSpan>,
{
    let key = word()
        .then(just(Tok::Dot).ignore_then(word()).repeated())
        .map_with(|_, e| span(e.span()))
        .labelled("key");
    let value = choice((
        number().map(RawValue::Number),
        word().map(RawValue::Word),
        just(Tok::Str).map_with(|_, e| RawValue::Str(span(e.span()))),
    ))
    .labelled("value");
    key.then_ignore(just(Tok::Eq))
        .then(value)
        .then_ignore(just(Tok::Semi).or_not())
        .then_ignore(end())
}

/// After a block keyword: nothing, `NAME`, or `NAME:NUMBERED`.
pub fn block_header<'t, I>() -> impl Parser<'t, I, Option<(Span, Option<Span>)>, Extra<'t>>
where
    I: ValueInput<'t, Token = Tok, Span = SimpleSpan>,
{
    word()
        .then(
            just(Tok::Colon)
                .ignore_then(word().labelled("numbered name such as SBR0"))
                .or_not(),
        )
        .or_not()
        .then_ignore(end())
}

/// After `NETWORK`: an optional number.
pub fn network_header<'t, I>() -> impl Parser<'t, I, Option<Span>, Extra<'t>>
where
    I: ValueInput<'t, Token = Tok, Span = SimpleSpan>,
{
    just(Tok::Int)
        .map_with(|_, e| span(e.span()))
        .labelled("network number")
        .or_not()
        .then_ignore(end())
}

/// Text of the first error of a failed line grammar: "expected X, found Y".
pub fn describe_error(err: &Rich<'_, Tok, SimpleSpan>) -> String {
    use chumsky::error::RichPattern;
    let mut expected: Vec<String> = err
        .expected()
        .filter_map(|p| match p {
            RichPattern::Token(t) => Some(t.describe().to_string()),
            RichPattern::Label(l) => Some(l.to_string()),
            RichPattern::EndOfInput => Some("end of line".to_string()),
            _ => None,
        })
        .collect();
    expected.sort();
    expected.dedup();
    let found = err.found().map(|t| t.describe()).unwrap_or("end of line");
    match expected.len() {
        0 => format!("unexpected {found}"),
        1 => format!("expected {}, found {found}", expected[0]),
        _ => {
            let last = expected.pop().unwrap_or_default();
            format!("expected {} or {last}, found {found}", expected.join(", "))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every sequence of up to five operand-alphabet tokens: the fast path gives the
    /// grammar's result whenever the grammar succeeds, and declines otherwise.
    #[test]
    fn simple_operand_list_agrees_with_the_grammar() {
        const ALPHABET: [Tok; 11] = [
            Tok::Word,
            Tok::Hash,
            Tok::Amp,
            Tok::Star,
            Tok::Plus,
            Tok::Minus,
            Tok::Int,
            Tok::Based,
            Tok::Real,
            Tok::Comma,
            Tok::Colon,
        ];
        let mut frontier: Vec<Vec<Tok>> = vec![Vec::new()];
        let mut all = frontier.clone();
        for _ in 0..5 {
            frontier = frontier
                .iter()
                .flat_map(|seq| {
                    ALPHABET.iter().map(move |t| {
                        let mut longer = seq.clone();
                        longer.push(*t);
                        longer
                    })
                })
                .collect();
            all.extend(frontier.iter().cloned());
        }
        let mut accepted = 0;
        for seq in &all {
            let toks: Vec<(Tok, SimpleSpan)> = seq
                .iter()
                .enumerate()
                .map(|(k, t)| (*t, SimpleSpan::from(2 * k..2 * k + 1)))
                .collect();
            let eoi = SimpleSpan::from(2 * toks.len()..2 * toks.len());
            let input = toks[..].map(eoi, |(t, s)| (t, s));
            let grammar = match operand_list().parse(input).into_output_errors() {
                (Some(ops), errs) if errs.is_empty() => Some(ops),
                _ => None,
            };
            accepted += usize::from(grammar.is_some());
            assert_eq!(simple_operand_list(&toks), grammar, "tokens {seq:?}");
        }
        assert!(accepted > 100, "only {accepted} sequences parse");
    }
}
