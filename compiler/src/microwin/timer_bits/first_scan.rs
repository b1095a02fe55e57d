//! A TOF's S7-200 bit is "the current value is below the preset", which must hold from
//! the first scan on: MAIN starts with a network that sets every off-delay timer whose
//! bit is used to its start value on the first scan (docs/microwin.md, "Timer and
//! counter bits").

use gutta_catalog::{BlockKind, Join, LadderClass, Width};

use super::TimerBitPass;
use crate::check::{CheckedInstruction, CheckedNetwork, CheckedOperand, CheckedUnit, Use};
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;

impl TimerBitPass<'_> {
    /// MAIN's first-scan network: `LD` the first-scan bit, then set every off-delay
    /// timer whose bit is used to its start value.
    pub(super) fn first_scan_network(
        &mut self,
        checked: &mut [CheckedUnit],
        inits: &[(CheckedOperand, CheckedOperand, Span)],
    ) {
        let at = inits[0].2;
        let Some(main) = checked
            .iter_mut()
            .find(|u| u.kind == BlockKind::Interrupt && u.number == 0)
        else {
            return; // E0408 says MAIN is missing.
        };
        let first_scan = self
            .target
            .memory
            .system_bits
            .iter()
            .find(|b| b.name == "FIRST_SCAN")
            .and_then(|b| self.target.memory.parse_address(&b.address).ok());
        let (Some(bit), Some(ld), Some(movw)) = (
            first_scan,
            self.target
                .instructions
                .plain(LadderClass::Contact, Some(Join::Load)),
            self.target.instructions.lookup("MOVW"),
        ) else {
            self.report(Diagnostic::new(
                Code::S7200TimerBit,
                at,
                format!(
                    "{} has no first-scan bit (`FIRST_SCAN`), which a TOF's S7-200 bit needs",
                    self.target.name()
                ),
            ));
            return;
        };
        let mut instructions = vec![CheckedInstruction {
            id: ld,
            operands: vec![CheckedOperand::Memory {
                address: bit,
                use_: Use::Value,
                width: Width::Bit,
            }],
            span: at,
        }];
        instructions.extend(inits.iter().map(|(start, timer, span)| CheckedInstruction {
            id: movw,
            operands: vec![*start, *timer],
            span: *span,
        }));
        match main.networks.first_mut() {
            Some(first) if first.number == 0 => {
                first.instructions.splice(0..0, instructions);
            }
            _ => main.networks.insert(
                0,
                CheckedNetwork {
                    number: 0,
                    title: None,
                    span: at,
                    instructions,
                },
            ),
        }
    }
}
