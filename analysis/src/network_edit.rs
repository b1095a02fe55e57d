//! Editing one network of a .lad text in place (docs/ladder.md, "Editing a network in
//! place"): replace a network's instruction lines, insert a network after another,
//! delete one. Every answer is a list of [`Edit`]s (byte range + replacement, like the
//! formatter's) that touches only that network (and, after an insert, the digits of
//! the NETWORK lines that must move up); every other byte of the file stays as it was.
//! Works on the syntax tree of the text (`ast::Program`, from [`parse`] or a
//! `CheckedFile`'s `ast`), whose spans say where each block and network is. No I/O.
//!
//! ```rust
//! use gutta_analysis::network_edit::{apply, parse, replace_network, BlockRef, NetworkRef};
//!
//! let text = "ORGANIZATION_BLOCK MAIN:OB1\r\nBEGIN\r\nNETWORK 1 // lamp\r\n\
//!             LD     I0.0\r\n=      Q0.0\r\nEND_ORGANIZATION_BLOCK\r\n";
//! let program = parse(text, false);
//! let at = NetworkRef { block: BlockRef::Name("MAIN"), network: 0 };
//! let edit = replace_network(text, &program, at, &["LDN    I0.0", "=      Q0.0"]).unwrap();
//! assert_eq!(apply(text, &[edit]), text.replace("LD  ", "LDN "));
//! ```

use std::fmt;

use gutta_compiler::source::{has_marker, Span};
use gutta_compiler::syntax::ast::{Network, Program, Unit};
use gutta_compiler::syntax::{parse_files, parse_microwin_files};

use crate::format::Edit;

/// A program block: its place among the program blocks of the text (0 = the first
/// `ORGANIZATION_BLOCK`, `SUBROUTINE_BLOCK` or `INTERRUPT_BLOCK`, data and system
/// blocks not counted: the ladder model's `blocks` order), or its name (`MAIN`), its
/// numbered name (`OB1`) or both (`MAIN:OB1`), any case.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BlockRef<'a> {
    Index(usize),
    Name(&'a str),
}

/// A network: its block and its place in the block (0 = the first network).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NetworkRef<'a> {
    pub block: BlockRef<'a>,
    pub network: usize,
}

/// A network to insert: its title (after `NETWORK n //`), comment lines (written as
/// `// line` before the instructions) and instruction lines.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct NewNetwork<'a> {
    pub title: Option<&'a str>,
    pub comment: &'a [&'a str],
    pub lines: &'a [&'a str],
}

/// Why an edit is refused; nothing is changed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum EditError {
    /// No block of that index or name.
    BlockNotFound(String),
    /// The name is a data block's: it has rows, not networks.
    NotAProgramBlock(String),
    /// The block has no network at that index.
    NetworkNotFound {
        block: String,
        network: usize,
        networks: usize,
    },
    /// A line, title or comment line holds a line break (each must be one line).
    LineBreak(String),
    /// The block's first network is instructions before any NETWORK line: a network
    /// written before them would take them in.
    NoNetworkLine(String),
}

impl fmt::Display for EditError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EditError::BlockNotFound(b) => write!(f, "no program block {b}"),
            EditError::NotAProgramBlock(b) => {
                write!(f, "{b} is a data block: it has no networks")
            }
            EditError::NetworkNotFound {
                block,
                network,
                networks,
            } => write!(
                f,
                "{block} has no network at index {network} (it has {networks})"
            ),
            EditError::LineBreak(l) => write!(f, "a line break inside one line: {l:?}"),
            EditError::NoNetworkLine(b) => write!(
                f,
                "the first network of {b} has no NETWORK line: no network can go before it"
            ),
        }
    }
}

impl std::error::Error for EditError {}

/// The syntax tree of one file's text, in its dialect (a Micro/WIN export when its
/// first line is the marker; an `.awl` file: `microwin` true), for the edits here.
pub fn parse(text: &str, microwin: bool) -> Program {
    let ends = [text.len()];
    if microwin || has_marker(text) {
        parse_microwin_files(text, &ends).program
    } else {
        parse_files(text, &ends).program
    }
}

/// Apply edits (non-overlapping, as the functions here return them) to a text.
pub fn apply(text: &str, edits: &[Edit]) -> String {
    let mut sorted: Vec<&Edit> = edits.iter().collect();
    sorted.sort_by_key(|e| e.span.start);
    let mut out = String::with_capacity(text.len() + 256);
    let mut at = 0;
    for e in sorted {
        out.push_str(&text[at..e.span.start as usize]);
        out.push_str(&e.text);
        at = e.span.end as usize;
    }
    out.push_str(&text[at..]);
    out
}

/// Replace the instruction lines of a network by `lines` (each one instruction line,
/// as written after its indentation). The NETWORK line, the comment lines before the
/// first instruction and everything after the last stay. A new line equal (blanks
/// around ignored) to the old line at its position keeps that line's bytes; others
/// take the indentation of the old line at their position (else of the last old
/// line) and the file's line ending. Comment and blank lines between instructions
/// stay before the line at the same position (those past the new last line follow it).
/// In a network without instructions the lines go after its NETWORK line and the
/// comment lines right after it, indented as the block's first instruction.
pub fn replace_network(
    text: &str,
    program: &Program,
    at: NetworkRef<'_>,
    lines: &[&str],
) -> Result<Edit, EditError> {
    no_line_breaks(lines.iter().copied())?;
    let (unit, net) = find(text, program, at)?;
    let eol = line_ending(text, net.span.start as usize);
    let Some((first, last)) = net.instructions.first().zip(net.instructions.last()) else {
        // No instruction yet: the lines go after the NETWORK line and its comments,
        // indented as the block's first instruction.
        let start = after_comment_lines(text, line_end(text, net.span.end as usize));
        let indent = block_indentation(text, unit);
        let mut new = String::new();
        if start == text.len() && !text.ends_with('\n') && !lines.is_empty() {
            new.push_str(eol);
        }
        for l in lines {
            new.push_str(indent);
            new.push_str(l.trim());
            new.push_str(eol);
        }
        return Ok(edit(start, start, new));
    };
    let start = line_start(text, first.span.start as usize);
    let end = content_end(text, last.span.end as usize);
    let old = old_lines(text, net);
    let mut pieces: Vec<(&str, Option<&str>)> = Vec::new();
    let mut owned = Vec::with_capacity(lines.len());
    for (i, l) in lines.iter().enumerate() {
        let old_line = old.instructions.get(i).or(old.instructions.last());
        owned.push(match old.instructions.get(i) {
            Some(o) if o.content.trim() == l.trim() => None,
            _ => {
                let indent = old_line.map_or("", |o| indentation(o.content));
                Some(format!("{indent}{}", l.trim()))
            }
        });
    }
    for (i, new) in owned.iter().enumerate() {
        if let Some(group) = old.groups.get(i) {
            pieces.extend(group.iter().map(|g| (g.content, g.ending)));
        }
        match new {
            Some(s) => pieces.push((s.as_str(), None)),
            None => {
                let o = &old.instructions[i];
                pieces.push((o.content, o.ending));
            }
        }
    }
    for group in old.groups.iter().skip(lines.len()) {
        pieces.extend(group.iter().map(|g| (g.content, g.ending)));
    }
    if pieces.is_empty() {
        // Nothing left: the lines go with their line endings.
        return Ok(edit(start, line_end(text, end), String::new()));
    }
    let mut new = String::with_capacity(end - start + 64);
    let count = pieces.len();
    for (i, (content, ending)) in pieces.into_iter().enumerate() {
        new.push_str(content);
        if i + 1 < count {
            new.push_str(ending.unwrap_or(eol));
        }
    }
    Ok(edit(start, end, new))
}

/// Insert a network after the network `after`: a NETWORK line (`NETWORK n // title`,
/// the keyword spelt as the block's first NETWORK line; `n` written when `after`'s line
/// writes a number), its comment lines and instructions, indented as the block's first
/// instruction, separated from `after` by the blank lines that separate `after` from
/// what comes before it. Numbers must increase within a block (E0414): the numbered
/// NETWORK lines that follow get new digits only as far as needed to stay increasing.
pub fn insert_network_after(
    text: &str,
    program: &Program,
    after: NetworkRef<'_>,
    network: &NewNetwork<'_>,
) -> Result<Vec<Edit>, EditError> {
    one_line_each(network)?;
    let (unit, net) = find(text, program, after)?;
    let eol = line_ending(text, net.span.start as usize);
    let number = effective_number(unit, after.network) + 1;
    let extent = network_extent(text, unit, after.network);
    let at = trim_blank_lines_back(text, extent.start as usize, extent.end as usize);
    let gap_start = trim_blank_lines_back(text, 0, line_start(text, net.span.start as usize));
    let mut new = String::new();
    if at > 0 && !text[..at].ends_with('\n') {
        new.push_str(eol);
    }
    new.push_str(&text[gap_start..line_start(text, net.span.start as usize)]);
    let written = (net.number.is_some() || net.header.is_none()).then_some(number);
    write_network(&mut new, text, unit, written, network, eol);
    let mut edits = vec![edit(at, at, new)];
    edits.extend(renumber_following(text, unit, after.network + 1, number));
    Ok(edits)
}

/// Insert a network as the first of a block (an empty block's first network): before
/// its first network, separated from it by the blank lines between its first and second
/// networks; in an empty block, before its END line. It takes the first network's
/// number (1 in an empty block), written when the first network's NETWORK line writes
/// one (always in an empty block); the numbered networks that follow move up as after
/// [`insert_network_after`].
pub fn insert_network_first(
    text: &str,
    program: &Program,
    block: BlockRef<'_>,
    network: &NewNetwork<'_>,
) -> Result<Vec<Edit>, EditError> {
    one_line_each(network)?;
    let unit = find_block(text, program, block)?;
    let Some(first) = unit.networks.first() else {
        let at = match unit.end {
            Some(end) => line_start(text, end.start as usize),
            None => text.len(),
        };
        let eol = line_ending(text, unit.header.span.start as usize);
        let mut new = String::new();
        if at > 0 && !text[..at].ends_with('\n') {
            new.push_str(eol);
        }
        write_network(&mut new, text, unit, Some(1), network, eol);
        return Ok(vec![edit(at, at, new)]);
    };
    if first.header.is_none() {
        let name = text[unit.header.name.range()].trim();
        return Err(EditError::NoNetworkLine(name.to_string()));
    }
    let eol = line_ending(text, first.span.start as usize);
    let at = line_start(text, first.span.start as usize);
    let number = first.number_after(None);
    let gap = unit.networks.get(1).map_or("", |second| {
        let end = line_start(text, second.span.start as usize);
        &text[trim_blank_lines_back(text, at, end)..end]
    });
    let mut new = String::new();
    let written = first.number.is_some().then_some(number);
    write_network(&mut new, text, unit, written, network, eol);
    new.push_str(gap);
    let mut edits = vec![edit(at, at, new)];
    edits.extend(renumber_following(text, unit, 0, number));
    Ok(edits)
}

/// A new network's lines: `NETWORK [n] [// title]` (the keyword spelt as the block's
/// first NETWORK line), `// comment` lines and instructions, indented as the block's
/// first instruction, each with `eol`.
fn write_network(
    out: &mut String,
    text: &str,
    unit: &Unit,
    number: Option<u32>,
    network: &NewNetwork<'_>,
    eol: &str,
) {
    let keyword = unit
        .networks
        .iter()
        .find_map(|n| n.header)
        .and_then(|h| text[h.range()].split_whitespace().next())
        .filter(|k| k.eq_ignore_ascii_case("NETWORK"))
        .unwrap_or("NETWORK");
    let indent = block_indentation(text, unit);
    out.push_str(keyword);
    if let Some(n) = number {
        out.push_str(&format!(" {n}"));
    }
    if let Some(title) = network.title.map(str::trim).filter(|t| !t.is_empty()) {
        out.push_str(" // ");
        out.push_str(title);
    }
    out.push_str(eol);
    for c in network.comment {
        out.push_str(indent);
        out.push_str(format!("// {}", c.trim()).trim_end());
        out.push_str(eol);
    }
    for l in network.lines {
        out.push_str(indent);
        out.push_str(l.trim());
        out.push_str(eol);
    }
}

/// The indentation of the block's first instruction line ("" in a block without one).
fn block_indentation<'t>(text: &'t str, unit: &Unit) -> &'t str {
    unit.networks
        .iter()
        .find_map(|n| n.instructions.first())
        .map_or("", |i| {
            indentation(&text[line_start(text, i.span.start as usize)..])
        })
}

fn one_line_each(network: &NewNetwork<'_>) -> Result<(), EditError> {
    no_line_breaks(network.title.into_iter())?;
    no_line_breaks(network.comment.iter().copied())?;
    no_line_breaks(network.lines.iter().copied())
}

/// Delete a network: its NETWORK line through the line before the next network's (or
/// the block's END line), its trailing blank lines with it. No other network is
/// renumbered: numbers need only increase.
pub fn delete_network(
    text: &str,
    program: &Program,
    at: NetworkRef<'_>,
) -> Result<Edit, EditError> {
    let (unit, _) = find(text, program, at)?;
    let extent = network_extent(text, unit, at.network);
    Ok(edit(
        extent.start as usize,
        extent.end as usize,
        String::new(),
    ))
}

/// Replace a network's heading: the title after its NETWORK line's keyword and number
/// (`NETWORK 3 // title`; `None` or blank: no title) and its comment lines, those
/// between the NETWORK line and the first instruction (written `// line`, indented as
/// the block's first instruction). The keyword, the number, the instructions and the
/// blank lines before the first instruction keep their bytes; a part that does not
/// change gives no edit. A network without a NETWORK line has no heading
/// (`NoNetworkLine`).
pub fn replace_heading(
    text: &str,
    program: &Program,
    at: NetworkRef<'_>,
    title: Option<&str>,
    comment: &[&str],
) -> Result<Vec<Edit>, EditError> {
    no_line_breaks(title.into_iter())?;
    no_line_breaks(comment.iter().copied())?;
    let (unit, net) = find(text, program, at)?;
    let Some(header) = net.header else {
        let name = text[unit.header.name.range()].trim();
        return Err(EditError::NoNetworkLine(name.to_string()));
    };
    let eol = line_ending(text, header.start as usize);
    let mut edits = Vec::new();

    // The title: what follows `//` on the NETWORK line.
    let line = line_start(text, header.start as usize);
    let end = content_end(text, line);
    let content = &text[line..end];
    let title = title.map(str::trim).filter(|t| !t.is_empty());
    let old_title = content.find("//").map(|i| content[i + 2..].trim());
    if old_title.filter(|t| !t.is_empty()) != title {
        let keep = content
            .find("//")
            .map_or(content, |i| &content[..i])
            .trim_end();
        let from = line + keep.len();
        let new = title.map_or(String::new(), |t| format!(" // {t}"));
        edits.push(edit(from, end, new));
    }

    // The comment lines: from the line after the NETWORK line to the first instruction
    // (without one, past the comment lines), blank lines at its end kept.
    let from = line_end(text, header.start as usize);
    let to = match net.instructions.first() {
        Some(first) => line_start(text, first.span.start as usize),
        None => after_comment_lines(text, from),
    };
    let to = trim_blank_lines_back(text, from, to.max(from));
    let old: Vec<&str> = text[from..to]
        .lines()
        .filter_map(|l| l.trim().strip_prefix("//"))
        .map(str::trim)
        .collect();
    let new: Vec<&str> = comment.iter().map(|c| c.trim()).collect();
    if old != new {
        let indent = block_indentation(text, unit);
        let mut lines = String::new();
        if from == text.len() && !text.ends_with('\n') && !new.is_empty() {
            lines.push_str(eol);
        }
        for c in &new {
            lines.push_str(indent);
            lines.push_str(format!("// {c}").trim_end());
            lines.push_str(eol);
        }
        edits.push(edit(from, to, lines));
    }
    Ok(edits)
}

/// Replace a block's `TITLE=` value (`None` or blank: the TITLE line goes); a block
/// without one gets a `TITLE=` line right after its header line. A title that does not
/// change gives no edit.
pub fn set_block_title(
    text: &str,
    program: &Program,
    block: BlockRef<'_>,
    title: Option<&str>,
) -> Result<Vec<Edit>, EditError> {
    no_line_breaks(title.into_iter())?;
    let unit = find_block(text, program, block)?;
    let title = title.map(str::trim).filter(|t| !t.is_empty());
    let eol = line_ending(text, unit.header.span.start as usize);
    Ok(match (unit.title, title) {
        (Some(old), Some(new)) if &text[old.range()] == new => Vec::new(),
        (Some(old), Some(new)) => vec![edit(old.start as usize, old.end as usize, new.to_string())],
        (Some(old), None) => {
            let start = line_start(text, old.start as usize);
            vec![edit(start, line_end(text, start), String::new())]
        }
        (None, Some(new)) => {
            let at = line_end(text, unit.header.span.start as usize);
            let mut line = String::new();
            if at == text.len() && !text.ends_with('\n') {
                line.push_str(eol);
            }
            line.push_str(&format!("TITLE={new}{eol}"));
            vec![edit(at, at, line)]
        }
        (None, None) => Vec::new(),
    })
}

// ---- finding -----------------------------------------------------------------------

fn find<'p>(
    text: &str,
    program: &'p Program,
    at: NetworkRef<'_>,
) -> Result<(&'p Unit, &'p Network), EditError> {
    let unit = find_block(text, program, at.block)?;
    let net = unit
        .networks
        .get(at.network)
        .ok_or_else(|| EditError::NetworkNotFound {
            block: text[unit.header.name.range()].trim().to_string(),
            network: at.network,
            networks: unit.networks.len(),
        })?;
    Ok((unit, net))
}

fn find_block<'p>(
    text: &str,
    program: &'p Program,
    block: BlockRef<'_>,
) -> Result<&'p Unit, EditError> {
    Ok(match block {
        BlockRef::Index(i) => program
            .units
            .get(i)
            .ok_or_else(|| EditError::BlockNotFound(format!("at index {i}")))?,
        BlockRef::Name(name) => {
            let named =
                |header: &gutta_compiler::syntax::ast::BlockHeader| names_block(text, header, name);
            match program.units.iter().find(|u| named(&u.header)) {
                Some(u) => u,
                None if program.data_blocks.iter().any(|d| named(&d.header)) => {
                    return Err(EditError::NotAProgramBlock(name.to_string()))
                }
                None => return Err(EditError::BlockNotFound(name.to_string())),
            }
        }
    })
}

/// Whether `wanted` (`MAIN`, `OB1` or `MAIN:OB1`) names the block.
fn names_block(
    text: &str,
    header: &gutta_compiler::syntax::ast::BlockHeader,
    wanted: &str,
) -> bool {
    let name = text[header.name.range()].trim();
    let id = header.number.map(|(_, s)| text[s.range()].trim());
    let is = |a: &str, b: &str| a.eq_ignore_ascii_case(b.trim());
    match wanted.split_once(':') {
        Some((n, i)) => is(name, n) && id.is_some_and(|id| is(id, i)),
        None => is(name, wanted) || id.is_some_and(|id| is(id, wanted)),
    }
}

/// The number the checker gives network `index` of the unit (`Network::number_after`).
fn effective_number(unit: &Unit, index: usize) -> u32 {
    let mut last = None;
    let mut number = 0;
    for net in &unit.networks[..=index] {
        number = net.number_after(last);
        if net.header.is_some() {
            last = Some(number);
        }
    }
    number
}

/// New digits for the numbered networks from `from` on while they would not be above
/// the number before them (`previous`, the inserted network's).
fn renumber_following(text: &str, unit: &Unit, from: usize, previous: u32) -> Vec<Edit> {
    let mut edits = Vec::new();
    let mut previous = previous;
    for net in unit.networks.iter().skip(from) {
        match (net.number, net.header) {
            (Some(n), Some(header)) if n <= previous => {
                previous += 1;
                if let Some(digits) = number_digits(text, header) {
                    edits.push(edit(digits.0, digits.1, previous.to_string()));
                }
            }
            (Some(_), _) => break,
            (None, _) => previous += 1,
        }
    }
    edits
}

/// The byte range of the number on a NETWORK line.
fn number_digits(text: &str, header: Span) -> Option<(usize, usize)> {
    let line = &text[header.range()];
    let keyword_end = line.find(|c: char| c.is_whitespace())?;
    let rest = &line[keyword_end..];
    let first = keyword_end + rest.find(|c: char| c.is_ascii_digit())?;
    let len = line[first..]
        .find(|c: char| !(c.is_ascii_digit() || c == '_'))
        .unwrap_or(line.len() - first);
    let start = header.start as usize + first;
    Some((start, start + len))
}

/// A network's lines: from its NETWORK line (or first instruction) to the next
/// network's NETWORK line, else the block's END line, else its last instruction's line
/// end.
fn network_extent(text: &str, unit: &Unit, index: usize) -> Span {
    let net = &unit.networks[index];
    let start = line_start(text, net.span.start as usize);
    let end = match (unit.networks.get(index + 1), unit.end) {
        (Some(next), _) => line_start(text, next.span.start as usize),
        (None, Some(end)) => line_start(text, end.start as usize),
        (None, None) => line_end(
            text,
            net.instructions.last().map_or(net.span.end, |i| i.span.end) as usize,
        ),
    };
    Span::new(start, end.max(start))
}

// ---- lines -------------------------------------------------------------------------

/// One line of the text: its content and its line ending (`None` at the end of text).
struct Line<'t> {
    content: &'t str,
    ending: Option<&'t str>,
}

/// A network's instruction lines and, before each but the first, the comment and blank
/// lines between it and the previous one.
struct OldLines<'t> {
    instructions: Vec<Line<'t>>,
    /// `groups[i]`: the lines before instruction `i` after instruction `i - 1`
    /// (`groups[0]` is always empty).
    groups: Vec<Vec<Line<'t>>>,
}

fn old_lines<'t>(text: &'t str, net: &Network) -> OldLines<'t> {
    let mut instructions = Vec::with_capacity(net.instructions.len());
    let mut groups = Vec::with_capacity(net.instructions.len());
    let mut prev_end: Option<usize> = None;
    for ins in &net.instructions {
        let start = line_start(text, ins.span.start as usize);
        let mut group = Vec::new();
        if let Some(from) = prev_end {
            let mut at = from;
            while at < start {
                let line = line_at(text, at);
                at = line_end(text, at);
                group.push(line);
            }
        }
        groups.push(group);
        instructions.push(line_at(text, start));
        prev_end = Some(line_end(text, start));
    }
    OldLines {
        instructions,
        groups,
    }
}

fn line_at(text: &str, start: usize) -> Line<'_> {
    let end = content_end(text, start);
    let next = line_end(text, start);
    Line {
        content: &text[start..end],
        ending: (next > end).then(|| &text[end..next]),
    }
}

/// The start of the line holding `offset`.
fn line_start(text: &str, offset: usize) -> usize {
    text[..offset].rfind('\n').map_or(0, |i| i + 1)
}

/// After the line ending of the line holding `offset` (the end of text on the last line).
fn line_end(text: &str, offset: usize) -> usize {
    text[offset..]
        .find('\n')
        .map_or(text.len(), |i| offset + i + 1)
}

/// The end of the line's content, before its `\r\n` or `\n`.
fn content_end(text: &str, offset: usize) -> usize {
    let end = text[offset..].find('\n').map_or(text.len(), |i| offset + i);
    if end > offset && text.as_bytes()[end - 1] == b'\r' {
        end - 1
    } else {
        end
    }
}

/// The line ending of the line at `offset`, else the text's first, else `\n`.
fn line_ending(text: &str, offset: usize) -> &'static str {
    let crlf = |s: &str| s.find('\n').map(|i| i > 0 && s.as_bytes()[i - 1] == b'\r');
    match crlf(&text[line_start(text, offset)..]).or_else(|| crlf(text)) {
        Some(true) => "\r\n",
        _ => "\n",
    }
}

/// The blanks a line starts with.
fn indentation(line: &str) -> &str {
    &line[..line.len() - line.trim_start_matches([' ', '\t']).len()]
}

/// From a line start, past the lines that are only a comment.
fn after_comment_lines(text: &str, mut at: usize) -> usize {
    while at < text.len()
        && text[at..content_end(text, at)]
            .trim_start()
            .starts_with("//")
    {
        at = line_end(text, at);
    }
    at
}

/// From a line start `end`, back over whole blank lines, not before `floor`.
fn trim_blank_lines_back(text: &str, floor: usize, mut end: usize) -> usize {
    while end > floor {
        let start = line_start(text, end - 1);
        if start < floor || !text[start..end].trim().is_empty() {
            break;
        }
        end = start;
    }
    end
}

fn no_line_breaks<'l>(lines: impl Iterator<Item = &'l str>) -> Result<(), EditError> {
    for l in lines {
        if l.contains(['\n', '\r']) {
            return Err(EditError::LineBreak(l.to_string()));
        }
    }
    Ok(())
}

fn edit(start: usize, end: usize, text: String) -> Edit {
    Edit {
        span: Span::new(start, end),
        text,
    }
}
