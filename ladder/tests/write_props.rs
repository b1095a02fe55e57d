//! The writer over generated rungs (docs/ladder.md, "From ladder to STL"): any rung in
//! the builder's form (series and parallels flattened, branches as the builder leaves
//! them) of contacts of every join, NOT and edges, boxes in series (MOVW, a timer, a
//! counter with its R path), coils, boxes ending branches (with and without ENO) and
//! nested output splits is written as STL that the builder draws as the same rung, and
//! that rung is written as the same lines.

mod common;

use std::sync::OnceLock;

use gutta_catalog::InstructionSet;
use gutta_ladder::model::{
    Body, BoxElement, Branch, BranchEnd, Coil, CoilKind, Contact, ContactKind, Network, Node,
    Operand, Pin, Rung,
};
use proptest::prelude::*;

fn set() -> &'static InstructionSet {
    static SET: OnceLock<InstructionSet> = OnceLock::new();
    SET.get_or_init(|| common::checked("").target.instructions.clone())
}

fn operand(text: &str) -> Operand {
    Operand {
        written: text.to_string(),
        address: None,
        symbol: None,
        comment: None,
        data_type: None,
    }
}

fn contact(mnemonic: &str, kind: ContactKind, immediate: bool, ops: &[&str]) -> Node {
    Node::Contact(Contact {
        id: 0,
        kind,
        mnemonic: mnemonic.to_string(),
        immediate,
        operands: ops.iter().map(|o| operand(o)).collect(),
        relation: (kind == ContactKind::Compare).then(|| ">=W".to_string()),
        line: 0,
    })
}

/// A contact that can start a path (in any form: the writer picks the form).
fn load_contact() -> impl Strategy<Value = Node> {
    (0..4u8, 0..8u8).prop_map(|(k, bit)| {
        let bit = format!("I0.{bit}");
        match k {
            0 => contact("LD", ContactKind::NormallyOpen, false, &[&bit]),
            1 => contact("AN", ContactKind::NormallyClosed, false, &[&bit]),
            2 => contact("OI", ContactKind::NormallyOpen, true, &[&bit]),
            _ => contact("AW>=", ContactKind::Compare, false, &["MW10", "100"]),
        }
    })
}

/// A box of the catalog: a timer's or counter's number is its title, the rest pins.
fn boxed(mnemonic: &str, ops: &[&str], power_inputs: Vec<(String, Node)>) -> BoxElement {
    let spec = set().get(set().lookup(mnemonic).expect("in the catalog"));
    let numbered = spec.kind.is_some();
    let title = if numbered { ops[0] } else { mnemonic };
    let skip = usize::from(numbered);
    let pins = ops[skip..]
        .iter()
        .zip(&gutta_ladder::names::pin_sides(spec)[skip..])
        .map(|(o, s)| Pin {
            name: s.name.clone(),
            output: s.output,
            operand: operand(o),
            input: s.input.clone(),
        })
        .collect();
    BoxElement {
        id: 0,
        mnemonic: spec.mnemonic.clone(),
        title: title.to_string(),
        pins,
        power_inputs,
        enable: spec.power_inputs.first().cloned().unwrap_or_default(),
        output: spec.power_output.clone(),
        line: 0,
        counted: numbered.then(|| Box::new(operand(title))),
        resolution_ms: None,
        shape: gutta_ladder::build::box_shape(spec),
    }
}

/// `items` in series, flattened as the builder flattens.
fn series(items: Vec<Node>) -> Node {
    let mut out = Vec::new();
    for n in items {
        match n {
            Node::Series(v) => out.extend(v),
            other => out.push(other),
        }
    }
    if out.len() == 1 {
        return out.remove(0);
    }
    Node::Series(out)
}

fn parallel(items: Vec<Node>) -> Node {
    let mut out = Vec::new();
    for n in items {
        match n {
            Node::Parallel(v) => out.extend(v),
            other => out.push(other),
        }
    }
    Node::Parallel(out)
}

/// A path from the left rail.
fn path(depth: u32) -> BoxedStrategy<Node> {
    if depth == 0 {
        return load_contact().boxed();
    }
    prop_oneof![
        2 => load_contact(),
        1 => (path(depth - 1), prop::collection::vec(in_series(depth - 1), 1..3))
            .prop_map(|(first, rest)| series(std::iter::once(first).chain(rest).collect())),
        1 => prop::collection::vec(path(depth - 1), 2..4).prop_map(parallel),
    ]
    .boxed()
}

/// What can follow in series: a contact, NOT or an edge, a parallel, a box.
fn in_series(depth: u32) -> BoxedStrategy<Node> {
    let leaf = prop_oneof![
        4 => load_contact(),
        1 => Just(contact("NOT", ContactKind::Not, false, &[])),
        1 => Just(contact("EU", ContactKind::PositiveEdge, false, &[])),
        1 => Just(Node::Box(boxed("MOVW", &["1", "MW10"], Vec::new()))),
        1 => Just(Node::Box(boxed("TON", &["T37", "100"], Vec::new()))),
    ];
    if depth == 0 {
        return leaf.boxed();
    }
    prop_oneof![
        4 => leaf,
        1 => prop::collection::vec(path(depth - 1), 2..4).prop_map(parallel),
        1 => path(depth - 1).prop_map(|r| Node::Box(boxed(
            "CTU",
            &["C0", "3"],
            vec![("R".to_string(), r)],
        ))),
    ]
    .boxed()
}

fn end() -> impl Strategy<Value = BranchEnd> {
    prop_oneof![
        3 => (0..8u8).prop_map(|bit| BranchEnd::Coil(Coil {
            id: 0,
            kind: CoilKind::Out,
            mnemonic: "=".to_string(),
            operand: operand(&format!("Q0.{bit}")),
            count: None,
            line: 0,
        })),
        1 => Just(BranchEnd::Coil(Coil {
            id: 0,
            kind: CoilKind::Set,
            mnemonic: "S".to_string(),
            operand: operand("M0.0"),
            count: Some(operand("2")),
            line: 0,
        })),
        1 => Just(BranchEnd::Box(boxed("MOVW", &["2", "MW12"], Vec::new()))),
        1 => Just(BranchEnd::Box(boxed("JMP", &["1"], Vec::new()))),
    ]
}

/// Two or more branches at one junction; a split only after series elements of its
/// own (the builder merges the rest).
fn branches(depth: u32) -> BoxedStrategy<Vec<Branch>> {
    let branch = if depth == 0 {
        (prop::collection::vec(in_series(0), 0..2), end())
            .prop_map(|(path, end)| Branch { path, end })
            .boxed()
    } else {
        prop_oneof![
            3 => (prop::collection::vec(in_series(depth - 1), 0..2), end())
                .prop_map(|(path, end)| Branch { path, end }),
            1 => (prop::collection::vec(in_series(depth - 1), 1..3), branches(depth - 1))
                .prop_map(|(path, list)| Branch { path, end: BranchEnd::Split(list) }),
        ]
        .boxed()
    };
    prop::collection::vec(branch, 2..4).boxed()
}

fn rung() -> impl Strategy<Value = Rung> {
    let single = end().prop_map(|end| {
        vec![Branch {
            path: Vec::new(),
            end,
        }]
    });
    (path(2), prop_oneof![1 => single, 2 => branches(2)]).prop_map(|(input, outputs)| Rung {
        input: Some(input),
        outputs,
    })
}

fn network(rung: Rung) -> Network {
    Network {
        number: 1,
        title: None,
        comment: Vec::new(),
        stl: Vec::new(),
        line: 0,
        body: Body::Rung(rung),
        stl_code: Vec::new(),
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, ..ProptestConfig::default() })]
    #[test]
    fn generated_rungs_round_trip_through_stl(rung in rung()) {
        let lines = gutta_ladder::write::rung(set(), &rung).expect("a well-formed rung writes");
        let built = common::ladder(&format!("NETWORK 1\n{}", lines.join("\n")));
        let again = &built.blocks[0].networks[0];
        prop_assert_eq!(
            common::render(again),
            common::render(&network(rung)),
            "written as:\n{}",
            lines.join("\n")
        );
        let Body::Rung(rung_again) = &again.body else { unreachable!("rendered as a rung") };
        prop_assert_eq!(gutta_ladder::write::rung(set(), rung_again).expect("writes"), lines);
    }
}
