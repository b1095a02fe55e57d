//! S7-200 interrupt event numbers in Micro/WIN exports (docs/microwin.md, "Interrupt
//! events") as the editor offers them: completion after `DTCH` in an export offers the
//! S7-200 numbers the target's data (`<Event MicroWin=>`) maps, and GUTTA's numbers
//! elsewhere. The compiler's side is gutta-compiler's tests/microwin_events.rs; its
//! renumbered target (a stdlib target with its event table edited) shows that the
//! numbers come from the data, not from an identity.

use std::sync::Arc;

use gutta_analysis::completion::completions;
use gutta_catalog::{stdlib, Target};
use gutta_compiler::source::SourceFile;
use gutta_compiler::{check_source, ExplicitTarget};

/// CPU-EC20 with timed interrupt 0 renumbered to GUTTA event 20 (still S7-200's 10),
/// and timed interrupt 1 (GUTTA 11) given no S7-200 number.
fn renumbered() -> ExplicitTarget {
    let mut target: Target = (*stdlib::shared("CPU-EC20").expect("stdlib target")).clone();
    for e in &mut target.memory.events {
        match e.number {
            10 => e.number = 20,
            11 => e.microwin = None,
            _ => {}
        }
    }
    target.memory.events.sort_by_key(|e| e.number);
    ExplicitTarget {
        target: Arc::new(target),
        origin: "a renumbered CPU-EC20".to_string(),
    }
}

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
