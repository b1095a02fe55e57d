//! S7-200 interrupt event numbers in Micro/WIN exports (docs/microwin.md, "Interrupt
//! events"): `ATCH`, `DTCH` and `CEVNT` of an export name S7-200 events, which the
//! target's data (`<Event MicroWin=>`) translates to its own; E0223 where the target has
//! no such event; files outside the dialect keep GUTTA's numbers; `dis --format awl`
//! writes the S7-200 numbers back. A target whose events are numbered unlike the S7-200
//! (a stdlib target with its event table edited) shows that the numbers come from the
//! data, not from an identity.

#![allow(clippy::disallowed_methods, reason = "a test reads docs/microwin.md")]

mod common;

use gutta_catalog::stdlib;
use gutta_compiler::diagnostics::render::{render, RenderStyle};
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, Compiled, ExplicitTarget};
use gutta_format::disasm::{disassemble_as, disassemble_with_errors, Format};

use common::renumbered;

fn stdlib_target(name: &str) -> ExplicitTarget {
    ExplicitTarget {
        target: stdlib::shared(name).expect("stdlib target"),
        origin: format!("--plc {name}"),
    }
}

/// MAIN attaches INT_0 to `attach` and runs `more` after it; INT_0 counts in MW0.
fn export(attach: &str, more: &str) -> String {
    format!(
        "ORGANIZATION_BLOCK MAIN:OB1\r\nTITLE=\r\nBEGIN\r\nNetwork 1\r\nLD     SM0.1\r\n\
         ATCH   INT_0:INT0, {attach}\r\n{more}ENI\r\nEND_ORGANIZATION_BLOCK\r\n\
         INTERRUPT_BLOCK INT_0:INT0\r\nTITLE=\r\nBEGIN\r\nNetwork 1\r\nLD     SM0.0\r\n\
         INCW   MW0\r\nEND_INTERRUPT_BLOCK\r\n"
    )
}

fn build(name: &str, text: &str, target: &ExplicitTarget) -> Compiled {
    compile(SourceFile::new(name, text), Some(target))
}

fn codes(c: &Compiled) -> Vec<&'static str> {
    c.checked
        .diagnostics()
        .iter()
        .map(|d| d.code.as_str())
        .collect()
}

/// The image's program as the toolchain's own STL, without comments.
fn stl(c: &Compiled, target: &ExplicitTarget) -> String {
    let image = c.image.as_ref().expect("an image");
    let d = disassemble_with_errors(image, &target.target);
    assert!(d.errors.is_empty(), "{:?}", d.errors);
    d.text
        .lines()
        .map(|l| l.split("//").next().unwrap_or("").trim_end())
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn s7_200_event_numbers_compile_to_the_targets_events() {
    let target = renumbered();
    let c = build(
        "main.awl",
        &export("10", "DTCH   10\r\nCEVNT  10\r\n"),
        &target,
    );
    assert_eq!(codes(&c), Vec::<&str>::new());
    let text = stl(&c, &target);
    assert!(text.contains("ATCH   INT1, 20"), "{text}");
    assert!(text.contains("DTCH   20"), "{text}");
    assert!(text.contains("CEVNT  20"), "{text}");
    assert_eq!(
        c.checked.microwin_summary().as_deref(),
        Some("S7-200 interrupts: INT_0 (INT0) -> INT1; S7-200 events: 10 -> 20 (TIMED0)")
    );
    // An edge event keeps its number there: no event part in the summary.
    let c = build("main.awl", &export("0", ""), &target);
    assert!(stl(&c, &target).contains("ATCH   INT1, 0"));
    assert_eq!(
        c.checked.microwin_summary().as_deref(),
        Some("S7-200 interrupts: INT_0 (INT0) -> INT1")
    );
}

#[test]
fn an_s7_200_event_the_target_lacks_is_e0223_at_the_operand() {
    let target = stdlib_target("CPU-EC20");
    let text = export("12", "");
    let c = build("main.awl", &text, &target);
    let diags = c.checked.diagnostics();
    assert_eq!(codes(&c), ["E0223"]);
    let at = text.find(", 12").expect("the operand") + 2;
    assert_eq!(diags[0].primary.span.range(), at..at + 2);
    let style = RenderStyle {
        color: false,
        unicode: false,
    };
    // ariadne pads some lines with blanks; compare without them.
    let shown: String = render(&c.checked.file, diags, style)
        .lines()
        .map(|l| format!("{}\n", l.trim_end()))
        .collect();
    let want = "\
[E0223] Error: S7-200 event 12 (HSC0 CV=PV) does not exist on CPU-EC20
   ,-[ main.awl:6:20 ]
   |
 6 | ATCH   INT_0:INT0, 12
   |                    ^|
   |                     `-- an S7-200 event number
   |
   | Help: S7-200 events CPU-EC20 has: 0 (I0.0 rising edge), 1 (I0.0 falling edge), 2 (I0.1 rising edge), 3 (I0.1 falling edge), 4 (I0.2 rising edge), 5 (I0.2 falling edge), 6 (I0.3 rising edge), 7 (I0.3 falling edge), 10 (timed interrupt 0 (SMB34)), 11 (timed interrupt 1 (SMB35))
---'
";
    assert_eq!(shown, want, "\n{shown}");
    // On a target that numbers timed interrupt 1 but gives it no S7-200 number, S7-200's
    // 11 does not exist there either, and the help no longer offers it.
    let c = build("main.awl", &export("11", ""), &renumbered());
    assert_eq!(codes(&c), ["E0223"]);
    let help = c.checked.diagnostics()[0].help.clone().unwrap_or_default();
    assert!(help.contains("10 (timed interrupt 0 (SMB34))"), "{help}");
    assert!(!help.contains("11 ("), "{help}");
}

#[test]
fn numbers_past_33_are_out_of_range() {
    let c = build("main.awl", &export("34", ""), &stdlib_target("CPU-EC20"));
    assert_eq!(codes(&c), ["E0307"]);
    assert_eq!(
        c.checked.diagnostics()[0].message,
        "EVNT of ATCH must be an S7-200 event number 0..33"
    );
}

#[test]
fn outside_the_dialect_event_numbers_are_gutta_numbers() {
    let target = renumbered();
    let lad = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.1\nATCH INT1, {N}\nENI\n\
               END_ORGANIZATION_BLOCK\nINTERRUPT_BLOCK INT_0:INT1\nBEGIN\nNETWORK 1\nLD SM0.0\n\
               INCW MW0\nEND_INTERRUPT_BLOCK\n";
    // GUTTA's 20 is timed interrupt 0 there; 10 is no event of that target.
    let c = build("main.lad", &lad.replace("{N}", "20"), &target);
    assert_eq!(codes(&c), Vec::<&str>::new());
    assert!(stl(&c, &target).contains("ATCH   INT1, 20"));
    assert_eq!(c.checked.microwin_summary(), None);
    let c = build("main.lad", &lad.replace("{N}", "10"), &target);
    assert_eq!(codes(&c), ["E0307"]);
    // And 12 on a stdlib target is GUTTA's "no such event", not E0223.
    let c = build(
        "main.lad",
        &lad.replace("{N}", "12"),
        &stdlib_target("CPU-EC20"),
    );
    assert_eq!(codes(&c), ["E0307"]);
    assert_eq!(
        c.checked.diagnostics()[0].message,
        "CPU-EC20 raises no interrupt event 12"
    );
}

#[test]
fn dis_format_awl_writes_s7_200_numbers_that_compile_back() {
    let target = renumbered();
    let c = build("main.awl", &export("10", "DTCH   10\r\n"), &target);
    let image = c.image.as_ref().expect("an image");
    let awl = disassemble_as(image, &target.target, Format::Awl);
    assert!(awl.errors.is_empty(), "{:?}", awl.errors);
    assert!(awl.text.contains("ATCH   INT_0, 10\r\n"), "{}", awl.text);
    assert!(awl.text.contains("DTCH   10\r\n"), "{}", awl.text);
    let again = build("again.awl", &awl.text, &target);
    assert_eq!(again.image.as_ref(), Some(image));
    // GUTTA's event 11 has no S7-200 number there: the awl layout cannot write it.
    let lad = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.1\nDTCH 11\n\
               END_ORGANIZATION_BLOCK\n";
    let c = build("main.lad", lad, &target);
    let image = c.image.as_ref().expect("an image");
    let awl = disassemble_as(image, &target.target, Format::Awl);
    assert_eq!(awl.errors.len(), 1, "{:?}", awl.errors);
    assert!(
        awl.errors[0].reason.contains("has no S7-200 number"),
        "{}",
        awl.errors[0]
    );
}

/// docs/microwin.md's table of interrupt events ("Interrupt events") is every stdlib
/// target's data: each row's S7-200 event maps to the GUTTA event it names, and every
/// mapped event has a row.
#[test]
fn the_documented_event_table_is_every_stdlib_targets_data() {
    let doc = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/microwin.md"),
    )
    .expect("read docs/microwin.md");
    let section = doc
        .split("### Interrupt events")
        .nth(1)
        .expect("the section")
        .split("\n#")
        .next()
        .unwrap_or("");
    let rows: Vec<(u32, String, u32, String)> = section
        .lines()
        .filter_map(|l| {
            let cells: Vec<&str> = l
                .trim()
                .strip_prefix('|')?
                .split('|')
                .map(str::trim)
                .collect();
            let s7 = cells.first()?.parse().ok()?;
            let mut gutta = cells.get(2)?.split_whitespace();
            let number = gutta.next()?.parse().ok()?;
            let name = gutta.next()?.trim_matches('`').to_string();
            Some((s7, cells.get(1)?.to_string(), number, name))
        })
        .collect();
    assert_eq!(rows.len(), 10, "{rows:?}");
    for name in stdlib::names() {
        let memory = &stdlib::shared(name).expect("stdlib target").memory;
        for (s7, meaning, number, event_name) in &rows {
            let event = memory.event_for_s7200(*s7).expect("mapped");
            assert_eq!(
                (event.number, &event.name),
                (*number, event_name),
                "{name}: {s7}"
            );
            let table = gutta_catalog::s7200::s7200_event(i64::from(*s7)).expect("S7-200 event");
            assert_eq!(table.meaning, meaning, "{s7}");
        }
        let mapped = memory
            .events
            .iter()
            .filter(|e| e.microwin.is_some())
            .count();
        assert_eq!(mapped, rows.len(), "{name}");
    }
}
