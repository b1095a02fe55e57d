//! The generic families' Steps (word logic, INC/DEC, divisions, MUL/DIV, shifts and
//! rotates, conversions, REAL math and compares, constants, SWAP, LDS, NOP) on fixed
//! cases: compiled code against the reference interpreter on every case, and against
//! the value written here on the edges (i16::MIN, overflow, division by zero, shift
//! counts 0 and over the width, NaN and infinities); `compile`'s refusals.

use gutta_jit::{
    compile, reference, Combine, Convert, Function, JitError, Layout, Logic, Module, RealOp, Rel,
    Shift, Step,
};

const MEMORY: u32 = 64;
const FLAGS: u32 = 60;
/// The bit that gives power flow (LD 20.0 before the step).
const POWER: u32 = 20;
/// Operand places: A (dst, or the one operand) at 0, B (src) at 8, the count byte at 16.
const A: u32 = 0;
const B: u32 = 8;
const COUNT: u32 = 16;

fn layout() -> Layout {
    Layout {
        memory_len: MEMORY,
        flags_at: FLAGS,
        stack_mask: 0x1FF,
        local: Some((40, 16)),
    }
}

/// Memory with A, B (little-endian u32), the count byte, the flags byte and power.
fn memory(a: u32, b: u32, count: u8, flags: u8, power: bool) -> Vec<u8> {
    let mut m = vec![0x77u8; MEMORY as usize];
    m[A as usize..A as usize + 4].copy_from_slice(&a.to_le_bytes());
    m[B as usize..B as usize + 4].copy_from_slice(&b.to_le_bytes());
    m[COUNT as usize] = count;
    m[FLAGS as usize] = flags;
    m[POWER as usize] = u8::from(power);
    m
}

/// A compiled function and what it was compiled from.
struct Prepared {
    layout: Layout,
    functions: Vec<Function>,
    module: Module,
}

impl Prepared {
    fn new(steps: Vec<Step>) -> Prepared {
        let layout = layout();
        let functions = vec![Function { steps }];
        let module = compile(&layout, &functions).expect("compiles");
        Prepared {
            layout,
            functions,
            module,
        }
    }

    /// `step` after LD POWER.0.
    fn powered(step: Step) -> Prepared {
        Prepared::new(vec![Step::Ld { at: POWER, bit: 0 }, step])
    }

    /// Run compiled and by the reference on `mem`; they must agree (memory, stack,
    /// count). Returns the memory and the stack.
    fn run(&self, mem: &[u8], stack: u32) -> (Vec<u8>, u32) {
        let (mut jm, mut js) = (mem.to_vec(), stack);
        let jc = self.module.run(0, &mut jm, &mut js);
        let (mut rm, mut rs) = (mem.to_vec(), stack);
        let rc = reference::run(&self.layout, &self.functions, 0, &mut rm, &mut rs);
        assert_eq!(jm, rm, "memory: {:?} on {mem:?}", self.functions[0]);
        assert_eq!(js, rs, "stack: {:?}", self.functions[0]);
        assert_eq!(jc, rc, "count: {:?}", self.functions[0]);
        (jm, js)
    }
}

/// Run `step` after LD POWER.0 (compiled and by the reference: `Prepared::run`).
fn run(step: Step, mem: &[u8]) -> (Vec<u8>, u32) {
    Prepared::powered(step).run(mem, 0)
}

fn run_steps(steps: Vec<Step>, mem: &[u8], stack: u32) -> (Vec<u8>, u32) {
    Prepared::new(steps).run(mem, stack)
}

fn word(m: &[u8], at: u32) -> u16 {
    u16::from_le_bytes([m[at as usize], m[at as usize + 1]])
}

fn dword(m: &[u8], at: u32) -> u32 {
    u32::from_le_bytes([
        m[at as usize],
        m[at as usize + 1],
        m[at as usize + 2],
        m[at as usize + 3],
    ])
}

/// Values that hit the edges of every width (and REAL specials as bits).
const VALUES: [u32; 22] = [
    0,
    1,
    2,
    7,
    0x7F,
    0x80,
    0xFF,
    0x100,
    0x7FFF,
    0x8000,
    0xFFFF,
    0x1_0000,
    0x7FFF_FFFF,
    0x8000_0000,
    0xFFFF_FFFF,
    0x1234_9876,
    0x0000_9999,
    0x0000_270F, // 9999
    0x3F00_0000, // 0.5
    0xBFC0_0000, // -1.5
    0x7F80_0000, // +inf
    0x7FC0_0001, // NaN
];

/// More REALs: rounding edges, huge, tiny, negative zero.
const REALS: [f32; 16] = [
    0.0,
    -0.0,
    0.5,
    -0.5,
    1.5,
    2.5,
    -2.5,
    0.499_999_97,
    8_388_607.5,
    2_147_483_520.0,
    2_147_483_648.0,
    -2_147_483_648.0,
    -2_147_483_904.0,
    f32::INFINITY,
    f32::NEG_INFINITY,
    f32::NAN,
];

/// Every boxed generic step of every kind and width, on A, B and COUNT.
fn boxed_steps() -> Vec<Step> {
    let mut steps = Vec::new();
    for width in [1, 2, 4] {
        for op in [Logic::And, Logic::Or, Logic::Xor] {
            steps.push(Step::Logic {
                op,
                src: B,
                dst: A,
                width,
            });
        }
        steps.push(Step::Invert { at: A, width });
        steps.push(Step::IncDec {
            at: A,
            width,
            up: true,
        });
        steps.push(Step::IncDec {
            at: A,
            width,
            up: false,
        });
        for op in [
            Shift::Right,
            Shift::Left,
            Shift::RotateRight,
            Shift::RotateLeft,
        ] {
            steps.push(Step::Shift {
                op,
                at: A,
                width,
                count: COUNT,
            });
        }
        steps.push(Step::Const {
            value: 0xA1B2_C3D4,
            dst: A,
            width,
        });
    }
    for width in [2, 4] {
        steps.push(Step::Divide {
            src: B,
            dst: A,
            width,
        });
    }
    steps.push(Step::MulWide { src: B, dst: A });
    steps.push(Step::DivWide { src: B, dst: A });
    for op in Convert::ALL {
        steps.push(Step::Convert { op, src: B, dst: A });
    }
    for op in [RealOp::Add, RealOp::Sub, RealOp::Mul, RealOp::Div] {
        steps.push(Step::RealMath { op, src: B, dst: A });
    }
    steps.push(Step::Sqrt { src: B, dst: A });
    steps.push(Step::Swap { at: A });
    steps
}

#[test]
fn every_boxed_step_agrees_with_the_reference_on_edge_values() {
    let counts = [0u8, 1, 7, 8, 9, 15, 16, 17, 31, 32, 33, 255];
    for step in boxed_steps() {
        let p = Prepared::powered(step);
        for &a in &VALUES {
            for &b in &VALUES {
                let count = counts[(a ^ b.rotate_left(3)) as usize % counts.len()];
                for flags in [0x00, 0xFF, 0xA5] {
                    p.run(&memory(a, b, count, flags, true), 0);
                }
            }
        }
        for &x in &REALS {
            for &y in &REALS {
                p.run(&memory(x.to_bits(), y.to_bits(), 3, 0x5A, true), 0);
            }
        }
    }
}

#[test]
fn shift_counts_from_0_to_255_on_every_width() {
    for step in boxed_steps() {
        if !matches!(step, Step::Shift { .. }) {
            continue;
        }
        let p = Prepared::powered(step);
        for count in 0..=255u8 {
            for a in [0x8000_0001, 0xFFFF_FFFF, 0x5A5A_A5A5, 0x0000_0080] {
                p.run(&memory(a, 0, count, 0x04, true), 0);
            }
        }
    }
}

#[test]
fn without_power_flow_nothing_changes() {
    for step in boxed_steps() {
        let m = memory(0x8000_0000, 0, 3, 0xC3, false);
        let (after, stack) = run(step.clone(), &m);
        assert_eq!(after, m, "{step:?}");
        assert_eq!(stack, 0);
    }
}

#[test]
fn steps_whose_result_covers_the_flags_byte() {
    for step in boxed_steps() {
        let moved = match step {
            Step::Logic { op, width, .. } => Step::Logic {
                op,
                src: B,
                dst: FLAGS - 1,
                width,
            },
            Step::Invert { width, .. } => Step::Invert { at: FLAGS, width },
            Step::IncDec { width, up, .. } => Step::IncDec {
                at: FLAGS - 1,
                width,
                up,
            },
            Step::Shift {
                op, width, count, ..
            } => Step::Shift {
                op,
                at: FLAGS,
                width,
                count,
            },
            Step::Divide { width, .. } => Step::Divide {
                src: B,
                dst: FLAGS,
                width,
            },
            Step::Convert { op, .. } => Step::Convert {
                op,
                src: FLAGS - 1,
                dst: FLAGS - 1,
            },
            Step::RealMath { op, .. } => Step::RealMath {
                op,
                src: FLAGS - 2,
                dst: FLAGS - 1,
            },
            other => other,
        };
        let p = Prepared::powered(moved);
        for flags in [0x00, 0x08, 0x40, 0xFF, 0x7F] {
            for b in [0, 1, 0xFFFF_FFFF, 0x3F80_0000] {
                p.run(&memory(0x1234, b, 4, flags, true), 0);
            }
        }
    }
}

#[test]
fn word_logic_and_invert_values_and_flags() {
    let (m, _) = run(
        Step::Logic {
            op: Logic::And,
            src: B,
            dst: A,
            width: 2,
        },
        &memory(0x1111_F0F0, 0x2222_0F0F, 0, 0xFF, true),
    );
    // Result 0 in 2 bytes: zero set, overflow and negative cleared, 3..7 kept; the
    // bytes past the word untouched.
    assert_eq!(
        (word(&m, A), word(&m, A + 2), m[FLAGS as usize]),
        (0, 0x1111, 0xF9)
    );
    let (m, _) = run(
        Step::Logic {
            op: Logic::Xor,
            src: B,
            dst: A,
            width: 1,
        },
        &memory(0x0F, 0xFF, 0, 0x00, true),
    );
    assert_eq!((m[A as usize], m[FLAGS as usize]), (0xF0, 0x00));
    let (m, _) = run(
        Step::Invert { at: A, width: 4 },
        &memory(0xFFFF_FFFF, 0, 0, 0x06, true),
    );
    assert_eq!((dword(&m, A), m[FLAGS as usize]), (0, 0x01));
}

#[test]
fn inc_and_dec_wrap_with_their_flags() {
    let inc = |width, up, a: u32, flags: u8| {
        let (m, _) = run(
            Step::IncDec { at: A, width, up },
            &memory(a, 0, 0, flags, true),
        );
        (dword(&m, A), m[FLAGS as usize])
    };
    // INCB 255: 0, zero and overflow, negative cleared (unsigned bytes).
    assert_eq!(inc(1, true, 0xAAAA_AAFF, 0x04), (0xAAAA_AA00, 0x03));
    // DECB 0: 255, overflow.
    assert_eq!(inc(1, false, 0x00, 0x00), (0xFF, 0x02));
    // INCW 32767: -32768, overflow and negative.
    assert_eq!(inc(2, true, 0x7FFF, 0x00).0 & 0xFFFF, 0x8000);
    assert_eq!(inc(2, true, 0x7FFF, 0x00).1, 0x06);
    // DECW -32768 (i16::MIN): 32767, overflow.
    assert_eq!(inc(2, false, 0x8000, 0xF0).1, 0xF2);
    // DECD 1: 0, zero.
    assert_eq!(inc(4, false, 1, 0xFF), (0, 0xF9));
    // INCD -1: 0, zero, no overflow.
    assert_eq!(inc(4, true, 0xFFFF_FFFF, 0x00), (0, 0x01));
}

#[test]
fn divisions_by_zero_and_the_one_overflow() {
    let div = |width, a: u32, b: u32, flags: u8| {
        let (m, _) = run(
            Step::Divide {
                src: B,
                dst: A,
                width,
            },
            &memory(a, b, 0, flags, true),
        );
        (dword(&m, A), m[FLAGS as usize])
    };
    // By zero: OUT unchanged, SM1.3 set, SM1.0..2 cleared, others kept.
    assert_eq!(div(2, 0x1234_0005, 0, 0xF7), (0x1234_0005, 0xF8));
    assert_eq!(div(4, 5, 0, 0x00), (5, 0x08));
    // MIN / -1: OUT unchanged, overflow, SM1.3 cleared.
    assert_eq!(div(2, 0x8000, 0xFFFF, 0x08), (0x8000, 0x02));
    assert_eq!(div(4, 0x8000_0000, 0xFFFF_FFFF, 0x0D), (0x8000_0000, 0x02));
    // -7 / 2 = -3 (toward zero), negative; the high word untouched.
    assert_eq!(div(2, 0x5555_FFF9, 2, 0x08), (0x5555_FFFD, 0x04));
    // MUL: -2 * 3 = -6 as a DINT from the low word of OUT.
    let (m, _) = run(
        Step::MulWide { src: B, dst: A },
        &memory(0x7FFF_FFFE, 3, 0, 0, true),
    );
    assert_eq!((dword(&m, A) as i32, m[FLAGS as usize]), (-6, 0x04));
    // DIV: -7 / 2: quotient -3 low, remainder -1 high.
    let (m, _) = run(
        Step::DivWide { src: B, dst: A },
        &memory(0x0000_FFF9, 2, 0, 0x08, true),
    );
    assert_eq!((dword(&m, A), m[FLAGS as usize]), (0xFFFF_FFFD, 0x04));
    let (m, _) = run(
        Step::DivWide { src: B, dst: A },
        &memory(0x0000_8000, 0xFFFF, 0, 0x00, true),
    );
    assert_eq!((dword(&m, A), m[FLAGS as usize]), (0x8000, 0x02));
}

#[test]
fn shifts_and_rotates_values_and_the_bit_moved_out() {
    let shift = |op, width, a: u32, n: u8, flags: u8| {
        let (m, _) = run(
            Step::Shift {
                op,
                at: A,
                width,
                count: COUNT,
            },
            &memory(a, 0, n, flags, true),
        );
        (dword(&m, A), m[FLAGS as usize])
    };
    // SRW 1: bit 0 moved out; negative kept.
    assert_eq!(shift(Shift::Right, 2, 0x0003, 1, 0x04), (0x0001, 0x06));
    // SRW 16: all out, the last one bit 15.
    assert_eq!(shift(Shift::Right, 2, 0x8000, 16, 0x00), (0, 0x03));
    // SRW 17: 0, nothing moved out counts.
    assert_eq!(shift(Shift::Right, 2, 0xFFFF, 17, 0x00), (0, 0x01));
    // SLB 0: unchanged, flag 1 cleared.
    assert_eq!(shift(Shift::Left, 1, 0x81, 0, 0x02).0 & 0xFF, 0x81);
    assert_eq!(shift(Shift::Left, 1, 0x81, 0, 0x02).1, 0x00);
    // SLD 1 of 0x80000001: bit 31 out.
    assert_eq!(shift(Shift::Left, 4, 0x8000_0001, 1, 0x00), (2, 0x02));
    // SLD 32: 0, bit 0 was the last out.
    assert_eq!(shift(Shift::Left, 4, 0x0000_0001, 32, 0x00), (0, 0x03));
    // RRW 1 of 1: 0x8000, the top bit of the result.
    assert_eq!(
        shift(Shift::RotateRight, 2, 0x0001, 1, 0x00).0 & 0xFFFF,
        0x8000
    );
    assert_eq!(shift(Shift::RotateRight, 2, 0x0001, 1, 0x00).1, 0x02);
    // RLB 9 = 1 (mod 8).
    assert_eq!(shift(Shift::RotateLeft, 1, 0x80, 9, 0x00).0 & 0xFF, 0x01);
    // RRD 32 = 0: unchanged, flag 1 cleared.
    assert_eq!(
        shift(Shift::RotateRight, 4, 0x8000_0000, 32, 0x02),
        (0x8000_0000, 0x00)
    );
}

#[test]
fn conversions_store_only_what_fits() {
    let conv = |op, b: u32, flags: u8| {
        let (m, _) = run(
            Step::Convert { op, src: B, dst: A },
            &memory(0xDEAD_BEEF, b, 0, flags, true),
        );
        (dword(&m, A), m[FLAGS as usize])
    };
    assert_eq!(conv(Convert::Bti, 0xFF, 0), (0xDEAD_00FF, 0));
    assert_eq!(conv(Convert::Itb, 255, 0x02), (0xDEAD_BEFF, 0x00));
    assert_eq!(conv(Convert::Itb, 256, 0x00), (0xDEAD_BEEF, 0x02));
    assert_eq!(conv(Convert::Itb, 0xFFFF, 0x00), (0xDEAD_BEEF, 0x02));
    assert_eq!(conv(Convert::Itd, 0x8000, 0), (0xFFFF_8000, 0));
    assert_eq!(conv(Convert::Dti, 0xFFFF_8000, 0x02), (0xDEAD_8000, 0x00));
    assert_eq!(conv(Convert::Dti, 0x0000_8000, 0x00), (0xDEAD_BEEF, 0x02));
    assert_eq!(conv(Convert::Dtr, 16_777_217, 0).0, 16_777_216f32.to_bits());
    assert_eq!(conv(Convert::Round, 2.5f32.to_bits(), 0).0, 3);
    assert_eq!(
        conv(Convert::Round, (-2.5f32).to_bits(), 0).0,
        (-3i32) as u32
    );
    assert_eq!(conv(Convert::Round, 0.499_999_97f32.to_bits(), 0).0, 0);
    assert_eq!(
        conv(Convert::Trunc, (-2.7f32).to_bits(), 0).0,
        (-2i32) as u32
    );
    assert_eq!(
        conv(Convert::Trunc, f32::NAN.to_bits(), 0),
        (0xDEAD_BEEF, 0x02)
    );
    assert_eq!(
        conv(Convert::Round, 2_147_483_648f32.to_bits(), 0),
        (0xDEAD_BEEF, 0x02)
    );
    assert_eq!(
        conv(Convert::Trunc, (-2_147_483_648f32).to_bits(), 0x02),
        (0x8000_0000, 0x00)
    );
    assert_eq!(
        conv(Convert::Bcdi, 0x9876, 0x40),
        (0xDEAD_0000 | 9876, 0x00)
    );
    assert_eq!(conv(Convert::Bcdi, 0x12A4, 0x00), (0xDEAD_BEEF, 0x40));
    assert_eq!(conv(Convert::Ibcd, 9999, 0x40), (0xDEAD_9999, 0x00));
    assert_eq!(conv(Convert::Ibcd, 10_000, 0x00), (0xDEAD_BEEF, 0x40));
    assert_eq!(conv(Convert::Ibcd, 0xFFFF, 0x00), (0xDEAD_BEEF, 0x40));
    // SEG of every nibble (the byte's high nibble ignored), DECO, ENCO.
    let segments = [
        0x3F, 0x06, 0x5B, 0x4F, 0x66, 0x6D, 0x7D, 0x07, 0x7F, 0x6F, 0x77, 0x7C, 0x39, 0x5E, 0x79,
        0x71,
    ];
    for (k, pattern) in segments.into_iter().enumerate() {
        assert_eq!(
            conv(Convert::Seg, 0xA0 | k as u32, 0),
            (0xDEAD_BE00 | pattern, 0)
        );
    }
    assert_eq!(conv(Convert::Deco, 0xFF, 0), (0xDEAD_8000, 0));
    assert_eq!(conv(Convert::Deco, 0x10, 0), (0xDEAD_0001, 0));
    assert_eq!(conv(Convert::Enco, 0x0000_8000, 0x02), (0xDEAD_BE0F, 0x00));
    assert_eq!(conv(Convert::Enco, 0x0001_0000, 0x00), (0xDEAD_BEEF, 0x02));
}

#[test]
fn real_math_flags_nan_infinity_and_division_by_zero() {
    let real = |op, a: f32, b: f32, flags: u8| {
        let (m, _) = run(
            Step::RealMath { op, src: B, dst: A },
            &memory(a.to_bits(), b.to_bits(), 0, flags, true),
        );
        (f32::from_bits(dword(&m, A)), m[FLAGS as usize])
    };
    assert_eq!(real(RealOp::Add, 1.5, 2.25, 0xFF), (3.75, 0xF8));
    assert_eq!(real(RealOp::Sub, 1.0, 3.0, 0x00), (-2.0, 0x04));
    assert_eq!(real(RealOp::Mul, 0.0, -5.0, 0x00).1, 0x01);
    assert_eq!(
        real(RealOp::Mul, f32::MAX, 2.0, 0x00),
        (f32::INFINITY, 0x02)
    );
    let (nan, flags) = real(RealOp::Sub, f32::INFINITY, f32::INFINITY, 0x00);
    assert!(nan.is_nan());
    assert_eq!(flags, 0x02);
    // By zero (either sign): OUT unchanged, SM1.3.
    assert_eq!(real(RealOp::Div, 7.0, -0.0, 0x07), (7.0, 0x08));
    assert_eq!(real(RealOp::Div, 7.0, 2.0, 0x08), (3.5, 0x00));
    // Two NaNs of different payloads: the compiled code and the reference give the
    // same NaN (x86: the first operand's, quieted).
    for op in [RealOp::Add, RealOp::Sub, RealOp::Mul, RealOp::Div] {
        for (a, b) in [(0x7FC0_0001, 0xFFC0_0002), (0xFF80_0003, 0x7FA0_0000)] {
            run(
                Step::RealMath { op, src: B, dst: A },
                &memory(a, b, 0, 0, true),
            );
        }
    }
    let (m, _) = run(
        Step::Sqrt { src: B, dst: A },
        &memory(0, (-4.0f32).to_bits(), 0, 0x04, true),
    );
    assert!(f32::from_bits(dword(&m, A)).is_nan());
    assert_eq!(m[FLAGS as usize], 0x02);
}

#[test]
fn real_compares_with_nan_and_every_combine() {
    let rels = [Rel::Eq, Rel::Ne, Rel::Lt, Rel::Le, Rel::Gt, Rel::Ge];
    for combine in [Combine::Load, Combine::And, Combine::Or] {
        for rel in rels {
            let p = Prepared::new(vec![Step::CompareReal {
                combine,
                rel,
                a: A,
                b: B,
            }]);
            for &x in &REALS {
                for &y in &REALS {
                    for stack in [0, 1, 2, 3, 0x1FF] {
                        p.run(&memory(x.to_bits(), y.to_bits(), 0, 0, true), stack);
                    }
                }
            }
        }
    }
    // NaN: only <> holds.
    let nan = memory(f32::NAN.to_bits(), f32::NAN.to_bits(), 0, 0, true);
    let pushed = |rel| {
        run_steps(
            vec![Step::CompareReal {
                combine: Combine::Load,
                rel,
                a: A,
                b: B,
            }],
            &nan,
            0,
        )
        .1
    };
    assert_eq!(rels.map(pushed), [0, 1, 0, 0, 0, 0]);
}

#[test]
fn const_swap_lds_and_nop() {
    let (m, _) = run(
        Step::Const {
            value: 0xA1B2_C3D4,
            dst: A,
            width: 2,
        },
        &memory(0, 0, 0, 0, true),
    );
    assert_eq!(dword(&m, A), 0x0000_C3D4);
    let (m, _) = run(Step::Swap { at: A }, &memory(0x5555_1234, 0, 0, 0, true));
    assert_eq!(dword(&m, A), 0x5555_3412);
    for n in [0u16, 1, 2, 8, 9, 31, 32, 255] {
        for stack in [0, 1, 0x2, 0x100, 0x155, 0x1FF, 0xAAA] {
            let (_, s) = run_steps(vec![Step::Lds { n }], &memory(0, 0, 0, 0, true), stack);
            let level = if n < 32 { (stack >> n) & 1 } else { 0 };
            assert_eq!(s, ((stack << 1) | level) & 0x1FF, "LDS {n} of {stack:#x}");
            let (_, s) = run_steps(vec![Step::Nop], &memory(0, 0, 0, 0, true), stack);
            assert_eq!(s, stack);
        }
    }
}

/// ENI/DISI: the byte is stored with power flow and without, the stack kept; a store
/// into the flags byte is what a later flag-writing step keeps.
#[test]
fn store_writes_its_byte_whatever_the_power_flow() {
    for power in [false, true] {
        for value in [0u8, 1, 0xA5] {
            let (m, s) = run(Step::Store { at: A, value }, &memory(0, 0, 0, 0, power));
            assert_eq!(m[A as usize], value, "power {power}");
            assert_eq!(m[A as usize + 1], 0, "only one byte");
            assert_eq!(s, u32::from(power));
        }
    }
    let (m, _) = Prepared::new(vec![
        Step::Ld { at: POWER, bit: 0 },
        Step::Store {
            at: FLAGS,
            value: 0xF0,
        },
        Step::IncDec {
            at: A,
            width: 2,
            up: true,
        },
    ])
    .run(&memory(0, 0, 0, 0x0F, true), 0);
    assert_eq!(
        m[FLAGS as usize], 0xF0,
        "flags 0-2 of INC (all 0), the rest stored"
    );
}

#[test]
fn out_of_range_and_bad_widths_are_refused() {
    let layout = layout();
    let refused = |step: Step| compile(&layout, &[Function { steps: vec![step] }]).err();
    let out = |at, width| JitError::OutOfRange {
        function: 0,
        step: 0,
        at,
        width,
    };
    assert_eq!(
        refused(Step::Logic {
            op: Logic::Or,
            src: 0,
            dst: MEMORY - 1,
            width: 2
        }),
        Some(out(MEMORY - 1, 2))
    );
    assert_eq!(
        refused(Step::Invert { at: 0, width: 3 }),
        Some(JitError::Width {
            function: 0,
            step: 0,
            width: 3
        })
    );
    assert_eq!(
        refused(Step::Divide {
            src: 0,
            dst: 0,
            width: 1
        }),
        Some(JitError::Width {
            function: 0,
            step: 0,
            width: 1
        })
    );
    assert_eq!(
        refused(Step::MulWide {
            src: 0,
            dst: MEMORY - 3
        }),
        Some(out(MEMORY - 3, 4))
    );
    assert_eq!(
        refused(Step::Shift {
            op: Shift::Left,
            at: 0,
            width: 1,
            count: MEMORY
        }),
        Some(out(MEMORY, 1))
    );
    assert_eq!(
        refused(Step::Convert {
            op: Convert::Itd,
            src: 0,
            dst: MEMORY - 2
        }),
        Some(out(MEMORY - 2, 4))
    );
    assert_eq!(
        refused(Step::Convert {
            op: Convert::Dti,
            src: MEMORY - 2,
            dst: 0
        }),
        Some(out(MEMORY - 2, 4))
    );
    assert_eq!(
        refused(Step::RealMath {
            op: RealOp::Div,
            src: u32::MAX,
            dst: 0
        }),
        Some(out(u32::MAX, 4))
    );
    assert_eq!(
        refused(Step::CompareReal {
            combine: Combine::Or,
            rel: Rel::Eq,
            a: 0,
            b: MEMORY - 3
        }),
        Some(out(MEMORY - 3, 4))
    );
    assert_eq!(
        refused(Step::Const {
            value: 1,
            dst: MEMORY,
            width: 1
        }),
        Some(out(MEMORY, 1))
    );
    assert_eq!(
        refused(Step::Swap { at: MEMORY - 1 }),
        Some(out(MEMORY - 1, 2))
    );
    assert_eq!(refused(Step::Lds { n: u16::MAX }), None);
}

#[test]
fn generic_steps_in_a_callee_keep_the_callers_l_bytes() {
    // A callee that writes L through every kind of step: the caller's L bytes it touches
    // are saved and restored around the call (lower.rs `accesses`).
    let layout = layout();
    let l = 40;
    let callee = Function {
        steps: std::iter::once(Step::Ld { at: POWER, bit: 0 })
            .chain(boxed_steps())
            .map(|s| match s {
                Step::Logic { op, width, .. } => Step::Logic {
                    op,
                    src: l + 4,
                    dst: l,
                    width,
                },
                Step::Invert { width, .. } => Step::Invert { at: l + 8, width },
                Step::Shift { op, width, .. } => Step::Shift {
                    op,
                    at: l + 4,
                    width,
                    count: l + 12,
                },
                Step::Convert { op, .. } => Step::Convert {
                    op,
                    src: l,
                    dst: l + 8,
                },
                Step::RealMath { op, .. } => Step::RealMath {
                    op,
                    src: l + 4,
                    dst: l + 12,
                },
                Step::Const { value, width, .. } => Step::Const {
                    value,
                    dst: l + 10,
                    width,
                },
                other => other,
            })
            .collect(),
    };
    let mut steps = vec![Step::Ld { at: POWER, bit: 0 }];
    steps.push(Step::Lps);
    steps.push(Step::Call {
        callee: 1,
        args: Vec::new(),
    });
    let functions = vec![Function { steps }, callee];
    let module = compile(&layout, &functions).expect("compiles");
    let mut mem = memory(5, 9, 3, 0, true);
    for (k, b) in mem[40..56].iter_mut().enumerate() {
        *b = 0x11 * k as u8;
    }
    let before = mem[40..56].to_vec();
    let (mut jm, mut js) = (mem.clone(), 0);
    module.run(0, &mut jm, &mut js);
    let (mut rm, mut rs) = (mem.clone(), 0);
    reference::run(&layout, &functions, 0, &mut rm, &mut rs);
    assert_eq!(jm, rm);
    assert_eq!(jm[40..56], before[..]);
}
