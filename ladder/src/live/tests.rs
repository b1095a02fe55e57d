//! Power flow on hand-built rungs: every contact kind, series, parallel, splits, boxes,
//! timers and counters, and the operand list.

use std::collections::{BTreeMap, BTreeSet};

use gutta_catalog::stdlib;
use gutta_format::{Symbol, SymbolTable};

use super::{operands, rung_power, Snapshot};
use crate::model::*;

fn op(address: &str) -> Operand {
    Operand {
        written: address.into(),
        address: Some(address.into()),
        symbol: None,
        comment: None,
        data_type: None,
    }
}

fn constant(text: &str) -> Operand {
    Operand {
        written: text.into(),
        address: None,
        symbol: None,
        comment: None,
        data_type: None,
    }
}

fn contact(id: u32, kind: ContactKind, operands: Vec<Operand>, relation: Option<&str>) -> Node {
    Node::Contact(Contact {
        id,
        kind,
        mnemonic: String::new(),
        immediate: false,
        operands,
        relation: relation.map(str::to_string),
        line: 1,
    })
}

fn no(id: u32, a: &str) -> Node {
    contact(id, ContactKind::NormallyOpen, vec![op(a)], None)
}

fn nc(id: u32, a: &str) -> Node {
    contact(id, ContactKind::NormallyClosed, vec![op(a)], None)
}

fn coil(id: u32, a: &str) -> Branch {
    Branch {
        path: vec![],
        end: BranchEnd::Coil(Coil {
            id,
            kind: CoilKind::Out,
            mnemonic: "=".into(),
            operand: op(a),
            count: None,
            line: 1,
        }),
    }
}

fn boxed(id: u32, mnemonic: &str, title: &str, pins: Vec<Operand>) -> BoxElement {
    BoxElement {
        id,
        mnemonic: mnemonic.into(),
        title: title.into(),
        pins: pins
            .into_iter()
            .map(|operand| Pin {
                name: "P".into(),
                output: false,
                operand,
                input: None,
            })
            .collect(),
        power_inputs: vec![],
        enable: "EN".into(),
        output: Some("ENO".into()),
        line: 1,
        counted: None,
        resolution_ms: None,
        shape: BoxShape::Box,
    }
}

fn rung(input: Node, outputs: Vec<Branch>) -> Rung {
    Rung {
        input: Some(input),
        outputs,
    }
}

/// The energized ids of `rung` with `values` (address = raw).
fn lit(rung: &Rung, values: &[(&str, u32)]) -> Vec<u32> {
    lit_with(rung, values, &SymbolTable::default())
}

fn lit_with(rung: &Rung, values: &[(&str, u32)], symbols: &SymbolTable) -> Vec<u32> {
    let target = stdlib::shared(stdlib::DEFAULT).unwrap();
    let values: BTreeMap<String, u32> = values.iter().map(|(a, v)| (a.to_string(), *v)).collect();
    let snapshot = Snapshot {
        target: &target,
        symbols,
        values: &values,
    };
    rung_power(rung, &snapshot).energized.into_iter().collect()
}

#[test]
fn normally_open_and_closed_contacts_in_series() {
    let r = rung(
        Node::Series(vec![no(0, "I0.0"), nc(1, "I0.1")]),
        vec![coil(2, "Q0.0")],
    );
    assert_eq!(lit(&r, &[("I0.0", 1), ("I0.1", 0)]), vec![0, 1, 2]);
    assert_eq!(lit(&r, &[("I0.0", 1), ("I0.1", 1)]), vec![0]);
    // The NC contact is closed but has no power in: it passes none.
    assert_eq!(lit(&r, &[("I0.0", 0), ("I0.1", 0)]), Vec::<u32>::new());
}

#[test]
fn parallel_branches_light_each_and_join_as_or() {
    let r = rung(
        Node::Series(vec![
            Node::Parallel(vec![no(0, "I0.0"), no(1, "I0.1")]),
            no(2, "I0.2"),
        ]),
        vec![coil(3, "Q0.0")],
    );
    assert_eq!(lit(&r, &[("I0.1", 1), ("I0.2", 1)]), vec![1, 2, 3]);
    assert_eq!(lit(&r, &[("I0.0", 1), ("I0.1", 1)]), vec![0, 1]);
    assert_eq!(lit(&r, &[("I0.2", 1)]), Vec::<u32>::new());
}

#[test]
fn not_inverts_power_and_edges_pass_none() {
    let not = rung(
        Node::Series(vec![
            no(0, "I0.0"),
            contact(1, ContactKind::Not, vec![], None),
        ]),
        vec![coil(2, "Q0.0")],
    );
    assert_eq!(lit(&not, &[]), vec![1, 2]);
    assert_eq!(lit(&not, &[("I0.0", 1)]), vec![0]);
    let edge = rung(
        Node::Series(vec![
            no(0, "I0.0"),
            contact(1, ContactKind::PositiveEdge, vec![], None),
        ]),
        vec![coil(2, "Q0.0")],
    );
    assert_eq!(lit(&edge, &[("I0.0", 1)]), vec![0]);
}

#[test]
fn compares_use_the_vm_types() {
    let cmp = |relation: &str, a: Operand, b: Operand| {
        rung(
            contact(0, ContactKind::Compare, vec![a, b], Some(relation)),
            vec![coil(1, "Q0.0")],
        )
    };
    // W is signed: 16#FFFF is -1, less than 5.
    let r = cmp("<W", op("MW0"), constant("5"));
    assert_eq!(lit(&r, &[("MW0", 0xFFFF)]), vec![0, 1]);
    assert_eq!(lit(&r, &[("MW0", 5)]), Vec::<u32>::new());
    // B is unsigned: 16#FF is 255, more than 5.
    let r = cmp(">B", op("MB0"), constant("16#05"));
    assert_eq!(lit(&r, &[("MB0", 0xFF)]), vec![0, 1]);
    let r = cmp(">=D", op("MD0"), op("MD4"));
    assert_eq!(lit(&r, &[("MD0", 7), ("MD4", 7)]), vec![0, 1]);
    assert_eq!(
        lit(&r, &[("MD0", (-8i32) as u32), ("MD4", 7)]),
        Vec::<u32>::new()
    );
    let r = cmp("<>R", op("MD0"), constant("1.5"));
    assert_eq!(lit(&r, &[("MD0", 1.5f32.to_bits())]), Vec::<u32>::new());
    assert_eq!(lit(&r, &[("MD0", 2.0f32.to_bits())]), vec![0, 1]);
}

#[test]
fn output_splits_carry_their_own_contacts() {
    let r = Rung {
        input: Some(no(0, "I1.0")),
        outputs: vec![Branch {
            path: vec![],
            end: BranchEnd::Split(vec![
                Branch {
                    path: vec![no(1, "I1.1")],
                    end: coil(2, "Q1.1").end,
                },
                Branch {
                    path: vec![nc(3, "I1.3")],
                    end: coil(4, "Q1.3").end,
                },
            ]),
        }],
    };
    assert_eq!(lit(&r, &[("I1.0", 1)]), vec![0, 3, 4]);
    assert_eq!(
        lit(&r, &[("I1.0", 1), ("I1.1", 1), ("I1.3", 1)]),
        vec![0, 1, 2]
    );
    assert_eq!(lit(&r, &[("I1.1", 1)]), Vec::<u32>::new());
}

#[test]
fn boxes_pass_en_to_eno_and_end_boxes_light_when_powered() {
    let r = rung(
        Node::Series(vec![
            no(0, "I0.0"),
            Node::Box(boxed(1, "MOVW", "MOVW", vec![])),
        ]),
        vec![coil(2, "Q0.0")],
    );
    assert_eq!(lit(&r, &[("I0.0", 1)]), vec![0, 1, 2]);
    assert_eq!(lit(&r, &[]), Vec::<u32>::new());
    let mut jump = boxed(1, "JMP", "JMP", vec![constant("1")]);
    jump.output = None;
    let r = rung(
        no(0, "I0.0"),
        vec![Branch {
            path: vec![],
            end: BranchEnd::Box(jump),
        }],
    );
    assert_eq!(lit(&r, &[("I0.0", 1)]), vec![0, 1]);
}

fn timer_rung(mnemonic: &str, title: &str, preset: Operand) -> Rung {
    rung(
        Node::Series(vec![
            no(0, "I0.0"),
            Node::Box(boxed(1, mnemonic, title, vec![preset])),
        ]),
        vec![coil(2, "Q0.0")],
    )
}

#[test]
fn timers_are_done_by_value_and_preset() {
    let ton = timer_rung("TON", "T5", constant("20"));
    assert_eq!(lit(&ton, &[("I0.0", 1), ("T5", 19)]), vec![0]);
    assert_eq!(lit(&ton, &[("I0.0", 1), ("T5", 20)]), vec![0, 1, 2]);
    // The preset may be a read operand.
    let ton = timer_rung("TON", "T5", op("MW4"));
    assert_eq!(lit(&ton, &[("I0.0", 1), ("T5", 20), ("MW4", 30)]), vec![0]);
    assert_eq!(
        lit(&ton, &[("I0.0", 1), ("T5", 30), ("MW4", 30)]),
        vec![0, 1, 2]
    );
    // TONR keeps its done output without IN.
    let tonr = timer_rung("TONR", "T5", constant("20"));
    assert_eq!(lit(&tonr, &[("T5", 25)]), vec![1, 2]);
    // TOF: on while IN, and while timing after IN fell; off once T reaches PT.
    let tof = timer_rung("TOF", "T5", constant("20"));
    assert_eq!(lit(&tof, &[("I0.0", 1)]), vec![0, 1, 2]);
    assert_eq!(lit(&tof, &[("T5", 3)]), vec![1, 2]);
    assert_eq!(lit(&tof, &[("T5", 20)]), Vec::<u32>::new());
    assert_eq!(lit(&tof, &[]), Vec::<u32>::new());
}

#[test]
fn counters_are_done_by_value_and_preset_and_a_symbol_names_one() {
    let ctu = timer_rung("CTU", "C1", constant("3"));
    assert_eq!(lit(&ctu, &[("C1", 2)]), Vec::<u32>::new());
    assert_eq!(lit(&ctu, &[("C1", 3)]), vec![1, 2]);
    let ctd = timer_rung("CTD", "C1", constant("3"));
    assert_eq!(lit(&ctd, &[("C1", 0)]), vec![1, 2]);
    assert_eq!(lit(&ctd, &[("C1", 1)]), Vec::<u32>::new());
    let symbols = SymbolTable::new(vec![Symbol {
        name: "Parts".into(),
        address: "C1".into(),
        data_type: None,
        comment: String::new(),
        origin: String::new(),
    }]);
    let named = timer_rung("CTUD", "Parts", constant("3"));
    assert_eq!(lit_with(&named, &[("C1", 4)], &symbols), vec![1, 2]);
}

#[test]
fn a_counters_reset_path_lights_its_own_contacts() {
    let mut ctu = boxed(2, "CTU", "C0", vec![constant("3")]);
    ctu.power_inputs = vec![("R".into(), no(1, "I2.4"))];
    let r = rung(
        Node::Series(vec![no(0, "I2.3"), Node::Box(ctu)]),
        vec![coil(3, "Q2.3")],
    );
    assert_eq!(lit(&r, &[("I2.4", 1)]), vec![1]);
}

#[test]
fn operands_are_every_address_once_in_drawing_order() {
    let target = stdlib::shared(stdlib::DEFAULT).unwrap();
    let mut ctu = boxed(2, "CTU", "C0", vec![op("MW10")]);
    ctu.power_inputs = vec![("R".into(), no(1, "I0.1"))];
    let network = |number, body| Network {
        number,
        title: None,
        comment: vec![],
        stl: vec![],
        line: 1,
        body,
        stl_code: vec![],
    };
    let ladder = Ladder {
        plc: stdlib::DEFAULT.into(),
        blocks: vec![Block {
            name: "MAIN".into(),
            numbered: "OB1".into(),
            title: None,
            networks: vec![
                network(
                    1,
                    Body::Rung(rung(
                        Node::Series(vec![no(0, "I0.0"), Node::Box(ctu)]),
                        vec![coil(3, "Q0.0")],
                    )),
                ),
                network(2, Body::Stl { reason: "x".into() }),
                network(3, Body::Rung(rung(nc(0, "I0.0"), vec![coil(1, "Q0.1")]))),
            ],
        }],
    };
    let got = operands(&ladder, &target, &SymbolTable::default());
    assert_eq!(got, ["I0.0", "I0.1", "C0", "MW10", "Q0.0", "Q0.1"]);
    let set: BTreeSet<&String> = got.iter().collect();
    assert_eq!(set.len(), got.len());
}
