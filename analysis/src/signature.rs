//! Signature help: the instruction whose operands the cursor is in, its operands with
//! role and allowed types, and the active one by comma position. A `CALL` shows the
//! called subroutine's parameters after its block operand. Plain data; no LSP types.

use gutta_catalog::rules::parameter_spec;
use gutta_catalog::{Instruction, OperandKind, OperandSpec, Role};

use super::place::{cursor_at, Place};
use gutta_compiler::syntax::ast::VarSection;
use gutta_compiler::CheckedFile;

/// One operand of a signature: its byte range in the signature's label, and a line
/// saying what it takes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SignatureParameter {
    pub label: (usize, usize),
    pub documentation: String,
}

/// An instruction's signature: `MOVW IN: WORD|INT|UINT, OUT: WORD|INT|UINT`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Signature {
    pub label: String,
    pub documentation: String,
    pub parameters: Vec<SignatureParameter>,
    /// The operand the cursor is in (none past the last one).
    pub active: Option<usize>,
}

/// Signature help at `offset`: only in an instruction's operands.
pub fn signature_help(checked: &CheckedFile, offset: usize) -> Option<Signature> {
    let cursor = cursor_at(checked, offset);
    let Place::Operand { mnemonic, index } = cursor.place else {
        return None;
    };
    let (ins, specs) = operand_specs(checked, mnemonic, offset)?;
    let mut label = ins.mnemonic.clone();
    let mut parameters = Vec::new();
    for (i, spec) in specs.iter().enumerate() {
        label.push_str(if i == 0 { " " } else { ", " });
        let start = label.len();
        label.push_str(&operand_label(spec));
        parameters.push(SignatureParameter {
            label: (start, label.len()),
            documentation: operand_documentation(checked, spec),
        });
    }
    Some(Signature {
        label,
        documentation: ins.summary.clone(),
        active: (index < parameters.len()).then_some(index),
        parameters,
    })
}

/// The instruction named by the mnemonic at `mnemonic` and its operands: the declared
/// ones, then for `CALL` the parameters of the subroutine its first operand names (on
/// the line that holds `offset`).
pub(super) fn operand_specs(
    checked: &CheckedFile,
    mnemonic: gutta_compiler::source::Span,
    offset: usize,
) -> Option<(&Instruction, Vec<OperandSpec>)> {
    let text = &checked.file.text;
    let set = &checked.target.instructions;
    let ins = set.get(set.lookup(text.get(mnemonic.range())?)?);
    let mut specs = ins.operands.clone();
    if ins.call_arguments {
        let line_end = text[offset..].find('\n').map_or(text.len(), |i| offset + i);
        let operands = text.get(mnemonic.end as usize..line_end)?;
        let operands = operands.split("//").next().unwrap_or("");
        let block = operands.split(',').next().unwrap_or("").trim();
        if let Some(unit) = unit_named(checked, block) {
            specs.extend(parameters(checked, unit));
        }
    }
    Some((ins, specs))
}

/// The unit (index into `ast.units`) a block operand names, by either of its names.
pub(super) fn unit_named(checked: &CheckedFile, name: &str) -> Option<usize> {
    if name.is_empty() {
        return None;
    }
    let text = &checked.file.text;
    checked.ast.units.iter().position(|u| {
        let own = text.get(u.header.name.range()).unwrap_or("");
        let numbered = u
            .header
            .number
            .and_then(|(_, s)| text.get(s.range()))
            .unwrap_or("");
        own.eq_ignore_ascii_case(name) || numbered.eq_ignore_ascii_case(name)
    })
}

/// A subroutine's parameters as operand specs, in argument order (VAR_INPUT,
/// VAR_IN_OUT, VAR_OUTPUT, each as declared).
fn parameters(checked: &CheckedFile, unit: usize) -> Vec<OperandSpec> {
    let text = &checked.file.text;
    let mut vars: Vec<_> = checked.ast.units[unit]
        .vars
        .iter()
        .filter(|v| v.section != VarSection::Temp)
        .collect();
    vars.sort_by_key(|v| v.section);
    vars.iter()
        .filter_map(|v| {
            let ty = text.get(v.ty.range())?.parse().ok()?;
            let role = match v.section {
                VarSection::Input => Role::In,
                VarSection::InOut => Role::InOut,
                _ => Role::Out,
            };
            let name = format!("#{}", text.get(v.name.range())?);
            Some(parameter_spec(name, role, ty))
        })
        .collect()
}

/// A subroutine's parameters as `#a: INT`, in argument order.
pub(super) fn parameter_labels(checked: &CheckedFile, unit: usize) -> Vec<String> {
    parameters(checked, unit)
        .iter()
        .map(operand_label)
        .collect()
}

/// `IN: WORD|INT`, `N: label`, `SBR: subroutine`, `EVNT: 0..255`.
fn operand_label(spec: &OperandSpec) -> String {
    let what = match spec.kind {
        OperandKind::Data => spec
            .types
            .iter()
            .map(|t| t.keyword())
            .collect::<Vec<_>>()
            .join("|"),
        OperandKind::Label => "label".to_string(),
        OperandKind::Block => match spec.block {
            Some(gutta_catalog::BlockKind::Interrupt) => "interrupt routine".to_string(),
            _ => "subroutine".to_string(),
        },
        OperandKind::Literal => "literal".to_string(),
    };
    format!("{}: {what}", spec.name)
}

/// The role, then what may stand in the operand.
fn operand_documentation(checked: &CheckedFile, spec: &OperandSpec) -> String {
    let role = match spec.role {
        Role::In => "IN",
        Role::Out => "OUT",
        Role::InOut => "IN_OUT",
    };
    let memory = &checked.target.memory;
    let what = match spec.kind {
        OperandKind::Data => {
            let mut parts = vec![match &spec.areas {
                Some(list) => format!("areas {}", list.join(", ")),
                None => "any area of its width".to_string(),
            }];
            if spec.constant {
                parts.push("a constant".into());
            }
            if spec.pointer {
                parts.push("`*pointer`".into());
            }
            if spec.address_of {
                parts.push("`&address`".into());
            }
            parts.join(", ")
        }
        OperandKind::Label => {
            let r = gutta_catalog::rules::label_range(spec);
            format!("a label number {}..{}", r.start(), r.end())
        }
        OperandKind::Block => "a block name".to_string(),
        OperandKind::Literal => {
            let r = gutta_catalog::rules::literal_range(spec, memory);
            format!("a number {}..{}", r.start(), r.end())
        }
    };
    format!("{role}: {what}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use gutta_compiler::source::SourceFile;

    fn help(body: &str) -> Option<Signature> {
        let text = format!(
            "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\n{body}\nEND_ORGANIZATION_BLOCK\n\
             SUBROUTINE_BLOCK ADD3:SBR0\nVAR\n t : INT;\nEND_VAR\nVAR_OUTPUT\n r : INT;\nEND_VAR\n\
             VAR_INPUT\n a : INT;\nEND_VAR\nBEGIN\nNETWORK 1\nLD SM0.0\nEND_SUBROUTINE_BLOCK\n"
        );
        let offset = text.find('|').expect("a cursor");
        let text = text.replacen('|', "", 1);
        let checked = gutta_compiler::check_source(SourceFile::new("t.lad", text), None);
        signature_help(&checked, offset)
    }

    #[test]
    fn active_operand_by_commas() {
        let s = help("MOVW MW0, |").expect("a signature");
        assert!(s.label.starts_with("MOVW IN: "), "{}", s.label);
        assert_eq!(s.active, Some(1));
        let (a, b) = s.parameters[1].label;
        assert!(s.label[a..b].starts_with("OUT: "));
        assert!(s.parameters[1].documentation.starts_with("OUT: "));
        assert_eq!(help("movw |").map(|s| s.active), Some(Some(0)));
        assert_eq!(help("MOVW MW0, MW2, |").map(|s| s.active), Some(None));
        assert_eq!(help("MOVW| MW0"), None);
        assert_eq!(help("XYZ |"), None);
    }

    #[test]
    fn call_shows_the_parameters() {
        let s = help("CALL ADD3, MW0, |").expect("a signature");
        assert_eq!(s.label, "CALL SBR: subroutine, #a: INT, #r: INT");
        assert_eq!(s.active, Some(2));
        assert!(s.parameters[2].documentation.starts_with("OUT"));
        let s = help("CALL sbr0, |").expect("a signature");
        assert_eq!(s.parameters.len(), 3);
    }
}
