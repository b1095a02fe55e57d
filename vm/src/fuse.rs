//! Fusing: runs of bit logic in a unit's operations become one chain of steps (docs/vm.md,
//! "Speed"), a network start alone one `NetworkLoad`, moves, math and compares one
//! operation per width, and a breakpoint is patched in. Record numbering never changes,
//! so a scan can stop at any record of a chain.

use crate::op::{
    Bit, ChainStep, Op, STEP_AND, STEP_ANDN, STEP_LOAD, STEP_LOADN, STEP_OR, STEP_ORN, STEP_STORE,
};

fn step(b: Bit, kind: u8) -> ChainStep {
    ChainStep {
        at: b.at,
        bit: b.mask.trailing_zeros() as u8,
        kind,
    }
}

fn chain_step(op: Op) -> Option<ChainStep> {
    let (b, kind) = match op {
        Op::A(b) => (b, STEP_AND),
        Op::An(b) => (b, STEP_ANDN),
        Op::O(b) => (b, STEP_OR),
        Op::On(b) => (b, STEP_ORN),
        Op::Assign(b) => (b, STEP_STORE),
        _ => return None,
    };
    Some(step(b, kind))
}

/// A network record followed by LD/LDN at `k`: the chain step that starts it.
fn network_start(ops: &[Op], k: usize) -> Option<ChainStep> {
    if !matches!(ops.get(k), Some(Op::Network)) {
        return None;
    }
    match ops.get(k + 1) {
        Some(&Op::Ld(b)) => Some(step(b, STEP_LOAD)),
        Some(&Op::Ldn(b)) => Some(step(b, STEP_LOADN)),
        _ => None,
    }
}

/// The operations the fast path runs: `plain` with the breakpoint (if any) patched in,
/// and fused: runs of bit logic become one chain (steps appended to `chain`). A chain
/// is A/AN/O/ON/`=` records, and whole networks that are a network record, LD/LDN and
/// such records; it covers at least two records. Fused operations sit at the first
/// record they cover; the records after keep their plain operations, so record
/// numbering is unchanged and a scan can stop at any of them. A chain that is only a
/// network record and its LD/LDN is a `NetworkLoad` instead. Every move, math and
/// compare becomes its operation of its width (`by_width`).
pub(crate) fn build(
    plain: &[Op],
    breakpoint: Option<usize>,
    chain: &mut Vec<ChainStep>,
) -> Vec<Op> {
    let mut ops = plain.to_vec();
    chain.clear();
    if let Some(op) = breakpoint.and_then(|pc| ops.get_mut(pc)) {
        *op = Op::Break;
    }
    let mut k = 0;
    while k < ops.len() {
        let first = chain.len();
        let mut j = k;
        loop {
            if chain.len() - first >= u16::MAX as usize - 1 {
                break;
            }
            if let Some(load) = network_start(&ops, j) {
                chain.push(load);
                j += 2;
            } else if j != k {
                break;
            }
            while let Some(step) = ops.get(j).and_then(|&op| chain_step(op)) {
                if chain.len() - first >= u16::MAX as usize {
                    break;
                }
                chain.push(step);
                j += 1;
            }
            if network_start(&ops, j).is_none() {
                break;
            }
        }
        let records = j - k;
        if records == 2 && chain.len() - first == 1 {
            // Just a network's start: one operation, no chain.
            let step = chain[first];
            ops[k] = Op::NetworkLoad {
                bit: Bit {
                    at: step.at,
                    mask: 1 << step.bit,
                },
                invert: u8::from(step.kind == STEP_LOADN),
            };
            chain.truncate(first);
            k = j;
        } else if records >= 2 {
            let steps = chain.len() - first;
            ops[k] = Op::Chain {
                first: u32::try_from(first).unwrap_or(u32::MAX),
                records: u32::try_from(records).unwrap_or(u32::MAX),
                networks: (records - steps) as u16,
            };
            k = j;
        } else {
            chain.truncate(first);
            k += 1;
        }
    }
    for op in &mut ops {
        *op = by_width(*op);
    }
    ops
}

/// A move, math or compare as its operation of its width.
fn by_width(op: Op) -> Op {
    match op {
        Op::Move { src, dst, width } => match width {
            1 => Op::MoveB { src, dst },
            2 => Op::MoveW { src, dst },
            _ => Op::MoveD { src, dst },
        },
        Op::Math {
            op,
            src,
            dst,
            width,
        } => match width {
            2 => Op::MathW { op, src, dst },
            _ => Op::MathD { op, src, dst },
        },
        Op::Compare {
            combine,
            rel,
            a,
            b,
            width,
        } => match width {
            1 => Op::CompareB { combine, rel, a, b },
            2 => Op::CompareW { combine, rel, a, b },
            _ => Op::CompareD { combine, rel, a, b },
        },
        op => op,
    }
}
