//! Rename: symbols (also their cell in a symbol table), locals, blocks by their symbolic
//! name (uses by the numbered name `SBR0` stay as they are) and label numbers; edits in
//! every file of the program, as byte spans of the joined text. A new name is refused,
//! with the reason, when it is not a name, is reserved, reads as a direct address
//! (E0212's rule), reads as a numbered block name, or is taken. Plain data only.

use std::fmt;

use super::navigation;
use gutta_compiler::check::{reads_as_address, DefKind, Definition};
use gutta_compiler::source::Span;
use gutta_compiler::syntax::{is_reserved, table::is_word};
use gutta_compiler::CheckedFile;

/// Why a rename is refused.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum RenameError {
    /// Nothing renamable at the position (an address, a mnemonic, a keyword...).
    NothingHere,
    /// The cursor is on a fixed name (`MAIN`, a numbered name such as `SBR0`).
    Fixed(String),
    NotAName(String),
    Reserved(String),
    ReadsAsAddress(String),
    ReadsAsBlockNumber(String),
    /// The new name is already `kind` `name`.
    Taken {
        name: String,
        what: &'static str,
    },
    /// A label number outside the instruction's range.
    BadLabel(String),
}

impl fmt::Display for RenameError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RenameError::NothingHere => {
                write!(f, "only symbols, locals, blocks and labels can be renamed")
            }
            RenameError::Fixed(why) => write!(f, "{why}"),
            RenameError::NotAName(n) => write!(
                f,
                "`{n}` is not a name: a letter or `_`, then letters, digits and `_`"
            ),
            RenameError::Reserved(n) => write!(f, "`{n}` is a reserved word"),
            RenameError::ReadsAsAddress(n) => write!(
                f,
                "`{n}` reads as a direct address (area, width letter, digits): not allowed as a name (E0212)"
            ),
            RenameError::ReadsAsBlockNumber(n) => {
                write!(f, "`{n}` reads as a numbered block name (OB, INT, SBR, DAT and a number)")
            }
            RenameError::Taken { name, what } => write!(f, "`{name}` is already {what}"),
            RenameError::BadLabel(n) => write!(f, "`{n}` is not a label number 0..255"),
        }
    }
}

/// The span of the name under `offset` and its text, when it can be renamed.
pub fn prepare_rename(checked: &CheckedFile, offset: usize) -> Result<(Span, String), RenameError> {
    let (span, d) = renamed_at(checked, offset)?;
    let def = &checked.output.definitions[d];
    if matches!(def.kind, DefKind::Unit | DefKind::DataBlock) {
        fixed_block_name(checked, def, span)?;
    }
    let text = checked
        .file
        .text
        .get(span.range())
        .unwrap_or("")
        .to_string();
    Ok((span, text))
}

/// The edits that rename what is at `offset` to `new_name` (`#name` for a local is
/// accepted), in text order.
pub fn rename(
    checked: &CheckedFile,
    offset: usize,
    new_name: &str,
) -> Result<Vec<(Span, String)>, RenameError> {
    let (at, d) = renamed_at(checked, offset)?;
    let def = &checked.output.definitions[d];
    let name = match def.kind {
        DefKind::Local => new_name.strip_prefix('#').unwrap_or(new_name),
        _ => new_name,
    };
    match def.kind {
        DefKind::Label => check_label(checked, d, name)?,
        DefKind::Unit | DefKind::DataBlock => {
            fixed_block_name(checked, def, at)?;
            check_name(checked, d, name)?;
        }
        _ => check_name(checked, d, name)?,
    }
    let mut edits = definition_edits(checked, d, name.trim());
    edits.sort_by_key(|(s, _)| (s.start, s.end));
    edits.dedup();
    Ok(edits)
}

/// The definition named at `offset` (as navigation finds it: a use, `JMP n` of a
/// label included, or the definition itself) and the span of the name there.
fn renamed_at(checked: &CheckedFile, offset: usize) -> Result<(Span, usize), RenameError> {
    // On the `#` of a local: its name.
    let on_hash = checked
        .file
        .text
        .get(offset..)
        .is_some_and(|t| t.starts_with('#'));
    navigation::definition_at(checked, offset + usize::from(on_hash))
        .ok_or(RenameError::NothingHere)
}

/// A block is renamed by its symbolic name: not MAIN, not from a use of its number.
fn fixed_block_name(checked: &CheckedFile, def: &Definition, at: Span) -> Result<(), RenameError> {
    let written = checked.file.text.get(at.range()).unwrap_or("");
    if def.name.eq_ignore_ascii_case("MAIN") {
        return Err(RenameError::Fixed(
            "MAIN is the main program's fixed name".into(),
        ));
    }
    if block_number_shaped(written) && at != def.span {
        return Err(RenameError::Fixed(format!(
            "`{written}` is the block's numbered name; rename the block at its header"
        )));
    }
    Ok(())
}

/// `SBR0`, `INT3`, `OB1`, `DAT2`: a numbered block name.
fn block_number_shaped(name: &str) -> bool {
    let upper = name.to_ascii_uppercase();
    ["OB", "INT", "SBR", "DAT"].iter().any(|p| {
        upper
            .strip_prefix(p)
            .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
    })
}

/// The new name of definition `d` is allowed.
fn check_name(checked: &CheckedFile, d: usize, name: &str) -> Result<(), RenameError> {
    if !is_word(name) {
        return Err(RenameError::NotAName(name.into()));
    }
    if is_reserved(name) {
        return Err(RenameError::Reserved(name.into()));
    }
    let def = &checked.output.definitions[d];
    if def.kind != DefKind::Local && reads_as_address(&checked.target, name) {
        return Err(RenameError::ReadsAsAddress(name.into()));
    }
    if def.kind != DefKind::Local && block_number_shaped(name) {
        return Err(RenameError::ReadsAsBlockNumber(name.into()));
    }
    let global = |k: DefKind| matches!(k, DefKind::Symbol | DefKind::Unit | DefKind::DataBlock);
    let clash = checked
        .output
        .definitions
        .iter()
        .enumerate()
        .find(|(i, o)| {
            *i != d
                && o.name.eq_ignore_ascii_case(name)
                && if def.kind == DefKind::Local {
                    o.kind == DefKind::Local && o.unit == def.unit
                } else {
                    global(o.kind)
                }
        });
    if let Some((_, o)) = clash {
        let what = match o.kind {
            DefKind::Symbol => "a symbol",
            DefKind::Local => "a local of this block",
            DefKind::Unit => "a program block",
            DefKind::DataBlock => "a data block",
            DefKind::Label => "a label",
        };
        return Err(RenameError::Taken {
            name: o.name.clone(),
            what,
        });
    }
    Ok(())
}

/// The definition's name and every use of it, except uses by a block's numbered name;
/// a header that only has its numbered name gets the new name in front (`NEW:SBR0`).
fn definition_edits(checked: &CheckedFile, d: usize, name: &str) -> Vec<(Span, String)> {
    let out = &checked.output;
    let text = &checked.file.text;
    let def = &out.definitions[d];
    let block = matches!(def.kind, DefKind::Unit | DefKind::DataBlock);
    let mut edits = Vec::new();
    let written = text.get(def.span.range()).unwrap_or("");
    if block && block_number_shaped(written) {
        edits.push((def.span, format!("{name}:{written}")));
    } else {
        edits.push((def.span, name.to_string()));
    }
    for r in navigation::uses(checked)
        .iter()
        .filter(|r| r.definition == d)
    {
        let used = text.get(r.span.range()).unwrap_or("");
        if block && block_number_shaped(used) {
            continue;
        }
        edits.push((r.span, name.to_string()));
    }
    edits
}

/// A label's new number: a number 0..255 no other label of its block has.
fn check_label(checked: &CheckedFile, d: usize, new: &str) -> Result<(), RenameError> {
    let n = new
        .trim()
        .parse::<u16>()
        .ok()
        .filter(|n| *n <= 255)
        .ok_or_else(|| RenameError::BadLabel(new.into()))?;
    let defs = &checked.output.definitions;
    let name = format!("LBL {n}");
    let taken = defs.iter().enumerate().any(|(i, o)| {
        i != d && o.kind == DefKind::Label && o.unit == defs[d].unit && o.name == name
    });
    if taken {
        return Err(RenameError::Taken {
            name: n.to_string(),
            what: "a label of this block",
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use gutta_compiler::source::SourceFile;
    use gutta_compiler::{check_program, ProgramSources};

    const A: &str = "SYMBOLS\n  Start : I0.0 // go\nEND_SYMBOLS\n\
        ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD Start\nJMP 3\nCALL ADD3, MW0\n\
        CALL SBR0, MW0\nNETWORK 2\nLBL 3\nEND_ORGANIZATION_BLOCK\n";
    const B: &str = "SUBROUTINE_BLOCK ADD3:SBR0\nVAR_INPUT\n  a : INT;\nEND_VAR\nBEGIN\n\
        NETWORK 1\nLD Start\nMOVW #a, MW2\nEND_SUBROUTINE_BLOCK\n";
    const CSV: &str = "Symbol,Address,Comment\nLamp,Q0.0,lamp\n";

    fn program() -> CheckedFile {
        check_program(
            ProgramSources {
                sources: vec![SourceFile::new("a.lad", A), SourceFile::new("b.lad", B)],
                symbol_tables: vec![SourceFile::new("t.csv", CSV)],
                ..Default::default()
            },
            None,
        )
    }

    /// The text with the edits applied.
    fn apply(
        checked: &CheckedFile,
        at: &str,
        nth: usize,
        new: &str,
    ) -> Result<String, RenameError> {
        let text = &checked.file.text;
        let offset = text.match_indices(at).nth(nth).expect("the text").0;
        let mut out = text.clone();
        for (s, t) in rename(checked, offset, new)?.into_iter().rev() {
            out.replace_range(s.range(), &t);
        }
        Ok(out)
    }

    #[test]
    fn symbols_in_every_file() {
        let c = program();
        assert!(c.diagnostics().is_empty(), "{:?}", c.diagnostics());
        let out = apply(&c, "Start", 1, "Go").expect("renamed");
        assert_eq!(out.matches("Go").count(), 3, "{out}");
        assert!(!out.contains("Start"));
        assert_eq!(
            prepare_rename(&c, A.find("Start").unwrap()).map(|p| p.1),
            Ok("Start".into())
        );
    }

    #[test]
    fn refusals() {
        let c = program();
        let e = |at: &str, new: &str| apply(&c, at, 0, new).unwrap_err().to_string();
        assert!(e("Start", "Lamp").contains("already a symbol"));
        assert!(e("Start", "lamp").contains("already a symbol"));
        assert!(e("Start", "MW10").contains("direct address"));
        assert!(e("Start", "VB100").contains("direct address"));
        assert!(e("Start", "END_VAR").contains("reserved"));
        assert!(e("Start", "2x").contains("not a name"));
        assert!(e("Start", "ADD3").contains("program block"));
        assert!(e("Start", "SBR4").contains("numbered block"));
        assert!(e("MAIN", "M2").contains("fixed name"));
        assert!(e("SBR0, MW0", "X").contains("numbered name"));
        assert!(e("MOVW", "X").contains("only symbols"));
    }

    #[test]
    fn csv_cell_locals_blocks_labels() {
        let c = program();
        let out = apply(&c, "Lamp", 0, "Light").expect("renamed");
        assert!(out.contains("Light,Q0.0,lamp"));
        let out = apply(&c, "#a", 0, "#x").expect("renamed");
        assert!(
            out.contains("  x : INT;") && out.contains("MOVW #x, MW2"),
            "{out}"
        );
        let out = apply(&c, "ADD3", 0, "Sum").expect("renamed");
        assert!(out.contains("CALL Sum, MW0") && out.contains("CALL SBR0, MW0"));
        assert!(out.contains("SUBROUTINE_BLOCK Sum:SBR0"));
        let out = apply(&c, "3\n", 0, "7").expect("renamed");
        assert!(out.contains("JMP 7") && out.contains("LBL 7"));
        assert!(apply(&c, "3\n", 0, "300").is_err());
    }

    #[test]
    fn data_blocks_by_their_name() {
        let text =
            "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\nEND_ORGANIZATION_BLOCK\n\
            DATA_BLOCK Init:DAT0\n  MW0 INT 5\nEND_DATA_BLOCK\n";
        let c = gutta_compiler::check_source(SourceFile::new("t.lad", text), None);
        assert!(c.diagnostics().is_empty(), "{:?}", c.diagnostics());
        let out = apply(&c, "Init", 0, "Start_values").expect("renamed");
        assert!(out.contains("DATA_BLOCK Start_values:DAT0"));
        assert!(apply(&c, "Init", 0, "DAT3").is_err());
    }

    #[test]
    fn a_header_with_only_its_number_gets_a_name() {
        let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\nCALL SBR0\n\
            END_ORGANIZATION_BLOCK\nSUBROUTINE_BLOCK SBR0\nBEGIN\nNETWORK 1\nLD SM0.0\n\
            END_SUBROUTINE_BLOCK\n";
        let c = gutta_compiler::check_source(SourceFile::new("t.lad", text), None);
        let out = apply(&c, "SBR0\nBEGIN", 0, "Helper").expect("renamed");
        assert!(out.contains("SUBROUTINE_BLOCK Helper:SBR0") && out.contains("CALL SBR0"));
    }
}
