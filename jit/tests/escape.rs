//! Step::Escape: without power flow it counts 1 and does nothing; with power flow the
//! function returns at once, the stack as the Escape found it, counting only what ran
//! before it, and `enter` names the Escape. Compiled against the reference and against
//! the values written here; the refusal of an Escape inside a called function.

use gutta_jit::{compile, reference, Exit, Function, JitError, Layout, Step};

const MEMORY: u32 = 32;

fn layout() -> Layout {
    Layout {
        memory_len: MEMORY,
        flags_at: 30,
        stack_mask: 0x1FF,
        local: Some((20, 8)),
    }
}

/// Run function `f` compiled and by the reference on `memory` with `stack`; they must
/// agree on memory, stack, count and exit. Returns the compiled run's.
fn both(functions: &[Function], f: usize, memory: &[u8], stack: u32) -> (Vec<u8>, u32, Exit) {
    let layout = layout();
    let module = compile(&layout, functions).expect("compiles");
    let (mut jm, mut js) = (memory.to_vec(), stack);
    let je = module.enter(f, &mut jm, &mut js);
    let (mut rm, mut rs) = (memory.to_vec(), stack);
    let re = reference::enter(&layout, functions, f, &mut rm, &mut rs);
    assert_eq!(jm, rm, "memory: {functions:?}");
    assert_eq!(js, rs, "stack: {functions:?}");
    assert_eq!(je, re, "exit: {functions:?}");
    // `run` is `enter` without the exit.
    let (mut m, mut s) = (memory.to_vec(), stack);
    assert_eq!(module.run(f, &mut m, &mut s), je.executed);
    (jm, js, je)
}

fn exit(executed: u64, escape: Option<u16>) -> Exit {
    Exit { executed, escape }
}

/// LD bit 0 of byte 0; = bit 0 of byte 1; Escape 7; = bit 1 of byte 1; NOT; = bit 2.
fn guarded() -> Vec<Function> {
    vec![Function {
        steps: vec![
            Step::Network,
            Step::Ld { at: 0, bit: 0 },
            Step::Assign { at: 1, bit: 0 },
            Step::Escape { id: 7 },
            Step::Assign { at: 1, bit: 1 },
            Step::Not,
            Step::Assign { at: 1, bit: 2 },
        ],
    }]
}

#[test]
fn an_escape_without_power_flow_counts_one_and_does_nothing() {
    let mut memory = vec![0u8; MEMORY as usize];
    memory[1] = 0x80;
    let (m, s, e) = both(&guarded(), 0, &memory, 0);
    // 6 instructions (the Network counts 0), the Escape among them.
    assert_eq!(e, exit(6, None));
    assert_eq!(m[1], 0x80 | 0b100);
    assert_eq!(s, 1);
}

#[test]
fn an_escape_with_power_flow_returns_at_once() {
    let mut memory = vec![0u8; MEMORY as usize];
    memory[0] = 1;
    let (m, s, e) = both(&guarded(), 0, &memory, 0x1F0);
    // LD and = ran; the Escape and what follows did not.
    assert_eq!(e, exit(2, Some(7)));
    assert_eq!(m[1], 0b1, "only the = before the escape ran");
    assert_eq!(
        s, 1,
        "the stack the escape found: the network cleared it, LD pushed 1"
    );
}

#[test]
fn escapes_first_last_and_in_a_row() {
    let steps = vec![
        Step::Escape { id: 0 },
        Step::Ld { at: 0, bit: 0 },
        Step::Escape { id: 1 },
        Step::Escape { id: 2 },
        Step::Ld { at: 0, bit: 1 },
        Step::Escape { id: 3 },
    ];
    let f = vec![Function { steps }];
    let memory = |b: u8| {
        let mut m = vec![0u8; MEMORY as usize];
        m[0] = b;
        m
    };
    // First, with the stack's top 1 at entry.
    assert_eq!(both(&f, 0, &memory(3), 1).2, exit(0, Some(0)));
    // Top 0: the first counts 1, LD bit 0 = 1 takes the second.
    assert_eq!(both(&f, 0, &memory(1), 0).2, exit(2, Some(1)));
    // LD 0, both in a row pass, LD bit 1 = 1 takes the last.
    assert_eq!(both(&f, 0, &memory(2), 0).2, exit(5, Some(3)));
    // None taken: all 6 count.
    let (_, s, e) = both(&f, 0, &memory(0), 0);
    assert_eq!(e, exit(6, None));
    assert_eq!(s, 0);
}

#[test]
fn an_escape_after_a_jump_and_a_call_counts_what_ran() {
    let functions = vec![
        Function {
            steps: vec![
                Step::Ld { at: 0, bit: 0 },
                // Taken when bit 0 is 1: skips the Escape 1 and the Label (2 counted).
                Step::Jump { label: 4 },
                Step::Escape { id: 1 },
                Step::Label { number: 4 },
                Step::Ld { at: 0, bit: 1 },
                Step::Call {
                    callee: 1,
                    args: Vec::new(),
                },
                Step::Escape { id: 2 },
                Step::Assign { at: 2, bit: 0 },
            ],
        },
        Function {
            steps: vec![
                Step::Ld { at: 0, bit: 2 },
                Step::Assign { at: 3, bit: 0 },
                Step::Not,
            ],
        },
    ];
    let memory = |b: u8| {
        let mut m = vec![0u8; MEMORY as usize];
        m[0] = b;
        m
    };
    // bit 0 = 1: jump over the first escape; bit 1 = 1: call (1 + 3), then escape 2.
    // Ran: LD, JMP, LD, CALL + 3 = 7.
    let (m, _, e) = both(&functions, 0, &memory(0b111), 0);
    assert_eq!(e, exit(7, Some(2)));
    assert_eq!(m[3], 1, "the callee ran");
    assert_eq!(m[2], 0, "the = after the escape did not");
    // bit 0 = 1 only: jump, no call, no escape: LD JMP LD CALL ESC = (Label skipped).
    assert_eq!(both(&functions, 0, &memory(0b001), 0).2, exit(6, None));
    // Nothing set: the jump not taken, escape 1 not taken either, Label counts.
    assert_eq!(both(&functions, 0, &memory(0), 0).2, exit(8, None));
}

#[test]
fn an_escape_inside_a_jump_span_is_taken_when_not_jumped_over() {
    let f = vec![Function {
        steps: vec![
            Step::Ld { at: 0, bit: 0 },
            Step::Jump { label: 1 },
            Step::Ld { at: 0, bit: 1 },
            Step::Escape { id: 9 },
            Step::Label { number: 1 },
            Step::Assign { at: 2, bit: 0 },
        ],
    }];
    let memory = |b: u8| {
        let mut m = vec![0u8; MEMORY as usize];
        m[0] = b;
        m
    };
    // Not jumped (bit 0 = 0), bit 1 = 1: LD JMP LD ran, then the escape.
    let (m, s, e) = both(&f, 0, &memory(0b10), 0);
    assert_eq!(e, exit(3, Some(9)));
    assert_eq!(s, 0b01, "LD 0 then LD 1 pushed: top 1, below 0");
    assert_eq!(m[2], 0);
    // Jumped: LD JMP =: 3, no exit.
    assert_eq!(both(&f, 0, &memory(0b11), 0).2, exit(3, None));
}

#[test]
fn an_escape_in_a_called_function_is_refused() {
    let functions = vec![
        Function {
            steps: vec![Step::Call {
                callee: 1,
                args: Vec::new(),
            }],
        },
        Function {
            steps: vec![Step::Not, Step::Escape { id: 3 }],
        },
    ];
    let e = compile(&layout(), &functions).expect_err("refused");
    assert_eq!(
        e,
        JitError::EscapeInCallee {
            function: 1,
            step: 1,
            caller: 0,
        }
    );
    assert!(e.to_string().contains("escape"));
    // Not called, the same function compiles.
    let alone = vec![functions[1].clone()];
    assert!(compile(&layout(), &alone).is_ok());
}
