//! `gutta-cc explain` covers every code the tools print: each code of each registry
//! (the compiler's E and W, the verifier's V, the target files' T) explains with exit
//! status 0 and its registry's text; a V code adds its docs/image-format.md row;
//! an unknown code is exit 2 with a did-you-mean.

use std::process::{Command, Output};

use gutta_catalog::CatalogErrorCode;
use gutta_compiler::diagnostics::Code;
use gutta_format::VerifyCode;

fn explain(code: &str) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gutta-cc"))
        .args(["explain", code])
        .output()
        .expect("gutta-cc runs")
}

/// `explain code` succeeds and prints `code` and `text` (a registry's summary).
fn assert_explains(code: &str, text: &str, failures: &mut Vec<String>) {
    let out = explain(code);
    let stdout = String::from_utf8_lossy(&out.stdout);
    if out.status.code() != Some(0) || !stdout.starts_with(code) || !stdout.contains(text) {
        failures.push(format!(
            "{code}: {:?}\n{stdout}{}",
            out.status.code(),
            String::from_utf8_lossy(&out.stderr)
        ));
    }
}

#[test]
fn every_code_of_every_registry_explains() {
    let mut failures = Vec::new();
    for c in Code::ALL {
        assert_explains(c.as_str(), c.title(), &mut failures);
    }
    for v in VerifyCode::ALL {
        assert_explains(v.as_str(), v.summary(), &mut failures);
    }
    for t in CatalogErrorCode::ALL {
        assert_explains(t.as_str(), t.summary(), &mut failures);
    }
    for p in gutta_io::PlantErrorCode::ALL {
        assert_explains(p.as_str(), p.summary(), &mut failures);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn a_v_code_shows_its_meaning_from_the_image_format_doc() {
    let out = explain("v0040");
    assert_eq!(out.status.code(), Some(0));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.starts_with("V0040 "), "{stdout}");
    assert!(
        stdout.contains(VerifyCode::UnmatchedLoop.summary()),
        "{stdout}"
    );
    // docs/image-format.md's row says more than the summary.
    assert!(
        stdout.contains("each `NEXT` closes the innermost open `FOR`"),
        "{stdout}"
    );
}

#[test]
fn every_v_code_has_its_row_in_the_image_format_doc() {
    for v in VerifyCode::ALL {
        let stdout = String::from_utf8_lossy(&explain(v.as_str()).stdout).into_owned();
        assert!(
            stdout.contains("(from docs/image-format.md, Verification)"),
            "{v}: {stdout}"
        );
    }
}

#[test]
fn an_unknown_code_is_a_usage_error_with_a_suggestion() {
    for (typed, meant) in [("V40", "V0040"), ("V0400", "V0040"), ("t3", "T0003")] {
        let out = explain(typed);
        assert_eq!(out.status.code(), Some(2), "{typed}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains(&format!("no code `{typed}`")), "{stderr}");
        assert!(
            stderr.contains(&format!("did you mean {meant}?")),
            "{stderr}"
        );
        assert!(out.stdout.is_empty());
    }
    let out = explain("Q1234567");
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("no code `Q1234567`"), "{stderr}");
    assert!(!stderr.contains("did you mean"), "{stderr}");
}
