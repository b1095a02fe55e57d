//! An S7-200 timer leaves the logic stack as it found it; a GUTTA timer leaves its done
//! state. So a timer box that an instruction reading the top of the stack follows is
//! wrapped in `LPS`/`LPP` (docs/microwin.md, "Timer and counter bits"), unless the
//! export says boxes keep GUTTA's meaning (`GUTTA_BOXES`).

use std::collections::BTreeMap;

use gutta_catalog::s7200_timers::S7200TimerFamily;
use gutta_catalog::{Flow, Instruction, LadderClass};

use super::TimerBitPass;
use crate::check::{CheckedInstruction, CheckedUnit, TimerBox};
use crate::diagnostics::{Code, Diagnostic};

impl TimerBitPass<'_> {
    /// Wrap each timer box that an instruction reading the top of the stack follows
    /// in `LPS`/`LPP`: an S7-200 timer leaves the stack as it found it.
    pub(super) fn keep_stack_around_boxes(
        &mut self,
        checked: &[CheckedUnit],
        boxes: &[TimerBox],
        edits: &mut BTreeMap<(usize, usize, usize), Vec<CheckedInstruction>>,
    ) {
        let set = &self.target.instructions;
        let (Some(lps), Some(lpp)) = (
            set.plain(LadderClass::Push, None),
            set.plain(LadderClass::Pop, None),
        ) else {
            return;
        };
        let max = i32::from(set.logic_stack_depth);
        for b in boxes {
            let list = &checked[b.unit].networks[b.network].instructions;
            let ins = &list[b.index];
            if set
                .get(ins.id)
                .kind
                .and_then(S7200TimerFamily::of_kind)
                .is_none()
            {
                continue;
            }
            let Some(next) = list.get(b.index + 1) else {
                continue;
            };
            let next_spec = set.get(next.id);
            if !reads_top_of_stack(next_spec) {
                continue;
            }
            if b.depth.is_some_and(|d| d >= max) {
                self.report(
                    Diagnostic::new(
                        Code::StackOverflow,
                        b.span,
                        format!(
                            "an S7-200 timer keeps its input on the logic stack for the next instruction; \
                             here that needs one more level than the {max} the stack holds"
                        ),
                    )
                    .help("combine branches with ALD or OLD before the timer"),
                );
                continue;
            }
            let at = ins.span;
            edits.insert(
                (b.unit, b.network, b.index),
                vec![
                    CheckedInstruction {
                        id: lps,
                        operands: Vec::new(),
                        span: at,
                    },
                    ins.clone(),
                    CheckedInstruction {
                        id: lpp,
                        operands: Vec::new(),
                        span: at,
                    },
                ],
            );
        }
    }
}

/// Whether an instruction reads the top of the logic stack (the catalog's `Flow`; of
/// the stack instructions, all but the pop and the read (`LPP`, `LRD`), which replace it).
fn reads_top_of_stack(spec: &Instruction) -> bool {
    match spec.flow {
        Flow::Load | Flow::Always => false,
        Flow::Stack => !matches!(spec.ladder, LadderClass::Pop | LadderClass::Read),
        Flow::Combine | Flow::Output | Flow::Box => true,
    }
}
