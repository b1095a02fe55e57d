//! The checker applies the rules of `gutta_catalog::rules`, the ones the verifier
//! applies too: operand names such as PORT and EVNT compare case-insensitively, and an
//! in-out or output parameter never takes `&` (a pointer value is only read).

use std::sync::Arc;

use gutta_catalog::{stdlib, Target, TargetSources};
use gutta_compiler::diagnostics::Code;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{check_source, ExplicitTarget};

/// The default target with its ManagerFun.xml edited.
fn target_with_manager_fun(edit: impl Fn(&str) -> String) -> ExplicitTarget {
    let (_, plc_type, manager_var) = stdlib::TARGETS[0];
    let text = std::str::from_utf8(stdlib::MANAGER_FUN).expect("UTF-8");
    let manager_fun = edit(text);
    let target = Target::load(TargetSources {
        plc_type,
        manager_var,
        manager_fun: manager_fun.as_bytes(),
    })
    .expect("the edited target loads");
    ExplicitTarget {
        target: Arc::new(target),
        origin: "an edited ManagerFun.xml".to_string(),
    }
}

/// The codes of a program's diagnostics on a target.
fn codes(source: &str, target: &ExplicitTarget) -> Vec<Code> {
    let file = SourceFile::new("rules.lad", source);
    check_source(file, Some(target))
        .diagnostics()
        .iter()
        .map(|d| d.code)
        .collect()
}

const MAIN_WITH: &str = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\n";

fn program(lines: &str) -> String {
    format!(
        "{MAIN_WITH}{lines}END_ORGANIZATION_BLOCK\n\
         INTERRUPT_BLOCK TICK:INT1\nBEGIN\nNETWORK 1\nLD SM0.0\n=  Q0.0\nEND_INTERRUPT_BLOCK\n"
    )
}

#[test]
fn port_and_evnt_compare_case_insensitively() {
    for (from, to) in [("PORT", "PORT"), ("PORT", "port"), ("EVNT", "Evnt")] {
        let target = target_with_manager_fun(|text| {
            text.replace(&format!(r#"Name="{from}""#), &format!(r#"Name="{to}""#))
        });
        // CPU-EC20 has one serial port (PORT 0) and no event 9.
        assert_eq!(codes(&program("EXCH MB20, 0\n"), &target), [], "{to}");
        assert_eq!(
            codes(&program("EXCH MB20, 1\n"), &target),
            [Code::ConstantOutOfRange],
            "{to}"
        );
        assert_eq!(codes(&program("ATCH TICK, 10\n"), &target), [], "{to}");
        assert_eq!(
            codes(&program("ATCH TICK, 9\n"), &target),
            [Code::ConstantOutOfRange],
            "{to}"
        );
    }
}

#[test]
fn only_an_input_parameter_takes_an_address() {
    let target = ExplicitTarget {
        target: stdlib::shared(stdlib::DEFAULT).expect("default target"),
        origin: "--plc CPU-EC20".to_string(),
    };
    let source = |section: &str, argument: &str| {
        format!(
            "{MAIN_WITH}CALL GET, {argument}\nEND_ORGANIZATION_BLOCK\n\
             SUBROUTINE_BLOCK GET:SBR0\n{section}\n  p : DWORD;\nEND_VAR\nBEGIN\n\
             NETWORK 1\nLD SM0.0\nMOVD MD0, #p\nEND_SUBROUTINE_BLOCK\n"
        )
    };
    assert_eq!(codes(&source("VAR_OUTPUT", "MD4"), &target), []);
    assert_eq!(
        codes(&source("VAR_OUTPUT", "&MB24"), &target),
        [Code::UseNotAllowed]
    );
    assert_eq!(
        codes(&source("VAR_IN_OUT", "&MB24"), &target),
        [Code::UseNotAllowed]
    );
    assert_eq!(codes(&source("VAR_INPUT", "&MB24"), &target), []);
}
