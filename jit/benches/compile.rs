//! gutta-jit's figures: the compile time of 10,000 bit-logic steps (networks of
//! LD/A/AN/O/=) and of 10,000 mixed steps (moves, math, compares, a leaf CALL per
//! network), the machine code size of each, and the run time per executed instruction
//! of the compiled code. Medians of repeated runs. `cargo bench -p gutta-jit --bench
//! compile` measures; `cargo test --benches` only runs everything once.

#![allow(
    clippy::disallowed_methods,
    clippy::disallowed_types,
    clippy::disallowed_macros,
    reason = "a benchmark is a program: it reads its arguments, times and prints"
)]

use std::hint::black_box;
use std::time::Instant;

use gutta_jit::{compile, Arg, Arith, Combine, Function, Layout, Rel, Step};

const MEMORY: u32 = 4096;
const STEPS: usize = 10_000;

fn layout() -> Layout {
    Layout {
        memory_len: MEMORY,
        flags_at: 4000,
        stack_mask: 0x1FF,
        local: Some((4064, 32)),
    }
}

/// A cheap deterministic sequence of memory indices (no two networks alike).
struct Addresses(u32);

impl Addresses {
    fn next(&mut self, below: u32) -> u32 {
        self.0 = self.0.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (self.0 >> 8) % below
    }
}

/// Networks of Network, LD, A, AN, O, = until `STEPS` steps.
fn bit_logic() -> Vec<Function> {
    let mut a = Addresses(1);
    let mut steps = Vec::with_capacity(STEPS);
    while steps.len() + 6 <= STEPS {
        let mut bit = || (a.next(2048), (a.next(8)) as u8);
        let ((l, lb), (x, xb), (n, nb), (o, ob), (q, qb)) = (bit(), bit(), bit(), bit(), bit());
        steps.extend([
            Step::Network,
            Step::Ld { at: l, bit: lb },
            Step::A { at: x, bit: xb },
            Step::An { at: n, bit: nb },
            Step::O { at: o, bit: ob },
            Step::Assign {
                at: 2048 + q,
                bit: qb,
            },
        ]);
    }
    vec![Function { steps }]
}

/// Networks of LD, a compare, a move, math, a leaf CALL with two arguments and an =,
/// until `STEPS` steps; function 1 is the leaf.
fn mixed() -> Vec<Function> {
    let mut a = Addresses(7);
    let mut steps = Vec::with_capacity(STEPS);
    while steps.len() + 8 <= STEPS {
        let word = |a: &mut Addresses| 2 * a.next(1000);
        steps.extend([
            Step::Network,
            Step::Ld {
                at: a.next(2048),
                bit: a.next(8) as u8,
            },
            Step::Compare {
                combine: Combine::And,
                rel: Rel::Lt,
                a: word(&mut a),
                b: word(&mut a),
                width: 2,
            },
            Step::Move {
                src: word(&mut a),
                dst: word(&mut a),
                width: 2,
            },
            Step::Math {
                op: Arith::Add,
                src: word(&mut a),
                dst: word(&mut a),
                width: 2,
            },
            Step::Call {
                callee: 1,
                args: vec![
                    Arg {
                        var: word(&mut a),
                        param: 4064,
                        width: 2,
                        input: true,
                        output: false,
                        bits: None,
                    },
                    Arg {
                        var: word(&mut a),
                        param: 4066,
                        width: 2,
                        input: false,
                        output: true,
                        bits: None,
                    },
                ],
            },
            Step::Assign {
                at: 2048 + a.next(1024),
                bit: a.next(8) as u8,
            },
        ]);
    }
    let leaf = vec![
        Step::Network,
        Step::Ld { at: 0, bit: 0 },
        Step::Not,
        Step::Move {
            src: 4064,
            dst: 4066,
            width: 2,
        },
        Step::Math {
            op: Arith::Mul,
            src: 4064,
            dst: 4066,
            width: 2,
        },
    ];
    vec![Function { steps }, Function { steps: leaf }]
}

/// The scan benchmark's mixed program (vm/benches/scan.rs, bench-native `mixed`) as the
/// VM hands it over: networks of LD SM0.0, MOVW, +I, *I, LDW>=, MOVD, +D and a CALL of
/// ADD1 (an INT in, an INT out: LD SM0.0, MOVW #a,#r, +I 1,#r), the constants in memory,
/// on the VM's layout (32 bytes of L).
fn vm_mixed() -> (Layout, Vec<Function>) {
    let layout = Layout {
        memory_len: 13_056,
        flags_at: 12_241,
        stack_mask: 0x1FF,
        local: Some((13_024, 32)),
    };
    let (sm0, one, two, three, hundred) = (12_240, 12_512, 12_516, 12_518, 12_520);
    let mut steps = Vec::new();
    let mut net = 1u32;
    while steps.len() + 9 <= 8_190 {
        let (a, b, c) = ((net * 2) % 32, 32 + (net * 2) % 32, 64 + (net * 2) % 32);
        let word = |n: u32| 576 + n;
        steps.extend([
            Step::Network,
            Step::Ld { at: sm0, bit: 0 },
            Step::Move {
                src: word(a),
                dst: word(b),
                width: 2,
            },
            Step::Math {
                op: Arith::Add,
                src: three,
                dst: word(b),
                width: 2,
            },
            Step::Math {
                op: Arith::Mul,
                src: two,
                dst: word(b),
                width: 2,
            },
            Step::Compare {
                combine: Combine::Load,
                rel: Rel::Ge,
                a: word(b),
                b: hundred,
                width: 2,
            },
            Step::Move {
                src: 616,
                dst: 620,
                width: 4,
            },
            Step::Math {
                op: Arith::Add,
                src: one,
                dst: 620,
                width: 4,
            },
            Step::Call {
                callee: 1,
                args: vec![
                    Arg {
                        var: word(b),
                        param: 13_024,
                        width: 2,
                        input: true,
                        output: false,
                        bits: None,
                    },
                    Arg {
                        var: word(c),
                        param: 13_026,
                        width: 2,
                        input: false,
                        output: true,
                        bits: None,
                    },
                ],
            },
        ]);
        net += 1;
    }
    let add1 = vec![
        Step::Network,
        Step::Ld { at: sm0, bit: 0 },
        Step::Move {
            src: 13_024,
            dst: 13_026,
            width: 2,
        },
        Step::Math {
            op: Arith::Add,
            src: one,
            dst: 13_026,
            width: 2,
        },
    ];
    (layout, vec![Function { steps }, Function { steps: add1 }])
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

fn main() {
    let bench = std::env::args().any(|a| a == "--bench");
    let (compiles, batches, runs) = if bench { (15, 31, 200) } else { (1, 1, 1) };
    println!("\ngutta-jit: {STEPS} steps, median of {compiles} compiles, run time median of {batches} x {runs} runs");
    println!(
        "{:<10} {:>12} {:>12} {:>12} {:>14} {:>12}",
        "program", "compile ms", "code bytes", "bytes/step", "instr/run", "ns/instr"
    );
    let (vm_layout, vm_functions) = vm_mixed();
    for (name, layout, functions) in [
        ("bit logic", layout(), bit_logic()),
        ("mixed", layout(), mixed()),
        ("vm mixed", vm_layout, vm_functions),
    ] {
        let steps: usize = functions.iter().map(|f| f.steps.len()).sum();
        let mut times = Vec::new();
        let mut module = None;
        for _ in 0..compiles {
            let t = Instant::now();
            let m = compile(&layout, black_box(&functions)).expect("the benchmark compiles");
            times.push(t.elapsed().as_secs_f64() * 1e3);
            module = Some(m);
        }
        let module = module.expect("compiled at least once");
        let mut memory: Vec<u8> = (0..layout.memory_len)
            .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
            .collect();
        if name == "vm mixed" {
            // As the scan benchmark sets them: SM0.0 on, the constants, the INT inputs
            // MW0..MW30 large enough that every compare holds.
            memory[12_240] = 1;
            for (at, v) in [(12_512u32, 1u32), (12_516, 2), (12_518, 3), (12_520, 100)] {
                let bytes = v.to_le_bytes();
                let w = if at == 12_512 { 4 } else { 2 };
                memory[at as usize..at as usize + w].copy_from_slice(&bytes[..w]);
            }
            for n in 0..16 {
                memory[576 + 2 * n..578 + 2 * n].copy_from_slice(&1000u16.to_le_bytes());
            }
        }
        let mut stack = 0;
        let executed = module.run(0, &mut memory, &mut stack);
        let mut per = Vec::new();
        for _ in 0..batches {
            let mut total = 0;
            let t = Instant::now();
            for _ in 0..runs {
                total += module.run(0, black_box(&mut memory), &mut stack);
            }
            per.push(t.elapsed().as_secs_f64() * 1e9 / total as f64);
        }
        println!(
            "{:<10} {:>12.2} {:>12} {:>12.1} {:>14} {:>12.3}",
            name,
            median(times),
            module.code_bytes(),
            module.code_bytes() as f64 / steps as f64,
            executed,
            median(per)
        );
    }
}
