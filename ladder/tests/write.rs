//! The writer's canonical STL (docs/ladder.md, "From ladder to STL"), one rung per rule:
//! the network is built from STL, written back, and the lines compared with the
//! canonical text; the refusals of shapes STL cannot say.

mod common;

use common::{checked, ladder};
use gutta_ladder::model::{Body, Branch, BranchEnd, Contact, ContactKind, Node, Operand, Rung};
use gutta_ladder::write;

/// The STL written for the one network `code`, its blanks collapsed.
fn written(code: &str) -> Vec<String> {
    let l = ladder(&format!("NETWORK 1\n{code}"));
    let set = instructions();
    let net = &l.blocks[0].networks[0];
    assert!(matches!(net.body, Body::Rung(_)), "{code}: {:?}", net.body);
    write::network(&set, net)
        .expect("writes")
        .iter()
        .map(|l| l.split_whitespace().collect::<Vec<_>>().join(" "))
        .collect()
}

fn instructions() -> gutta_catalog::InstructionSet {
    checked("").target.instructions.clone()
}

/// `code` is canonical: written back as it is.
fn canonical(code: &str) {
    assert_eq!(written(code).join("\n"), code);
}

#[test]
fn contacts_take_the_load_form_first_and_the_and_or_forms_after() {
    canonical("LD I0.0\nA I0.1\nAN I0.2\nO I0.3\nON I0.4\n= Q0.0");
    canonical("LDN I0.0\nAI I0.1\nONI I0.2\n=I Q0.0");
    canonical("LDW>= MW20, 100\nAB<> MB1, 0\nOR< MD4, 1.5\n= Q0.0");
    canonical("LD I0.0\nNOT\nEU\nED\n= Q0.0");
}

#[test]
fn a_parallel_of_series_uses_old_and_a_series_of_parallels_ald() {
    canonical("LD I0.0\nO I0.1\nLD I0.2\nO I0.3\nALD\n= Q0.0");
    canonical("LD I0.0\nA I0.1\nLDN I0.2\nA I0.3\nOLD\n= Q0.0");
    // A single contact after a series is an `O`, not a path of its own.
    canonical("LD I0.0\nA I0.1\nO I0.2\n= Q0.0");
}

#[test]
fn non_canonical_stl_is_written_in_the_canonical_form() {
    // `LD`+`ALD` of one contact is `A`; an `OLD` of single contacts is `O`.
    assert_eq!(
        written("LD I0.0\nLD I0.1\nALD\n= Q0.0"),
        ["LD I0.0", "A I0.1", "= Q0.0"]
    );
    assert_eq!(
        written("LD I0.0\nLD I0.1\nOLD\n= Q0.0"),
        ["LD I0.0", "O I0.1", "= Q0.0"]
    );
    // `LDS 0` is `LPS`.
    assert_eq!(
        written("LD I0.0\nLDS 0\nA I0.1\n= Q0.0\nLPP\n= Q0.1"),
        ["LD I0.0", "LPS", "A I0.1", "= Q0.0", "LPP", "= Q0.1"]
    );
}

#[test]
fn output_branches_push_only_where_a_branch_changes_the_power() {
    // Coils leave the power as it was: no LPS, as Micro/WIN writes it.
    canonical("LD I0.0\n= Q0.0\nS M0.0, 1\nR M0.1, 3");
    canonical("LD I0.0\n= Q0.0\nA I0.1\n= Q0.1");
    canonical("LD I1.0\nLPS\nA I1.1\n= Q1.1\nLRD\nA I1.2\n= Q1.2\nLPP\nAN I1.3\n= Q1.3");
    // After the last branch with contacts of its own, LPP; coils after it need nothing.
    canonical("LD I0.0\nLPS\nA I0.1\n= Q0.1\nLPP\n= Q0.2\n= Q0.3");
    canonical("LD I0.0\nLPS\nA I0.1\n= Q0.1\nLRD\n= Q0.2\nA I0.3\n= Q0.3\nLPP\n= Q0.4");
    // Nested splits.
    canonical("LD I0.0\nLPS\nA I0.1\nLPS\nA I0.2\n= Q0.2\nLPP\n= Q0.1\nLPP\n= Q0.0");
}

#[test]
fn boxes_write_their_power_inputs_first_and_operands_in_stl_order() {
    canonical("LD I0.0\nTON T37, 100\n= Q0.0");
    canonical("LD I2.3\nLD I2.4\nCTU C0, 3\n= Q2.3");
    canonical("LD I0.0\nLD I0.1\nA I0.2\nLD I0.3\nCTUD C1, 5\n= Q0.0");
    canonical("LD SM0.0\nMOVW 1, MW10\n+I MW10, MW12");
    // A box with ENO before another branch changes the power: it is pushed.
    canonical("LD I0.0\nLPS\nMOVW 1, MW10\nLPP\n= Q0.0");
    // A box that ends power leaves it: no push.
    canonical("LD I0.0\nJMP 1\n= Q0.0");
}

#[test]
fn a_box_on_the_rail_is_written_alone() {
    assert_eq!(written("LBL 1"), ["LBL 1"]);
}

#[test]
fn a_network_shown_as_stl_is_written_as_stored() {
    let l = ladder("NETWORK 1\nLD I0.0\n= Q0.0\nLD I0.1\n= Q0.1");
    let net = &l.blocks[0].networks[0];
    assert!(matches!(net.body, Body::Stl { .. }));
    assert_eq!(
        write::network(&instructions(), net).expect("writes"),
        net.stl
    );
}

fn contact(mnemonic: &str, kind: ContactKind, operand: &str) -> Node {
    Node::Contact(Contact {
        id: 0,
        kind,
        mnemonic: mnemonic.to_string(),
        immediate: false,
        operands: vec![Operand {
            written: operand.to_string(),
            address: None,
            symbol: None,
            comment: None,
            data_type: None,
        }]
        .into_iter()
        .filter(|o| !o.written.is_empty())
        .collect(),
        relation: None,
        line: 0,
    })
}

fn rung_of(input: Node) -> Rung {
    let Body::Rung(r) = &ladder("NETWORK 1\nLD I0.0\n= Q0.0").blocks[0].networks[0].body else {
        panic!("a rung");
    };
    Rung {
        input: Some(input),
        outputs: r.outputs.clone(),
    }
}

#[test]
fn shapes_stl_cannot_say_are_refused_with_a_reason() {
    let set = instructions();
    let not = contact("NOT", ContactKind::Not, "");
    let err = write::rung(&set, &rung_of(not.clone())).unwrap_err();
    assert_eq!(err.message, "`NOT` cannot start a power path");
    let err = write::rung(
        &set,
        &rung_of(Node::Parallel(vec![
            contact("LD", ContactKind::NormallyOpen, "I0.0"),
            not,
        ])),
    )
    .unwrap_err();
    assert_eq!(err.message, "`NOT` cannot start a power path");
    let err = write::rung(
        &set,
        &rung_of(contact("LDX", ContactKind::NormallyOpen, "I0.0")),
    )
    .unwrap_err();
    assert_eq!(err.message, "`LDX` is not an instruction");
    let mut no_output = rung_of(contact("LD", ContactKind::NormallyOpen, "I0.0"));
    no_output.outputs.clear();
    assert_eq!(
        write::rung(&set, &no_output).unwrap_err().message,
        "the rung has no output"
    );
    let mut empty_split = rung_of(contact("LD", ContactKind::NormallyOpen, "I0.0"));
    empty_split.outputs = vec![Branch {
        path: Vec::new(),
        end: BranchEnd::Split(Vec::new()),
    }];
    assert_eq!(
        write::rung(&set, &empty_split).unwrap_err().message,
        "a split without branches"
    );
}

#[test]
fn a_network_is_written_with_its_title_and_comment() {
    let code = "NETWORK 3 // start and stop\n// a latch\n// with two lines\nLD I0.0\nO Q0.0\nAN I0.1\n= Q0.0";
    let l = ladder(code);
    let net = &l.blocks[0].networks[0];
    let text = write::network_text(&instructions(), net).expect("writes");
    assert_eq!(
        text[..3],
        [
            "NETWORK 3 // start and stop",
            "// a latch",
            "// with two lines"
        ]
    );
    let again = ladder(&text.join("\n"));
    let net_again = &again.blocks[0].networks[0];
    assert_eq!(
        (&net_again.number, &net_again.title, &net_again.comment),
        (&net.number, &net.title, &net.comment)
    );
    assert_eq!(common::render(net_again), common::render(net));
    let untitled = ladder("NETWORK 1\nLD I0.0\n= Q0.0");
    assert_eq!(
        write::network_text(&instructions(), &untitled.blocks[0].networks[0]).expect("writes")[0],
        "NETWORK 1"
    );
}

#[test]
fn an_s7200_timer_leaves_the_power_so_outputs_after_it_need_no_push() {
    // In a Micro/WIN export a timer ends its branch and leaves its input on the stack.
    let text = format!(
        "// dialect: microwin\n{}",
        common::main_with("NETWORK 1\nLD I0.0\nTON T37, 100\nA T37\n= Q0.0")
    );
    let l = gutta_ladder::build(&checked(&text));
    let net = &l.blocks[0].networks[0];
    assert_eq!(
        common::render(net),
        "no(I0.0) -> { [T37 PT=100] ; no(T37) out(Q0.0) }"
    );
    let lines: Vec<String> = write::network(&instructions(), net)
        .expect("writes")
        .iter()
        .map(|l| l.split_whitespace().collect::<Vec<_>>().join(" "))
        .collect();
    assert_eq!(lines, ["LD I0.0", "TON T37, 100", "A T37", "= Q0.0"]);
}
