//! Sequence control relays of a Micro/WIN export drawn as Micro/WIN's LAD draws them
//! (docs/ladder.md, "Sequence control relays"): `LSCR` the `SCR` box on the rail with
//! its S bit above, `SCRT` the coil `(SCRT)` with its S bit above, `CSCRE` the coil
//! `(SCRE)` at the end of its branch, `SCRE` the coil `(SCRE)` on the rail; S operands
//! named over the GUTTA address they went to; each written back as its STL line; an SVG
//! snapshot of a step's networks.

mod common;

use gutta_ladder::model::{Body, BoxElement, BoxShape, BranchEnd, Ladder, Network, Node, Rung};
use gutta_ladder::svg::{network_svg_with, DrawOptions, Names};

use common::{checked, checked_file, main_with, root};

fn sequence() -> (gutta_compiler::CheckedFile, Ladder) {
    let checked = checked_file(&root().join("tests/data/microwin/scr_sequence_utf8_crlf.awl"));
    assert!(!checked.has_errors(), "{:?}", checked.diagnostics());
    let ladder = gutta_ladder::build(&checked);
    (checked, ladder)
}

fn network(ladder: &Ladder, number: u32) -> &Network {
    ladder.blocks[0]
        .networks
        .iter()
        .find(|n| n.number == number)
        .expect("network")
}

fn rung(net: &Network) -> &Rung {
    match &net.body {
        Body::Rung(r) => r,
        Body::Stl { reason } => panic!("network {} is STL: {reason}", net.number),
    }
}

/// The box ending the rung's only branch.
fn end_box(r: &Rung) -> &BoxElement {
    assert_eq!(r.outputs.len(), 1);
    match &r.outputs[0].end {
        BranchEnd::Box(b) => b,
        other => panic!("not a box: {other:?}"),
    }
}

#[test]
fn lscr_is_the_scr_box_on_the_rail_with_its_s_bit_over_its_address() {
    let (_, ladder) = sequence();
    let r = rung(network(&ladder, 2));
    assert!(r.input.is_none(), "on the rail");
    let b = end_box(r);
    assert_eq!(b.mnemonic, "LSCR");
    assert_eq!(b.title, "SCR");
    assert_eq!(b.shape, BoxShape::Label);
    assert_eq!(b.output, None);
    let s = &b.pins[0].operand;
    assert_eq!(s.written, "S0.0");
    assert_eq!(s.symbol.as_deref(), Some("S0.0"));
    // The S area's default: SB0 = MB96 (the summary line of the file).
    assert_eq!(s.address.as_deref(), Some("M96.0"));
    assert_eq!(s.data_type.as_deref(), Some("BOOL"));
}

#[test]
fn scrt_is_a_jump_coil_at_the_end_of_its_branch_with_its_s_bit_above() {
    let (_, ladder) = sequence();
    let r = rung(network(&ladder, 3));
    assert!(matches!(&r.input, Some(Node::Contact(c)) if c.operands[0].written == "I0.0"));
    let b = end_box(r);
    assert_eq!((b.mnemonic.as_str(), b.title.as_str()), ("SCRT", "SCRT"));
    assert_eq!(b.shape, BoxShape::Jump);
    assert_eq!(b.pins.len(), 1);
    assert_eq!(b.pins[0].operand.symbol.as_deref(), Some("S0.1"));
    assert_eq!(b.pins[0].operand.address.as_deref(), Some("M96.1"));
}

#[test]
fn cscre_is_an_scre_coil_at_the_end_of_its_branch() {
    let (_, ladder) = sequence();
    let r = rung(network(&ladder, 11));
    assert!(r.input.is_some(), "under the power of I0.2");
    let b = end_box(r);
    assert_eq!((b.mnemonic.as_str(), b.title.as_str()), ("CSCRE", "SCRE"));
    assert_eq!(b.shape, BoxShape::Jump);
    assert!(b.pins.is_empty());
}

#[test]
fn scre_is_an_scre_coil_on_the_rail() {
    let (_, ladder) = sequence();
    for number in [4, 8, 14, 17] {
        let r = rung(network(&ladder, number));
        assert!(r.input.is_none(), "network {number} on the rail");
        let b = end_box(r);
        assert_eq!((b.mnemonic.as_str(), b.title.as_str()), ("SCRE", "SCRE"));
        assert_eq!(b.shape, BoxShape::Jump);
    }
}

#[test]
fn every_network_of_the_sequence_is_drawn_and_written_back_as_its_lines() {
    let (checked, ladder) = sequence();
    let set = &checked.target.instructions;
    for net in &ladder.blocks[0].networks {
        let r = rung(net);
        let written = gutta_ladder::write::rung(set, r).expect("written");
        let stored: Vec<String> = net
            .stl
            .iter()
            .map(|l| l.split_whitespace().collect::<Vec<_>>().join(" "))
            .collect();
        let written: Vec<String> = written
            .iter()
            .map(|l| l.split_whitespace().collect::<Vec<_>>().join(" "))
            .collect();
        assert_eq!(written, stored, "network {}", net.number);
    }
}

#[test]
fn a_symbol_at_an_s_address_is_drawn_over_its_gutta_address() {
    let checked = checked_file(&root().join("tests/data/microwin/scr_symbols_gbk_crlf.awl"));
    assert!(!checked.has_errors(), "{:?}", checked.diagnostics());
    let ladder = gutta_ladder::build(&checked);
    let b = end_box(rung(network(&ladder, 2)));
    assert_eq!(b.mnemonic, "LSCR");
    let s = &b.pins[0].operand;
    assert_eq!(s.written, "初始步");
    assert_eq!(s.symbol.as_deref(), Some("初始步"));
    assert_eq!(s.address.as_deref(), Some("M96.0"));
    let t = end_box(rung(network(&ladder, 3)));
    assert_eq!(t.pins[0].operand.symbol.as_deref(), Some("加热步"));
    assert_eq!(t.pins[0].operand.address.as_deref(), Some("M96.1"));
}

#[test]
fn outside_a_micro_win_export_an_scr_line_is_no_instruction() {
    let c = checked(&main_with("NETWORK 1\nLD I0.0\nSCRT 1"));
    let ladder = gutta_ladder::build(&c);
    let net = &ladder.blocks[0].networks[0];
    match &net.body {
        Body::Stl { reason } => assert!(reason.contains("is not an instruction"), "{reason}"),
        Body::Rung(_) => panic!("drawn"),
    }
}

fn svg(ladder: &Ladder, number: u32, names: Names) -> String {
    let block = &ladder.blocks[0];
    let options = DrawOptions {
        names,
        ..DrawOptions::default()
    };
    network_svg_with(block, network(ladder, number), &options)
}

#[test]
fn the_svg_reads_scr_scrt_and_scre_and_keeps_the_stl_mnemonic() {
    let (_, ladder) = sequence();
    let cases = [
        (9, "LSCR", "SCR", Some("M96.2")),
        (13, "SCRT", "SCRT", Some("M96.3")),
        (11, "CSCRE", "SCRE", None),
        (14, "SCRE", "SCRE", None),
    ];
    for (number, mnemonic, title, operand) in cases {
        for names in [Names::Lad, Names::Stl] {
            let els = common::xml::parse(&format!("<svg>{}</svg>", svg(&ladder, number, names))).0;
            let b = els
                .iter()
                .position(|e| e.attr("data-mnemonic") == Some(mnemonic))
                .unwrap_or_else(|| panic!("network {number}: no {mnemonic}"));
            assert!(
                els.iter()
                    .any(|e| e.has_class("title") && e.parents.contains(&b) && e.text == title),
                "network {number}: {mnemonic} titled {title}"
            );
            let shape = if mnemonic == "LSCR" { "label" } else { "jump" };
            assert!(els[b].has_class(shape), "network {number}: {shape}");
            if let Some(address) = operand {
                assert!(
                    els.iter().any(|e| e.has_class("pin")
                        && e.parents.contains(&b)
                        && e.attr("data-operand") == Some(address)),
                    "network {number}: S bit at {address}"
                );
            }
        }
    }
}

#[test]
fn snapshot_of_a_step_of_the_sequence() {
    let (_, ladder) = sequence();
    let svg: Vec<String> = (9..=14)
        .map(|number| svg(&ladder, number, Names::Lad))
        .collect();
    insta::assert_snapshot!("scr_step_2", svg.join("\n"));
}
