//! The builder's rule (docs/ladder.md, "Which networks are ladder"), one hand-written
//! network per rule with its expected rung in the compact rendering of
//! `common/mod.rs`, every refusal with its wording, and the network's texts, operands
//! and ids.

mod common;

use common::{checked, ids, ladder, main_with, one, rendered};
use gutta_ladder::model::{Body, BranchEnd, ContactKind, Node};

#[test]
fn contacts_in_series_and_parallel() {
    assert_eq!(
        one("LD I0.0\nA I0.1\nAN I0.2\nO I0.3\nON I0.4\n= Q0.0"),
        "(no(I0.0) no(I0.1) nc(I0.2) | no(I0.3) | nc(I0.4)) -> out(Q0.0)"
    );
}

#[test]
fn ald_and_old_combine_the_two_top_paths() {
    assert_eq!(
        one("LD I0.0\nO I0.1\nLD I0.2\nO I0.3\nALD\n= Q0.0"),
        "(no(I0.0) | no(I0.1)) (no(I0.2) | no(I0.3)) -> out(Q0.0)"
    );
    assert_eq!(
        one("LD I0.0\nA I0.1\nLDN I0.2\nA I0.3\nOLD\n= Q0.0"),
        "(no(I0.0) no(I0.1) | nc(I0.2) no(I0.3)) -> out(Q0.0)"
    );
}

#[test]
fn not_and_edges_are_contacts_in_series() {
    assert_eq!(
        one("LD I0.0\nNOT\nEU\nED\n= Q0.0"),
        "no(I0.0) not() pos-edge() neg-edge() -> out(Q0.0)"
    );
}

#[test]
fn immediate_contacts_and_coils() {
    assert_eq!(
        one("LDI I0.0\nANI I0.1\nONI I0.2\n=I Q0.0\nSI Q0.1, 2\nRI Q0.2, 1"),
        "(noI(I0.0) ncI(I0.1) | ncI(I0.2)) -> { out-immediate(Q0.0) ; set-immediate(Q0.1,2) ; reset-immediate(Q0.2,1) }"
    );
}

#[test]
fn compares_are_contacts_with_both_operands() {
    assert_eq!(
        one("LDW>= MW20, 100\nAB<> MB1, 0\nOR< MD4, 1.5\n= Q0.0"),
        "(compare>=W(MW20,100) compare<>B(MB1,0) | compare<R(MD4,1.5)) -> out(Q0.0)"
    );
}

#[test]
fn outputs_on_the_same_path_are_parallel_branches() {
    assert_eq!(
        one("LD I0.0\n= Q0.0\nS M0.0, 1\nR M0.1, 3"),
        "no(I0.0) -> { out(Q0.0) ; set(M0.0,1) ; reset(M0.1,3) }"
    );
}

#[test]
fn lps_lrd_lpp_make_output_branches() {
    assert_eq!(
        one("LD I1.0\nLPS\nA I1.1\n= Q1.1\nLRD\nA I1.2\n= Q1.2\nLPP\nAN I1.3\n= Q1.3"),
        "no(I1.0) -> { no(I1.1) out(Q1.1) ; no(I1.2) out(Q1.2) ; nc(I1.3) out(Q1.3) }"
    );
}

#[test]
fn nested_branches() {
    let code =
        "LD I0.0\nLPS\nA I0.1\nLPS\nA I0.2\n= Q0.0\nLPP\nA I0.3\n= Q0.1\nLPP\nA I0.4\n= Q0.2";
    assert_eq!(
        one(code),
        "no(I0.0) -> { no(I0.1) { no(I0.2) out(Q0.0) ; no(I0.3) out(Q0.1) } ; no(I0.4) out(Q0.2) }"
    );
    let rung = match &ladder(&format!("NETWORK 1\n{code}")).blocks[0].networks[0].body {
        Body::Rung(r) => r.clone(),
        other => panic!("{other:?}"),
    };
    assert!(matches!(&rung.outputs[0].end, BranchEnd::Split(inner) if inner.len() == 2));
}

/// Micro/WIN writes a branch whose first output has no contacts of its own without LPS:
/// the output leaves the power where it was, so what follows is a branch below it.
#[test]
fn an_output_then_contacts_is_a_branch_below_the_output() {
    assert_eq!(
        one("LD I0.0\n= Q0.0\nA I0.1\n= Q0.1"),
        "no(I0.0) -> { out(Q0.0) ; no(I0.1) out(Q0.1) }"
    );
    assert_eq!(
        one("LD I0.0\n= Q0.0\nA I0.1\n= Q0.1\nA I0.2\n= Q0.2"),
        "no(I0.0) -> { out(Q0.0) ; no(I0.1) { out(Q0.1) ; no(I0.2) out(Q0.2) } }"
    );
    // A branch in parallel inside an output branch, written with ALD.
    assert_eq!(
        one("LD I0.0\n= Q0.0\nLD I0.1\nO I0.2\nALD\n= Q0.1"),
        "no(I0.0) -> { out(Q0.0) ; (no(I0.1) | no(I0.2)) out(Q0.1) }"
    );
}

#[test]
fn boxes_in_series_or_at_the_end_of_a_branch() {
    assert_eq!(
        one("LD I0.0\nMOVW 5, MW10"),
        "no(I0.0) -> [MOVW IN=5 OUT>MW10]"
    );
    // `+I MW10, MW12` is ADD_I with IN1 = MW12 (the in/out OUT, drawn on both sides) and
    // IN2 = MW10.
    assert_eq!(
        one("LD I0.0\nMOVW 5, MW10\n+I MW10, MW12\n= Q0.0"),
        "no(I0.0) [MOVW IN=5 OUT>MW10] [+I IN2=MW10 OUT>MW12] -> out(Q0.0)"
    );
    assert_eq!(
        one("LD I0.0\n= Q0.0\nMOVW 5, MW10\nINCW MW12"),
        "no(I0.0) -> { out(Q0.0) ; [MOVW IN=5 OUT>MW10] [INCW OUT>MW12] }"
    );
    assert_eq!(
        one("LD I0.0\nJMP 1\n= Q0.0"),
        "no(I0.0) -> { [JMP N=1] ; out(Q0.0) }"
    );
}

/// A box (or `NOT`, `EU`, `ED`) acts on the power it is given, and in ladder that is
/// everything before it in series. A path holding one may come first in an `ALD` (the
/// box keeps its power) or be ORed by `OLD` (a parallel path starts at the left rail, as
/// it did alone), and is drawn; ANDed after another path it is refused (see
/// `refusals_name_the_instruction_and_its_line`).
#[test]
fn a_path_with_a_box_is_drawn_where_the_box_keeps_its_power() {
    let cases = [
        (
            "LD I0.0\nLD I0.1\nTON T37, 100\nOLD\n= Q0.0",
            "(no(I0.0) | no(I0.1) [T37 PT=100]) -> out(Q0.0)",
        ),
        (
            "LD I0.0\nLD I0.1\nLD I0.2\nCTU C0, 1\nOLD\n= Q0.0",
            "(no(I0.0) | no(I0.1) [C0 PV=1 R:no(I0.2)]) -> out(Q0.0)",
        ),
        (
            "LD I0.0\nLD I0.1\nEU\nOLD\n= Q0.0",
            "(no(I0.0) | no(I0.1) pos-edge()) -> out(Q0.0)",
        ),
        (
            "LD I0.0\nMOVW 1, MW0\nLD I0.1\nO I0.2\nALD\n= Q0.0",
            "no(I0.0) [MOVW IN=1 OUT>MW0] (no(I0.1) | no(I0.2)) -> out(Q0.0)",
        ),
    ];
    let set = gutta_catalog::stdlib::default_target()
        .expect("stdlib")
        .instructions;
    for (code, drawn) in cases {
        assert_eq!(one(code), drawn, "{code}");
        // Written back, the rung is the same STL: the drawing means what it says.
        let l = ladder(&format!("NETWORK 1\n{code}"));
        let Body::Rung(rung) = &l.blocks[0].networks[0].body else {
            panic!("{code}")
        };
        let written: Vec<String> = gutta_ladder::write::rung(&set, rung)
            .expect("written")
            .iter()
            .map(|l| l.split_whitespace().collect::<Vec<_>>().join(" "))
            .collect();
        assert_eq!(written, code.lines().collect::<Vec<_>>(), "{code}");
    }
}

#[test]
fn call_boxes_have_the_parameters_as_pins() {
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\nCALL SBR0, MW0, MW2\n\
        END_ORGANIZATION_BLOCK\nSUBROUTINE_BLOCK ADD1:SBR0\nVAR_OUTPUT\n  y : INT;\nEND_VAR\n\
        VAR_INPUT\n  x : INT;\nEND_VAR\nBEGIN\nNETWORK 1\nLD SM0.0\nMOVW #x, #y\n+I 1, #y\n\
        END_SUBROUTINE_BLOCK\n";
    let l = gutta_ladder::build(&checked(text));
    assert_eq!(
        common::render(&l.blocks[0].networks[0]),
        "no(SM0.0) -> [ADD1 x=MW0 y>MW2]"
    );
    assert_eq!(l.blocks[1].name, "ADD1");
    assert_eq!(l.blocks[1].numbered, "SBR0");
}

#[test]
fn timers_are_boxes_whose_done_output_continues() {
    assert_eq!(
        one("LD I0.0\nTON T37, 100\n= Q0.0"),
        "no(I0.0) [T37 PT=100] -> out(Q0.0)"
    );
    let l = ladder("NETWORK 1\nLD I0.0\nTON T37, 100\n= Q0.0");
    let Body::Rung(r) = &l.blocks[0].networks[0].body else {
        panic!()
    };
    let Some(Node::Series(v)) = &r.input else {
        panic!()
    };
    let Node::Box(b) = &v[1] else { panic!() };
    assert_eq!(
        (b.mnemonic.as_str(), b.enable.as_str(), b.output.as_deref()),
        ("TON", "IN", Some("Q"))
    );
}

#[test]
fn counters_take_their_other_inputs_from_lower_levels() {
    assert_eq!(
        one("LD I0.0\nLD I0.1\nA I0.2\nCTU C0, 3\n= Q0.0"),
        "no(I0.0) [C0 PV=3 R:no(I0.1) no(I0.2)] -> out(Q0.0)"
    );
    assert_eq!(
        one("LD I0.0\nLD I0.1\nLD I0.2\nCTUD C1, 10"),
        "no(I0.0) -> [C1 PV=10 CD:no(I0.1) R:no(I0.2)]"
    );
    assert_eq!(
        one("LD I0.0\nLD I0.1\nCTD C2, 5\n= Q0.1"),
        "no(I0.0) [C2 PV=5 LD:no(I0.1)] -> out(Q0.1)"
    );
}

/// In a Micro/WIN export a timer leaves its input on the stack, as on an S7-200: the
/// box ends its branch and what follows hangs in parallel.
#[test]
fn an_s7200_timer_ends_its_branch() {
    let text =
        "// dialect: microwin\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\nLD Always_On\n\
        TON T37, 100\n= Q0.0\nNetwork 2\nLD T37\n= Q0.1\nEND_ORGANIZATION_BLOCK\n";
    let l = gutta_ladder::build(&checked(text));
    let r: Vec<String> = l.blocks[0].networks.iter().map(common::render).collect();
    assert_eq!(
        r,
        [
            "no(Always_On) -> { [T37 PT=100] ; out(Q0.0) }",
            "no(T37) -> out(Q0.1)"
        ]
    );
    // Micro/WIN's system symbol is the target's system bit.
    let Body::Rung(rung) = &l.blocks[0].networks[0].body else {
        panic!()
    };
    let Some(Node::Contact(c)) = &rung.input else {
        panic!()
    };
    assert_eq!(c.operands[0].address.as_deref(), Some("SM0.0"));
    assert_eq!(c.operands[0].symbol.as_deref(), Some("Always_On"));
}

#[test]
fn instructions_without_power_flow_alone_are_a_rung_on_the_rail() {
    let r = rendered("NETWORK 1\nLD I0.0\nJMP 4\nNETWORK 2\nLBL 4\nNETWORK 3\nRET");
    assert_eq!(r[1], "| -> [LBL N=4]");
    assert_eq!(r[2], "| -> [RET]");
}

#[test]
fn a_counter_can_hang_on_an_output_branch() {
    // CU is the power after I0.0, R its own path from the rail.
    assert_eq!(
        one("LD I0.0\n= Q0.0\nLD I0.1\nCTU C0, 3"),
        "no(I0.0) -> { out(Q0.0) ; [C0 PV=3 R:no(I0.1)] }"
    );
}

#[test]
fn ids_follow_the_drawing_order() {
    let l = ladder("NETWORK 1\nLD I0.0\nLD I0.1\nCTU C0, 3\nLPS\nA I0.2\n= Q0.0\nLPP\nMOVW 1, MW0");
    let net = &l.blocks[0].networks[0];
    let got = ids(net);
    let numbers: Vec<u32> = got.iter().map(|(id, _)| *id).collect();
    assert_eq!(
        numbers,
        (0..got.len() as u32).collect::<Vec<_>>(),
        "{got:?}"
    );
    let names: Vec<&str> = got.iter().map(|(_, n)| n.as_str()).collect();
    assert_eq!(
        names,
        ["no(I0.0)", "no(I0.1)", "C0", "no(I0.2)", "Q0.0", "MOVW"]
    );
}

#[test]
fn operands_keep_the_written_text_the_address_and_the_symbol() {
    let text = "SYMBOLS\n  Start : i0.0\nEND_SYMBOLS\n".to_string()
        + &main_with(
            "NETWORK 1\nLD Start\nA i0.1\nMOVW *MD4, MW10\nMOVD &VB0, MD20\nMOVW 16#FF, mw30",
        );
    let l = gutta_ladder::build(&checked(&text));
    let Body::Rung(r) = &l.blocks[0].networks[0].body else {
        panic!("{:?}", l.blocks[0].networks[0].body)
    };
    let Some(Node::Series(v)) = &r.input else {
        panic!()
    };
    let Node::Contact(start) = &v[0] else {
        panic!()
    };
    assert_eq!(start.operands[0].written, "Start");
    assert_eq!(start.operands[0].address.as_deref(), Some("I0.0"));
    assert_eq!(start.operands[0].symbol.as_deref(), Some("Start"));
    assert_eq!(start.kind, ContactKind::NormallyOpen);
    let Node::Contact(direct) = &v[1] else {
        panic!()
    };
    assert_eq!(direct.operands[0].written, "i0.1");
    assert_eq!(direct.operands[0].address.as_deref(), Some("I0.1"));
    assert_eq!(direct.operands[0].symbol, None);
    let Node::Box(pointer) = &v[2] else { panic!() };
    assert_eq!(pointer.pins[0].operand.written, "*MD4");
    assert_eq!(pointer.pins[0].operand.address, None);
    let Node::Box(address_of) = &v[3] else {
        panic!()
    };
    assert_eq!(address_of.pins[0].operand.written, "&VB0");
    assert_eq!(address_of.pins[0].operand.address, None);
    let BranchEnd::Box(constant) = &r.outputs[0].end else {
        panic!()
    };
    assert_eq!(constant.pins[0].operand.address, None);
    assert_eq!(constant.pins[1].operand.address.as_deref(), Some("MW30"));
}

#[test]
fn titles_comments_stl_lines_and_numbers() {
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nTITLE=The main program\nBEGIN\n\
        NETWORK 1 // start the pump\n// first comment line\n//   second\nLD I0.0 // the button\n\n= Q0.0\n\
        NETWORK\nLD I0.1\n= Q0.1\nEND_ORGANIZATION_BLOCK\n";
    let l = gutta_ladder::build(&checked(text));
    let b = &l.blocks[0];
    assert_eq!((b.name.as_str(), b.numbered.as_str()), ("MAIN", "OB1"));
    assert_eq!(b.title.as_deref(), Some("The main program"));
    let n = &b.networks[0];
    assert_eq!(n.title.as_deref(), Some("start the pump"));
    assert_eq!(n.comment, ["first comment line", "second"]);
    assert_eq!(n.stl, ["LD I0.0 // the button", "= Q0.0"]);
    assert_eq!((n.number, n.line), (1, 4));
    assert_eq!((b.networks[1].number, b.networks[1].line), (2, 10));
    assert_eq!(l.plc, "CPU-EC20");
}

/// Every refusal reason, with its wording.
#[test]
fn refusals_name_the_instruction_and_its_line() {
    // Network lines start at line 3 (after ORGANIZATION_BLOCK and BEGIN).
    let cases: [(&str, &str); 21] = [
        (
            "LD I0.0\n= Q0.0\nLD I0.1\n= Q0.1",
            "`LD I0.1` at line 6 starts a second power path",
        ),
        ("LD I0.0", "`LD I0.0` at line 4 starts a power path that reaches no output"),
        ("LD I0.0\n= Q0.0\nA I0.1", "`A I0.1` at line 6 leads to no output"),
        ("A I0.0\n= Q0.0", "`A I0.0` at line 4 needs 1 level of the logic stack; 0 are loaded"),
        ("LD I0.0\nALD\n= Q0.0", "`ALD` at line 5 needs 2 levels of the logic stack; 1 is loaded"),
        ("LD I0.0\nLPS\nA I0.1\n= Q0.0", "`LPS` at line 5 has no matching `LPP`"),
        (
            "LD I0.0\n= Q0.0\nO I0.1\n= Q0.1",
            "`O I0.1` at line 6 puts a contact in parallel with a path that already feeds an output",
        ),
        (
            "LD I0.0\n= Q0.0\nLD I0.1\nOLD\n= Q0.1",
            "`OLD` at line 7 puts a path in parallel with one that already feeds an output",
        ),
        (
            "LD I0.0\nLD I0.1\n= Q0.0\nALD\n= Q0.1",
            "`ALD` at line 7 combines a path that already feeds an output",
        ),
        (
            "LD I0.0\nLD I0.1\nLDS 1\n= Q0.0",
            "`LDS 1` at line 6 copies a lower level of the logic stack, which ladder cannot draw",
        ),
        (
            "LD I0.0\n= Q0.0\nLBL 1",
            "`LBL 1` at line 6 runs without power flow, and the network has power flow",
        ),
        ("LBL 1\nRET", "`RET` at line 5 is a second instruction without power flow in the network"),
        (
            "LD SM0.0\nFOR MW0, 1, 10\nINCW MW2\nNEXT",
            "`FOR MW0, 1, 10` at line 5 starts a loop whose body is in the same network",
        ),
        ("LD I0.0\nMOVW 1,\n= Q0.0", "`MOVW 1,` at line 5 did not parse"),
        ("LD I0.0\nSCRT 1\n= Q0.0", "`SCRT 1` at line 5 is not an instruction of CPU-EC20"),
        (
            "LD I0.0\nLD I0.1\n= Q0.0\nCTU C0, 3",
            "`CTU C0, 3` at line 7 takes its R input from a path that already feeds an output",
        ),
        (
            "LD I0.0\nLPS\nLPP\nA I0.1",
            "`A I0.1` at line 7 leads to no output",
        ),
        (
            "LD I0.3\nLD I0.0\nLD I0.1\nCTU C0, 1\nALD\n= Q0.0",
            "`ALD` at line 8 puts the path of `CTU C0, 1` at line 7 in series after the path of \
             `LD I0.3` at line 4: `CTU C0, 1` would take its power through that path too",
        ),
        (
            "LD I0.0\n= Q0.0\nLD I0.1\nTON T37, 100\nALD\n= Q0.1",
            "`ALD` at line 8 puts the path of `TON T37, 100` at line 7 in series after a path that \
             already feeds an output: `TON T37, 100` would take its power through that path too",
        ),
        (
            "LD I0.0\nLD I0.1\nMOVW 1, MW0\nO I0.2\nALD\n= Q0.0",
            "`ALD` at line 8 puts the path of `MOVW 1, MW0` at line 6 in series after the path of \
             `LD I0.0` at line 4: `MOVW 1, MW0` would take its power through that path too",
        ),
        (
            "LD I0.0\nLD I0.1\nNOT\nALD\n= Q0.0",
            "`ALD` at line 7 puts the path of `NOT` at line 6 in series after the path of \
             `LD I0.0` at line 4: `NOT` would take its power through that path too",
        ),
    ];
    for (code, reason) in cases {
        assert_eq!(one(code), format!("STL: {reason}"), "{code}");
    }
    assert_eq!(
        rendered("NETWORK 1\nNETWORK 2\nLD I0.0\n= Q0.0")[0],
        "STL: network 1 is empty"
    );
}

#[test]
fn a_network_with_errors_elsewhere_is_still_drawn() {
    // An unknown symbol is the checker's business: the network is still one rung.
    assert_eq!(one("LD Nowhere\n= Q0.0"), "no(Nowhere) -> out(Q0.0)");
}

/// A network shown as STL keeps its instructions, each with its line in `stl` (comment
/// lines between them counted), its operands resolved as a rung's are; a rung has none.
#[test]
fn stl_networks_keep_their_instructions_with_their_lines() {
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n\
        NETWORK 1\nLD I0.0\n= Q0.0\n// the second rung\nLDN M0.1\n\n= Q0.1\n\
        NETWORK 2\nLD I0.1\n= Q0.2\nEND_ORGANIZATION_BLOCK\n";
    let l = gutta_ladder::build(&checked(text));
    let n = &l.blocks[0].networks[0];
    assert!(matches!(n.body, Body::Stl { .. }), "{:?}", n.body);
    assert_eq!(
        n.stl,
        [
            "LD I0.0",
            "= Q0.0",
            "// the second rung",
            "LDN M0.1",
            "= Q0.1"
        ]
    );
    let code: Vec<(usize, &str, Vec<Option<&str>>)> = n
        .stl_code
        .iter()
        .map(|i| {
            let ops = i.operands.iter().map(|o| o.address.as_deref()).collect();
            (i.index, i.mnemonic.as_str(), ops)
        })
        .collect();
    assert_eq!(
        code,
        [
            (0, "LD", vec![Some("I0.0")]),
            (1, "=", vec![Some("Q0.0")]),
            (3, "LDN", vec![Some("M0.1")]),
            (4, "=", vec![Some("Q0.1")]),
        ]
    );
    assert!(l.blocks[0].networks[1].stl_code.is_empty());
}
