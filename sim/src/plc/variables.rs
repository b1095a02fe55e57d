//! Variables through the protocol: STATUS_VAR_READ/WRITE and the force functions, by
//! packed address (docs/vm.md, "Status and debugging"). A request with one address
//! outside an area fails whole and writes nothing. Only `Plc::dispatch` calls these.

use gutta_format::PackedOperand;
use gutta_vm::Vm;

use super::{Plc, Refusal};
use crate::vm_access;

/// The USE field value that makes STATUS_VAR_FORCE_WRITE release a force (our
/// extension; docs/simulator.md).
pub use gutta_format::RELEASE_USE;

impl Plc {
    /// STATUS_VAR_READ: the 4 bytes at each address.
    pub(super) fn read_vars(&self, addresses: &[PackedOperand]) -> Result<Vec<u32>, Refusal> {
        self.read_each(addresses, vm_access::read_packed)
    }

    /// STATUS_VAR_FORCE_READ: the force value of each address.
    pub(super) fn read_forces(&self, addresses: &[PackedOperand]) -> Result<Vec<u32>, Refusal> {
        self.read_each(addresses, vm_access::read_force_packed)
    }

    /// STATUS_VAR_WRITE: every pair, or none when an address is bad.
    pub(super) fn write_vars(&mut self, pairs: Vec<(PackedOperand, u32)>) -> Result<(), Refusal> {
        self.check_each(&pairs)?;
        for (address, value) in pairs {
            vm_access::write_packed(&mut self.vm, address.0, value)
                .map_err(|e| Refusal::Access(e.0))?;
        }
        Ok(())
    }

    /// STATUS_VAR_FORCE_WRITE: force every pair (USE 15 releases), or none when an
    /// address is bad.
    pub(super) fn write_forces(&mut self, pairs: Vec<(PackedOperand, u32)>) -> Result<(), Refusal> {
        self.check_each(&pairs)?;
        for (address, value) in pairs {
            if address.use_code() == RELEASE_USE {
                // Our extension: USE 15 releases the force (UM4001 has no
                // unforce; a PLC that ignores USE forces the value sent, which
                // the client makes the current value).
                vm_access::unforce_packed(&mut self.vm, address.0);
            } else {
                vm_access::force_packed(&mut self.vm, address.0, value)
                    .map_err(|e| Refusal::Access(e.0))?;
            }
        }
        Ok(())
    }

    /// Every address read, or the first refusal.
    fn read_each(
        &self,
        addresses: &[PackedOperand],
        read: impl Fn(&Vm, u32) -> Result<[u8; 4], gutta_vm::AccessError>,
    ) -> Result<Vec<u32>, Refusal> {
        addresses
            .iter()
            .map(|a| {
                read(&self.vm, a.0)
                    .map(u32::from_le_bytes)
                    .map_err(|e| Refusal::Access(e.0))
            })
            .collect()
    }

    /// Every address of a write checked first, so a bad one writes nothing.
    fn check_each(&self, pairs: &[(PackedOperand, u32)]) -> Result<(), Refusal> {
        for (address, _) in pairs {
            vm_access::read_packed(&self.vm, address.0).map_err(|e| Refusal::Access(e.0))?;
        }
        Ok(())
    }
}
