//! Advice for an export exported one block per file (docs/microwin.md, "One block per
//! file"): MicroWIN SMART writes the main program, each subroutine and each interrupt
//! routine to its own `.awl` file, and a program of only some of them lacks the rest.
//! E0408 (no MAIN) for files that hold one block each, and E0206 (no block named X) for
//! a `CALL` or `ATCH` of a name that looks like a block of another file (`SBR_1`,
//! `INT_0`, `子程序_2`, `SBR3`, a `NAME:SBRn` operand), say to pass the export's files
//! together, with the command. The checker gets the help texts as plain data
//! (`Conventions::missing_main_help`, `Conventions::block_elsewhere_help`).

use std::collections::HashMap;

use gutta_catalog::{rules, OperandKind as SpecKind, Target};

use crate::source::{PartKind, SourceFile, Span};
use crate::syntax::ast::{BlockPrefix, OperandKind, Prefix, Program};

/// The default names Micro/WIN and MicroWIN SMART give blocks, by UI language: a
/// prefix and the block's number (`SBR_0`, `中断程序_1`); `SBRn`/`INTn` are the
/// numbered names, and a `NAME:SBRn` operand names a block whatever NAME is.
const DEFAULT_BLOCK_PREFIXES: &[&str] = &["SBR_", "INT_", "SBR", "INT", "子程序_", "中断程序_"];

/// Whether `name` is a default block name: a prefix of [`DEFAULT_BLOCK_PREFIXES`] (ASCII
/// letters in any case) and a decimal number.
fn is_default_block_name(name: &str) -> bool {
    DEFAULT_BLOCK_PREFIXES.iter().any(|prefix| {
        name.get(..prefix.len())
            .is_some_and(|head| head.eq_ignore_ascii_case(prefix))
            && name[prefix.len()..].bytes().all(|b| b.is_ascii_digit())
            && name.len() > prefix.len()
    })
}

/// Whether the text after an operand is Micro/WIN's `:SBRn` / `:INTn` (the parser keeps
/// only the NAME of `NAME:SBRn`).
fn has_numbered_suffix(after: &str) -> bool {
    let Some(rest) = after.strip_prefix(':') else {
        return false;
    };
    let word: String = rest
        .chars()
        .take_while(|c| c.is_ascii_alphanumeric())
        .collect();
    is_default_block_name(&word)
}

/// The command that compiles the export's files together: the given sources, a
/// stand-in for the main program's file when none of them has one, `extra` (the file
/// a missing block is in, if it can be guessed) and `...`.
fn command(file: &SourceFile, main_missing: bool, extra: Option<String>) -> String {
    let mut words = vec!["gutta-cc".to_string()];
    if main_missing {
        words.push("MAIN.awl".to_string());
    }
    words.extend(
        file.parts()
            .into_iter()
            .filter(|p| p.kind == PartKind::Source)
            .map(|p| p.name),
    );
    words.extend(extra);
    words.push("...".to_string());
    words.join(" ")
}

/// E0408's help when the program's files hold one code block each and none is the main
/// program: the export's other files, the one with OB1 among them, belong with them.
/// None when some file holds several blocks (a whole export without OB1: the default
/// help applies).
pub(super) fn missing_main_help(program: &Program, file: &SourceFile) -> Option<String> {
    let sources: Vec<_> = file
        .parts()
        .into_iter()
        .filter(|p| p.kind == PartKind::Source)
        .collect();
    let blocks_in = |start: usize, end: usize| {
        program
            .units
            .iter()
            .filter(|u| (start..end).contains(&(u.header.span.start as usize)))
            .count()
    };
    let one_each =
        !program.units.is_empty() && sources.iter().all(|p| blocks_in(p.start, p.end) <= 1);
    one_each.then(|| {
        format!(
            "these files hold single blocks of a program exported one block per file; pass the export's files together, the one with `ORGANIZATION_BLOCK ...:OB1` among them: `{}` (an S7-200 INTERRUPT_BLOCK INTn is interrupt routine INT(n+1) here, never the main program)",
            command(file, true, None)
        )
    })
}

/// E0206's help for each block operand (`CALL SBR_1`, `ATCH INT_0:INT0, 10`) whose name
/// looks like a block of another file of the export, by the operand's span: the
/// checker uses it if no block of the program has that name.
pub(super) fn block_elsewhere_help(
    program: &Program,
    file: &SourceFile,
    target: &Target,
) -> HashMap<Span, String> {
    let text = &file.text;
    let set = &target.instructions;
    let has_main = program.units.iter().any(|u| {
        u.header.number.is_some_and(|(n, _)| {
            n.prefix == BlockPrefix::Ob || (n.prefix == BlockPrefix::Int && n.number == 0)
        })
    });
    let mut help = HashMap::new();
    for net in program.units.iter().flat_map(|u| &u.networks) {
        for ins in &net.instructions {
            let Some(id) = set.lookup(text.get(ins.mnemonic.range()).unwrap_or("")) else {
                continue;
            };
            let spec = set.get(id);
            for (op, os) in net.operands_of(ins).iter().zip(&spec.operands) {
                if os.kind != SpecKind::Block {
                    continue;
                }
                let OperandKind::Name {
                    prefix: Prefix::None,
                    local: false,
                    name,
                } = op.kind
                else {
                    continue;
                };
                let written = text.get(name.range()).unwrap_or("");
                let after = text.get(name.end as usize..).unwrap_or("");
                if !is_default_block_name(written) && !has_numbered_suffix(after) {
                    continue;
                }
                let what = match rules::unit_operand_kind(os) {
                    gutta_catalog::BlockKind::Subroutine => "subroutine",
                    gutta_catalog::BlockKind::Interrupt => "interrupt routine",
                };
                help.insert(
                    name,
                    format!(
                        "`{written}` looks like a {what} of another file of an export written one block per file; pass the export's files together: `{}`",
                        command(file, !has_main, Some(format!("{written}.awl")))
                    ),
                );
            }
        }
    }
    help
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_block_names_in_every_ui_language() {
        for name in [
            "SBR_0",
            "sbr_12",
            "INT_3",
            "SBR1",
            "int0",
            "子程序_2",
            "中断程序_0",
        ] {
            assert!(is_default_block_name(name), "{name}");
        }
        for name in ["SBR_", "Motor", "SBR_1a", "子程序", "MAIN"] {
            assert!(!is_default_block_name(name), "{name}");
        }
        assert!(has_numbered_suffix(":SBR3, 1"));
        assert!(has_numbered_suffix(":INT0"));
        assert!(!has_numbered_suffix(", 10"));
    }
}
