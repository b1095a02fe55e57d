//! Tests of the runner's own header language and values (header.rs, values.rs): what
//! each line means and which malformed lines are refused, naming their line. They
//! build no program and run no VM.

use gutta_catalog::stdlib;

use crate::header::Wait::{Ms, Now, Scans};
use crate::header::{parse_header, Action, Wait};
use crate::values::{parse_number, parse_value, resolve, Assignment, Bits, Value};

#[test]
fn header_lines_are_read_as_documented() {
    let text = "// plc: EC30-EK51\n// A plain comment: with a colon.\n// scans: 3\n\
                // later: free text\n// set: MW0=-1\n// expect: MW2 = 16#0E01  // explained here\n\
                // expect: Q0.0 = 1\n\nORGANIZATION_BLOCK MAIN\n";
    let h = parse_header(text).expect("header parses");
    assert_eq!(h.plc.as_deref(), Some("EC30-EK51"));
    assert_eq!(h.scans, Some((3, 3)));
    assert_eq!(h.tail_scans(), 3);
    assert_eq!(
        (h.sets[0].var.as_str(), &h.sets[0].value),
        ("MW0", &Value::Number(-1))
    );
    assert_eq!(
        (h.expects[0].line, &h.expects[0].value),
        (6, &Value::Number(0x0E01))
    );
    assert_eq!(h.expects[1].var, "Q0.0");
    assert!(h.steps.is_empty());
}

#[test]
fn steps_are_read_in_order_with_their_waits() {
    let text = "// scan-ms: 10\n// set: I0.0 = 1\n// after 61 scans: expect Q0.0 = 1 // 610 ms\n\
                // then set: I0.0 = 0\n// after 1 scan: expect Q0.0 = 0\n\
                // after 500 ms: expect MB40 = \"a // b\"\n// then force: Q0.1 = 1\n\
                // then unforce: Q0.1\n// after 2 scans: fault 3\n// then reset:\n\
                // then stop:\n// then expect: STOP\n// then run:\n// expect: MW0 = 7\n";
    let h = parse_header(text).expect("header parses");
    let waits: Vec<Wait> = h.steps.iter().map(|s| s.wait).collect();
    assert_eq!(
        waits,
        [
            Scans(61),
            Now,
            Scans(1),
            Ms(500),
            Now,
            Now,
            Scans(2),
            Now,
            Now,
            Now,
            Now
        ]
    );
    assert_eq!(h.steps[0].line, 3);
    assert_eq!(h.stepped_scans(), 61 + 1 + 50 + 2);
    assert_eq!(
        h.tail_scans(),
        0,
        "without `scans:` the run ends with the steps"
    );
    assert!(matches!(&h.steps[3].action,
        Action::Expect(a) if a.value == Value::Text(b"a // b".to_vec())));
    assert!(matches!(&h.steps[5].action, Action::Unforce { var } if var == "Q0.1"));
    assert!(matches!(h.steps[6].action, Action::Fault(3)));
    assert!(matches!(h.steps[7].action, Action::Reset));
    assert!(matches!(
        h.steps[9].action,
        Action::ExpectMode { running: false }
    ));
    assert!(matches!(h.steps[10].action, Action::Run));
    assert_eq!(h.expects[0].line, 14);
    let free = parse_header(
        "// after ATT 10, 20: a comment\n// Then the sum: another\n// expect: MW0 = 1\n",
    )
    .expect("free text");
    assert!(
        free.steps.is_empty(),
        "words with capitals or commas are comments"
    );
    let only_now = parse_header("// then force: Q0.0 = 1\n// expect: Q0.0 = 1\n").expect("parses");
    assert_eq!(only_now.tail_scans(), 1, "at least one scan");
}

#[test]
fn malformed_header_lines_name_their_line() {
    for (text, wanted) in [
        ("// scans: many\n// expect: MW0 = 1\n", "line 1"),
        (
            "// expect: MW0 = 1\n// expcet: MW0 = 1\n",
            "line 2: unknown header key",
        ),
        (
            "// expect: MW0 = 1\n// scan: 2\n",
            "line 2: unknown header key",
        ),
        ("// expect: MW0 is 1\n", "line 1"),
        ("// expect: MW0 = 16#XY\n", "line 1"),
        ("// expect: MB0 = \"open\n", "line 1"),
        ("// scans: 2\n", "checks nothing"),
        (
            "// expect: MW0 = 1\nORGANIZATION_BLOCK MAIN\n// expect: MW2 = 1\n",
            "line 3: `// expect:` after the header",
        ),
        (
            "// expect: MW0 = 1\nORGANIZATION_BLOCK MAIN\n// after 2 scans: expect MW2 = 1\n",
            "line 3: `// after 2 scans:` after the header",
        ),
        (
            "// after 2 scans: expcet MW0 = 1\n",
            "line 1: unknown action",
        ),
        ("// after two scans: expect MW0 = 1\n", "line 1"),
        ("// after 0 scans: expect MW0 = 1\n", "line 1"),
        ("// after 2 s: expect MW0 = 1\n", "line 1"),
        (
            "// then sett: MW0 = 1\n// expect: MW0 = 1\n",
            "line 1: unknown action",
        ),
        ("// then: set MW0 = 1\n// expect: MW0 = 1\n", "line 1"),
        (
            "// then the sum: 3\n// expect: MW0 = 1\n",
            "line 1: `then the sum` is not",
        ),
        ("// then fault: 3\n", "line 1: a fault happens in a scan"),
        ("// after 1 scan: reset now\n// expect: MW0 = 1\n", "line 1"),
        (
            "// after 1 scan: force MB0 = \"x\"\n// expect: MW0 = 1\n",
            "line 1",
        ),
        (
            "// scan-ms: 7\n// after 50 ms: expect MW0 = 1\n",
            "line 2: 50 ms",
        ),
        (
            "// scans: 3\n// after 5 scans: expect MW0 = 1\n",
            "line 1: `scans: 3`, but the steps",
        ),
        (
            "// after 1 scan: expect MW0 = 1\n// set: MW2 = 1\n",
            "line 2: a plain `// set:` after a step",
        ),
        (
            "// expect: MW2 = 1\n// after 1 scan: expect MW0 = 1\n",
            "line 1: a plain `// expect:` before a step",
        ),
        (
            "// fault: 3\n// after 1 scan: expect MW0 = 1\n",
            "line 1: a plain `// fault:` beside steps",
        ),
    ] {
        let errors = parse_header(text).expect_err(text);
        assert!(
            errors.iter().any(|e| e.contains(wanted)),
            "{text:?}: {errors:?}"
        );
    }
}

#[test]
fn values_are_numbers_or_texts() {
    assert_eq!(parse_number("2#1010"), Ok(10));
    assert_eq!(parse_number("-16#10"), Ok(-16));
    assert_eq!(parse_value("\"1A2f\""), Ok(Value::Text(b"1A2f".to_vec())));
    assert!(parse_value("\"\"").is_err(), "an empty text");
}

#[test]
fn values_resolve_against_the_target() {
    let target = stdlib::shared(stdlib::DEFAULT).expect("target");
    let minus_one = Assignment {
        line: 5,
        var: "MW0".into(),
        value: Value::Number(-1),
    };
    let r = resolve(&target, &minus_one).expect("resolves");
    assert!(
        matches!(r.bits, Bits::Word(0xFFFF)),
        "negative values are masked to the width"
    );
    let text = Assignment {
        line: 6,
        var: "MB40".into(),
        value: Value::Text(b"1A".to_vec()),
    };
    let Bits::Bytes(bytes) = resolve(&target, &text).expect("resolves").bits else {
        panic!("a text resolves to bytes");
    };
    assert_eq!(
        bytes
            .iter()
            .map(|(a, b)| (a.offset, *b))
            .collect::<Vec<_>>(),
        [(40, b'1'), (41, b'A')]
    );
    let too_big = Assignment {
        line: 4,
        var: "MB0".into(),
        value: Value::Number(256),
    };
    let err = resolve(&target, &too_big).expect_err("256 is no byte");
    assert!(err.starts_with("line 4"), "{err}");
    let text_on_word = Assignment {
        line: 7,
        var: "MW40".into(),
        value: Value::Text(b"1A".to_vec()),
    };
    let err = resolve(&target, &text_on_word).expect_err("a text needs bytes");
    assert!(err.starts_with("line 7"), "{err}");
}
