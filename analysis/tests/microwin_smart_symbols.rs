//! MicroWIN SMART's default I/O names in a Micro/WIN export (docs/microwin.md,
//! "MicroWIN SMART's I/O symbols") as the editor sees them: hover over `CPU_输入11`
//! shows the bit it stands for, I1.3, as hover over `Always_On` shows SM0.0; the
//! compiler's side is gutta-compiler's tests/microwin_advice.rs.

use gutta_analysis::navigation::hover;
use gutta_compiler::check_source;
use gutta_compiler::source::SourceFile;

#[test]
fn hover_shows_the_bit_of_a_smart_name_as_of_a_system_symbol() {
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\nLD Always_On\nA CPU_输入11\n= CPU_Output9\nEND_ORGANIZATION_BLOCK\n";
    let checked = check_source(SourceFile::new("main.awl", text), None);
    assert!(
        checked.diagnostics().is_empty(),
        "{:?}",
        checked.diagnostics()
    );
    let at = |name: &str| {
        let offset = text.find(name).expect("name in text") + 1;
        hover(&checked, offset).map(|(_, t)| t).unwrap_or_default()
    };
    assert!(
        at("Always_On").starts_with("`SM0.0`"),
        "{}",
        at("Always_On")
    );
    assert!(
        at("CPU_输入11").starts_with("`I1.3`: BIT"),
        "{}",
        at("CPU_输入11")
    );
    assert!(
        at("CPU_Output9").starts_with("`Q1.1`"),
        "{}",
        at("CPU_Output9")
    );
}
