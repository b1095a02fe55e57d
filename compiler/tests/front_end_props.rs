//! Property tests of the whole front end (`check_source`): it never panics on any text
//! (arbitrary strings, token soup from the language's own alphabet, and program-shaped
//! files with random instruction lines), every span it returns lies inside the text on
//! char boundaries, and the same text always gives the same result. Case counts are
//! kept small so the suite runs in seconds in debug builds; the fuzzer goes deeper.

use std::sync::OnceLock;

use gutta_catalog::stdlib;
use gutta_compiler::source::{SourceFile, Span};
use gutta_compiler::{check_source, CheckedFile, ExplicitTarget};
use proptest::prelude::*;
use proptest::sample::select;

fn default_target() -> &'static ExplicitTarget {
    static TARGET: OnceLock<ExplicitTarget> = OnceLock::new();
    TARGET.get_or_init(|| ExplicitTarget {
        target: stdlib::shared(stdlib::DEFAULT).expect("the embedded default target loads"),
        origin: "the property test".to_string(),
    })
}

/// Every mnemonic of the default target's instruction set.
fn mnemonics() -> Vec<String> {
    default_target()
        .target
        .instructions
        .names()
        .map(|(n, _)| n.to_string())
        .collect()
}

const KEYWORDS: &[&str] = &[
    "PLC_TYPE",
    "SYMBOLS",
    "END_SYMBOLS",
    "ORGANIZATION_BLOCK",
    "END_ORGANIZATION_BLOCK",
    "SUBROUTINE_BLOCK",
    "END_SUBROUTINE_BLOCK",
    "INTERRUPT_BLOCK",
    "END_INTERRUPT_BLOCK",
    "DATA_BLOCK",
    "END_DATA_BLOCK",
    "SYSTEM_BLOCK",
    "END_SYSTEM_BLOCK",
    "BEGIN",
    "NETWORK",
    "Network",
    "VAR_INPUT",
    "VAR_OUTPUT",
    "VAR_IN_OUT",
    "VAR",
    "VAR_TEMP",
    "END_VAR",
    "TITLE=",
    "TITLE= a title",
];

const OPERANDS: &[&str] = &[
    "I0.0",
    "I1.7",
    "Q0.0",
    "M0.0",
    "M9.8",
    "MB24",
    "MW10",
    "MW11",
    "MD4",
    "VB100",
    "VW0",
    "&MB24",
    "&MW10",
    "*MD4",
    "*MW4",
    "*#p",
    "#a",
    "#t",
    "#p",
    "#nope",
    "SM0.0",
    "SM0.1",
    "SMB2",
    "AIW0",
    "AQW2",
    "T5",
    "T37",
    "TW5",
    "C3",
    "HC0",
    "J0",
    "K0",
    "L0.0",
    "LW2",
    "MAIN",
    "OB1",
    "INT1",
    "SBR0",
    "SBR9",
    "DAT0",
    "ADD3",
    "TICK",
    "Start",
    "Lamp",
    "Pump1",
    "X5",
    "16#0E01",
    "16#",
    "16#FFFFFFFFF",
    "2#1010",
    "8#19",
    "+5",
    "-3",
    "0",
    "255",
    "256",
    "32768",
    "-32769",
    "65536",
    "1.5",
    "1.5e3",
    "-70000",
    "4294967296",
    "99999999999999999999",
    "M99999999999999999999.0",
    "PORT0.BAUD",
    "PASSWORD",
];

const PUNCTUATION: &[&str] = &[
    ",",
    ":",
    ";",
    ":=",
    "(",
    ")",
    "+",
    "-",
    "*",
    "/",
    "&",
    "#",
    ".",
    "<",
    ">",
    "<>",
    "<=",
    ">=",
    "=",
    "\"",
    "\"1234\"",
    "\"a\\\"b\"",
    "\\",
    "//",
    "// note",
    " ",
    " ",
    "  ",
    "\t",
    "\n",
    "\n",
    "\n",
    "\r\n",
    "\r",
    "\u{FEFF}",
    "启动",
    "é",
    "\u{0}",
    "?",
    "@",
    "$",
];

/// One piece of token soup.
fn token() -> impl Strategy<Value = String> {
    prop_oneof![
        3 => select(mnemonics()),
        2 => select(KEYWORDS).prop_map(str::to_string),
        3 => select(OPERANDS).prop_map(str::to_string),
        4 => select(PUNCTUATION).prop_map(str::to_string),
        1 => "[a-zA-Z_][a-zA-Z0-9_]{0,6}",
    ]
}

fn token_soup() -> impl Strategy<Value = String> {
    prop::collection::vec(token(), 0..80).prop_map(|v| v.concat())
}

/// `MNEMONIC op, op // comment` (sometimes with odd separators).
fn instruction_line() -> impl Strategy<Value = String> {
    (
        select(mnemonics()),
        prop::collection::vec(select(OPERANDS), 0..4),
        select(&[", ", ",", " ", ",,", ", // c"][..]),
        select(&["", " // note", "\r", " ;"][..]),
    )
        .prop_map(|(m, ops, sep, end)| format!("{m:<6} {}{end}", ops.join(sep)))
}

fn body() -> impl Strategy<Value = String> {
    prop::collection::vec(
        prop_oneof![
            8 => instruction_line(),
            1 => (1u32..5).prop_map(|n| format!("Network {n} // title")),
            1 => token_soup(),
        ],
        0..24,
    )
    .prop_map(|lines| lines.join("\n"))
}

/// A program with symbols, MAIN, a subroutine with locals, an interrupt, a data block
/// and a system block, whose code lines are random instructions.
fn program() -> impl Strategy<Value = String> {
    (body(), body(), body(), token_soup()).prop_map(|(main, sub, data, system)| {
        format!(
            "SYMBOLS\n  Start : I0.0\n  Lamp : Q0.0 // lamp\nEND_SYMBOLS\n\
             ORGANIZATION_BLOCK MAIN:OB1\nTITLE=main\nVAR\n  t : INT;\n  p : DWORD;\nEND_VAR\n\
             BEGIN\nNetwork 1\n{main}\nEND_ORGANIZATION_BLOCK\n\
             SUBROUTINE_BLOCK ADD3:SBR0\nVAR_INPUT\n  a, b : INT;\nEND_VAR\nVAR_OUTPUT\n  r : INT;\nEND_VAR\n\
             BEGIN\nNetwork 1\n{sub}\nEND_SUBROUTINE_BLOCK\n\
             INTERRUPT_BLOCK TICK:INT1\nBEGIN\nNetwork 1\nLD SM0.0\nINCW MW30\nEND_INTERRUPT_BLOCK\n\
             DATA_BLOCK TABLE1:DAT0\n  MW22 UINT 6\n{data}\nEND_DATA_BLOCK\n\
             SYSTEM_BLOCK\n  PORT0.BAUD = 38400\n{system}\nEND_SYSTEM_BLOCK\n"
        )
    })
}

fn check(text: &str, target: Option<&ExplicitTarget>) -> CheckedFile {
    check_source(SourceFile::new("prop.lad", text), target)
}

/// Every span of the result lies inside the (BOM-stripped) text, on char boundaries.
fn spans_in_text(checked: &CheckedFile) -> Result<(), TestCaseError> {
    let text = checked.file.text.as_str();
    let ok = |s: Span| {
        let (a, b) = (s.start as usize, s.end as usize);
        a <= b && b <= text.len() && text.is_char_boundary(a) && text.is_char_boundary(b)
    };
    for d in checked.diagnostics() {
        prop_assert!(ok(d.primary.span), "primary span of {:?}", d);
        for s in &d.secondary {
            prop_assert!(ok(s.span), "secondary span of {:?}", d);
        }
    }
    let out = &checked.output;
    for def in &out.definitions {
        prop_assert!(ok(def.span), "definition {:?}", def);
    }
    for r in &out.references {
        prop_assert!(ok(r.span), "reference {:?}", r);
        prop_assert!(r.definition < out.definitions.len(), "reference {:?}", r);
    }
    for (s, _) in &out.addresses {
        prop_assert!(ok(*s), "address span {:?}", s);
    }
    for (s, _) in &out.mnemonics {
        prop_assert!(ok(*s), "mnemonic span {:?}", s);
    }
    Ok(())
}

/// Checks `text` twice: no panic, spans inside the text, identical results.
fn holds(text: &str, target: Option<&ExplicitTarget>) -> Result<(), TestCaseError> {
    let first = check(text, target);
    spans_in_text(&first)?;
    let second = check(text, target);
    prop_assert_eq!(first.diagnostics(), second.diagnostics());
    prop_assert_eq!(&first.output.definitions, &second.output.definitions);
    prop_assert_eq!(&first.output.references, &second.output.references);
    prop_assert_eq!(&first.output.program, &second.output.program);
    prop_assert_eq!(first.has_errors(), first.output.program.is_none());
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    #[test]
    fn arbitrary_text(text in any::<String>()) {
        holds(&text, Some(default_target()))?;
    }

    #[test]
    fn token_soup_text(text in token_soup()) {
        holds(&text, Some(default_target()))?;
    }

    #[test]
    fn program_shaped_text(text in program()) {
        holds(&text, Some(default_target()))?;
    }
}

proptest! {
    // Without an explicit target every check loads a stdlib target: fewer cases.
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    #[test]
    fn plc_type_lines_resolve_without_panic(
        name in prop_oneof![
            select(stdlib::names().collect::<Vec<_>>()).prop_map(str::to_string),
            "[A-Za-z0-9 ()_-]{0,20}",
        ],
        rest in token_soup(),
    ) {
        holds(&format!("PLC_TYPE {name}\n{rest}"), None)?;
    }
}
