//! The only unsafe code of the crate (docs/vm-jit.md, "The unsafe module"): turning the
//! finalized code addresses into function pointers, calling them, freeing the code when
//! the module goes. Everything it relies on is established elsewhere and restated at each
//! block: `check.rs` proved every access of the generated code lies inside
//! `memory_len` bytes, and `run` is only given a slice of exactly that length.

use std::sync::Mutex;

use cranelift_jit::JITModule;
use cranelift_module::FuncId;

/// The native signature of every generated function (`lower.rs`: the ISA's default
/// calling convention, which is the platform's C convention): memory, logic stack, the
/// exit word (written 1 + an Escape's id when the function returns at it, else left),
/// and the instructions executed.
type Entry = unsafe extern "C" fn(*mut u8, *mut u32, *mut u32) -> i64;

/// Finalized code: one entry per function, and the module owning the code memory.
pub(crate) struct Code {
    entries: Vec<Entry>,
    memory_len: u32,
    /// Only taken by `Drop` (a Mutex so `Code` is Sync without an unsafe claim: the
    /// JITModule's RefCell is never reached through a shared reference).
    module: Mutex<Option<JITModule>>,
}

impl Code {
    /// Take the finalized module (`finalize_definitions` done) and its functions' ids.
    pub(crate) fn new(module: JITModule, ids: &[FuncId], memory_len: u32) -> Code {
        let entries = ids
            .iter()
            .map(|&id| {
                let address = module.get_finalized_function(id);
                // SAFETY: `address` is the start of function `id`, finalized (relocated,
                // made executable) by `finalize_definitions`, and compiled with the
                // signature (ptr, ptr, ptr) -> i64 in the ISA's default calling convention,
                // which is `extern "C"` on the host: the pointer types agree.
                unsafe { std::mem::transmute::<*const u8, Entry>(address) }
            })
            .collect();
        Code {
            entries,
            memory_len,
            module: Mutex::new(Some(module)),
        }
    }

    pub(crate) fn len(&self) -> usize {
        self.entries.len()
    }

    /// Call function `f` on `memory` (its length checked here again: the soundness of
    /// the call depends on it). Returns the instructions executed and the exit word (0:
    /// ran to its end; 1 + id: returned at the Escape `id`).
    #[inline]
    pub(crate) fn run(&self, f: usize, memory: &mut [u8], stack: &mut u32) -> (u64, u32) {
        assert_eq!(
            memory.len(),
            self.memory_len as usize,
            "gutta-jit: memory length"
        );
        let entry = self.entries[f];
        // SAFETY: the code stays mapped while `self` lives (freed only in Drop, which
        // cannot run during this borrow). It reads and writes only `memory[..memory_len]`
        // (every index + width checked by check.rs at compile time, asserted equal to
        // the slice's length above), the u32 behind `stack` and the u32 `exit` (a local
        // here, written only by an Escape's early return), all exclusively borrowed
        // here; its calls go only to other functions of this module (no recursion,
        // checked), with their own stack slots and the same exit word (never written
        // by a callee: check.rs refuses an Escape in a called function). It has no
        // other effects.
        let mut exit = 0u32;
        let executed = unsafe { entry(memory.as_mut_ptr(), stack, &mut exit) };
        (executed as u64, exit)
    }
}

impl Drop for Code {
    fn drop(&mut self) {
        let module = match self.module.get_mut() {
            Ok(module) => module.take(),
            Err(poisoned) => poisoned.into_inner().take(),
        };
        if let Some(module) = module {
            self.entries.clear();
            // SAFETY: the entries pointing into the code are gone (cleared above, and
            // `Code` is their only holder); no call can be running, since `run` borrows
            // `self` and we hold it mutably.
            unsafe { module.free_memory() };
        }
    }
}
