//! The debugger through the protocol: STATUS_DEBUG_WRITE (run or single-step stop),
//! STATUS_DEBUG_SCAN (a step), STATUS_DEBUG_RESET, STATUS_DEBUG_INFOR_READ/WRITE (the
//! breakpoint; function 0xFF clears it, our decision). The VM's debugger keeps the
//! state; this module only translates protocol values into its calls.

use gutta_protocol::message::{Breakpoint, DebugInfo, DebugStep};
use gutta_vm::{Position, Step};

use super::{Plc, Refusal};

impl Plc {
    /// STATUS_DEBUG_WRITE: run until a breakpoint, or stop at the next instruction.
    pub(super) fn debug_run(&mut self, run: bool) -> Result<(), Refusal> {
        if run {
            self.vm.debug_run();
            Ok(())
        } else {
            self.vm
                .debug_stop()
                .map_err(|e| Refusal::Debug(e.to_string()))
        }
    }

    /// STATUS_DEBUG_SCAN: one step in, over or out.
    pub(super) fn debug_step(&mut self, step: DebugStep) -> Result<(), Refusal> {
        let step = match step {
            DebugStep::In => Step::In,
            DebugStep::Over => Step::Over,
            DebugStep::Out => Step::Out,
        };
        self.vm
            .debug_step(step)
            .map(|_| ())
            .map_err(|e| Refusal::Debug(e.to_string()))
    }

    /// STATUS_DEBUG_RESET: reset into single-step stop.
    pub(super) fn debug_reset(&mut self) -> Result<(), Refusal> {
        self.vm
            .debug_reset()
            .map_err(|e| Refusal::Debug(e.to_string()))
    }

    /// STATUS_DEBUG_INFOR_READ.
    /// Byte 15 (ERROR) says why a PLC has no program when its flash does
    /// (`Plc::error_code`), else carries the VM's fault code.
    pub(super) fn debug_info(&self) -> DebugInfo {
        let info = crate::vm_access::debug_info(&self.vm);
        DebugInfo {
            error: self.error_code(info.error),
            ..info
        }
    }

    /// STATUS_DEBUG_INFOR_WRITE: set the breakpoint; function 0xFF clears it.
    pub(super) fn set_breakpoint(&mut self, breakpoint: Breakpoint) -> Result<(), Refusal> {
        let at = (breakpoint.index != 0xFF).then_some(Position {
            function: breakpoint.index,
            network: breakpoint.network,
            step: breakpoint.step,
        });
        self.vm
            .set_breakpoint(at)
            .map_err(|e| Refusal::Debug(e.to_string()))
    }
}
