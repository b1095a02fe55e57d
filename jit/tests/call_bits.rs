//! Calls with BOOL arguments (`Arg::bits`), compiled against the reference and against
//! the values written here: bit inputs, outputs and in-outs, several parameters in one
//! byte of L, a bit output into an output byte (Q) and into the caller's own L, a
//! parameter byte the callee never touches (the narrowed L save must still hold it),
//! and what `compile` refuses.

use gutta_jit::{compile, reference, Arg, Function, JitError, Layout, Module, Step};

const MEMORY: u32 = 64;
/// The caller's and callee's L: bytes 40..56.
const L: u32 = 40;
/// An output image byte (Q).
const Q: u32 = 30;

fn layout() -> Layout {
    Layout {
        memory_len: MEMORY,
        flags_at: 60,
        stack_mask: 0x1FF,
        local: Some((L, 16)),
    }
}

fn bit_arg(var: u32, var_bit: u8, param: u32, param_bit: u8, input: bool, output: bool) -> Arg {
    Arg {
        var,
        param,
        width: 1,
        input,
        output,
        bits: Some((var_bit, param_bit)),
    }
}

/// Run function 0 compiled and by the reference; they must agree. The compiled memory.
fn both(layout: &Layout, functions: &[Function], module: &Module, memory: &[u8]) -> Vec<u8> {
    let (mut jm, mut js) = (memory.to_vec(), 0);
    let jc = module.run(0, &mut jm, &mut js);
    let (mut rm, mut rs) = (memory.to_vec(), 0);
    let rc = reference::run(layout, functions, 0, &mut rm, &mut rs);
    assert_eq!(jm, rm, "memory: {functions:?}");
    assert_eq!((js, jc), (rs, rc), "stack and count: {functions:?}");
    jm
}

/// Function 0 calls 1 when bit 0 of byte 20 is set. Arguments: inputs M10.3 -> L40.0
/// and M10.5 -> L40.1, in-out M11.7 <-> L40.2, output Q30.2 <- L40.3, output into the
/// caller's L50.6 <- L41.0, a WORD input 12 -> L42 between them. The callee: L40.3 :=
/// L40.0 AND L40.1; L40.2 := NOT L40.2; L41.0 := NOT L40.4 (cleared: 1); M13.0 := the
/// low bit of the WORD parameter.
fn program() -> Vec<Function> {
    let args = vec![
        bit_arg(10, 3, L, 0, true, false),
        bit_arg(10, 5, L, 1, true, false),
        bit_arg(11, 7, L, 2, true, true),
        Arg {
            var: 12,
            param: L + 2,
            width: 2,
            input: true,
            output: false,
            bits: None,
        },
        bit_arg(Q, 2, L, 3, false, true),
        bit_arg(50, 6, L + 1, 0, false, true),
    ];
    vec![
        Function {
            steps: vec![
                Step::Network,
                Step::Ld { at: 20, bit: 0 },
                Step::Call { callee: 1, args },
            ],
        },
        Function {
            steps: vec![
                Step::Network,
                Step::Ld { at: L, bit: 0 },
                Step::A { at: L, bit: 1 },
                Step::Assign { at: L, bit: 3 },
                Step::Ldn { at: L, bit: 2 },
                Step::Assign { at: L, bit: 2 },
                Step::Ldn { at: L, bit: 4 },
                Step::Assign { at: L + 1, bit: 0 },
                Step::Ld { at: L + 2, bit: 0 },
                Step::Assign { at: 13, bit: 0 },
            ],
        },
    ]
}

#[test]
fn bool_inputs_outputs_and_in_outs_pass_their_bits() {
    let layout = layout();
    let functions = program();
    let module = compile(&layout, &functions).expect("compiles");
    for m10 in [0x00u8, 0x08, 0x20, 0x28, 0xD7, 0xFF] {
        for m11 in [0x00u8, 0x80, 0x7F, 0xFF] {
            for q in [0x00u8, 0xFF, 0x04, 0xFB] {
                for word in [0u8, 1] {
                    let mut memory = vec![0u8; MEMORY as usize];
                    memory[10] = m10;
                    memory[11] = m11;
                    memory[12] = word;
                    memory[20] = 1;
                    memory[Q as usize] = q;
                    for (i, b) in memory[L as usize..L as usize + 16].iter_mut().enumerate() {
                        *b = 0x35 ^ (i as u8 * 17);
                    }
                    let m = both(&layout, &functions, &module, &memory);
                    let and = (m10 >> 3) & (m10 >> 5) & 1;
                    assert_eq!(
                        m[Q as usize],
                        (q & !4) | (and << 2),
                        "Q30.2 = M10.3 AND M10.5"
                    );
                    assert_eq!(m[11], m11 ^ 0x80, "M11.7 inverted, the rest kept");
                    assert_eq!(m[13] & 1, word, "the WORD beside the bits");
                    let mut l = memory[L as usize..L as usize + 16].to_vec();
                    l[10] |= 0x40;
                    assert_eq!(
                        m[L as usize..L as usize + 16],
                        l[..],
                        "the caller's L restored, then L50.6 := 1 written into it"
                    );
                }
            }
        }
    }
}

#[test]
fn a_call_without_power_passes_nothing() {
    let layout = layout();
    let functions = program();
    let module = compile(&layout, &functions).expect("compiles");
    let mut memory = vec![0xA5u8; MEMORY as usize];
    memory[20] = 0;
    assert_eq!(both(&layout, &functions, &module, &memory), memory);
}

/// The callee touches none of its parameters' bytes: an input written into L45.1 must
/// still be undone (the caller's L45 comes back whole), and an output read from L46.1
/// is the cleared 0, not the caller's bit there.
#[test]
fn parameter_bytes_the_callee_never_touches_are_saved_cleared_and_restored() {
    let layout = layout();
    let functions = vec![
        Function {
            steps: vec![
                Step::Ld { at: 20, bit: 0 },
                Step::Call {
                    callee: 1,
                    args: vec![
                        bit_arg(10, 0, L + 5, 1, true, false),
                        bit_arg(12, 4, L + 6, 1, false, true),
                    ],
                },
            ],
        },
        Function {
            steps: vec![Step::Ld { at: 0, bit: 0 }, Step::Assign { at: 1, bit: 0 }],
        },
    ];
    let module = compile(&layout, &functions).expect("compiles");
    for (m10, l45, l46) in [(1u8, 0x00u8, 0xFFu8), (0, 0xFF, 0x02), (1, 0x5A, 0xA5)] {
        let mut memory = vec![0u8; MEMORY as usize];
        memory[10] = m10;
        memory[12] = 0xFF;
        memory[20] = 1;
        memory[(L + 5) as usize] = l45;
        memory[(L + 6) as usize] = l46;
        let m = both(&layout, &functions, &module, &memory);
        assert_eq!(m[(L + 5) as usize], l45, "L45 restored");
        assert_eq!(m[(L + 6) as usize], l46, "L46 restored");
        assert_eq!(m[12], 0xEF, "M12.4 := the cleared L46.1");
    }
}

#[test]
fn compile_refuses_bad_bool_arguments() {
    let layout = layout();
    let call = |arg: Arg| {
        vec![
            Function {
                steps: vec![Step::Call {
                    callee: 1,
                    args: vec![arg],
                }],
            },
            Function { steps: vec![] },
        ]
    };
    let bad_bit = call(bit_arg(10, 8, L, 0, true, false));
    assert!(matches!(
        compile(&layout, &bad_bit),
        Err(JitError::BitNumber { bit: 8, .. })
    ));
    let bad_param_bit = call(bit_arg(10, 0, L, 9, false, true));
    assert!(matches!(
        compile(&layout, &bad_param_bit),
        Err(JitError::BitNumber { bit: 9, .. })
    ));
    let mut wide = bit_arg(10, 0, L, 0, true, true);
    wide.width = 2;
    assert!(matches!(
        compile(&layout, &call(wide)),
        Err(JitError::Width { width: 2, .. })
    ));
    let outside = call(bit_arg(MEMORY, 0, L, 0, true, false));
    assert!(matches!(
        compile(&layout, &outside),
        Err(JitError::OutOfRange { .. })
    ));
}
