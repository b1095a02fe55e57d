//! S7-200 interrupt event numbers in Micro/WIN exports (docs/microwin.md, "Interrupt
//! events") as the editor offers them: completion after `DTCH` in an export offers the
//! S7-200 numbers the target's data (`<Event MicroWin=>`) maps, and GUTTA's numbers
//! elsewhere. The compiler's side is gutta-compiler's tests/microwin_events.rs; its
//! renumbered target (a stdlib target with its event table edited) shows that the
//! numbers come from the data, not from an identity.

// The renumbered target is the compiler tests' (the same data, one definition).
#[path = "../../compiler/tests/common/mod.rs"]
mod common;

use gutta_analysis::completion::completions;
use gutta_compiler::check_source;
use gutta_compiler::source::SourceFile;

use common::renumbered;

#[test]
fn completion_offers_s7_200_numbers_in_an_export() {
    let target = renumbered();
    let offered = |name: &str, text: &str| -> Vec<String> {
        let checked = check_source(SourceFile::new(name, text), Some(&target));
        let at = text.find("DTCH ").expect("DTCH") + 5;
        completions(&checked, at)
            .items
            .into_iter()
            .map(|i| i.label)
            .collect()
    };
    let main =
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.1\nDTCH \nEND_ORGANIZATION_BLOCK\n";
    // S7-200's 10 is GUTTA's 20 there; GUTTA's 11 has no S7-200 number.
    let export = offered("main.awl", main);
    assert!(export.contains(&"10".to_string()), "{export:?}");
    assert!(!export.contains(&"20".to_string()) && !export.contains(&"11".to_string()));
    let lad = offered("main.lad", main);
    assert!(
        lad.contains(&"20".to_string()) && lad.contains(&"11".to_string()),
        "{lad:?}"
    );
    assert!(!lad.contains(&"10".to_string()), "{lad:?}");
}
