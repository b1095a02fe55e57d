//! Renders an [`InstructionSet`] as the Markdown instruction reference
//! (`docs/instructions.md`). Pure text, no I/O.

use std::fmt::Write;

use super::{cell, yes_no};
use crate::{BlockKind, Instruction, InstructionSet, OperandKind, OperandSpec};

/// The whole reference: a header, a table of contents by family, then one section per
/// instruction (mnemonic, opcode, flow and stack effect, operands, summary, description,
/// example). Families and instructions appear in opcode order.
pub fn instruction_reference(set: &InstructionSet) -> String {
    let families = families_in_opcode_order(set);
    let mut out = String::new();
    out.push_str("# GUTTA instruction reference\n\n");
    out.push_str(
        "<!-- Generated from stdlib/ManagerFun.xml by gutta_catalog::docs::instruction_reference.\n\
         Do not edit: run `UPDATE_DOCS=1 cargo test -p gutta-catalog --test instruction_set`. -->\n\n",
    );
    let _ = writeln!(
        out,
        "{} instructions in {} families. Logic stack: {} levels; subroutine calls nest {} deep; \
         `FOR` loops nest {} deep.",
        set.instructions.len(),
        families.len(),
        set.logic_stack_depth,
        set.call_depth,
        set.for_depth
    );
    out.push_str(
        "The file format and the meaning of every column are in \
         [instruction-schema.md](instruction-schema.md).\n\n",
    );
    out.push_str(
        "Operands are listed in STL source order. **Flow** says how an instruction uses the \
         logic stack: *Load* pushes, *Combine* changes the top, *Output* writes from the top, \
         *Box* runs only while the top is 1, *Always* runs regardless, *Stack* reads and \
         replaces the levels its stack effect gives, on every execution.\n\n",
    );

    out.push_str("## Contents\n\n| Family | Opcodes | Instructions |\n| --- | --- | --- |\n");
    for family in &families {
        let links: Vec<String> = family
            .members
            .iter()
            .map(|ins| format!("[`{}`](#{})", ins.mnemonic, instruction_anchor(ins)))
            .collect();
        let _ = writeln!(
            out,
            "| [{}](#{}) | {} | {} |",
            cell(&family.name),
            family_anchor(&family.name),
            family.opcode_ranges(),
            links.join(" ")
        );
    }

    for family in &families {
        let _ = write!(
            out,
            "\n<a id=\"{}\"></a>\n\n## {}\n",
            family_anchor(&family.name),
            family.name
        );
        for ins in &family.members {
            write_instruction(&mut out, ins);
        }
    }
    out
}

/// A family and its instructions, in opcode order.
struct Family<'a> {
    name: String,
    members: Vec<&'a Instruction>,
}

impl Family<'_> {
    /// The opcode high bytes the family uses, as `0x01xx`.
    fn opcode_ranges(&self) -> String {
        let mut highs: Vec<u16> = self.members.iter().map(|i| i.opcode >> 8).collect();
        highs.dedup();
        highs
            .iter()
            .map(|h| format!("`0x{h:02X}xx`"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

fn families_in_opcode_order(set: &InstructionSet) -> Vec<Family<'_>> {
    let mut sorted: Vec<&Instruction> = set.instructions.iter().collect();
    sorted.sort_by_key(|i| i.opcode);
    let mut families: Vec<Family<'_>> = Vec::new();
    for ins in sorted {
        match families.iter_mut().find(|f| f.name == ins.family) {
            Some(f) => f.members.push(ins),
            None => families.push(Family {
                name: ins.family.clone(),
                members: vec![ins],
            }),
        }
    }
    families
}

fn write_instruction(out: &mut String, ins: &Instruction) {
    let _ = write!(
        out,
        "\n<a id=\"{}\"></a>\n\n### `{}`\n\n{}\n\n",
        instruction_anchor(ins),
        ins.mnemonic,
        ins.summary
    );
    let _ = writeln!(
        out,
        "Opcode `0x{:04X}` · Flow **{}** · logic stack: needs {}, {}",
        ins.opcode,
        ins.flow.keyword(),
        ins.stack_needs,
        signed(ins.stack_delta)
    );
    let _ = writeln!(out, "\n{}", nature(ins));
    if ins.units != crate::UnitScope::ALL {
        let _ = writeln!(out, "\nOnly in: {}.", ins.units.describe());
    }
    if !ins.aliases.is_empty() {
        let names: Vec<String> = ins.aliases.iter().map(|a| format!("`{a}`")).collect();
        let _ = writeln!(out, "\nAliases: {}", names.join(", "));
    }
    out.push('\n');
    if ins.operands.is_empty() {
        out.push_str("No operands.\n");
    } else {
        out.push_str(
            "| Operand | Role | Kind | Types | Areas | Constant | Pointer | Notes |\n\
             | --- | --- | --- | --- | --- | --- | --- | --- |\n",
        );
        for op in &ins.operands {
            write_operand_row(out, op);
        }
    }
    if ins.call_arguments {
        out.push_str(
            "\nFurther operands are the arguments of the called unit, in its declared order.\n",
        );
    }
    if !ins.description.is_empty() {
        let _ = write!(out, "\n{}\n", ins.description);
    }
    if !ins.example.is_empty() {
        let _ = write!(out, "\n```stl\n{}\n```\n", ins.example);
    }
}

/// What the instruction is: its ladder element and what goes with it
/// (docs/instruction-schema.md, "What an instruction is").
fn nature(ins: &Instruction) -> String {
    let mut parts = vec![format!("Ladder **{}**", ins.ladder.keyword())];
    if let Some(logic) = ins.logic {
        parts.push(format!("joins with **{}**", logic.keyword()));
    }
    if let Some(op) = ins.compare {
        parts.push(format!("relation `{}`", op.symbol()));
    }
    if ins.immediate {
        parts.push("immediate".to_string());
    }
    if let Some(kind) = ins.kind {
        parts.push(format!("kind **{}**", kind.keyword()));
    }
    if !ins.power_inputs.is_empty() {
        let pins: Vec<String> = ins.power_inputs.iter().map(|p| format!("`{p}`")).collect();
        parts.push(format!("power inputs {}", pins.join(", ")));
        parts.push(match &ins.power_output {
            Some(o) => format!("power output `{o}`"),
            None => "no power output".to_string(),
        });
    }
    if let Some(role) = ins.loop_role {
        parts.push(format!("loop **{}**", role.keyword()));
    }
    parts.join(" · ")
}

fn write_operand_row(out: &mut String, op: &OperandSpec) {
    let kind = match op.kind {
        OperandKind::Data => "Data",
        OperandKind::Label => "Label",
        OperandKind::Block => "Block",
        OperandKind::Literal => "Literal",
    };
    let types = if op.types.is_empty() {
        "-".to_string()
    } else {
        op.types
            .iter()
            .map(|t| t.keyword())
            .collect::<Vec<_>>()
            .join(" ")
    };
    let data = op.kind == OperandKind::Data;
    let areas = match (&op.areas, data) {
        (Some(list), _) => list.join(" "),
        (None, true) => "any".to_string(),
        (None, false) => "-".to_string(),
    };
    let mut notes = Vec::new();
    if op.address_of {
        notes.push("`&` address-of allowed".to_string());
    }
    match (op.min, op.max) {
        (Some(lo), Some(hi)) => notes.push(format!("{lo}..{hi}")),
        (Some(lo), None) => notes.push(format!(">= {lo}")),
        (None, Some(hi)) => notes.push(format!("<= {hi}")),
        (None, None) => {}
    }
    match op.block {
        Some(BlockKind::Subroutine) => notes.push("a subroutine".to_string()),
        Some(BlockKind::Interrupt) => notes.push("an interrupt routine".to_string()),
        None => {}
    }
    let _ = writeln!(
        out,
        "| `{}` | {} | {} | {} | {} | {} | {} | {} |",
        op.name,
        op.role.keyword(),
        kind,
        types,
        areas,
        yes_no(op.constant),
        yes_no(op.pointer),
        cell(&notes.join("; "))
    );
}

fn signed(n: i8) -> String {
    if n > 0 {
        format!("+{n}")
    } else {
        n.to_string()
    }
}

/// Stable anchor of an instruction: its opcode (mnemonics like `LDB<>` make poor slugs).
fn instruction_anchor(ins: &Instruction) -> String {
    format!("op-{:04x}", ins.opcode)
}

fn family_anchor(name: &str) -> String {
    let slug: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect();
    format!("family-{slug}")
}
