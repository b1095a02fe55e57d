//! Issue 15's drawing speed bar (criterion): a generated ladder of 1,000 networks of
//! realistic size (5-15 elements each: series contacts, parallel blocks, compare
//! contacts, MOVW and TON boxes, a CTU with its R path, output splits) drawn to one SVG
//! document (`svg_1000_networks`) and to the HTML page (`html_1000_networks`). The bar
//! for building and drawing together is < 100 ms; building is `build.rs`'s bench. The
//! setup checks the element counts and that every network is drawn, so a bench that
//! stopped measuring what it says fails. `cargo bench -p gutta-ladder --bench draw`
//! measures; `cargo test --benches` runs each once.

#![allow(clippy::disallowed_macros, reason = "a bench prints what it measured")]

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use gutta_ladder::html::{ladder_html, HtmlOptions};
use gutta_ladder::model::{
    Block, Body, BoxElement, BoxShape, Branch, BranchEnd, Coil, CoilKind, Contact, ContactKind,
    Ladder, Network, Node, Operand, Pin, Rung,
};
use gutta_ladder::svg::ladder_svg;

const NETWORKS: u32 = 1_000;

/// A small deterministic generator (xorshift), so every run draws the same ladder.
struct Random(u64);

impl Random {
    fn below(&mut self, n: u32) -> u32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 % u64::from(n)) as u32
    }
}

struct Generator {
    random: Random,
    next_id: u32,
}

impl Generator {
    fn id(&mut self) -> u32 {
        self.next_id += 1;
        self.next_id - 1
    }

    fn bit(&mut self, area: &str) -> Operand {
        let (byte, bit) = (self.random.below(16), self.random.below(8));
        let address = format!("{area}{byte}.{bit}");
        let symbol = (self.random.below(2) == 0).then(|| format!("Sym_{area}{byte}_{bit}"));
        Operand {
            written: symbol.clone().unwrap_or_else(|| address.clone()),
            address: Some(address),
            symbol,
            comment: None,
            data_type: None,
        }
    }

    fn word(&mut self) -> Operand {
        let address = format!("MW{}", 2 * self.random.below(50));
        Operand {
            written: address.clone(),
            address: Some(address),
            symbol: None,
            comment: None,
            data_type: None,
        }
    }

    fn contact(&mut self) -> Node {
        let id = self.id();
        let compare = self.random.below(8) == 0;
        let (kind, operands, relation) = if compare {
            let operands = vec![self.word(), constant("100")];
            (ContactKind::Compare, operands, Some(">=W".to_string()))
        } else if self.random.below(3) == 0 {
            (ContactKind::NormallyClosed, vec![self.bit("I")], None)
        } else {
            (ContactKind::NormallyOpen, vec![self.bit("I")], None)
        };
        Node::Contact(Contact {
            id,
            kind,
            mnemonic: "A".to_string(),
            immediate: false,
            operands,
            relation,
            line: id,
        })
    }

    /// A path of about `size` elements: contacts in series, sometimes a parallel block.
    fn path(&mut self, size: u32) -> Node {
        let mut items = Vec::new();
        let mut left = size.max(1);
        while left > 0 {
            if left >= 3 && self.random.below(3) == 0 {
                let a = Node::Series(vec![self.contact(), self.contact()]);
                items.push(Node::Parallel(vec![a, self.contact()]));
                left -= 3;
            } else {
                items.push(self.contact());
                left -= 1;
            }
        }
        if items.len() == 1 {
            items.pop().unwrap_or_else(|| self.contact())
        } else {
            Node::Series(items)
        }
    }

    fn coil(&mut self) -> Branch {
        let id = self.id();
        let kind = [CoilKind::Out, CoilKind::Set, CoilKind::Reset][self.random.below(3) as usize];
        let count = (kind != CoilKind::Out).then(|| constant("1"));
        Branch {
            path: vec![],
            end: BranchEnd::Coil(Coil {
                id,
                kind,
                mnemonic: "=".to_string(),
                operand: self.bit("Q"),
                count,
                line: id,
            }),
        }
    }

    fn boxed(&mut self, mnemonic: &str) -> BoxElement {
        let id = self.id();
        let (title, enable, pins, power_inputs) = match mnemonic {
            "TON" => (
                "T37".to_string(),
                "IN",
                vec![pin("PT", false, constant("50"))],
                vec![],
            ),
            "CTU" => {
                let reset = self.path(2);
                (
                    "C1".to_string(),
                    "CU",
                    vec![pin("PV", false, constant("10"))],
                    vec![("R".to_string(), reset)],
                )
            }
            _ => {
                let (a, b) = (self.word(), self.word());
                (
                    mnemonic.to_string(),
                    "EN",
                    vec![pin("IN", false, a), pin("OUT", true, b)],
                    vec![],
                )
            }
        };
        BoxElement {
            id,
            mnemonic: mnemonic.to_string(),
            title,
            pins,
            power_inputs,
            enable: enable.to_string(),
            output: Some(if enable == "EN" { "ENO" } else { "Q" }.to_string()),
            line: id,
            counted: None,
            resolution_ms: None,
            shape: BoxShape::Box,
        }
    }

    /// One network of 5-15 elements.
    fn network(&mut self, number: u32) -> Network {
        self.next_id = 0;
        let size = 5 + self.random.below(11);
        let shape = self.random.below(5);
        let input_size = size.saturating_sub(2).max(1);
        let input = self.path(input_size);
        let outputs = match shape {
            0 => {
                let movw = self.boxed("MOVW");
                let coil = self.coil();
                vec![
                    Branch {
                        path: vec![],
                        end: BranchEnd::Box(movw),
                    },
                    coil,
                ]
            }
            1 => {
                let ton = self.boxed("TON");
                vec![Branch {
                    path: vec![],
                    end: BranchEnd::Box(ton),
                }]
            }
            2 => {
                let ctu = self.boxed("CTU");
                vec![Branch {
                    path: vec![],
                    end: BranchEnd::Box(ctu),
                }]
            }
            _ => vec![self.coil(), self.coil()],
        };
        Network {
            number,
            title: Some(format!("network {number}")),
            comment: vec![],
            stl: vec![],
            line: number * 10,
            body: Body::Rung(Rung {
                input: Some(input),
                outputs,
            }),
            stl_code: vec![],
        }
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

fn pin(name: &str, output: bool, operand: Operand) -> Pin {
    Pin {
        name: name.to_string(),
        output,
        operand,
        input: None,
    }
}

fn generated_ladder() -> Ladder {
    let mut generator = Generator {
        random: Random(0x2545_F491_4F6C_DD1D),
        next_id: 0,
    };
    let networks = (1..=NETWORKS).map(|n| generator.network(n)).collect();
    Ladder {
        plc: "CPU-EC20".to_string(),
        blocks: vec![Block {
            name: "MAIN".to_string(),
            numbered: "OB1".to_string(),
            title: None,
            networks,
        }],
    }
}

fn bench_draw(c: &mut Criterion) {
    let ladder = generated_ladder();
    let svg = ladder_svg(&ladder);
    let html = ladder_html(&ladder, &HtmlOptions::default());
    let count = |text: &str, needle: &str| text.matches(needle).count();
    assert_eq!(count(&svg, "class=\"network\""), NETWORKS as usize);
    assert_eq!(count(&html, "class=\"network\""), NETWORKS as usize);
    let elements = count(&svg, "data-id=");
    assert!(
        (5 * NETWORKS as usize..=17 * NETWORKS as usize).contains(&elements),
        "{elements} elements: not 5-15 a network"
    );
    assert!(count(&svg, "class=\"box\"") > 100 && count(&svg, "data-kind=\"compare\"") > 100);

    c.bench_function("svg_1000_networks", |b| {
        b.iter(|| black_box(ladder_svg(black_box(&ladder))))
    });
    c.bench_function("html_1000_networks", |b| {
        b.iter(|| black_box(ladder_html(black_box(&ladder), &HtmlOptions::default())))
    });
}

/// The generated program of the front end's scaling benchmark
/// (`compiler/benches/scale_program`), cut to its first networks by size: checked once,
/// then built into the model and drawn to SVG, both timed (`build_and_draw_program`).
#[path = "../../compiler/benches/scale_program/mod.rs"]
#[allow(
    dead_code,
    reason = "the generator also serves the compiler's benchmark"
)]
mod scale_program;

fn bench_build_and_draw(c: &mut Criterion) {
    let target = scale_program::bench_target();
    // About 8 lines a network, with subroutines, an interrupt routine, data and system
    // blocks around: 10,000 lines hold more than 1,000 networks.
    let text = scale_program::generate(10_000);
    let checked = gutta_compiler::check_source(
        gutta_compiler::source::SourceFile::new("scale.lad", text),
        Some(&target),
    );
    assert!(!checked.has_errors(), "the generated program checks clean");
    let ladder = gutta_ladder::build(&checked);
    let networks: usize = ladder.blocks.iter().map(|b| b.networks.len()).sum();
    let drawn = ladder
        .blocks
        .iter()
        .flat_map(|b| &b.networks)
        .filter(|n| matches!(n.body, Body::Rung(_)))
        .count();
    assert!(networks >= 1_000, "{networks} networks");
    println!("build_and_draw_program: {networks} networks, {drawn} drawn as ladder");
    c.bench_function("build_and_draw_program", |b| {
        b.iter(|| {
            let ladder = gutta_ladder::build(black_box(&checked));
            black_box(ladder_svg(&ladder))
        })
    });
}

criterion_group!(benches, bench_draw, bench_build_and_draw);
criterion_main!(benches);
