//! UM4001's byte-level access to the VM, built from its typed operations: the
//! STATUS_VAR_READ / STATUS_VAR_WRITE / STATUS_VAR_FORCE_READ / STATUS_VAR_FORCE_WRITE
//! payloads by packed address (the 32-bit layout of docs/image-format.md; USE is
//! ignored) and the 16-byte DEBUG_INFOR block. The VM knows no protocol byte layout;
//! this file knows nothing of the VM's insides. docs/simulator.md.

use gutta_catalog::Address;
use gutta_format::PackedOperand;
use gutta_protocol::message::{Breakpoint, DebugInfo};
use gutta_vm::{AccessError, ForceError, Position, Vm};

/// The variable a packed address names (USE ignored).
fn variable(address: u32) -> Result<Address, AccessError> {
    PackedOperand(address)
        .variable()
        .map_err(|e| AccessError(format!("{address:#010X}: {e}")))
}

/// 4 bytes of `area` from `at`, zero past its end; `at` itself must be inside.
fn four_bytes(area: &[u8], at: usize, slot: u8) -> Result<[u8; 4], AccessError> {
    if at >= area.len() {
        return Err(AccessError(format!(
            "slot {slot} byte {at} outside its {} bytes",
            area.len()
        )));
    }
    let mut out = [0u8; 4];
    for (k, b) in area[at..].iter().take(4).enumerate() {
        out[k] = *b;
    }
    Ok(out)
}

/// STATUS_VAR_READ: the 4 bytes from the first byte of a packed address (only SLOT and
/// OFFSET count). Bytes past the end of the area read as 0; a first byte outside the
/// area is an error.
pub fn read_packed(vm: &Vm, address: u32) -> Result<[u8; 4], AccessError> {
    let op = PackedOperand(address);
    let area = vm
        .memory()
        .area(op.slot())
        .ok_or_else(|| AccessError(format!("no area in slot {}", op.slot())))?;
    four_bytes(area, usize::from(op.offset()), op.slot())
}

/// STATUS_VAR_WRITE: write `value` where SLOT, WIDTH, BIT_OFFSET and OFFSET say (USE is
/// ignored); a forced bit takes the value as its force value too (UM4001), so the
/// write holds.
pub fn write_packed(vm: &mut Vm, address: u32, value: u32) -> Result<(), AccessError> {
    vm.write_through_forces(variable(address)?, value)
}

/// STATUS_VAR_FORCE_READ: 4 bytes of the force value image from the first byte of a
/// packed address (0 where nothing is forced; areas that cannot be forced read 0).
pub fn read_force_packed(vm: &Vm, address: u32) -> Result<[u8; 4], AccessError> {
    let op = PackedOperand(address);
    let (_, image) = vm.force_image(op.slot());
    if image.is_empty() {
        return Err(AccessError(format!("no area in slot {}", op.slot())));
    }
    four_bytes(&image, usize::from(op.offset()), op.slot())
}

/// STATUS_VAR_FORCE_WRITE: force the variable at a packed address to `value`.
pub fn force_packed(vm: &mut Vm, address: u32, value: u32) -> Result<(), ForceError> {
    let a = variable(address).map_err(|e| ForceError(e.0))?;
    vm.force(a, value)
}

/// Our extension of STATUS_VAR_FORCE_WRITE (USE 15): release the force of the variable
/// at a packed address. A word with a bad WIDTH releases nothing.
pub fn unforce_packed(vm: &mut Vm, address: u32) {
    if let Ok(a) = variable(address) {
        vm.unforce(a);
    }
}

/// DEBUG_INFOR_READ: breakpoint (0xFF / 0xFFFF: none), paused position (0xFF when not
/// paused), saved L bytes and logic stack (16 bits each), open calls, error code.
pub fn debug_info(vm: &Vm) -> DebugInfo {
    let state = vm.debug_state();
    let none = Position {
        function: 0xFF,
        network: 0xFFFF,
        step: 0xFFFF,
    };
    let bp = state.breakpoint.unwrap_or(none);
    let at = state.paused_at.unwrap_or(none);
    DebugInfo {
        breakpoint: Breakpoint {
            index: bp.function,
            network: bp.network,
            step: bp.step,
        },
        state_index: at.function,
        state_network: at.network,
        state_step: at.step,
        stack_data: u16::try_from(state.saved_local_bytes).unwrap_or(u16::MAX),
        stack_logic: (state.logic_stack & 0xFFFF) as u16,
        sp: u8::try_from(state.call_depth).unwrap_or(u8::MAX),
        error: state.error_code,
    }
}
