//! Diagnostics for what S7-200 programs use and GUTTA lacks (issue 13): every S7-200-only
//! mnemonic of the catalog's table is E0220 on every target and never gets a
//! did-you-mean; every Micro/WIN system symbol is E0221; an undefined name is one
//! error however often it is used. docs/microwin.md lists every row of the table.

#![allow(
    clippy::disallowed_methods,
    reason = "tests read the docs they keep in sync"
)]

use gutta_catalog::s7200::{S7200_INSTRUCTIONS, S7200_SYSTEM_SYMBOLS, SCR_MNEMONICS};
use gutta_catalog::stdlib;
use gutta_compiler::diagnostics::{Code, Diagnostic};
use gutta_compiler::source::SourceFile;
use gutta_compiler::{check_source, ExplicitTarget};

fn diagnostics(text: String, plc: &str) -> Vec<Diagnostic> {
    let explicit = ExplicitTarget {
        target: stdlib::shared(plc).expect("stdlib target"),
        origin: format!("--plc {plc}"),
    };
    let checked = check_source(SourceFile::new("s7200.lad", text), Some(&explicit));
    checked.diagnostics().to_vec()
}

fn main_with(body: &str) -> String {
    format!(
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\n{body}\nEND_ORGANIZATION_BLOCK\n"
    )
}

#[test]
fn s7200_mnemonics_are_named_never_mistaken_for_another_instruction() {
    for plc in stdlib::names() {
        for ins in S7200_INSTRUCTIONS {
            let text = main_with(&format!("{} MB0", ins.mnemonic));
            let diags = diagnostics(text.clone(), plc);
            let line = format!("\n{} MB0", ins.mnemonic);
            let at = text.find(&line).expect("mnemonic in text") as u32 + 1;
            assert_eq!(diags.len(), 1, "{plc} {}: {diags:#?}", ins.mnemonic);
            let d = &diags[0];
            assert_eq!(d.code, Code::S7200Instruction, "{plc} {}", ins.mnemonic);
            assert_eq!(d.primary.span.start, at, "{}", ins.mnemonic);
            assert!(d.message.contains("S7-200"), "{}", d.message);
            assert!(d.fixes.is_empty(), "{}: {:?}", ins.mnemonic, d.fixes);
            let help = d.help.as_deref().unwrap_or("");
            assert!(!help.contains("did you mean"), "{}: {help}", ins.mnemonic);
            if let Some(alt) = ins.instead {
                assert!(help.contains(alt), "{}: {help}", ins.mnemonic);
            }
        }
    }
}

#[test]
fn micro_win_system_symbols_are_e0221_with_their_gutta_address() {
    for s in S7200_SYSTEM_SYMBOLS {
        let diags = diagnostics(main_with(&format!("MOVB {}, MB0", s.name)), stdlib::DEFAULT);
        assert_eq!(diags.len(), 1, "{}: {diags:#?}", s.name);
        assert_eq!(diags[0].code, Code::S7200Area, "{}", s.name);
        let help = diags[0].help.as_deref().unwrap_or("");
        // The target's data (its ManagerVar.xml `MicroWin` attribute) says which bit
        // the name stands for, else the S7-200 table's GUTTA address where the target
        // has it (`Scan_Time`, which the target names `Last_Scan_Time`); the help
        // declares it so.
        let target = stdlib::shared(stdlib::DEFAULT).expect("the default target");
        let here = target
            .memory
            .microwin_system_bit(s.name)
            .map(|b| b.address.clone())
            .or_else(|| {
                s.gutta_address
                    .filter(|a| target.memory.parse_address(a).is_ok())
                    .map(str::to_string)
            });
        match here {
            Some(a) => assert!(help.contains(&format!("{} : {a}", s.name)), "{help}"),
            None => assert!(help.contains(s.s7200_address), "{help}"),
        }
    }
}

#[test]
fn s_area_and_accumulators_say_the_area_is_missing() {
    let diags = diagnostics(main_with("= S0.0\nMOVW MW0, AC1"), stdlib::DEFAULT);
    let messages: Vec<&str> = diags.iter().map(|d| d.message.as_str()).collect();
    assert_eq!(diags.len(), 2, "{messages:?}");
    assert!(diags.iter().all(|d| d.code == Code::S7200Area));
    assert!(messages[0].contains("has no area S"), "{messages:?}");
    assert!(messages[1].contains("has no accumulators"), "{messages:?}");
}

#[test]
fn an_undefined_symbol_used_100_times_is_one_error_listing_the_others() {
    let mut body = String::from("= Q0.0\n");
    for i in 0..100 {
        body.push_str(&format!("NETWORK {}\nLD Motor_On\n= Q0.{}\n", i + 2, i % 8));
    }
    let text = main_with(&body);
    let diags = diagnostics(text.clone(), stdlib::DEFAULT);
    let errors: Vec<&Diagnostic> = diags.iter().filter(|d| d.is_error()).collect();
    assert_eq!(errors.len(), 1, "{errors:#?}");
    let d = errors[0];
    assert_eq!(d.code, Code::UndefinedSymbol);
    assert_eq!(
        d.primary.span.start as usize,
        text.find("Motor_On").expect("use")
    );
    assert!(d.message.contains("99 more times"), "{}", d.message);
    assert_eq!(d.secondary.len(), 5);
    let mut uses = text.match_indices("Motor_On").skip(1);
    for label in &d.secondary {
        assert_eq!(Some(label.span.start as usize), uses.next().map(|(i, _)| i));
        assert_eq!(label.message.as_deref(), Some("also used here"));
    }
}

#[test]
fn two_undefined_names_are_two_errors_and_a_single_use_has_no_count() {
    let diags = diagnostics(main_with("= Pump\nLD Valve\n= Pump"), stdlib::DEFAULT);
    assert_eq!(diags.len(), 2, "{diags:#?}");
    assert_eq!(
        diags[0].message,
        "undefined symbol `Pump` (also used 1 more time)"
    );
    assert_eq!(diags[1].message, "undefined symbol `Valve`");
    assert!(diags[1].secondary.is_empty());
}

#[test]
fn an_s7200_int0_collides_with_main_at_its_numbered_name() {
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD I0.0\n= Q0.0\nEND_ORGANIZATION_BLOCK\n\
                INTERRUPT_BLOCK INT_0:INT0\nBEGIN\nNETWORK 1\nLD SM0.0\nINCW MW0\nEND_INTERRUPT_BLOCK\n";
    let diags = diagnostics(text.to_string(), stdlib::DEFAULT);
    assert_eq!(diags.len(), 1, "{diags:#?}");
    let d = &diags[0];
    assert_eq!(d.code, Code::DuplicateBlock);
    let at = text.find(":INT0").expect("header") + 1;
    assert_eq!(d.primary.span.start as usize, at);
    assert_eq!(d.primary.span.end as usize, at + 4);
    assert!(d.message.contains("GUTTA's MAIN is INT0"), "{}", d.message);
    assert_eq!(
        d.secondary[0].span.start as usize,
        text.find("OB1").expect("OB1")
    );
}

#[test]
fn docs_list_every_row_of_the_s7200_table() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/microwin.md");
    let docs = std::fs::read_to_string(path).expect("docs/microwin.md");
    for ins in S7200_INSTRUCTIONS {
        let row = format!("| `{}` | {} |", ins.mnemonic, ins.what);
        if SCR_MNEMONICS.contains(&ins.mnemonic) {
            // Compiled in the dialect: "Sequence control relays", not the lacks table.
            assert!(!docs.contains(&row), "docs/microwin.md still lists {row}");
            assert!(docs.contains(&format!("`{}`", ins.mnemonic)));
            continue;
        }
        assert!(docs.contains(&row), "docs/microwin.md lacks {row}");
        if let Some(alt) = ins.instead {
            assert!(docs.contains(alt), "docs/microwin.md lacks {alt}");
        }
    }
    for s in S7200_SYSTEM_SYMBOLS {
        let row = format!(
            "| `{}` | {} | {} | {} |",
            s.name,
            s.s7200_address,
            s.gutta_address.unwrap_or("none"),
            s.what
        );
        assert!(docs.contains(&row), "docs/microwin.md lacks {row}");
    }
}
