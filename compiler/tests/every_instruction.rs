//! Every instruction of the stdlib ManagerFun.xml encodes: its documented example,
//! placed in a program, compiles, and the image holds an instruction record with its
//! opcode. The catalog is walked, so a new instruction without a working example fails.

use gutta_catalog::stdlib;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};
use gutta_format::{decode_instructions, PageKind, Record};

/// A program around an instruction's example: MAIN holds it (or a subroutine or an
/// interrupt routine, where the instruction belongs there), plus what examples refer to:
/// the subroutine LED:SBR0 with one INT input, the interrupt routine TICK:INT1.
fn program_for(mnemonic: &str, example: &str, units: gutta_catalog::UnitScope) -> String {
    let body = if example.lines().next().is_some_and(|l| {
        let first = l
            .split_whitespace()
            .next()
            .unwrap_or("")
            .to_ascii_uppercase();
        first.starts_with("LD")
            || first == "LBL"
            || first == "NEXT"
            || first == "RET"
            || first == "RETI"
            || first == "NOP"
            || first == "ENI"
            || first == "DISI"
    }) {
        example.to_string()
    } else {
        format!("LD     SM0.0\n{example}")
    };
    let code = format!("NETWORK 1\n{body}\n");
    let _ = mnemonic;
    let (main, sbr, int) = if units.main {
        (
            code,
            "NETWORK 1\nLD SM0.0\nINCW MW100\n".to_string(),
            "NETWORK 1\nLD SM0.0\nINCW MW102\n".to_string(),
        )
    } else if units.subroutine {
        (
            "NETWORK 1\nLD SM0.0\nCALL LED, MW40\n".to_string(),
            code,
            "NETWORK 1\nLD SM0.0\nINCW MW102\n".to_string(),
        )
    } else {
        (
            "NETWORK 1\nLD SM0.0\nCALL LED, MW40\n".to_string(),
            "NETWORK 1\nLD SM0.0\nINCW MW100\n".to_string(),
            code,
        )
    };
    format!(
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n{main}END_ORGANIZATION_BLOCK\n\
         SUBROUTINE_BLOCK LED:SBR0\nVAR_INPUT\n  value : INT;\nEND_VAR\nBEGIN\n{sbr}END_SUBROUTINE_BLOCK\n\
         INTERRUPT_BLOCK TICK:INT1\nBEGIN\n{int}END_INTERRUPT_BLOCK\n"
    )
}

#[test]
fn every_instruction_encodes() {
    let target = stdlib::shared(stdlib::DEFAULT).expect("default target");
    let explicit = ExplicitTarget {
        target: target.clone(),
        origin: "test".into(),
    };
    let mut failures = Vec::new();
    for ins in &target.instructions.instructions {
        let text = program_for(&ins.mnemonic, &ins.example, ins.units);
        let compiled = compile(
            SourceFile::new(format!("{}.lad", ins.mnemonic), text.clone()),
            Some(&explicit),
        );
        let Some(image) = compiled.image else {
            let d: Vec<String> = compiled
                .checked
                .diagnostics()
                .iter()
                .filter(|d| d.is_error())
                .map(|d| format!("{} {}", d.code.as_str(), d.message))
                .collect();
            failures.push(format!("{}: does not compile: {d:?}\n{text}", ins.mnemonic));
            continue;
        };
        let found = image.pages.iter().filter(|(id, _)| id.kind == PageKind::Instruction).any(|(_, bytes)| {
            decode_instructions(bytes).is_ok_and(|recs| recs.iter().any(|(_, r)| matches!(r, Record::Instruction { opcode, .. } if *opcode == ins.opcode)))
        });
        if !found {
            failures.push(format!(
                "{}: opcode 0x{:04X} not in the image",
                ins.mnemonic, ins.opcode
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} instructions fail:\n{}",
        failures.len(),
        target.instructions.instructions.len(),
        failures.join("\n")
    );
}
