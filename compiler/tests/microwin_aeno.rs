//! AENO and Micro/WIN's LAD temporaries L60-L63 (docs/microwin.md, "AENO" and "LAD
//! temporaries L60-L63"): what an AENO line compiles to and where, E0225's and E0226's
//! wording, the note naming the blocks, and GUTTA's own language, where AENO stays
//! E0220 and L60 stays E0306. The VM side is tests/data/run/microwin_aeno.lad and
//! microwin_ltemp.lad; the corpus tests/data/microwin/aeno_*.awl and ltemp_*.awl.

use gutta_catalog::stdlib;
use gutta_compiler::check::{CheckedOperand, CheckedUnit};
use gutta_compiler::diagnostics::Code;
use gutta_compiler::microwin::NoteKind;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{check_source, CheckedFile};

fn check(name: &str, text: &str) -> CheckedFile {
    check_source(SourceFile::new(name, text.to_string()), None)
}

fn main_with(body: &str) -> String {
    format!("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\n{body}\nEND_ORGANIZATION_BLOCK\n")
}

fn main_unit(c: &CheckedFile) -> &CheckedUnit {
    let program = c.output.program.as_ref().expect("a checked program");
    &program.units[0]
}

/// The mnemonic and operand addresses of each instruction whose span starts at `at`.
fn lines_at(c: &CheckedFile, at: usize) -> Vec<(String, Vec<String>)> {
    let set = &c.target.instructions;
    main_unit(c)
        .networks
        .iter()
        .flat_map(|n| &n.instructions)
        .filter(|i| i.span.start as usize == at)
        .map(|i| {
            let ops = i
                .operands
                .iter()
                .map(|o| match o {
                    CheckedOperand::Memory { address, .. } => {
                        c.target.memory.format_address(address)
                    }
                    other => format!("{other:?}"),
                })
                .collect();
            (set.get(i.id).mnemonic.clone(), ops)
        })
        .collect()
}

#[test]
fn aeno_after_a_division_is_an_of_its_two_flags_at_the_aeno_line() {
    let text = main_with("LD I0.0\n/I MW2, MW4\nAENO\nMOVW MW4, MW6\nAENO\n= Q0.0");
    let c = check("MAIN.awl", &text);
    assert!(!c.has_errors(), "{:#?}", c.diagnostics());
    let first = text.find("AENO").unwrap();
    assert_eq!(
        lines_at(&c, first),
        vec![
            ("AN".to_string(), vec!["SM1.1".to_string()]),
            ("AN".to_string(), vec!["SM1.3".to_string()]),
        ]
    );
    // After MOVW, which cannot fail: nothing.
    let second = text.rfind("AENO").unwrap();
    assert!(lines_at(&c, second).is_empty());
}

#[test]
fn e0225_says_why_the_eno_is_unknown() {
    let cases = [
        (
            "AENO\nLD I0.0\n= Q0.0",
            "`AENO` at the start of a network has no box before it",
        ),
        (
            "LD I0.0\nAENO\n= Q0.0",
            "`AENO` follows `LD`, which is no box with an ENO",
        ),
        (
            "LD I0.0\nJMP 1\nAENO\nLBL 1",
            "`AENO` follows `JMP`, which is a coil or jump in LAD",
        ),
        (
            "LD I0.0\nSHRB I0.1, M2.0, 8\nAENO",
            "`AENO` follows `SHRB`, whose S7-200 ENO is 0 on an illegal length",
        ),
        ("LD I0.0\nINCW MW0\nAENO MW2", "`AENO` takes no operand"),
    ];
    for (body, want) in cases {
        let text = main_with(body);
        let c = check("MAIN.awl", &text);
        let d: Vec<_> = c
            .diagnostics()
            .iter()
            .filter(|d| d.code == Code::S7200Aeno)
            .collect();
        assert_eq!(d.len(), 1, "{body}: {:#?}", c.diagnostics());
        assert!(d[0].message.starts_with(want), "{body}: {}", d[0].message);
        assert!(
            c.diagnostics().iter().all(|x| x.code == Code::S7200Aeno),
            "{body}: one mistake, one diagnostic: {:#?}",
            c.diagnostics()
        );
    }
}

#[test]
fn outside_the_dialect_aeno_stays_e0220_and_l60_stays_e0306() {
    let c = check("main.lad", &main_with("LD I0.0\nINCW MW0\nAENO\n= L60.0"));
    let codes: Vec<Code> = c.diagnostics().iter().map(|d| d.code).collect();
    assert_eq!(
        codes,
        vec![Code::S7200Instruction, Code::AddressOutOfTarget]
    );
    let help = c.diagnostics()[0].help.as_deref().unwrap_or("");
    assert!(help.contains("Micro/WIN export"), "{help}");
}

#[test]
fn l60_goes_to_the_last_bytes_of_l_and_the_note_says_so() {
    let text = main_with("LD I0.0\n= L60.0\nLD L60.0\n= Q0.0\nLD SM0.0\nMOVD MD0, LD60\nMOVW LW62, MW8\nMOVB LB63, MB10");
    let c = check("MAIN.awl", &text);
    assert!(!c.has_errors(), "{:#?}", c.diagnostics());
    let size = stdlib::shared(stdlib::DEFAULT)
        .unwrap()
        .memory
        .area("L")
        .unwrap()
        .size;
    let placed = |s: &str| lines_at(&c, text.find(s).unwrap());
    let base = size - 4;
    assert_eq!(placed("= L60.0")[0].1, vec![format!("L{base}.0")]);
    assert_eq!(placed("MOVD")[0].1[1], format!("LD{base}"));
    assert_eq!(placed("MOVW LW62")[0].1[0], format!("LW{}", base + 2));
    assert_eq!(placed("MOVB LB63")[0].1[0], format!("LB{}", base + 3));
    let notes = c.microwin_notes();
    let note = notes
        .iter()
        .find(|n| n.kind == NoteKind::LTemporaries)
        .expect("a note");
    assert_eq!(
        note.message,
        format!(
            "L60-L63 (Micro/WIN's LAD temporaries) in LB{base}-LB{} in MAIN",
            base + 3
        )
    );
}

#[test]
fn e0226_names_the_locals_that_take_the_bytes() {
    let mut locals = String::new();
    for i in 0..15 {
        locals.push_str(&format!("t{i}:INT;\n"));
    }
    let text = format!(
        "{}SUBROUTINE_BLOCK SBR_0:SBR0\nVAR\n{locals}END_VAR\nBEGIN\nNetwork 1\nLD I0.0\n= L61.2\nLD L61.2\n= Q0.1\nEND_SUBROUTINE_BLOCK\n",
        main_with("LD SM0.0\nCALL SBR_0")
    );
    let c = check("MAIN.awl", &text);
    let d: Vec<_> = c
        .diagnostics()
        .iter()
        .filter(|d| d.code == Code::S7200LTemporaries)
        .collect();
    assert_eq!(d.len(), 1, "{:#?}", c.diagnostics());
    let d = d[0];
    assert_eq!(d.primary.span.start as usize, text.find("L61.2").unwrap());
    assert!(
        d.message
            .contains("temporaries Micro/WIN uses for LAD networks converted to STL"),
        "{}",
        d.message
    );
    assert!(
        d.message.contains("SBR_0's locals take LB0-LB29"),
        "{}",
        d.message
    );
    assert_eq!(
        d.secondary[0].span.start as usize,
        text.find("t14:INT").unwrap()
    );
    assert!(d
        .help
        .as_deref()
        .unwrap_or("")
        .contains("fewer or smaller locals"));
    // MAIN does not use them: no note.
    assert!(c
        .microwin_notes()
        .iter()
        .all(|n| n.kind != NoteKind::LTemporaries));
}
