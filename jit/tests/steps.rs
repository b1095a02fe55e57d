//! Every Step on fixed cases, compiled code against the reference interpreter and, where
//! the value matters (overflow edges, flags, stack depth, bits of one byte, calls), against
//! the value written here; the errors of `compile` and the panic of `run`.

use gutta_jit::{
    compile, reference, Arg, Arith, Combine, Function, JitError, Layout, Module, Rel, Step,
};

const MEMORY: u32 = 64;
const FLAGS: u32 = 60;

fn layout() -> Layout {
    Layout {
        memory_len: MEMORY,
        flags_at: FLAGS,
        stack_mask: 0x1FF,
        local: Some((40, 16)),
    }
}

fn function(steps: Vec<Step>) -> Function {
    Function { steps }
}

/// Run function `f` compiled and by the reference on `memory`/`stack`; they must agree.
/// Returns the compiled run's memory, stack and count.
fn both(
    layout: &Layout,
    functions: &[Function],
    module: &Module,
    f: usize,
    memory: &[u8],
    stack: u32,
) -> (Vec<u8>, u32, u64) {
    let (mut jm, mut js) = (memory.to_vec(), stack);
    let jc = module.run(f, &mut jm, &mut js);
    let (mut rm, mut rs) = (memory.to_vec(), stack);
    let rc = reference::run(layout, functions, f, &mut rm, &mut rs);
    assert_eq!(jm, rm, "memory of function {f}: {:?}", functions[f]);
    assert_eq!(js, rs, "stack of function {f}: {:?}", functions[f]);
    assert_eq!(jc, rc, "count of function {f}: {:?}", functions[f]);
    (jm, js, jc)
}

fn memory_with(pairs: &[(u32, u8)]) -> Vec<u8> {
    let mut m = vec![0u8; MEMORY as usize];
    for &(at, v) in pairs {
        m[at as usize] = v;
    }
    m
}

const STACKS: [u32; 9] = [0, 1, 2, 3, 0x0FF, 0x100, 0x155, 0x1FE, 0x1FF];
const BYTES: [u8; 4] = [0x00, 0xFF, 0xA5, 0x5A];

#[test]
fn every_bit_step_on_every_bit_and_stack() {
    let layout = layout();
    let mut functions = Vec::new();
    for bit in 0..8 {
        for make in [
            |at, bit| Step::Ld { at, bit },
            |at, bit| Step::Ldn { at, bit },
            |at, bit| Step::A { at, bit },
            |at, bit| Step::An { at, bit },
            |at, bit| Step::O { at, bit },
            |at, bit| Step::On { at, bit },
            |at, bit| Step::Assign { at, bit },
        ] {
            functions.push(function(vec![make(3, bit)]));
        }
    }
    let module = compile(&layout, &functions).expect("compiles");
    for f in 0..functions.len() {
        for byte in BYTES {
            for stack in STACKS {
                let (_, _, count) = both(
                    &layout,
                    &functions,
                    &module,
                    f,
                    &memory_with(&[(3, byte)]),
                    stack,
                );
                assert_eq!(count, 1);
            }
        }
    }
    // Pinned values: LD of a set bit pushes 1 and drops the 10th level; = writes one bit.
    let (_, s, _) = both(
        &layout,
        &functions,
        &module,
        0,
        &memory_with(&[(3, 0x01)]),
        0x1FF,
    );
    assert_eq!(s, 0x1FF);
    let assign_bit_5 = 5 * 7 + 6;
    let (m, s, _) = both(
        &layout,
        &functions,
        &module,
        assign_bit_5,
        &memory_with(&[(3, 0xFF)]),
        0x2,
    );
    assert_eq!((m[3], s), (0xDF, 0x2));
}

#[test]
fn stack_steps_keep_the_depth_mask() {
    let layout = layout();
    let functions: Vec<Function> = [
        Step::Not,
        Step::Ald,
        Step::Old,
        Step::Lps,
        Step::Lrd,
        Step::Lpp,
    ]
    .into_iter()
    .map(|s| function(vec![s]))
    .collect();
    let module = compile(&layout, &functions).expect("compiles");
    for f in 0..functions.len() {
        for stack in 0..0x400 {
            both(&layout, &functions, &module, f, &memory_with(&[]), stack);
        }
    }
    // LPS of a full stack: the bottom level falls off (mask 0x1FF).
    let (_, s, _) = both(&layout, &functions, &module, 3, &memory_with(&[]), 0x1FF);
    assert_eq!(s, 0x1FF);
    let (_, s, _) = both(&layout, &functions, &module, 3, &memory_with(&[]), 0x101);
    assert_eq!(s, 0x003);
}

#[test]
fn bits_of_the_same_byte_see_each_others_writes() {
    let layout = layout();
    let functions = vec![function(vec![
        Step::Network,
        Step::Ld { at: 7, bit: 0 },
        Step::Assign { at: 7, bit: 1 },
        Step::Network,
        Step::Ld { at: 7, bit: 1 },
        Step::Not,
        Step::Assign { at: 7, bit: 7 },
        Step::Network,
        Step::Ldn { at: 7, bit: 7 },
        Step::A { at: 7, bit: 0 },
        Step::On { at: 7, bit: 2 },
        Step::Assign { at: 7, bit: 2 },
    ])];
    let module = compile(&layout, &functions).expect("compiles");
    for byte in 0..=255u8 {
        let (m, _, count) = both(
            &layout,
            &functions,
            &module,
            0,
            &memory_with(&[(7, byte)]),
            0,
        );
        assert_eq!(count, 9);
        let b0 = byte & 1;
        let b2 = ((byte >> 2) & 1 == 0) || b0 == 1;
        let expected = (byte & 0x78) | b0 | (b0 << 1) | (u8::from(b2) << 2) | ((b0 ^ 1) << 7);
        assert_eq!(m[7], expected, "from {byte:#04x}");
    }
}

/// dst (2 or 4 bytes at 0) := dst op src (at 8), flags preset to `flags`; returns the
/// result (sign-extended) and the flags byte.
fn math(op: Arith, width: u8, dst: i32, src: i32, flags: u8) -> (i64, u8) {
    let layout = layout();
    let functions = vec![function(vec![
        Step::Network,
        Step::Ld { at: 20, bit: 0 },
        Step::Math {
            op,
            src: 8,
            dst: 0,
            width,
        },
    ])];
    let module = compile(&layout, &functions).expect("compiles");
    let mut memory = memory_with(&[(20, 1), (FLAGS, flags)]);
    memory[0..4].copy_from_slice(&dst.to_le_bytes());
    memory[8..12].copy_from_slice(&src.to_le_bytes());
    if width == 2 {
        memory[2..4].copy_from_slice(&[0xEE, 0xEE]);
    }
    let (m, _, _) = both(&layout, &functions, &module, 0, &memory, 0);
    if width == 2 {
        assert_eq!(
            m[2..4],
            [0xEE, 0xEE],
            "a 2-byte result stays in its 2 bytes"
        );
    }
    let r = if width == 2 {
        i64::from(i16::from_le_bytes([m[0], m[1]]))
    } else {
        i64::from(i32::from_le_bytes([m[0], m[1], m[2], m[3]]))
    };
    (r, m[FLAGS as usize])
}

#[test]
fn math_overflow_edges_and_flags() {
    const Z: u8 = 1;
    const O: u8 = 2;
    const N: u8 = 4;
    let m16 = i32::from(i16::MIN);
    assert_eq!(
        math(Arith::Mul, 2, m16, -1, 0),
        (i64::from(i16::MIN), O | N)
    );
    assert_eq!(
        math(Arith::Add, 2, 0x7FFF, 1, 0),
        (i64::from(i16::MIN), O | N)
    );
    assert_eq!(math(Arith::Sub, 2, m16, 1, 0), (0x7FFF, O));
    assert_eq!(math(Arith::Add, 2, 5, -5, 0), (0, Z));
    assert_eq!(math(Arith::Mul, 2, 256, 256, 0), (0, Z | O));
    assert_eq!(math(Arith::Sub, 2, 3, 5, 0), (-2, N));
    assert_eq!(
        math(Arith::Mul, 4, i32::MIN, -1, 0),
        (i64::from(i32::MIN), O | N)
    );
    assert_eq!(
        math(Arith::Add, 4, i32::MAX, 1, 0),
        (i64::from(i32::MIN), O | N)
    );
    assert_eq!(
        math(Arith::Sub, 4, i32::MIN, 1, 0),
        (i64::from(i32::MAX), O)
    );
    assert_eq!(math(Arith::Mul, 4, 0x10000, 0x10000, 0), (0, Z | O));
    assert_eq!(
        math(Arith::Mul, 4, -46341, 46341, 0),
        (i64::from(-46341i32.wrapping_mul(46341)), O)
    );
    // Flags bits 3..7 are kept, bits 0..2 replaced.
    assert_eq!(math(Arith::Add, 2, 1, 1, 0xFF), (2, 0xF8));
    assert_eq!(math(Arith::Add, 4, 0, 0, 0xA8 | O | N), (0, 0xA8 | Z));
}

#[test]
fn math_and_move_run_only_with_power_flow() {
    let layout = layout();
    let functions = vec![function(vec![
        Step::Ld { at: 20, bit: 0 },
        Step::Math {
            op: Arith::Add,
            src: 8,
            dst: 0,
            width: 4,
        },
        Step::Move {
            src: 8,
            dst: 12,
            width: 4,
        },
    ])];
    let module = compile(&layout, &functions).expect("compiles");
    let memory = memory_with(&[(8, 7), (FLAGS, 0x07)]);
    let (m, _, count) = both(&layout, &functions, &module, 0, &memory, 0);
    assert_eq!(
        (m, count),
        (memory.clone(), 3),
        "nothing written without power flow"
    );
    let (m, _, _) = both(
        &layout,
        &functions,
        &module,
        0,
        &memory_with(&[(8, 7), (20, 1)]),
        0,
    );
    assert_eq!((m[0], m[12], m[FLAGS as usize]), (7, 7, 0));
}

#[test]
fn math_whose_result_covers_the_flags_byte() {
    let layout = layout();
    let functions = vec![function(vec![
        Step::Ld { at: 20, bit: 0 },
        Step::Math {
            op: Arith::Sub,
            src: 8,
            dst: FLAGS - 1,
            width: 4,
        },
    ])];
    let module = compile(&layout, &functions).expect("compiles");
    for v in [0u8, 1, 0x80, 0xFF] {
        let mut memory = memory_with(&[(20, 1), (8, v), (11, v)]);
        memory[(FLAGS - 1) as usize..(FLAGS + 3) as usize]
            .copy_from_slice(&[0x11, 0xF3, 0x01, 0x80]);
        both(&layout, &functions, &module, 0, &memory, 0);
    }
}

#[test]
fn moves_of_every_width_including_overlaps() {
    let layout = layout();
    let mut functions = Vec::new();
    for width in [1, 2, 4] {
        for (src, dst) in [(0, 16), (0, 1), (1, 0), (5, 5), (60, 0)] {
            functions.push(function(vec![Step::Move { src, dst, width }]));
        }
    }
    let module = compile(&layout, &functions).expect("compiles");
    let memory: Vec<u8> = (0..MEMORY as u8).map(|i| i.wrapping_mul(37)).collect();
    for f in 0..functions.len() {
        both(&layout, &functions, &module, f, &memory, 1);
    }
    let (m, _, _) = both(&layout, &functions, &module, 12, &memory, 1);
    assert_eq!(m[0..4], memory[1..5], "a 4-byte move one byte down");
}

#[test]
fn compares_signed_and_unsigned_with_each_combine() {
    let layout = layout();
    let mut functions = Vec::new();
    for width in [1, 2, 4] {
        for combine in [Combine::Load, Combine::And, Combine::Or] {
            for rel in [Rel::Eq, Rel::Ne, Rel::Lt, Rel::Le, Rel::Gt, Rel::Ge] {
                functions.push(function(vec![Step::Compare {
                    combine,
                    rel,
                    a: 0,
                    b: 4,
                    width,
                }]));
            }
        }
    }
    let module = compile(&layout, &functions).expect("compiles");
    let values: [[u8; 4]; 6] = [
        [0, 0, 0, 0],
        [1, 0, 0, 0],
        [0xC8, 0, 0, 0],
        [0xFF, 0xFF, 0xFF, 0xFF],
        [0x00, 0x80, 0x00, 0x80],
        [0xFF, 0x7F, 0xFF, 0x7F],
    ];
    for f in 0..functions.len() {
        for a in values {
            for b in values {
                for stack in [0, 1, 2, 0x1FF] {
                    let mut memory = memory_with(&[]);
                    memory[0..4].copy_from_slice(&a);
                    memory[4..8].copy_from_slice(&b);
                    both(&layout, &functions, &module, f, &memory, stack);
                }
            }
        }
    }
    // Width 1 is unsigned: 200 > 1; width 2 is signed: -1 < 1.
    let gt_load = |width: usize| (width * 3) * 6 + 4;
    let mut memory = memory_with(&[(0, 200), (4, 1)]);
    assert_eq!(
        both(&layout, &functions, &module, gt_load(0), &memory, 0).1,
        1
    );
    memory[0..2].copy_from_slice(&[0xFF, 0xFF]);
    assert_eq!(
        both(&layout, &functions, &module, gt_load(1), &memory, 0).1,
        0
    );
}

/// Function 0 calls 1 (a leaf) with an input, an output and an in-out argument; the
/// callee uses L (its own, cleared) and the caller's L comes back.
fn calling() -> Vec<Function> {
    let args = vec![
        Arg {
            var: 0,
            param: 40,
            width: 2,
            input: true,
            output: false,
            bits: None,
        },
        Arg {
            var: 4,
            param: 44,
            width: 4,
            input: false,
            output: true,
            bits: None,
        },
        Arg {
            var: 8,
            param: 48,
            width: 1,
            input: true,
            output: true,
            bits: None,
        },
    ];
    let leaf = vec![
        Step::Network,
        Step::Ld { at: 52, bit: 0 }, // L cleared: 0
        Step::Not,
        Step::Move {
            src: 40,
            dst: 44,
            width: 2,
        },
        Step::Math {
            op: Arith::Add,
            src: 48,
            dst: 48,
            width: 2,
        },
        Step::Assign { at: 30, bit: 3 },
    ];
    vec![
        function(vec![
            Step::Network,
            Step::Ld { at: 20, bit: 0 },
            Step::Call { callee: 1, args },
            Step::Assign { at: 21, bit: 0 },
        ]),
        function(leaf),
    ]
}

#[test]
fn a_call_runs_the_callee_with_its_own_l_and_restores_the_callers() {
    let layout = layout();
    let functions = calling();
    let module = compile(&layout, &functions).expect("compiles");
    let mut memory = memory_with(&[(0, 0x34), (1, 0x12), (8, 9), (20, 1)]);
    for (i, b) in memory[40..56].iter_mut().enumerate() {
        *b = 0xA0 + i as u8;
    }
    let (m, s, count) = both(&layout, &functions, &module, 0, &memory, 0x1F0);
    assert_eq!(count, 3 + 5, "3 steps of the caller, 5 of the callee");
    assert_eq!(
        m[4..8],
        [0x34, 0x12, 0, 0],
        "output: the moved input, upper L bytes zero"
    );
    assert_eq!(m[8], 18, "in-out: 9 + 9");
    assert_eq!(m[40..56], memory[40..56], "the caller's L restored");
    assert_eq!(m[30], 0x08, "the callee's = ran");
    assert_eq!((m[21], s), (1, 1), "the caller's stack as before the call");
}

#[test]
fn a_call_without_power_flow_counts_one_and_runs_nothing() {
    let layout = layout();
    let functions = calling();
    let module = compile(&layout, &functions).expect("compiles");
    let memory = memory_with(&[(0, 0x34), (8, 9), (44, 0x55)]);
    let (m, _, count) = both(&layout, &functions, &module, 0, &memory, 0);
    assert_eq!(count, 3);
    assert_eq!(m[..21], memory[..21]);
    assert_eq!(m[22..], memory[22..]);
}

#[test]
fn calls_without_an_l_area_and_nested_calls() {
    let mut layout = layout();
    layout.local = None;
    let mut functions = calling();
    functions[1].steps.push(Step::Call {
        callee: 2,
        args: vec![],
    });
    functions.push(function(vec![
        Step::Ld { at: 0, bit: 2 },
        Step::Assign { at: 31, bit: 0 },
    ]));
    let module = compile(&layout, &functions).expect("compiles");
    let memory = memory_with(&[(0, 0x04), (20, 1)]);
    let (m, _, count) = both(&layout, &functions, &module, 0, &memory, 0);
    assert_eq!(count, 3 + 6 + 2);
    assert_eq!(m[31], 1);
}

#[test]
fn out_of_range_steps_are_refused() {
    let layout = layout();
    let refused = |step: Step| compile(&layout, &[function(vec![Step::Not, step])]).map(|_| ());
    assert_eq!(
        refused(Step::Ld { at: MEMORY, bit: 0 }),
        Err(JitError::OutOfRange {
            function: 0,
            step: 1,
            at: MEMORY,
            width: 1
        })
    );
    assert!(matches!(
        refused(Step::Move {
            src: 0,
            dst: MEMORY - 3,
            width: 4
        }),
        Err(JitError::OutOfRange {
            at: 61,
            width: 4,
            ..
        })
    ));
    assert!(matches!(
        refused(Step::Compare {
            combine: Combine::Or,
            rel: Rel::Eq,
            a: u32::MAX,
            b: 0,
            width: 2
        }),
        Err(JitError::OutOfRange { .. })
    ));
    assert!(matches!(
        refused(Step::Assign { at: 0, bit: 8 }),
        Err(JitError::BitNumber { bit: 8, .. })
    ));
    assert!(matches!(
        refused(Step::Math {
            op: Arith::Add,
            src: 0,
            dst: 2,
            width: 1
        }),
        Err(JitError::Width { width: 1, .. })
    ));
    assert!(matches!(
        refused(Step::Move {
            src: 0,
            dst: 2,
            width: 3
        }),
        Err(JitError::Width { width: 3, .. })
    ));
    assert!(matches!(
        refused(Step::Call {
            callee: 1,
            args: vec![]
        }),
        Err(JitError::NoSuchCallee { callee: 1, .. })
    ));
    // The last byte is fine.
    assert_eq!(
        refused(Step::Move {
            src: 0,
            dst: MEMORY - 4,
            width: 4
        }),
        Ok(())
    );
    let arg = Arg {
        var: 0,
        param: MEMORY - 1,
        width: 2,
        input: false,
        output: false,
        bits: None,
    };
    let call = Step::Call {
        callee: 0,
        args: vec![arg],
    };
    let two = [function(vec![]), function(vec![call])];
    assert!(matches!(
        compile(&layout, &two),
        Err(JitError::OutOfRange {
            function: 1,
            step: 0,
            at: 63,
            width: 2
        })
    ));
    for (flags_at, local) in [(MEMORY, None), (0, Some((MEMORY - 4, 5)))] {
        let bad = Layout {
            flags_at,
            local,
            ..layout
        };
        let e = compile(&bad, &[function(vec![Step::Not])]).map(|_| ());
        assert!(matches!(e, Err(JitError::Layout { .. })), "{e:?}");
        assert!(e.unwrap_err().to_string().contains("outside the memory"));
    }
}

#[test]
fn cycles_of_calls_are_refused() {
    let layout = layout();
    let call = |callee| Step::Call {
        callee,
        args: vec![],
    };
    let own = compile(&layout, &[function(vec![call(0)])]).map(|_| ());
    assert_eq!(own, Err(JitError::Recursion { function: 0 }));
    let three = [
        function(vec![call(1)]),
        function(vec![Step::Not, call(2)]),
        function(vec![call(1)]),
    ];
    let e = compile(&layout, &three).map(|_| ());
    assert!(
        matches!(e, Err(JitError::Recursion { function: 1 | 2 })),
        "{e:?}"
    );
    assert!(e.unwrap_err().to_string().contains("cycle"));
    // A diamond is no cycle.
    let diamond = [
        function(vec![call(1), call(2)]),
        function(vec![call(3)]),
        function(vec![call(3)]),
        function(vec![]),
    ];
    assert!(compile(&layout, &diamond).is_ok());
}

#[test]
fn run_refuses_memory_of_another_length_before_running() {
    let layout = layout();
    let module = compile(&layout, &[function(vec![Step::Ld { at: 0, bit: 0 }])]).expect("compiles");
    let mut short = vec![1u8; MEMORY as usize - 1];
    let mut stack = 5;
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        module.run(0, &mut short, &mut stack)
    }));
    let message = result.expect_err("a short memory panics");
    let text = message
        .downcast_ref::<String>()
        .cloned()
        .unwrap_or_default();
    assert!(text.contains("63 bytes"), "{text}");
    assert_eq!(stack, 5, "nothing ran");
}

#[test]
fn a_module_runs_on_another_thread() {
    let layout = layout();
    let functions = vec![function(vec![
        Step::Ld { at: 0, bit: 1 },
        Step::Assign { at: 1, bit: 0 },
    ])];
    let module = compile(&layout, &functions).expect("compiles");
    assert!(module.code_bytes() > 0);
    let handle = std::thread::spawn(move || {
        let mut memory = memory_with(&[(0, 2)]);
        let mut stack = 0;
        let count = module.run(0, &mut memory, &mut stack);
        (memory[1], stack, count)
    });
    assert_eq!(handle.join().expect("the thread ran"), (1, 1, 2));
}

/// `steps` followed by Not pairs until it has more than 64 steps (a long callee: the
/// same results, more instructions).
fn long(mut steps: Vec<Step>) -> Vec<Step> {
    while steps.len() <= 66 {
        steps.extend([Step::Not, Step::Not]);
    }
    steps
}

#[test]
fn a_long_callee_gives_the_same_results_and_counts_its_steps() {
    let layout = layout();
    let small = calling();
    let mut large = calling();
    large[1].steps = long(large[1].steps.clone());
    let extra = large[1].steps.len() as u64 - small[1].steps.len() as u64;
    let (ms, ml) = (
        compile(&layout, &small).expect("compiles"),
        compile(&layout, &large).expect("compiles"),
    );
    for power in [0u8, 1] {
        let mut memory = memory_with(&[(0, 0x34), (1, 0x12), (8, 9), (20, power)]);
        for (i, b) in memory[40..56].iter_mut().enumerate() {
            *b = 0xA0 + i as u8;
        }
        for stack in STACKS {
            let (m1, s1, c1) = both(&layout, &small, &ms, 0, &memory, stack);
            let (m2, s2, c2) = both(&layout, &large, &ml, 0, &memory, stack);
            assert_eq!((m1, s1), (m2, s2));
            assert_eq!(c2, c1 + u64::from(power) * extra);
        }
    }
}

/// Function 0 calls 1 with power; 1 holds a Call of 2 that runs only when bit 0 of byte
/// 16 is set, then (with power) boxed steps on both sides of a Compare and a Call of 3
/// (long); 2 reads an L byte that is no parameter (cleared: 0) and
/// writes L.
fn nested() -> Vec<Function> {
    let arg = |var, param, input, output| Arg {
        var,
        param,
        width: 2,
        input,
        output,
        bits: None,
    };
    vec![
        function(vec![
            Step::Network,
            Step::Ld { at: 20, bit: 0 },
            Step::Call {
                callee: 1,
                args: vec![arg(0, 40, true, false), arg(2, 42, false, true)],
            },
            Step::Move {
                src: 0,
                dst: 10,
                width: 2,
            },
        ]),
        function(vec![
            Step::Network,
            Step::Ld { at: 16, bit: 0 },
            Step::Call {
                callee: 2,
                args: vec![arg(40, 44, true, true)],
            },
            Step::Network,
            Step::Ld { at: 20, bit: 0 },
            Step::Math {
                op: Arith::Add,
                src: 40,
                dst: 42,
                width: 2,
            },
            Step::Compare {
                combine: Combine::Load,
                rel: Rel::Gt,
                a: 42,
                b: 12,
                width: 2,
            },
            Step::Move {
                src: 42,
                dst: 14,
                width: 2,
            },
            Step::Lpp,
            Step::Call {
                callee: 3,
                args: vec![arg(42, 46, true, false)],
            },
            Step::Assign { at: 17, bit: 1 },
        ]),
        function(vec![
            Step::Network,
            Step::Ldn { at: 50, bit: 3 },
            Step::Math {
                op: Arith::Mul,
                src: 44,
                dst: 44,
                width: 2,
            },
            Step::Move {
                src: 44,
                dst: 52,
                width: 2,
            },
        ]),
        function(long(vec![
            Step::Network,
            Step::Ld { at: 55, bit: 7 },
            Step::Not,
            Step::Move {
                src: 46,
                dst: 18,
                width: 2,
            },
        ])),
    ]
}

#[test]
fn nested_calls_with_and_without_power_and_a_compare_between_boxes() {
    let layout = layout();
    let functions = nested();
    let module = compile(&layout, &functions).expect("compiles");
    let large = functions[3].steps.len() as u64 - 1;
    for (inner, threshold) in [(0u8, 0u8), (1, 0), (1, 100), (0, 100)] {
        let mut memory = memory_with(&[(0, 7), (2, 5), (12, threshold), (16, inner), (20, 1)]);
        for (i, b) in memory[40..56].iter_mut().enumerate() {
            *b = 0x90 ^ i as u8;
        }
        let (m, s, count) = both(&layout, &functions, &module, 0, &memory, 0);
        let x = if inner == 1 { 49 } else { 7 };
        assert_eq!(m[2], x, "output: L 42 (cleared) + the (squared) input");
        assert_eq!(m[10], 7, "the input variable unchanged");
        let compared = x > threshold;
        assert_eq!(
            m[14],
            if compared { x } else { 0 },
            "the Move after the Compare"
        );
        assert_eq!(m[18], x, "the real call ran with its input");
        assert_eq!(m[17] & 2, 2, "the callee's = after its Lpp");
        assert_eq!(m[40..56], memory[40..56], "the caller's L restored");
        assert_eq!(s, 1);
        // 3 of function 0, 9 of function 1 (each Call counts 1), what 2 and 3 ran.
        let inner_count = if inner == 1 { 3 } else { 0 };
        assert_eq!(count, 3 + 9 + inner_count + large);
    }
}

#[test]
fn a_compare_between_boxed_steps_decides_the_boxes_after_it() {
    let layout = layout();
    let functions = vec![function(vec![
        Step::Ld { at: 0, bit: 0 },
        Step::Move {
            src: 1,
            dst: 2,
            width: 1,
        },
        Step::Compare {
            combine: Combine::And,
            rel: Rel::Eq,
            a: 1,
            b: 3,
            width: 1,
        },
        Step::Move {
            src: 1,
            dst: 4,
            width: 1,
        },
        Step::Not,
        Step::Math {
            op: Arith::Add,
            src: 1,
            dst: 6,
            width: 2,
        },
    ])];
    let module = compile(&layout, &functions).expect("compiles");
    for (power, third) in [(1u8, 7u8), (1, 8), (0, 7)] {
        let memory = memory_with(&[(0, power), (1, 7), (3, third)]);
        let (m, _, count) = both(&layout, &functions, &module, 0, &memory, 0);
        assert_eq!(count, 6);
        assert_eq!(m[2], 7 * power);
        let equal = power == 1 && third == 7;
        assert_eq!(m[4], if equal { 7 } else { 0 });
        assert_eq!(
            m[6],
            if equal { 0 } else { 7 },
            "runs when the AND was false"
        );
    }
}

/// Two Math steps in one power run: the first one's flags are not stored when the second
/// sets them again, unless something between (a Move of the flags byte) or the second
/// itself (an operand on the flags byte) reads them.
#[test]
fn flags_of_a_math_are_kept_when_anything_reads_them_before_the_next_math() {
    let layout = layout();
    let math = |op, src, dst| Step::Math {
        op,
        src,
        dst,
        width: 2,
    };
    let functions = vec![
        // Overwritten: only the second Math's flags remain (8 * 0 = 0: zero).
        function(vec![
            Step::Ld { at: 0, bit: 0 },
            math(Arith::Sub, 4, 2),
            math(Arith::Mul, 6, 8),
        ]),
        // A Move of the flags byte between the two sees the first's flags.
        function(vec![
            Step::Ld { at: 0, bit: 0 },
            math(Arith::Sub, 4, 2),
            Step::Move {
                src: FLAGS,
                dst: 12,
                width: 1,
            },
            math(Arith::Mul, 6, 8),
        ]),
        // The second Math reads the flags byte as its source.
        function(vec![
            Step::Ld { at: 0, bit: 0 },
            math(Arith::Sub, 4, 2),
            math(Arith::Add, FLAGS - 1, 14),
        ]),
        // The first Math's result covers the flags byte, the second sets the flags.
        function(vec![
            Step::Ld { at: 0, bit: 0 },
            math(Arith::Add, 4, FLAGS),
            math(Arith::Mul, 6, 8),
        ]),
    ];
    let module = compile(&layout, &functions).expect("compiles");
    // 2: 1 - 0x7FFF overflows below (negative and overflow flags: no, 1 - 32767 is
    // -32766: negative only); 8 * 0 = 0.
    let memory = memory_with(&[(0, 1), (2, 1), (4, 0xFF), (5, 0x7F), (8, 8), (FLAGS, 0xF8)]);
    for f in 0..functions.len() {
        let (m, _, _) = both(&layout, &functions, &module, f, &memory, 0);
        match f {
            0 => assert_eq!(m[FLAGS as usize], 0xF8 | 1, "zero from the Mul"),
            1 => assert_eq!(
                (m[12], m[FLAGS as usize]),
                (0xF8 | 4, 0xF8 | 1),
                "the Move saw the Sub's negative flag"
            ),
            2 => assert_eq!(m[15], 0xF8 | 4, "the Add read the Sub's flags (high byte)"),
            _ => {}
        }
    }
}

// ---- timers, counters, edges, S/R, jumps (issue 31) ------------------------------------

use gutta_jit::{CounterKind, Preset, TimerKind};

/// The T (or C) word, its 8 bytes of state, the edge byte, a preset word.
const T: u32 = 0;
const STATE: u32 = 8;
const EDGE: u32 = 20;
const PRESET: u32 = 24;

fn word(m: &[u8], at: u32) -> i16 {
    i16::from_le_bytes([m[at as usize], m[at as usize + 1]])
}

fn set_word(m: &mut [u8], at: u32, v: i16) {
    m[at as usize..at as usize + 2].copy_from_slice(&v.to_le_bytes());
}

/// Run the single function of `step` once per entry of `tops` (the stack before each
/// execution), compiled and by the reference; returns the memory and the stack after
/// each execution.
fn executions(step: Step, memory: &mut Vec<u8>, stacks: &[u32]) -> Vec<(Vec<u8>, u32)> {
    let layout = layout();
    let functions = vec![function(vec![step])];
    let module = compile(&layout, &functions).expect("compiles");
    stacks
        .iter()
        .map(|&stack| {
            let (m, s, count) = both(&layout, &functions, &module, 0, memory, stack);
            assert_eq!(count, 1);
            *memory = m.clone();
            (m, s)
        })
        .collect()
}

fn timer(kind: TimerKind, preset: Preset, res: u32, scan_ms: u32) -> Step {
    Step::Timer {
        kind,
        at: T,
        state: STATE,
        preset,
        res,
        scan_ms,
    }
}

#[test]
fn ton_counts_units_from_its_second_execution_to_the_preset_and_past_it() {
    let mut m = memory_with(&[]);
    // res 100, 100 ms a scan: the first execution starts the clock.
    let runs = executions(
        timer(TimerKind::On, Preset::Const(3), 100, 100),
        &mut m,
        &[1; 6],
    );
    let values: Vec<(i16, u32)> = runs.iter().map(|(m, s)| (word(m, T), *s)).collect();
    assert_eq!(values, [(0, 0), (1, 0), (2, 0), (3, 1), (4, 1), (5, 1)]);
    // Power gone: the value and the clock are reset.
    let runs = executions(
        timer(TimerKind::On, Preset::Const(3), 100, 100),
        &mut m,
        &[0b10],
    );
    assert_eq!((word(&runs[0].0, T), runs[0].1), (0, 0b10));
    assert_eq!(&runs[0].0[STATE as usize..STATE as usize + 8], &[0; 8]);
    // The preset from memory, and the value capped at i16::MAX.
    let mut m = memory_with(&[]);
    set_word(&mut m, PRESET, i16::MAX);
    set_word(&mut m, T, i16::MAX - 2);
    let runs = executions(
        timer(TimerKind::On, Preset::Word(PRESET), 1, 7),
        &mut m,
        &[1, 1, 1, 1],
    );
    let values: Vec<(i16, u32)> = runs.iter().map(|(m, s)| (word(m, T), *s)).collect();
    assert_eq!(
        values,
        [
            (i16::MAX - 2, 0),
            (i16::MAX, 1),
            (i16::MAX, 1),
            (i16::MAX, 1)
        ]
    );
    // A preset of 0 or below is done at once.
    let mut m = memory_with(&[]);
    let runs = executions(
        timer(TimerKind::On, Preset::Const(-1), 10, 10),
        &mut m,
        &[1],
    );
    assert_eq!(runs[0].1, 1);
}

#[test]
fn the_resolution_keeps_the_remainder_of_each_scan() {
    for (res, after_30) in [(1, 203), (10, 20), (100, 2)] {
        let mut m = memory_with(&[]);
        let runs = executions(
            timer(TimerKind::Retentive, Preset::Const(i16::MAX), res, 7),
            &mut m,
            &[1; 30],
        );
        // 29 advancing executions of 7 ms each.
        assert_eq!(word(&runs[29].0, T), after_30, "res {res}");
    }
}

#[test]
fn tof_is_armed_by_power_and_runs_out_after_it() {
    let mut m = memory_with(&[]);
    let tof = timer(TimerKind::Off, Preset::Const(2), 10, 10);
    // Never powered: not armed, stays off.
    let runs = executions(tof.clone(), &mut m, &[0, 0]);
    assert!(runs.iter().all(|(_, s)| *s == 0));
    // Powered: on, armed; then off: starts, counts 1, 2 and falls.
    let runs = executions(tof.clone(), &mut m, &[1, 0, 0, 0, 0]);
    let values: Vec<(i16, u32)> = runs.iter().map(|(m, s)| (word(m, T), *s)).collect();
    assert_eq!(values, [(0, 1), (0, 1), (1, 1), (2, 0), (2, 0)]);
    // Disarmed: the flags word has neither RUNNING nor ARMED.
    assert_eq!(runs[4].0[STATE as usize + 4], 0);
    // Power again in the middle of a run-out: back to 0, armed again.
    let runs = executions(tof, &mut m, &[1, 0, 0, 1]);
    let values: Vec<(i16, u32)> = runs.iter().map(|(m, s)| (word(m, T), *s)).collect();
    assert_eq!(values, [(0, 1), (0, 1), (1, 1), (0, 1)]);
}

#[test]
fn tonr_keeps_its_value_without_power() {
    let mut m = memory_with(&[]);
    let tonr = timer(TimerKind::Retentive, Preset::Const(3), 10, 10);
    let runs = executions(tonr, &mut m, &[1, 1, 1, 0, 0, 1, 1, 1]);
    let values: Vec<(i16, u32)> = runs.iter().map(|(m, s)| (word(m, T), *s)).collect();
    assert_eq!(
        values,
        [
            (0, 0),
            (1, 0),
            (2, 0),
            (2, 0),
            (2, 0),
            (2, 0),
            (3, 1),
            (4, 1)
        ]
    );
}

fn counter(kind: CounterKind, preset: Preset, max: i16) -> Step {
    Step::Counter {
        kind,
        at: T,
        state: STATE,
        preset,
        max,
    }
}

#[test]
fn counters_count_edges_up_to_max_down_to_their_limits_and_reset_or_load() {
    // CTU: stack bit 1 = CU, bit 0 = R; pushes done after popping both.
    let mut m = memory_with(&[]);
    let ctu = counter(CounterKind::Up, Preset::Const(2), 3);
    let runs = executions(ctu.clone(), &mut m, &[0b10, 0b00, 0b10, 0b10, 0b00, 0b110]);
    let values: Vec<(i16, u32)> = runs.iter().map(|(m, s)| (word(m, T), *s)).collect();
    // Level CU does not count twice; the last has a third level kept below.
    assert_eq!(values, [(1, 0), (1, 0), (2, 1), (2, 1), (2, 1), (3, 0b11)]);
    let runs = executions(ctu.clone(), &mut m, &[0, 0b10]);
    // At max (3) it stays.
    assert_eq!(word(&runs[1].0, T), 3);
    let runs = executions(ctu, &mut m, &[0b11]);
    assert_eq!((word(&runs[0].0, T), runs[0].1), (0, 0));
    // CTD: bit 1 = CD, bit 0 = LD; done when 0, stops at 0.
    let mut m = memory_with(&[]);
    set_word(&mut m, PRESET, 2);
    let ctd = counter(CounterKind::Down, Preset::Word(PRESET), i16::MAX);
    let runs = executions(ctd, &mut m, &[0b01, 0b10, 0, 0b10, 0, 0b10]);
    let values: Vec<(i16, u32)> = runs.iter().map(|(m, s)| (word(m, T), *s)).collect();
    assert_eq!(values, [(2, 0), (1, 0), (1, 0), (0, 1), (0, 1), (0, 1)]);
    // CTUD: bit 2 = CU, bit 1 = CD, bit 0 = R; both edges at once: no count; stops at
    // i16::MIN and at max.
    let mut m = memory_with(&[]);
    set_word(&mut m, T, i16::MIN + 1);
    let ctud = counter(CounterKind::UpDown, Preset::Const(i16::MIN + 1), 5);
    let runs = executions(ctud.clone(), &mut m, &[0b010, 0, 0b010, 0, 0b110, 0, 0b100]);
    let values: Vec<(i16, u32)> = runs.iter().map(|(m, s)| (word(m, T), *s)).collect();
    let mut want = vec![(i16::MIN, 0); 6];
    want.push((i16::MIN + 1, 1));
    assert_eq!(values, want);
    set_word(&mut m, T, 5);
    let runs = executions(ctud.clone(), &mut m, &[0, 0b100]);
    assert_eq!(word(&runs[1].0, T), 5);
    let runs = executions(ctud, &mut m, &[0b101]);
    assert_eq!((word(&runs[0].0, T), runs[0].1), (0, 1));
}

#[test]
fn edges_fire_once_per_change() {
    for rising in [true, false] {
        let mut m = memory_with(&[]);
        let runs = executions(
            Step::Edge {
                rising,
                state: EDGE,
            },
            &mut m,
            &[0b10, 0b11, 0b11, 0b10, 0b10, 0b11],
        );
        let tops: Vec<u32> = runs.iter().map(|(_, s)| *s).collect();
        if rising {
            assert_eq!(tops, [0b10, 0b11, 0b10, 0b10, 0b10, 0b11]);
        } else {
            assert_eq!(tops, [0b10, 0b10, 0b10, 0b11, 0b10, 0b10]);
        }
        assert_eq!(runs[5].0[EDGE as usize], 1);
    }
}

#[test]
fn set_bits_cross_bytes_and_n_zero_touches_nothing() {
    for (bit, n, value) in [
        (5u8, 20u16, true),
        (5, 20, false),
        (0, 8, true),
        (0, 64, true),
        (3, 1, false),
        (7, 2, true),
        (2, 0, true),
        (0, 77, false),
    ] {
        let step = Step::SetBits {
            at: 4,
            bit,
            n,
            value,
        };
        for byte in [0x00, 0xFF, 0xA5] {
            let mut m = vec![byte; MEMORY as usize];
            let before = m.clone();
            let runs = executions(step.clone(), &mut m, &[1, 0]);
            let mut want = before.clone();
            for k in 0..u32::from(n) {
                let b = u32::from(bit) + k;
                let i = (4 + b / 8) as usize;
                want[i] = if value {
                    want[i] | 1 << (b % 8)
                } else {
                    want[i] & !(1 << (b % 8))
                };
            }
            assert_eq!(runs[0].0, want, "bit {bit} n {n} {value}");
            // Without power: nothing more.
            assert_eq!(runs[1].0, want);
        }
    }
}

#[test]
fn jumps_skip_to_after_their_label_and_count_what_ran() {
    let layout = layout();
    let steps = vec![
        Step::Ld { at: 0, bit: 0 },
        Step::Jump { label: 7 },
        Step::Assign { at: 1, bit: 0 },
        Step::Network,
        Step::Ld { at: 0, bit: 1 },
        Step::Assign { at: 1, bit: 1 },
        Step::Label { number: 7 },
        Step::Ld { at: 0, bit: 2 },
        Step::Assign { at: 1, bit: 2 },
    ];
    let functions = vec![function(steps)];
    let module = compile(&layout, &functions).expect("compiles");
    // Not taken: everything runs, the label counts 1.
    let (m, s, count) = both(&layout, &functions, &module, 0, &memory_with(&[(0, 6)]), 0);
    assert_eq!((m[1], s, count), (6, 0b11, 8));
    // Taken: the three records after it up to its label skip (the label too).
    let (m, s, count) = both(&layout, &functions, &module, 0, &memory_with(&[(0, 7)]), 0);
    assert_eq!((m[1], s, count), (4, 0b11, 4));
}

#[test]
fn a_jump_over_a_call_skips_the_callees_count() {
    let layout = layout();
    let functions = vec![
        function(vec![
            Step::Ld { at: 0, bit: 0 },
            Step::Jump { label: 1 },
            Step::Call {
                callee: 1,
                args: vec![],
            },
            Step::Label { number: 1 },
            Step::Label { number: 2 },
        ]),
        function(vec![
            Step::Ld { at: 0, bit: 1 },
            Step::Assign { at: 1, bit: 0 },
            Step::Assign { at: 1, bit: 1 },
        ]),
    ];
    let module = compile(&layout, &functions).expect("compiles");
    let (m, _, count) = both(&layout, &functions, &module, 0, &memory_with(&[(0, 0)]), 0);
    // LD, JMP (not taken), CALL (no power: counts 1), LBL, LBL.
    assert_eq!((m[1], count), (0, 5));
    let (m, _, count) = both(&layout, &functions, &module, 0, &memory_with(&[(0, 1)]), 1);
    // LD, JMP taken, the second LBL.
    assert_eq!((m[1], count), (0, 3));
    // A jump not taken then a call that runs its three steps.
    let functions2 = vec![
        function(vec![
            Step::Ldn { at: 0, bit: 0 },
            Step::Jump { label: 1 },
            Step::Ld { at: 0, bit: 1 },
            Step::Call {
                callee: 1,
                args: vec![],
            },
            Step::Label { number: 1 },
        ]),
        functions[1].clone(),
    ];
    let module = compile(&layout, &functions2).expect("compiles");
    let (m, _, count) = both(&layout, &functions2, &module, 0, &memory_with(&[(0, 3)]), 0);
    assert_eq!((m[1], count), (3, 8));
}

#[test]
fn timers_counters_edges_s_r_and_jumps_out_of_range_are_refused() {
    let layout = layout();
    let refused = |step: Step| compile(&layout, &[function(vec![step])]).map(|_| ());
    let t = |at, state, preset, res| Step::Timer {
        kind: TimerKind::On,
        at,
        state,
        preset,
        res,
        scan_ms: 10,
    };
    assert!(refused(t(MEMORY - 2, MEMORY - 8, Preset::Word(MEMORY - 2), 1)).is_ok());
    assert!(matches!(
        refused(t(MEMORY - 1, 0, Preset::Const(1), 1)),
        Err(JitError::OutOfRange { width: 2, .. })
    ));
    assert!(matches!(
        refused(t(0, MEMORY - 7, Preset::Const(1), 1)),
        Err(JitError::OutOfRange { width: 8, .. })
    ));
    assert!(matches!(
        refused(t(0, 8, Preset::Word(MEMORY - 1), 1)),
        Err(JitError::OutOfRange { width: 2, .. })
    ));
    let e = refused(t(0, 8, Preset::Const(1), 0));
    assert!(
        matches!(e, Err(JitError::Resolution { step: 0, .. })),
        "{e:?}"
    );
    assert!(e.unwrap_err().to_string().contains("resolution"));
    let c = |state| Step::Counter {
        kind: CounterKind::Up,
        at: 0,
        state,
        preset: Preset::Const(1),
        max: 1,
    };
    assert!(refused(c(MEMORY - 4)).is_ok());
    assert!(matches!(
        refused(c(MEMORY - 3)),
        Err(JitError::OutOfRange { width: 4, .. })
    ));
    assert!(matches!(
        refused(Step::Edge {
            rising: true,
            state: MEMORY
        }),
        Err(JitError::OutOfRange { width: 1, .. })
    ));
    let s = |at, bit, n| Step::SetBits {
        at,
        bit,
        n,
        value: true,
    };
    assert!(refused(s(MEMORY - 2, 7, 9)).is_ok());
    assert!(refused(s(MEMORY, 0, 0)).is_ok(), "n = 0 touches nothing");
    assert_eq!(
        refused(s(MEMORY - 2, 7, 10)),
        Err(JitError::OutOfRange {
            function: 0,
            step: 0,
            at: MEMORY,
            width: 1
        })
    );
    assert!(matches!(
        refused(s(0, 8, 1)),
        Err(JitError::BitNumber { bit: 8, .. })
    ));
    let jumps = |steps: Vec<Step>| compile(&layout, &[function(steps)]).map(|_| ());
    let e = jumps(vec![Step::Label { number: 3 }, Step::Jump { label: 3 }]);
    assert_eq!(
        e,
        Err(JitError::NoLabel {
            function: 0,
            step: 1,
            label: 3
        })
    );
    assert!(e.unwrap_err().to_string().contains("label 3"));
    assert!(matches!(
        jumps(vec![Step::Jump { label: 4 }]),
        Err(JitError::NoLabel { label: 4, .. })
    ));
    let e = jumps(vec![
        Step::Jump { label: 3 },
        Step::Label { number: 3 },
        Step::Label { number: 3 },
    ]);
    assert_eq!(
        e,
        Err(JitError::DuplicateLabel {
            function: 0,
            step: 2,
            label: 3
        })
    );
    assert!(e.unwrap_err().to_string().contains("already"));
}
