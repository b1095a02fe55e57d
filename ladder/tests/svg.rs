//! Golden SVG of hand-built networks covering every element (insta snapshots in
//! tests/snapshots/), plus the properties every drawing must have: well-formed XML, the
//! same bytes for the same model, the class and data-* names of issue 15 on every
//! element, every wire powered by the rail or an element of its network, and no two
//! element cells overlapping in a 30-wide or a 20-deep network.

mod common;

use common::xml::Element;
use gutta_ladder::html::{ladder_html, HtmlOptions};
use gutta_ladder::layout::{layout_network, Rect};
use gutta_ladder::model::{
    Block, Body, BoxElement, BoxShape, Branch, BranchEnd, Coil, CoilKind, Contact, ContactKind,
    Ladder, Network, Node, Operand, Pin, Rung,
};
use gutta_ladder::svg::{ladder_svg, network_svg};

// ---- model builders ------------------------------------------------------------------

fn addr(a: &str) -> Operand {
    Operand {
        written: a.to_string(),
        address: Some(a.to_string()),
        symbol: None,
        comment: None,
        data_type: None,
    }
}

fn sym(name: &str, a: &str) -> Operand {
    Operand {
        written: name.to_string(),
        address: Some(a.to_string()),
        symbol: Some(name.to_string()),
        comment: None,
        data_type: None,
    }
}

fn constant(text: &str) -> Operand {
    Operand {
        written: text.to_string(),
        address: None,
        symbol: None,
        comment: None,
        data_type: None,
    }
}

fn contact(id: u32, kind: ContactKind, mnemonic: &str, operands: Vec<Operand>) -> Node {
    Node::Contact(Contact {
        id,
        kind,
        mnemonic: mnemonic.to_string(),
        immediate: mnemonic.ends_with('I') && kind != ContactKind::Not,
        relation: None,
        operands,
        line: id + 1,
    })
}

fn no(id: u32, operand: Operand) -> Node {
    contact(id, ContactKind::NormallyOpen, "A", vec![operand])
}

fn compare(id: u32, relation: &str, a: Operand, b: Operand) -> Node {
    Node::Contact(Contact {
        id,
        kind: ContactKind::Compare,
        mnemonic: format!("LD{relation}"),
        immediate: false,
        relation: Some(relation.to_string()),
        operands: vec![a, b],
        line: id + 1,
    })
}

fn coil(id: u32, kind: CoilKind, operand: Operand, count: Option<Operand>) -> BranchEnd {
    let mnemonic = match kind {
        CoilKind::Out => "=",
        CoilKind::Set => "S",
        CoilKind::Reset => "R",
        CoilKind::OutImmediate => "=I",
        CoilKind::SetImmediate => "SI",
        CoilKind::ResetImmediate => "RI",
    };
    BranchEnd::Coil(Coil {
        id,
        kind,
        mnemonic: mnemonic.to_string(),
        operand,
        count,
        line: id + 1,
    })
}

fn out(id: u32, operand: Operand) -> Branch {
    Branch {
        path: vec![],
        end: coil(id, CoilKind::Out, operand, None),
    }
}

fn pin(name: &str, output: bool, operand: Operand) -> Pin {
    Pin {
        name: name.to_string(),
        output,
        operand,
        input: None,
    }
}

#[allow(clippy::too_many_arguments)]
fn boxed(
    id: u32,
    mnemonic: &str,
    title: &str,
    enable: &str,
    output: Option<&str>,
    pins: Vec<Pin>,
    power_inputs: Vec<(String, Node)>,
) -> BoxElement {
    BoxElement {
        id,
        mnemonic: mnemonic.to_string(),
        title: title.to_string(),
        pins,
        power_inputs,
        enable: enable.to_string(),
        output: output.map(str::to_string),
        line: id + 1,
        counted: None,
        resolution_ms: None,
        shape: BoxShape::Box,
    }
}

fn rung(input: Option<Node>, outputs: Vec<Branch>) -> Body {
    Body::Rung(Rung { input, outputs })
}

fn network(number: u32, title: Option<&str>, comment: &[&str], body: Body) -> Network {
    Network {
        number,
        title: title.map(str::to_string),
        comment: comment.iter().map(|c| c.to_string()).collect(),
        stl: vec!["LD I0.0".to_string(), "= Q0.0".to_string()],
        line: number * 10,
        body,
        stl_code: vec![],
    }
}

fn main_block(networks: Vec<Network>) -> Block {
    Block {
        name: "MAIN".to_string(),
        numbered: "OB1".to_string(),
        title: None,
        networks,
    }
}

// ---- the networks of the snapshots -----------------------------------------------------

fn every_contact() -> Network {
    let series = Node::Series(vec![
        contact(
            0,
            ContactKind::NormallyOpen,
            "LD",
            vec![sym("Start", "I0.0")],
        ),
        contact(
            1,
            ContactKind::NormallyClosed,
            "AN",
            vec![sym("Stop", "I0.1")],
        ),
        contact(2, ContactKind::PositiveEdge, "EU", vec![]),
        contact(3, ContactKind::NegativeEdge, "ED", vec![]),
        contact(4, ContactKind::Not, "NOT", vec![]),
        compare(5, ">=W", sym("Level", "MW20"), constant("100")),
        contact(6, ContactKind::NormallyOpen, "AI", vec![addr("I0.2")]),
        contact(7, ContactKind::NormallyClosed, "ANI", vec![addr("I0.3")]),
    ]);
    network(
        1,
        Some("every contact"),
        &[],
        rung(Some(series), vec![out(8, sym("Motor", "Q0.0"))]),
    )
}

fn every_coil() -> Network {
    let outputs = vec![
        out(1, addr("Q0.0")),
        Branch {
            path: vec![],
            end: coil(2, CoilKind::Set, sym("Lamp", "Q0.1"), Some(constant("3"))),
        },
        Branch {
            path: vec![],
            end: coil(3, CoilKind::Reset, addr("M1.0"), Some(constant("8"))),
        },
        Branch {
            path: vec![],
            end: coil(4, CoilKind::OutImmediate, addr("Q0.4"), None),
        },
        Branch {
            path: vec![],
            end: coil(5, CoilKind::SetImmediate, addr("Q0.5"), Some(constant("2"))),
        },
        Branch {
            path: vec![],
            end: coil(
                6,
                CoilKind::ResetImmediate,
                addr("Q0.6"),
                Some(addr("VB10")),
            ),
        },
    ];
    network(2, None, &[], rung(Some(no(0, addr("I0.0"))), outputs))
}

fn boxes() -> Network {
    // LD I0.0, MOVW in series, then a TON and a CALL in parallel outputs.
    let movw = boxed(
        1,
        "MOVW",
        "MOVW",
        "EN",
        Some("ENO"),
        vec![
            pin("IN", false, constant("16#00FF")),
            pin("OUT", true, sym("Setpoint", "MW10")),
        ],
        vec![],
    );
    let ton = boxed(
        2,
        "TON",
        "T37",
        "IN",
        Some("Q"),
        vec![pin("PT", false, constant("50"))],
        vec![],
    );
    let call = boxed(
        3,
        "CALL",
        "ADD3",
        "EN",
        Some("ENO"),
        vec![
            pin("a", false, addr("VW0")),
            pin("b", false, constant("#x")),
            pin("sum", true, sym("Total", "VW4")),
        ],
        vec![],
    );
    let input = Node::Series(vec![no(0, sym("Run", "I0.0")), Node::Box(movw)]);
    network(
        3,
        Some("boxes"),
        &[],
        rung(
            Some(input),
            vec![
                Branch {
                    path: vec![],
                    end: BranchEnd::Box(ton),
                },
                Branch {
                    path: vec![],
                    end: BranchEnd::Box(call),
                },
            ],
        ),
    )
}

fn counter() -> Network {
    // LD I0.0 (CU), LD I0.1 (R), CTU C0, 10; then = Q0.0 on its output.
    let ctu = boxed(
        1,
        "CTU",
        "C0",
        "CU",
        Some("Q"),
        vec![pin("PV", false, constant("10"))],
        vec![(
            "R".to_string(),
            Node::Series(vec![no(2, sym("Reset", "I0.1")), no(3, addr("M0.0"))]),
        )],
    );
    let input = Node::Series(vec![no(0, addr("I0.0")), Node::Box(ctu)]);
    network(
        4,
        Some("counter with reset"),
        &[],
        rung(Some(input), vec![out(4, addr("Q0.0"))]),
    )
}

fn parallels() -> Network {
    // Series with a parallel block nested three deep.
    let deep = Node::Parallel(vec![
        Node::Series(vec![
            no(1, addr("I0.1")),
            Node::Parallel(vec![
                Node::Series(vec![
                    no(2, addr("I0.2")),
                    Node::Parallel(vec![no(3, addr("I0.3")), no(4, addr("I0.4"))]),
                ]),
                no(5, addr("I0.5")),
            ]),
        ]),
        no(6, addr("I0.6")),
    ]);
    let input = Node::Series(vec![no(0, addr("I0.0")), deep, no(7, addr("I0.7"))]);
    network(5, None, &[], rung(Some(input), vec![out(8, addr("Q0.0"))]))
}

fn stack_split() -> Network {
    // LPS / LRD / LPP with an LPS nested in the second branch.
    let outputs = vec![
        Branch {
            path: vec![no(1, addr("I0.1"))],
            end: coil(2, CoilKind::Out, addr("Q0.1"), None),
        },
        Branch {
            path: vec![no(3, addr("I0.2"))],
            end: BranchEnd::Split(vec![
                Branch {
                    path: vec![no(4, addr("I0.3"))],
                    end: coil(5, CoilKind::Out, addr("Q0.2"), None),
                },
                Branch {
                    path: vec![],
                    end: coil(6, CoilKind::Set, addr("Q0.3"), Some(constant("1"))),
                },
            ]),
        },
        Branch {
            path: vec![contact(
                7,
                ContactKind::NormallyClosed,
                "AN",
                vec![addr("I0.4")],
            )],
            end: coil(8, CoilKind::Out, addr("Q0.4"), None),
        },
    ];
    network(6, None, &[], rung(Some(no(0, addr("I0.0"))), outputs))
}

fn stl() -> Network {
    network(
        7,
        Some("not a rung"),
        &[],
        Body::Stl {
            reason: "two power paths from the left rail (LD at line 72 starts a second rung)"
                .to_string(),
        },
    )
}

fn escaping() -> Network {
    network(
        8,
        Some("a < b & c > \"d\""),
        &["first comment line", "电机 <启动> & 'stop'"],
        rung(
            Some(no(0, sym("启动按钮", "I0.0"))),
            vec![out(1, sym("a<b&c", "Q0.0"))],
        ),
    )
}

fn snapshot_networks() -> Vec<(&'static str, Network)> {
    vec![
        ("every_contact", every_contact()),
        ("every_coil", every_coil()),
        ("boxes", boxes()),
        ("counter", counter()),
        ("parallels", parallels()),
        ("stack_split", stack_split()),
        ("stl", stl()),
        ("escaping", escaping()),
    ]
}

fn ladder() -> Ladder {
    let sbr = Block {
        name: "ADD3".to_string(),
        numbered: "SBR0".to_string(),
        title: Some("adds & returns".to_string()),
        networks: vec![every_coil(), stl()],
    };
    Ladder {
        plc: "CPU-EC20".to_string(),
        blocks: vec![
            main_block(snapshot_networks().into_iter().map(|(_, n)| n).collect()),
            sbr,
        ],
    }
}

// ---- helpers over the output ---------------------------------------------------------

/// Parse `text` as XML (strict: tests/common/xml.rs): its elements and text content.
fn parse_xml(text: &str) -> (Vec<Element>, String) {
    common::xml::parse(text)
}

fn wrap(group: &str) -> String {
    format!("<svg xmlns=\"http://www.w3.org/2000/svg\">{group}</svg>")
}

// ---- golden snapshots -----------------------------------------------------------------

#[test]
fn snapshots_of_every_element() {
    let block = main_block(vec![]);
    for (name, net) in snapshot_networks() {
        let svg = network_svg(&block, &net);
        parse_xml(&wrap(&svg));
        insta::assert_snapshot!(name, svg);
    }
}

#[test]
fn snapshot_of_a_ladder_document() {
    let svg = ladder_svg(&ladder());
    parse_xml(&svg);
    insta::assert_snapshot!("ladder_document", svg);
}

#[test]
fn snapshot_of_the_page() {
    let options = HtmlOptions {
        title: "tank & pump".to_string(),
        live_script: Some("const a = 1; // </script> must not end the element".to_string()),
        ..HtmlOptions::default()
    };
    let html = ladder_html(&ladder(), &options);
    insta::assert_snapshot!("page", html);
}

// ---- properties ------------------------------------------------------------------------

#[test]
fn the_page_is_well_formed_self_contained_and_holds_every_network() {
    let options = HtmlOptions {
        title: "t".to_string(),
        live_script: Some("window.live = true;".to_string()),
        ..HtmlOptions::default()
    };
    let html = ladder_html(&ladder(), &options);
    let (elements, _) = parse_xml(&html);
    let networks = elements.iter().filter(|e| e.has_class("network")).count();
    let expected: usize = ladder().blocks.iter().map(|b| b.networks.len()).sum();
    assert_eq!(networks, expected);
    assert_eq!(
        elements.iter().filter(|e| e.name == "svg").count(),
        expected,
        "one inline svg per network"
    );
    assert_eq!(elements.iter().filter(|e| e.name == "script").count(), 1);
    for e in &elements {
        for (key, value) in &e.attrs {
            let external = ["http:", "https:", "//"]
                .iter()
                .any(|p| value.starts_with(p));
            assert!(
                !external || key == "xmlns",
                "external reference {key}={value}"
            );
        }
        assert!(
            e.name != "link" && e.name != "img",
            "external resource {}",
            e.name
        );
    }
    assert!(html.contains(".on"), "the on style");
    assert!(html.contains(".forced"), "the forced style");
    let index_links = elements
        .iter()
        .filter(|e| e.name == "a" && e.attr("href").is_some_and(|h| h.starts_with("#block-")))
        .count();
    assert_eq!(index_links, 2);
}

#[test]
fn the_same_model_gives_the_same_bytes() {
    let first = (
        ladder_svg(&ladder()),
        ladder_html(&ladder(), &HtmlOptions::default()),
    );
    let second = (
        ladder_svg(&ladder()),
        ladder_html(&ladder(), &HtmlOptions::default()),
    );
    assert_eq!(first, second);
}

#[test]
fn every_element_carries_its_class_and_data() {
    let block = main_block(vec![]);
    let mut kinds = std::collections::BTreeSet::new();
    let mut counts = [0usize; 3];
    for (name, net) in snapshot_networks() {
        let (elements, _) = parse_xml(&wrap(&network_svg(&block, &net)));
        let group = &elements[1];
        assert!(group.has_class("network"), "{name}");
        assert_eq!(group.attr("data-block"), Some("MAIN"));
        assert_eq!(
            group.attr("data-network"),
            Some(net.number.to_string().as_str())
        );
        if let Body::Stl { reason } = &net.body {
            assert!(group.has_class("stl"));
            assert_eq!(group.attr("data-reason"), Some(reason.as_str()));
            // Each STL line is `text.stl.stl-line[data-index]`, in order, for the live
            // view's `data-rlo`.
            let lines: Vec<&str> = elements
                .iter()
                .filter(|e| e.has_class("stl-line"))
                .map(|e| {
                    assert!(e.has_class("stl"), "{name}");
                    e.attr("data-index").expect("data-index")
                })
                .collect();
            let indexes: Vec<String> = (0..net.stl.len()).map(|i| i.to_string()).collect();
            assert_eq!(lines, indexes, "{name}");
            continue;
        }
        let mut ids = std::collections::BTreeSet::new();
        for e in &elements {
            for (i, class) in ["contact", "coil", "box"].iter().enumerate() {
                if e.has_class(class) {
                    counts[i] += 1;
                    let id: u32 = e.attr("data-id").expect("data-id").parse().unwrap();
                    assert!(ids.insert(id), "{name}: id {id} twice");
                    assert!(e.attr("data-operand").is_some(), "{name}: data-operand");
                    if *class == "box" {
                        assert!(e.attr("data-mnemonic").is_some_and(|m| !m.is_empty()));
                    } else {
                        kinds.insert(format!("{class}:{}", e.attr("data-kind").unwrap()));
                    }
                }
            }
        }
        for e in elements.iter().filter(|e| e.has_class("wire")) {
            let after = e.attr("data-after").expect("data-after");
            assert!(!after.is_empty(), "{name}: a wire without power source");
            for token in after.split(' ') {
                assert!(
                    token == "rail" || ids.contains(&token.parse::<u32>().unwrap()),
                    "{name}: wire after unknown {token}"
                );
            }
        }
    }
    let expected = [
        "contact:no",
        "contact:nc",
        "contact:pos-edge",
        "contact:neg-edge",
        "contact:not",
        "contact:compare",
        "coil:out",
        "coil:set",
        "coil:reset",
        "coil:out-immediate",
        "coil:set-immediate",
        "coil:reset-immediate",
    ];
    for kind in expected {
        assert!(kinds.contains(kind), "no {kind} drawn");
    }
    assert!(counts.iter().all(|&c| c > 0), "{counts:?}");
}

#[test]
fn operands_show_symbol_and_address_and_text_is_escaped() {
    let block = main_block(vec![]);
    let (elements, text) = parse_xml(&wrap(&network_svg(&block, &escaping())));
    assert!(text.contains("a < b & c > \"d\""), "{text}");
    assert!(text.contains("电机 <启动> & 'stop'"), "{text}");
    assert!(text.contains("启动按钮") && text.contains("I0.0"));
    assert!(text.contains("a<b&c"));
    let coil = elements.iter().find(|e| e.has_class("coil")).unwrap();
    assert_eq!(coil.attr("data-operand"), Some("Q0.0"));
    let contact = elements.iter().find(|e| e.has_class("contact")).unwrap();
    assert_eq!(contact.attr("data-operand"), Some("I0.0"));
    assert_eq!(contact.attr("data-kind"), Some("no"));
}

/// No two element cells of a network overlap, and everything lies inside its size.
fn assert_no_overlap(net: &Network) -> (i32, i32) {
    let layout = layout_network(net).expect("a rung");
    let cells: Vec<Rect> = layout.elements.iter().map(|e| e.cell).collect();
    for (i, a) in cells.iter().enumerate() {
        assert!(
            a.x >= 0 && a.y >= layout.header_h,
            "cell {a:?} above the rung"
        );
        assert!(
            a.x + a.w <= layout.width && a.y + a.h <= layout.height,
            "{a:?} outside"
        );
        for b in &cells[i + 1..] {
            assert!(!a.overlaps(b), "cells overlap: {a:?} and {b:?}");
        }
    }
    for w in &layout.wires {
        assert!(w.x1 == w.x2 || w.y1 == w.y2, "a slanted wire {w:?}");
        assert!(w.x1 <= w.x2, "a wire drawn backwards {w:?}");
        assert!(
            w.x2 <= layout.width && w.y1.max(w.y2) <= layout.height,
            "{w:?} outside"
        );
    }
    (layout.width, layout.height)
}

#[test]
fn thirty_wide_does_not_overlap_and_scrolls() {
    let mut items: Vec<Node> = (0..29)
        .map(|i| {
            no(
                i,
                sym(&format!("Sensor_{i}"), &format!("I{}.{}", i / 8, i % 8)),
            )
        })
        .collect();
    items.push(compare(29, "<=D", addr("VD100"), constant("123456")));
    let net = network(
        1,
        None,
        &[],
        rung(Some(Node::Series(items)), vec![out(30, addr("Q0.0"))]),
    );
    let (width, _) = assert_no_overlap(&net);
    assert!(width > 30 * 90, "not wrapped: {width}");
    assert_eq!(layout_network(&net).unwrap().elements.len(), 31);
}

#[test]
fn twenty_deep_does_not_overlap() {
    // Each level: (contact, deeper) in series, in parallel with a contact.
    let mut node = no(0, addr("I0.0"));
    let mut id = 1;
    for _ in 0..20 {
        let series = Node::Series(vec![no(id, addr("M0.0")), node]);
        node = Node::Parallel(vec![series, no(id + 1, addr("M0.1"))]);
        id += 2;
    }
    // And an output split nested 20 deep.
    let mut branch = out(id, addr("Q0.0"));
    id += 1;
    for _ in 0..20 {
        branch = Branch {
            path: vec![no(id, addr("M1.0"))],
            end: BranchEnd::Split(vec![branch, out(id + 1, addr("Q0.1"))]),
        };
        id += 2;
    }
    let net = network(1, None, &[], rung(Some(node), vec![branch]));
    let (_, height) = assert_no_overlap(&net);
    assert!(height > 21 * 84);
    let layout = layout_network(&net).unwrap();
    assert_eq!(layout.elements.len(), id as usize);
}

#[test]
fn snapshot_networks_do_not_overlap() {
    for (_, net) in snapshot_networks() {
        if matches!(net.body, Body::Rung(_)) {
            assert_no_overlap(&net);
        }
    }
}
