//! Code actions: the quick fixes of the diagnostics in a range. Each fix a diagnostic
//! carries (did-you-mean replacements, a missing END_ line, E0302's address of the
//! right width) is one action; an undefined symbol also gets "declare it", which
//! inserts `Name : ADDRESS` into the file's SYMBOLS block (or creates the block), the
//! address a free one of the width and area the use needs (`free_address.rs`), or a
//! placeholder where the use says nothing. An action is preferred when it is its
//! diagnostic's only one. Plain data; nothing is applied here.

use gutta_compiler::diagnostics::{Code, Diagnostic};
use gutta_compiler::source::{PartKind, Span};
use gutta_compiler::CheckedFile;

/// One quick fix.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CodeAction {
    pub title: String,
    /// Index into the checked file's diagnostics.
    pub diagnostic: usize,
    /// Byte spans of the joined text and their replacements, in text order.
    pub edits: Vec<(Span, String)>,
    pub preferred: bool,
}

/// The text a declared symbol's address is left as.
pub const ADDRESS_PLACEHOLDER: &str = "// TODO: address";

/// Quick fixes of the diagnostics whose primary span meets `range`.
pub fn code_actions(checked: &CheckedFile, range: Span) -> Vec<CodeAction> {
    let mut actions = Vec::new();
    for (i, d) in checked.diagnostics().iter().enumerate() {
        let span = d.primary.span;
        if span.start > range.end || span.end < range.start {
            continue;
        }
        let first = actions.len();
        for fix in &d.fixes {
            let mut edits = fix.edits.clone();
            edits.sort_by_key(|(s, _)| (s.start, s.end));
            actions.push(CodeAction {
                title: fix.title.clone(),
                diagnostic: i,
                edits,
                preferred: false,
            });
        }
        if d.code == Code::UndefinedSymbol {
            actions.extend(declare_symbol(checked, d, i));
        }
        if actions.len() == first + 1 {
            actions[first].preferred = true;
        }
    }
    actions
}

/// `Name : M0.0` (a free address the use takes, else `// TODO: address`) at the end of
/// the last SYMBOLS block of the diagnostic's file (of any source file when it has
/// none), or a new block at the file's top.
fn declare_symbol(checked: &CheckedFile, d: &Diagnostic, index: usize) -> Option<CodeAction> {
    let text = &checked.file.text;
    let name = text.get(d.primary.span.range())?;
    let free = crate::free_address::for_use(checked, d.primary.span);
    let address = free.as_deref().unwrap_or(ADDRESS_PLACEHOLDER);
    let file = &checked.file;
    let parts = file.parts();
    let own = file.part_index(d.primary.span.start as usize);
    let in_source = |s: Span| parts[file.part_index(s.start as usize)].kind == PartKind::Source;
    let decls = checked.ast.symbols.iter().filter(|s| in_source(s.name));
    let last = decls
        .clone()
        .rfind(|s| file.part_index(s.name.start as usize) == own)
        .or_else(|| decls.clone().next_back());
    let edit = match last {
        Some(decl) => {
            let line_start = text[..decl.name.start as usize]
                .rfind('\n')
                .map_or(0, |i| i + 1);
            let indent = &text[line_start..decl.name.start as usize];
            let after = text[decl.name.end as usize..]
                .find('\n')
                .map_or(text.len(), |i| decl.name.end as usize + i + 1);
            let prefix = if after == text.len() && !text.ends_with('\n') {
                "\n"
            } else {
                ""
            };
            (
                Span::new(after, after),
                format!("{prefix}{indent}{name} : {address}\n"),
            )
        }
        None => {
            let part = &parts[own];
            let at = block_insertion_point(&text[part.start..part.end]) + part.start;
            (
                Span::new(at, at),
                format!("SYMBOLS\n  {name} : {address}\nEND_SYMBOLS\n\n"),
            )
        }
    };
    let title = match &free {
        Some(a) => format!("Declare symbol `{name}` as {a} in SYMBOLS"),
        None => format!("Declare symbol `{name}` in SYMBOLS"),
    };
    Some(CodeAction {
        title,
        diagnostic: index,
        edits: vec![edit],
        preferred: false,
    })
}

/// Where a new block goes in a file: after a leading `PLC_TYPE` line, else before the
/// first line that is not blank or a comment.
fn block_insertion_point(file: &str) -> usize {
    let mut at = 0;
    for line in file.split_inclusive('\n') {
        let t = line.trim();
        if t.is_empty() || t.starts_with("//") {
            at += line.len();
            continue;
        }
        let first = t.split_whitespace().next().unwrap_or("");
        if first.eq_ignore_ascii_case("PLC_TYPE") {
            return at + line.len();
        }
        return at;
    }
    at
}

#[cfg(test)]
mod tests {
    use super::*;
    use gutta_compiler::source::SourceFile;

    fn fixed(text: &str, at: &str, title: &str) -> String {
        let c = gutta_compiler::check_source(SourceFile::new("t.lad", text), None);
        let offset = text.find(at).expect("the text");
        let actions = code_actions(&c, Span::new(offset, offset));
        let a = actions
            .iter()
            .find(|a| a.title.starts_with(title))
            .unwrap_or_else(|| panic!("no `{title}` in {actions:?}"));
        let mut out = text.to_string();
        for (s, t) in a.edits.iter().rev() {
            out.replace_range(s.range(), t);
        }
        out
    }

    const MAIN: &str = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\n";

    #[test]
    fn did_you_mean_replaces() {
        let out = fixed(
            &format!("{MAIN}LD I0.0\nMOWV MW0, MW2\nEND_ORGANIZATION_BLOCK\n"),
            "MOWV",
            "Replace",
        );
        assert!(out.contains("MOVW MW0, MW2"), "{out}");
        let text = format!("SYMBOLS\n  Start : I0.0\nEND_SYMBOLS\n{MAIN}LD Strat\n= Q0.0\nEND_ORGANIZATION_BLOCK\n");
        let c = gutta_compiler::check_source(SourceFile::new("t.lad", text.as_str()), None);
        let at = text.find("Strat").unwrap();
        let actions = code_actions(&c, Span::new(at, at + 2));
        assert_eq!(actions.len(), 2, "{actions:?}");
        assert!(actions.iter().all(|a| !a.preferred));
        let out = fixed(&text, "Strat", "Replace with `Start`");
        assert!(out.contains("LD Start"));
    }

    #[test]
    fn declare_into_symbols_or_a_new_block() {
        let text = format!(
            "SYMBOLS\n    Start : I0.0 // go\nEND_SYMBOLS\n{MAIN}LD Pump\nEND_ORGANIZATION_BLOCK\n"
        );
        let out = fixed(&text, "Pump", "Declare symbol `Pump` as M0.0");
        assert!(out.contains("// go\n    Pump : M0.0\nEND_SYMBOLS"), "{out}");
        let text = format!("// header\nPLC_TYPE CPU-EC20\n{MAIN}LD Pump\nEND_ORGANIZATION_BLOCK\n");
        let out = fixed(&text, "Pump", "Declare");
        assert!(
            out.starts_with("// header\nPLC_TYPE CPU-EC20\nSYMBOLS\n  Pump : M0.0\nEND_SYMBOLS\n\nORGANIZATION_BLOCK"),
            "{out}"
        );
        let c = gutta_compiler::check_source(SourceFile::new("t.lad", text.as_str()), None);
        let at = text.find("Pump").unwrap();
        assert!(code_actions(&c, Span::new(at, at))[0].preferred);
    }

    #[test]
    fn a_declared_symbol_gets_a_free_address_of_its_width_or_a_placeholder() {
        let text = format!(
            "SYMBOLS\n  Start : M0.0\nEND_SYMBOLS\n{MAIN}LD Start\n= M0.1\nMOVW MW0, Speed\nCALL S, Arg\nEND_ORGANIZATION_BLOCK\n\
             SUBROUTINE_BLOCK S:SBR0\nVAR_INPUT\n  a : INT;\nEND_VAR\nBEGIN\nNETWORK 1\nLD SM0.0\nEND_SUBROUTINE_BLOCK\n"
        );
        let out = fixed(&text, "Speed", "Declare symbol `Speed` as MW2");
        assert!(
            out.contains("  Start : M0.0\n  Speed : MW2\nEND_SYMBOLS"),
            "{out}"
        );
        let out = fixed(&text, "Arg", "Declare symbol `Arg` in SYMBOLS");
        assert!(out.contains("  Arg : // TODO: address\n"), "{out}");
    }

    #[test]
    fn a_width_mismatch_becomes_the_address_of_the_width_at_the_same_byte() {
        let text = format!(
            "{MAIN}LD I0.0\nMOVW MB4, MW2\nINCD MW8\nMOVW M0.0, MW6\nEND_ORGANIZATION_BLOCK\n"
        );
        let out = fixed(
            &text,
            "MB4",
            "Replace `MB4` with `MW4` (the word at the same byte)",
        );
        assert!(out.contains("MOVW MW4, MW2"), "{out}");
        let out = fixed(&text, "MW8", "Replace `MW8` with `MD8`");
        assert!(out.contains("INCD MD8"), "{out}");
        // A bit: which word was meant is not known; no fix.
        let c = gutta_compiler::check_source(SourceFile::new("t.lad", text.as_str()), None);
        let at = text.find("M0.0").expect("M0.0");
        assert!(code_actions(&c, Span::new(at, at)).is_empty());
    }

    #[test]
    fn missing_end_lines() {
        let out = fixed(
            &format!("{MAIN}LD I0.0\n= Q0.0\n"),
            "ORGANIZATION_BLOCK",
            "Add",
        );
        assert!(out.ends_with("= Q0.0\nEND_ORGANIZATION_BLOCK\n"), "{out}");
        let text =
            format!("{MAIN}LD I0.0\n= Q0.0\nSUBROUTINE_BLOCK S\nBEGIN\nEND_SUBROUTINE_BLOCK");
        let out = fixed(&text, "ORGANIZATION_BLOCK", "Add");
        assert!(
            out.contains("= Q0.0\nEND_ORGANIZATION_BLOCK\nSUBROUTINE_BLOCK"),
            "{out}"
        );
        let out = fixed(
            "SUBROUTINE_BLOCK S\nVAR\n a : INT;\nBEGIN\nEND_SUBROUTINE_BLOCK\n",
            "VAR",
            "Add",
        );
        assert!(out.contains(" a : INT;\nEND_VAR\nBEGIN"), "{out}");
    }
}
