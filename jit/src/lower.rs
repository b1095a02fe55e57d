//! Steps to Cranelift IR to machine code: one Cranelift function per `Function`, of
//! signature (mem: ptr, stack: ptr) -> i64 (the instructions executed). The logic stack
//! lives in an SSA variable (loaded from `stack` at entry, stored at return), memory is
//! accessed at compile-time-constant offsets from `mem`, each run of Move/Math/Call
//! shares one block entered only with power flow, a Call is a direct call that saves
//! only the L bytes its callee can touch. It trusts `check.rs`: every
//! offset it emits has been checked against the memory's length. No unsafe code here.

use cranelift_codegen::ir::condcodes::{FloatCC, IntCC};
use cranelift_codegen::ir::types::{F32, I16, I32, I64, I8};
use cranelift_codegen::ir::{
    AbiParam, Block, Endianness, FuncRef, InstBuilder, MemFlagsData, StackSlot, StackSlotData,
    StackSlotKind, Type, Value,
};
use cranelift_codegen::isa::TargetFrontendConfig;
use cranelift_codegen::settings::{self, Configurable};
use cranelift_codegen::Context;
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext, Variable};
use cranelift_jit::{JITBuilder, JITModule};
use cranelift_module::{default_libcall_names, FuncId, Linkage, Module as _};

use crate::call::Code;
use crate::{
    Arith, Combine, Convert, CounterKind, Function, JitError, Layout, Logic, Preset, RealOp, Rel,
    Shift, Step, TimerKind,
};

/// The compiled functions and their machine code size.
pub(crate) struct Compiled {
    pub code: Code,
    pub code_bytes: usize,
}

fn cranelift(e: impl std::fmt::Display) -> JitError {
    JitError::Cranelift(e.to_string())
}

/// What `lower` knows of every function before emitting any: which bytes of L it may
/// touch. (Inlining small callees in place of their Calls was measured and dropped: the
/// scan benchmark's mixed program ran slower inlined, 0.86 against 0.59 ns/instr in
/// `benches/compile.rs`, and compiled slower; docs/vm-jit.md.)
struct Plan {
    /// Per function, the bytes of L (relative to its start) any access of it, or of its
    /// callees, or of its Calls' arguments, can touch.
    touched: Vec<Vec<bool>>,
}

impl Plan {
    fn new(layout: &Layout, functions: &[Function]) -> Plan {
        let mut plan = Plan {
            touched: vec![Vec::new(); functions.len()],
        };
        let mut done = vec![false; functions.len()];
        for f in 0..functions.len() {
            plan.visit(layout, functions, f, &mut done);
        }
        plan
    }

    /// Fill in function `f` after its callees (no cycles: `check.rs`).
    fn visit(&mut self, layout: &Layout, functions: &[Function], f: usize, done: &mut [bool]) {
        if done[f] {
            return;
        }
        let local_len = layout.local.map_or(0, |(_, len)| len as usize);
        let mut touched = vec![false; local_len];
        for step in &functions[f].steps {
            if let Step::Call { callee, args } = step {
                let c = *callee as usize;
                self.visit(layout, functions, c, done);
                for a in args {
                    mark(layout, &mut touched, a.var, a.width);
                }
                let call = self.call_touches(layout, c, args);
                for (t, c) in touched.iter_mut().zip(call) {
                    *t |= c;
                }
            } else {
                for (at, width) in accesses(layout, step) {
                    mark(layout, &mut touched, at, width);
                }
            }
        }
        self.touched[f] = touched;
        done[f] = true;
    }

    /// The bytes of L a Call of `callee` with `args` must save, clear and restore: what
    /// the callee can touch and the parameters the inputs are stored into. Bytes outside
    /// this set are neither read nor written between the save and the restore, so
    /// clearing and restoring them cannot be observed.
    fn call_touches(&self, layout: &Layout, callee: usize, args: &[crate::Arg]) -> Vec<bool> {
        let mut touched = self.touched[callee].clone();
        for a in args {
            mark(layout, &mut touched, a.param, a.width);
        }
        touched
    }
}

/// Mark the bytes `at..at + width` that lie in L.
fn mark(layout: &Layout, touched: &mut [bool], at: u32, width: u8) {
    let Some((start, len)) = layout.local else {
        return;
    };
    let (lo, hi) = (u64::from(at), u64::from(at) + u64::from(width));
    let (l_lo, l_hi) = (u64::from(start), u64::from(start) + u64::from(len));
    for byte in lo.max(l_lo)..hi.min(l_hi) {
        touched[(byte - l_lo) as usize] = true;
    }
}

/// The memory (index, width) a step other than a Call reads or writes.
fn accesses(layout: &Layout, step: &Step) -> Vec<(u32, u8)> {
    match *step {
        Step::Timer {
            at, state, preset, ..
        } => {
            let mut v = vec![(at, 2), (state, 8)];
            if let Preset::Word(p) = preset {
                v.push((p, 2));
            }
            v
        }
        Step::Counter {
            at, state, preset, ..
        } => {
            let mut v = vec![(at, 2), (state, 4)];
            if let Preset::Word(p) = preset {
                v.push((p, 2));
            }
            v
        }
        Step::Edge { state, .. } => vec![(state, 1)],
        Step::SetBits { at, bit, n, .. } => {
            // In pieces of at most 128 bytes (widths are u8); inside the memory (check).
            let (first, bytes) = crate::check::bit_span(at, bit, n);
            (0..bytes)
                .step_by(128)
                .map(|k| ((first + k) as u32, (bytes - k).min(128) as u8))
                .collect()
        }
        Step::Jump { .. } | Step::Label { .. } | Step::Escape { .. } => Vec::new(),
        Step::Ld { at, .. }
        | Step::Ldn { at, .. }
        | Step::A { at, .. }
        | Step::An { at, .. }
        | Step::O { at, .. }
        | Step::On { at, .. }
        | Step::Assign { at, .. } => vec![(at, 1)],
        Step::Move { src, dst, width } => vec![(src, width), (dst, width)],
        Step::Math {
            src, dst, width, ..
        } => vec![(src, width), (dst, width), (layout.flags_at, 1)],
        Step::Compare { a, b, width, .. } => vec![(a, width), (b, width)],
        Step::Network
        | Step::Not
        | Step::Ald
        | Step::Old
        | Step::Lps
        | Step::Lrd
        | Step::Lpp
        | Step::Call { .. } => Vec::new(),
        // ---- Generic families ----
        Step::Logic {
            src, dst, width, ..
        }
        | Step::Divide { src, dst, width } => {
            vec![(src, width), (dst, width), (layout.flags_at, 1)]
        }
        Step::Invert { at, width } | Step::IncDec { at, width, .. } => {
            vec![(at, width), (layout.flags_at, 1)]
        }
        Step::MulWide { src, dst } | Step::DivWide { src, dst } => {
            vec![(src, 2), (dst, 4), (layout.flags_at, 1)]
        }
        Step::Shift {
            at, width, count, ..
        } => vec![(at, width), (count, 1), (layout.flags_at, 1)],
        Step::Convert { op, src, dst } => {
            let (from, to) = op.widths();
            vec![(src, from), (dst, to), (layout.flags_at, 1)]
        }
        Step::RealMath { src, dst, .. } | Step::Sqrt { src, dst } => {
            vec![(src, 4), (dst, 4), (layout.flags_at, 1)]
        }
        Step::CompareReal { a, b, .. } => vec![(a, 4), (b, 4)],
        Step::Const { dst, width, .. } => vec![(dst, width)],
        Step::Swap { at } => vec![(at, 2)],
        Step::Store { at, .. } => vec![(at, 1)],
        Step::Lds { .. } | Step::Nop => Vec::new(),
    }
}

/// Compile checked functions (`check::check` passed).
pub(crate) fn lower(layout: &Layout, functions: &[Function]) -> Result<Compiled, JitError> {
    let mut flags = settings::builder();
    flags.set("opt_level", "speed").map_err(cranelift)?;
    // What cranelift-jit requires of its ISA (JITBuilder::with_flags sets the same).
    flags
        .set("use_colocated_libcalls", "false")
        .map_err(cranelift)?;
    flags.set("is_pic", "false").map_err(cranelift)?;
    let isa = cranelift_native::builder()
        .map_err(|m| JitError::Cranelift(format!("host machine is not supported: {m}")))?
        .finish(settings::Flags::new(flags))
        .map_err(cranelift)?;
    let mut module = JITModule::new(JITBuilder::with_isa(isa, default_libcall_names()));
    let ptr = module.target_config().pointer_type();
    let mut signature = module.make_signature();
    // Memory, logic stack, exit word (`call.rs`).
    signature.params.push(AbiParam::new(ptr));
    signature.params.push(AbiParam::new(ptr));
    signature.params.push(AbiParam::new(ptr));
    signature.returns.push(AbiParam::new(I64));
    let ids = (0..functions.len())
        .map(|i| {
            module
                .declare_function(&format!("gutta_jit_{i}"), Linkage::Local, &signature)
                .map_err(cranelift)
        })
        .collect::<Result<Vec<FuncId>, JitError>>()?;
    let plan = Plan::new(layout, functions);
    let mut ctx = module.make_context();
    let mut builder_ctx = FunctionBuilderContext::new();
    let mut code_bytes = 0;
    for (function, &id) in functions.iter().zip(&ids) {
        ctx.func.signature = signature.clone();
        // The functions this one calls, declared in it once each.
        let mut callees: Vec<Option<FuncRef>> = vec![None; functions.len()];
        for step in &function.steps {
            if let Step::Call { callee, .. } = step {
                let c = *callee as usize;
                if callees[c].is_none() {
                    callees[c] = Some(module.declare_func_in_func(ids[c], &mut ctx.func));
                }
            }
        }
        build(
            &mut ctx,
            &mut builder_ctx,
            layout,
            &plan,
            function,
            &callees,
            module.target_config(),
        );
        module
            .define_function(id, &mut ctx)
            .map_err(|e| cranelift(format!("{e:?}")))?;
        code_bytes += ctx.compiled_code().map_or(0, |c| c.code_buffer().len());
        module.clear_context(&mut ctx);
    }
    module.finalize_definitions().map_err(cranelift)?;
    let code = Code::new(module, &ids, layout.memory_len);
    Ok(Compiled { code, code_bytes })
}

/// The memory accesses of the generated code: never trapping (`check.rs` keeps them in
/// the slice), little-endian whatever the host, not assumed aligned.
fn memory_flags() -> MemFlagsData {
    MemFlagsData::new()
        .with_notrap()
        .with_endianness(Endianness::Little)
}

fn width_type(width: u8) -> Type {
    match width {
        1 => I8,
        2 => I16,
        4 => I32,
        _ => I64,
    }
}

/// Build the IR of one function into `ctx.func`.
fn build(
    ctx: &mut Context,
    builder_ctx: &mut FunctionBuilderContext,
    layout: &Layout,
    plan: &Plan,
    function: &Function,
    callees: &[Option<FuncRef>],
    frontend: TargetFrontendConfig,
) {
    let ptr = frontend.pointer_type();
    let mut b = FunctionBuilder::new(&mut ctx.func, builder_ctx);
    let entry = b.create_block();
    b.append_block_params_for_function_params(entry);
    b.switch_to_block(entry);
    b.seal_block(entry);
    let params = b.block_params(entry);
    let (mem, stack_ptr, exit_ptr) = (params[0], params[1], params[2]);
    let s = b.declare_var(I32);
    let count = b.declare_var(I64);
    // The stack pointer is a `&mut u32`: aligned and valid.
    let s0 = b.ins().load(I32, MemFlagsData::trusted(), stack_ptr, 0);
    b.def_var(s, s0);
    let instructions = function
        .steps
        .iter()
        .filter(|s| **s != Step::Network)
        .count() as i64;
    let c0 = b.ins().iconst(I64, instructions);
    b.def_var(count, c0);
    let flags_kept = b.declare_var(I32);
    let mut e = Emitter {
        b,
        mem,
        ptr,
        stack_ptr,
        exit_ptr,
        s,
        count,
        flags_kept,
        layout,
        plan,
        callees,
        callee_stack: None,
        labels: std::collections::BTreeMap::new(),
    };
    e.reload_flags();
    e.steps(&function.steps);
    let Emitter { mut b, .. } = e;
    let s_end = b.use_var(s);
    b.ins().store(MemFlagsData::trusted(), s_end, stack_ptr, 0);
    let c_end = b.use_var(count);
    b.ins().return_(&[c_end]);
    b.finalize(frontend);
}

/// Whether a Math followed by `after` (the rest of its power run, which runs with it)
/// leaves flags bits 0..2 that nothing can see: a later Math of the run sets them again
/// and nothing up to and including that Math reads or writes the flags byte (a Call
/// might, so it ends the search). Bits 3..7 stay what they were either way, and the
/// later Math reads them from memory (`Emitter::flags_kept`), so skipping the earlier flags
/// is exact.
fn flags_overwritten(layout: &Layout, after: &[Step]) -> bool {
    let touches = |at: u32, width: u8| {
        let flags = u64::from(layout.flags_at);
        (u64::from(at)..u64::from(at) + u64::from(width)).contains(&flags)
    };
    for step in after {
        match *step {
            Step::Math {
                src, dst, width, ..
            } => return !touches(src, width) && !touches(dst, width),
            Step::Move { src, dst, width } if !touches(src, width) && !touches(dst, width) => {}
            _ => return false,
        }
    }
    false
}

struct Emitter<'a, 'b> {
    b: FunctionBuilder<'a>,
    mem: Value,
    ptr: Type,
    /// Where the logic stack is returned (an Escape stores it before its early return).
    stack_ptr: Value,
    /// The exit word: an Escape taken stores 1 + its id there; passed on to callees,
    /// which hold no Escape (`check.rs`).
    exit_ptr: Value,
    /// The logic stack.
    s: Variable,
    count: Variable,
    /// Bits 3..7 of the flags byte as they are in memory: read once at entry, read
    /// again after any store that may change them (a result covering the byte, a real
    /// call, an = of one of its bits); a Math only sets bits 0..2. Math takes them from
    /// here, so no Math waits on another's store of the byte, nor on its value.
    flags_kept: Variable,
    layout: &'b Layout,
    plan: &'b Plan,
    callees: &'b [Option<FuncRef>],
    /// The callee's logic stack of a real call, made at the first one.
    callee_stack: Option<StackSlot>,
    /// Per label number, the block after its Label, made at the first Jump to it.
    labels: std::collections::BTreeMap<u16, Block>,
}

impl Emitter<'_, '_> {
    /// A 32-bit constant (Cranelift wants i32 immediates zero-extended).
    fn k(&mut self, v: u32) -> Value {
        self.b.ins().iconst(I32, i64::from(v))
    }

    /// Base and offset of memory index `at` (offsets are i32; beyond them, add).
    fn addr(&mut self, at: u32) -> (Value, i32) {
        match i32::try_from(at) {
            Ok(off) => (self.mem, off),
            Err(_) => (self.b.ins().iadd_imm_u(self.mem, i64::from(at)), 0),
        }
    }

    fn load(&mut self, ty: Type, at: u32) -> Value {
        let (base, off) = self.addr(at);
        self.b.ins().load(ty, memory_flags(), base, off)
    }

    fn store(&mut self, v: Value, at: u32) {
        let (base, off) = self.addr(at);
        self.b.ins().store(memory_flags(), v, base, off);
        let width = self.b.func.dfg.value_type(v).bytes();
        self.stored(at, width);
    }

    /// After a store of `width` bytes at `at`: read the flags byte again if it was one.
    fn stored(&mut self, at: u32, width: u32) {
        let flags_at = u64::from(self.layout.flags_at);
        if (u64::from(at)..u64::from(at) + u64::from(width)).contains(&flags_at) {
            self.reload_flags();
        }
    }

    fn reload_flags(&mut self) {
        let v = self.byte(self.layout.flags_at);
        let kept = self.b.ins().band_imm_u(v, 0xF8);
        self.b.def_var(self.flags_kept, kept);
    }

    /// The byte at `at`, zero-extended to i32.
    fn byte(&mut self, at: u32) -> Value {
        let (base, off) = self.addr(at);
        self.b.ins().uload8(I32, memory_flags(), base, off)
    }

    /// Bit `bit` of the byte at `at` (0 or 1), inverted if asked.
    fn bit(&mut self, at: u32, bit: u8, invert: bool) -> Value {
        let byte = self.byte(at);
        let shifted = self.b.ins().ushr_imm_u(byte, i64::from(bit));
        let v = self.b.ins().band_imm_u(shifted, 1);
        if invert {
            self.b.ins().bxor_imm_u(v, 1)
        } else {
            v
        }
    }

    /// s := ((s << 1) | v) & mask
    fn push(&mut self, s: Value, v: Value) -> Value {
        let shifted = self.b.ins().ishl_imm_u(s, 1);
        let or = self.b.ins().bor(shifted, v);
        let mask = self.k(self.layout.stack_mask);
        self.b.ins().band(or, mask)
    }

    /// s & (!1 | v)
    fn and_top(&mut self, s: Value, v: Value) -> Value {
        let not_one = self.k(!1);
        let keep = self.b.ins().bor(v, not_one);
        self.b.ins().band(s, keep)
    }

    /// Emit `steps` on the current logic stack: runs of boxed steps in one power block.
    fn steps(&mut self, steps: &[Step]) {
        let mut i = 0;
        while i < steps.len() {
            if let Step::Jump { label } = steps[i] {
                self.jump(label, &steps[i + 1..]);
                i += 1;
                continue;
            }
            if let Step::Label { number } = steps[i] {
                self.label(number);
                i += 1;
                continue;
            }
            if let Step::Escape { id } = steps[i] {
                self.escape(id, &steps[i..]);
                i += 1;
                continue;
            }
            if !steps[i].is_box() {
                self.step(&steps[i]);
                i += 1;
                continue;
            }
            let run = steps[i..].iter().take_while(|s| s.is_box()).count();
            let s = self.b.use_var(self.s);
            let boxes = &steps[i..i + run];
            self.with_power(s, |e| {
                for (k, step) in boxes.iter().enumerate() {
                    let flags_live = !flags_overwritten(e.layout, &boxes[k + 1..]);
                    e.boxed(step, flags_live);
                }
            });
            i += run;
        }
    }

    /// A Move, Math or Call, power flow known; a Math sets the flags only if
    /// `flags_live`.
    fn boxed(&mut self, step: &Step, flags_live: bool) {
        match *step {
            Step::Move { src, dst, width } => {
                let v = self.load(width_type(width), src);
                self.store(v, dst);
            }
            Step::Math {
                op,
                src,
                dst,
                width,
            } => self.math(op, src, dst, width, flags_live),
            Step::Call { callee, ref args } => self.call(callee as usize, args),
            Step::SetBits { at, bit, n, value } => self.set_bits(at, bit, n, value),
            _ if step.is_box() => self.generic(step),
            _ => self.step(step),
        }
    }

    /// A step that is not boxed (a boxed one here does nothing: `steps` routes them).
    fn step(&mut self, step: &Step) {
        let s = self.b.use_var(self.s);
        let new = match *step {
            Step::Timer {
                kind,
                at,
                state,
                preset,
                res,
                scan_ms,
            } => {
                let done = self.timer(kind, at, state, preset, res, scan_ms, s);
                let rest = self.b.ins().band_imm_u(s, i64::from(!1u32));
                self.b.ins().bor(rest, done)
            }
            Step::Counter {
                kind,
                at,
                state,
                preset,
                max,
            } => self.counter(kind, at, state, preset, max, s),
            Step::Edge { rising, state } => self.edge(rising, state, s),
            Step::Network => self.k(0),
            Step::Ld { at, bit } | Step::Ldn { at, bit } => {
                let v = self.bit(at, bit, matches!(step, Step::Ldn { .. }));
                self.push(s, v)
            }
            Step::A { at, bit } | Step::An { at, bit } => {
                let v = self.bit(at, bit, matches!(step, Step::An { .. }));
                self.and_top(s, v)
            }
            Step::O { at, bit } | Step::On { at, bit } => {
                let v = self.bit(at, bit, matches!(step, Step::On { .. }));
                self.b.ins().bor(s, v)
            }
            Step::Assign { at, bit } => {
                let byte = self.byte(at);
                let cleared = self.b.ins().band_imm_u(byte, i64::from(!(1u8 << bit)));
                let top = self.b.ins().band_imm_u(s, 1);
                let set = self.b.ins().ishl_imm_u(top, i64::from(bit));
                let new = self.b.ins().bor(cleared, set);
                let (base, off) = self.addr(at);
                self.b.ins().istore8(memory_flags(), new, base, off);
                self.stored(at, 1);
                s
            }
            Step::Not => self.b.ins().bxor_imm_u(s, 1),
            Step::Ald => {
                let rest = self.b.ins().ushr_imm_u(s, 1);
                let not_one = self.k(!1);
                let keep = self.b.ins().bor(s, not_one);
                self.b.ins().band(rest, keep)
            }
            Step::Old => {
                let rest = self.b.ins().ushr_imm_u(s, 1);
                let top = self.b.ins().band_imm_u(s, 1);
                self.b.ins().bor(rest, top)
            }
            Step::Lps => {
                let top = self.b.ins().band_imm_u(s, 1);
                self.push(s, top)
            }
            Step::Lrd => {
                let not_one = self.k(!1);
                let rest = self.b.ins().band(s, not_one);
                let second = self.b.ins().ushr_imm_u(s, 1);
                let second = self.b.ins().band_imm_u(second, 1);
                self.b.ins().bor(rest, second)
            }
            Step::Lpp => self.b.ins().ushr_imm_u(s, 1),
            Step::Compare {
                combine,
                rel,
                a,
                b,
                width,
            } => {
                let r = self.compare(rel, a, b, width);
                match combine {
                    Combine::Load => self.push(s, r),
                    Combine::And => self.and_top(s, r),
                    Combine::Or => self.b.ins().bor(s, r),
                }
            }
            // `steps` emits them in a power block, or as jumps and labels.
            Step::Move { .. }
            | Step::Math { .. }
            | Step::Call { .. }
            | Step::SetBits { .. }
            | Step::Jump { .. }
            | Step::Label { .. }
            | Step::Escape { .. } => s,
            // ---- Generic families ----
            Step::CompareReal { combine, rel, a, b } => {
                let x = self.load(F32, a);
                let y = self.load(F32, b);
                let cc = match rel {
                    Rel::Eq => FloatCC::Equal,
                    Rel::Ne => FloatCC::NotEqual,
                    Rel::Lt => FloatCC::LessThan,
                    Rel::Le => FloatCC::LessThanOrEqual,
                    Rel::Gt => FloatCC::GreaterThan,
                    Rel::Ge => FloatCC::GreaterThanOrEqual,
                };
                let r = self.b.ins().fcmp(cc, x, y);
                let r = self.b.ins().uextend(I32, r);
                match combine {
                    Combine::Load => self.push(s, r),
                    Combine::And => self.and_top(s, r),
                    Combine::Or => self.b.ins().bor(s, r),
                }
            }
            Step::Lds { n } => {
                let level = if n < 32 {
                    let shifted = self.b.ins().ushr_imm_u(s, i64::from(n));
                    self.b.ins().band_imm_u(shifted, 1)
                } else {
                    self.k(0)
                };
                self.push(s, level)
            }
            Step::Nop => s,
            Step::Store { at, value } => {
                let v = self.b.ins().iconst(I8, i64::from(value));
                self.store(v, at);
                s
            }
            // `steps` emits them in a power block.
            Step::Logic { .. }
            | Step::Invert { .. }
            | Step::IncDec { .. }
            | Step::Divide { .. }
            | Step::MulWide { .. }
            | Step::DivWide { .. }
            | Step::Shift { .. }
            | Step::Convert { .. }
            | Step::RealMath { .. }
            | Step::Sqrt { .. }
            | Step::Const { .. }
            | Step::Swap { .. } => s,
        };
        self.b.def_var(self.s, new);
    }

    /// Branch on the top of the stack `s`: to the first block returned when it is 1,
    /// to the second when 0; both sealed (this branch is their only way in), the
    /// builder left where it was.
    fn branch_on_power(&mut self, s: Value) -> (Block, Block) {
        let top = self.b.ins().band_imm_u(s, 1);
        let (taken, next) = (self.b.create_block(), self.b.create_block());
        self.b.ins().brif(top, taken, &[], next, &[]);
        self.b.seal_block(taken);
        self.b.seal_block(next);
        (taken, next)
    }

    /// Emit `body` in a block entered only when the top of the stack `s` is 1.
    fn with_power(&mut self, s: Value, body: impl FnOnce(&mut Self)) {
        let then = self.b.create_block();
        let after = self.b.create_block();
        let top = self.b.ins().band_imm_u(s, 1);
        self.b.ins().brif(top, then, &[], after, &[]);
        self.b.seal_block(then);
        self.b.switch_to_block(then);
        body(self);
        self.b.ins().jump(after, &[]);
        self.b.seal_block(after);
        self.b.switch_to_block(after);
    }

    /// Emit `then` in a block entered when `cond` is not 0, `els` in one entered when it
    /// is; both continue after (values cross by variables).
    fn branch(&mut self, cond: Value, then: impl FnOnce(&mut Self), els: impl FnOnce(&mut Self)) {
        let (yes, no, after) = (
            self.b.create_block(),
            self.b.create_block(),
            self.b.create_block(),
        );
        self.b.ins().brif(cond, yes, &[], no, &[]);
        self.b.seal_block(yes);
        self.b.seal_block(no);
        self.b.switch_to_block(yes);
        then(self);
        self.b.ins().jump(after, &[]);
        self.b.switch_to_block(no);
        els(self);
        self.b.ins().jump(after, &[]);
        self.b.seal_block(after);
        self.b.switch_to_block(after);
    }

    /// JMP: with power flow, the count loses the steps it skips (up to and including its
    /// Label, which does not run when jumped to; a Call skipped adds nothing either, it
    /// adds its callee's count only when it runs) and the code goes on after the Label.
    /// `after` are the steps that follow the Jump (its Label among them: `check.rs`).
    fn jump(&mut self, label: u16, after: &[Step]) {
        let skipped = after
            .iter()
            .position(|s| *s == Step::Label { number: label })
            .map_or(after, |k| &after[..=k])
            .iter()
            .filter(|s| **s != Step::Network)
            .count() as i64;
        let target = *self
            .labels
            .entry(label)
            .or_insert_with(|| self.b.create_block());
        let s = self.b.use_var(self.s);
        let (taken, next) = self.branch_on_power(s);
        self.b.switch_to_block(taken);
        let count = self.b.use_var(self.count);
        let count = self.b.ins().iadd_imm_s(count, -skipped);
        self.b.def_var(self.count, count);
        self.b.ins().jump(target, &[]);
        self.b.switch_to_block(next);
    }

    /// Escape: with power flow, store the stack and 1 + `id`, and return the count less
    /// what has not run: `rest` (the Escape and the steps after it; the count holds
    /// them all until a Jump skips some, and no Jump after it has run yet). Without,
    /// nothing (it counts 1, already in the count).
    fn escape(&mut self, id: u16, rest: &[Step]) {
        let not_run = rest.iter().filter(|s| **s != Step::Network).count() as i64;
        let s = self.b.use_var(self.s);
        let (taken, next) = self.branch_on_power(s);
        self.b.set_cold_block(taken);
        self.b.switch_to_block(taken);
        self.b
            .ins()
            .store(MemFlagsData::trusted(), s, self.stack_ptr, 0);
        let exit = self.k(u32::from(id) + 1);
        self.b
            .ins()
            .store(MemFlagsData::trusted(), exit, self.exit_ptr, 0);
        let count = self.b.use_var(self.count);
        let count = self.b.ins().iadd_imm_s(count, -not_run);
        self.b.ins().return_(&[count]);
        self.b.switch_to_block(next);
    }

    /// LBL: the code after it, where the jumps to it land (they all precede it, so its
    /// block is sealed here).
    fn label(&mut self, number: u16) {
        if let Some(block) = self.labels.remove(&number) {
            self.b.ins().jump(block, &[]);
            self.b.seal_block(block);
            self.b.switch_to_block(block);
        }
    }

    /// S/R, power flow known: the first and last bytes read, changed in their bits and
    /// written; the whole bytes between stored as constants, 8 bytes at a time.
    fn set_bits(&mut self, at: u32, bit: u8, n: u16, value: bool) {
        let (first, bytes) = crate::check::bit_span(at, bit, n);
        let end_bit = u64::from(bit) + u64::from(n);
        let mut k = 0u64;
        while k < bytes {
            let lo = (k * 8).max(u64::from(bit));
            let hi = ((k + 1) * 8).min(end_bit);
            let idx = (first + k) as u32;
            if lo == k * 8 && hi == (k + 1) * 8 {
                // A run of whole bytes.
                let whole = (k..bytes).take_while(|&j| (j + 1) * 8 <= end_bit).count() as u64;
                let mut j = 0;
                for (size, ty) in [(8u64, I64), (4, I32), (2, I16), (1, I8)] {
                    while whole - j >= size {
                        let v = if value { -1 } else { 0 };
                        let c = self.b.ins().iconst(ty, v);
                        self.store(c, idx + j as u32);
                        j += size;
                    }
                }
                k += whole;
                continue;
            }
            let mask = (((1u32 << (hi - lo)) - 1) << (lo - k * 8)) as u8;
            let byte = self.byte(idx);
            let new = if value {
                self.b.ins().bor_imm_u(byte, i64::from(mask))
            } else {
                self.b.ins().band_imm_u(byte, i64::from(!mask))
            };
            let (base, off) = self.addr(idx);
            self.b.ins().istore8(memory_flags(), new, base, off);
            self.stored(idx, 1);
            k += 1;
        }
    }

    /// A signed INT at `at`, sign-extended to i64.
    fn int(&mut self, at: u32) -> Value {
        let (base, off) = self.addr(at);
        self.b.ins().sload16(I64, memory_flags(), base, off)
    }

    /// Store the low 16 bits of the i64 `v` at `at`.
    fn set_int(&mut self, at: u32, v: Value) {
        let (base, off) = self.addr(at);
        self.b.ins().istore16(memory_flags(), v, base, off);
        self.stored(at, 2);
    }

    fn preset(&mut self, preset: Preset) -> Value {
        match preset {
            Preset::Const(v) => self.b.ins().iconst(I64, i64::from(v)),
            Preset::Word(at) => self.int(at),
        }
    }

    /// Hidden state word `k` (u32 LE) at `state`, as i32.
    fn word(&mut self, state: u32, k: u32) -> Value {
        self.load(I32, state + 4 * k)
    }

    fn set_word(&mut self, state: u32, k: u32, v: Value) {
        self.store(v, state + 4 * k);
    }

    /// A running timer's clock (`reference::advance`): the units elapsed (i64). Both
    /// words are written whether the clock starts or runs (the flags with RUNNING set,
    /// which a running clock has already; word 0 is 0 when starting): the same bytes as
    /// the reference, which writes the flags only when starting.
    fn advance(&mut self, state: u32, res: u32, scan_ms: u32) -> Value {
        let flags = self.word(state, 1);
        let w0 = self.word(state, 0);
        let running = self.b.ins().band_imm_u(flags, 1);
        let set = self.b.ins().bor_imm_u(flags, 1);
        self.set_word(state, 1, set);
        let w0 = self.b.ins().uextend(I64, w0);
        let total = self.b.ins().iadd_imm_u(w0, i64::from(scan_ms));
        let (rem, units) = if res == 1 {
            (self.b.ins().iconst(I64, 0), total)
        } else {
            (
                self.b.ins().urem_imm_u(total, i64::from(res)),
                self.b.ins().udiv_imm_u(total, i64::from(res)),
            )
        };
        let zero = self.b.ins().iconst(I64, 0);
        let rem = self.b.ins().select(running, rem, zero);
        let rem = self.b.ins().ireduce(I32, rem);
        self.set_word(state, 0, rem);
        self.b.ins().select(running, units, zero)
    }

    /// Stop the clock: word 0 := 0, flags & !RUNNING & !`also`.
    fn stop(&mut self, state: u32, also: u32) {
        let flags = self.word(state, 1);
        let zero = self.k(0);
        self.set_word(state, 0, zero);
        let cleared = self.b.ins().band_imm_u(flags, i64::from(!(1 | also)));
        self.set_word(state, 1, cleared);
    }

    /// t + units capped at `cap` when units > 0 and t < cap, else t (all i64).
    fn count_up(&mut self, t: Value, units: Value, cap: Value) -> Value {
        let sum = self.b.ins().iadd(t, units);
        let capped = self.b.ins().smin(sum, cap);
        let some = self.b.ins().icmp_imm_s(IntCC::SignedGreaterThan, units, 0);
        let below = self.b.ins().icmp(IntCC::SignedLessThan, t, cap);
        let both = self.b.ins().band(some, below);
        self.b.ins().select(both, capped, t)
    }

    /// TON/TOF/TONR in the order of `reference::timer` (loads and stores in the same
    /// order, so overlapping operands agree too): the done state (i32 0/1).
    #[allow(clippy::too_many_arguments)]
    fn timer(
        &mut self,
        kind: TimerKind,
        at: u32,
        state: u32,
        preset: Preset,
        res: u32,
        scan_ms: u32,
        s: Value,
    ) -> Value {
        const MAX: i64 = i16::MAX as i64;
        let pt = self.preset(preset);
        let top = self.b.ins().band_imm_u(s, 1);
        let done = self.b.declare_var(I32);
        match kind {
            TimerKind::On => self.branch(
                top,
                |e| {
                    let units = e.advance(state, res, scan_ms);
                    let t = e.int(at);
                    let max = e.b.ins().iconst(I64, MAX);
                    // Storing t back when it does not change writes what is there.
                    let t = e.count_up(t, units, max);
                    e.set_int(at, t);
                    let none = e.b.ins().icmp_imm_s(IntCC::SignedLessThanOrEqual, pt, 0);
                    let reached = e.b.ins().icmp(IntCC::SignedGreaterThanOrEqual, t, pt);
                    let d = e.b.ins().bor(none, reached);
                    let d = e.b.ins().uextend(I32, d);
                    e.b.def_var(done, d);
                },
                |e| {
                    e.stop(state, 0);
                    let zero = e.b.ins().iconst(I64, 0);
                    e.set_int(at, zero);
                    let d = e.k(0);
                    e.b.def_var(done, d);
                },
            ),
            TimerKind::Off => self.branch(
                top,
                |e| {
                    e.stop(state, 0);
                    let flags = e.word(state, 1);
                    let armed = e.b.ins().bor_imm_u(flags, 2);
                    e.set_word(state, 1, armed);
                    let zero = e.b.ins().iconst(I64, 0);
                    e.set_int(at, zero);
                    let d = e.k(1);
                    e.b.def_var(done, d);
                },
                |e| {
                    let flags = e.word(state, 1);
                    let armed = e.b.ins().band_imm_u(flags, 2);
                    e.branch(
                        armed,
                        |e| {
                            let units = e.advance(state, res, scan_ms);
                            let t = e.int(at);
                            let t = e.count_up(t, units, pt);
                            e.set_int(at, t);
                            let below = e.b.ins().icmp(IntCC::SignedLessThan, t, pt);
                            e.branch(
                                below,
                                |e| {
                                    let d = e.k(1);
                                    e.b.def_var(done, d);
                                },
                                |e| {
                                    e.stop(state, 2);
                                    let d = e.k(0);
                                    e.b.def_var(done, d);
                                },
                            );
                        },
                        |e| {
                            let d = e.k(0);
                            e.b.def_var(done, d);
                        },
                    );
                },
            ),
            TimerKind::Retentive => {
                // t is read before the clock runs: stored only when it changes.
                let t = self.int(at);
                let tv = self.b.declare_var(I64);
                self.b.def_var(tv, t);
                self.branch(
                    top,
                    |e| {
                        let units = e.advance(state, res, scan_ms);
                        let max = e.b.ins().iconst(I64, MAX);
                        let new = e.count_up(t, units, max);
                        let changed = e.b.ins().icmp(IntCC::NotEqual, new, t);
                        e.branch(
                            changed,
                            |e| {
                                e.set_int(at, new);
                                e.b.def_var(tv, new);
                            },
                            |_| {},
                        );
                    },
                    |e| e.stop(state, 0),
                );
                let t = self.b.use_var(tv);
                let d = self.b.ins().icmp(IntCC::SignedGreaterThanOrEqual, t, pt);
                let d = self.b.ins().uextend(I32, d);
                self.b.def_var(done, d);
            }
        }
        self.b.use_var(done)
    }

    /// A counter input's edge (`reference::counter_edge`): records `now` (i32 0/1) in
    /// flag `bit` of word 0; whether it rose (i32 0/1).
    fn counter_edge(&mut self, state: u32, bit: u32, now: Value) -> Value {
        let flags = self.word(state, 0);
        let before = self.b.ins().band_imm_u(flags, i64::from(bit));
        let cleared = self.b.ins().band_imm_u(flags, i64::from(!bit));
        let set = self.b.ins().imul_imm_u(now, i64::from(bit));
        let new = self.b.ins().bor(cleared, set);
        self.set_word(state, 0, new);
        let was = self.b.ins().icmp_imm_u(IntCC::NotEqual, before, 0);
        let was = self.b.ins().uextend(I32, was);
        self.b.ins().band_not(now, was)
    }

    /// CTU/CTD/CTUD (`reference::counter`): the new stack. The count is stored whether
    /// it changes or not (read just before, nothing written in between: the same bytes).
    fn counter(
        &mut self,
        kind: CounterKind,
        at: u32,
        state: u32,
        preset: Preset,
        max: i16,
        s: Value,
    ) -> Value {
        let pv = self.preset(preset);
        let level = |e: &mut Self, k: i64| {
            let v = e.b.ins().ushr_imm_u(s, k);
            e.b.ins().band_imm_u(v, 1)
        };
        let (pops, done) = match kind {
            CounterKind::Up => {
                let (r, cu) = (level(self, 0), level(self, 1));
                let up = self.counter_edge(state, 1, cu);
                let c = self.int(at);
                let below = self
                    .b
                    .ins()
                    .icmp_imm_s(IntCC::SignedLessThan, c, i64::from(max));
                let below = self.b.ins().uextend(I32, below);
                let inc = self.b.ins().band(up, below);
                let plus = self.b.ins().iadd_imm_s(c, 1);
                let c = self.b.ins().select(inc, plus, c);
                let zero = self.b.ins().iconst(I64, 0);
                let c = self.b.ins().select(r, zero, c);
                self.set_int(at, c);
                (2, self.b.ins().icmp(IntCC::SignedGreaterThanOrEqual, c, pv))
            }
            CounterKind::Down => {
                let (ld, cd) = (level(self, 0), level(self, 1));
                let down = self.counter_edge(state, 2, cd);
                let c = self.int(at);
                let above = self.b.ins().icmp_imm_s(IntCC::SignedGreaterThan, c, 0);
                let above = self.b.ins().uextend(I32, above);
                let dec = self.b.ins().band(down, above);
                let minus = self.b.ins().iadd_imm_s(c, -1);
                let c = self.b.ins().select(dec, minus, c);
                let c = self.b.ins().select(ld, pv, c);
                self.set_int(at, c);
                (2, self.b.ins().icmp_imm_s(IntCC::Equal, c, 0))
            }
            CounterKind::UpDown => {
                let (r, cd, cu) = (level(self, 0), level(self, 1), level(self, 2));
                let up = self.counter_edge(state, 1, cu);
                let down = self.counter_edge(state, 2, cd);
                let c = self.int(at);
                let below = self
                    .b
                    .ins()
                    .icmp_imm_s(IntCC::SignedLessThan, c, i64::from(max));
                let below = self.b.ins().uextend(I32, below);
                let inc = self.b.ins().band_not(up, down);
                let inc = self.b.ins().band(inc, below);
                let above =
                    self.b
                        .ins()
                        .icmp_imm_s(IntCC::SignedGreaterThan, c, i64::from(i16::MIN));
                let above = self.b.ins().uextend(I32, above);
                let dec = self.b.ins().band_not(down, up);
                let dec = self.b.ins().band(dec, above);
                let plus = self.b.ins().iadd_imm_s(c, 1);
                let minus = self.b.ins().iadd_imm_s(c, -1);
                let c1 = self.b.ins().select(dec, minus, c);
                let c1 = self.b.ins().select(inc, plus, c1);
                let zero = self.b.ins().iconst(I64, 0);
                let c1 = self.b.ins().select(r, zero, c1);
                self.set_int(at, c1);
                (
                    3,
                    self.b.ins().icmp(IntCC::SignedGreaterThanOrEqual, c1, pv),
                )
            }
        };
        let rest = self.b.ins().ushr_imm_u(s, pops);
        let done = self.b.ins().uextend(I32, done);
        self.push(rest, done)
    }

    /// EU/ED: the top becomes whether the input rose (fell) since the previous
    /// execution; the state byte keeps the input.
    fn edge(&mut self, rising: bool, state: u32, s: Value) -> Value {
        let now = self.b.ins().band_imm_u(s, 1);
        let before = self.byte(state);
        let (base, off) = self.addr(state);
        self.b.ins().istore8(memory_flags(), now, base, off);
        self.stored(state, 1);
        let was = self.b.ins().icmp_imm_u(IntCC::NotEqual, before, 0);
        let was = self.b.ins().uextend(I32, was);
        let out = if rising {
            self.b.ins().band_not(now, was)
        } else {
            self.b.ins().band_not(was, now)
        };
        let rest = self.b.ins().band_imm_u(s, i64::from(!1u32));
        self.b.ins().bor(rest, out)
    }

    /// dst := dst op src in the width (signed overflow), the SM1 flags if `flags_live`.
    fn math(&mut self, op: Arith, src: u32, dst: u32, width: u8, flags_live: bool) {
        let ty = width_type(width);
        let a = self.load(ty, dst);
        let b = self.load(ty, src);
        // Signed overflow of the operation in the width: the exact result (in i64 from
        // the sign-extended operands) does not fit.
        let (r, overflow) = match op {
            Arith::Add => self.b.ins().sadd_overflow(a, b),
            Arith::Sub => self.b.ins().ssub_overflow(a, b),
            Arith::Mul => self.b.ins().smul_overflow(a, b),
        };
        self.store(r, dst);
        if !flags_live {
            return;
        }
        let zero = self.b.ins().icmp_imm_s(IntCC::Equal, r, 0);
        let zero = self.b.ins().uextend(I32, zero);
        let overflow = self.b.ins().uextend(I32, overflow);
        let overflow = self.b.ins().ishl_imm_u(overflow, 1);
        // The sign bit moved to bit 2.
        let r32 = if ty == I32 {
            r
        } else {
            self.b.ins().uextend(I32, r)
        };
        let sign = self.b.ins().ushr_imm_u(r32, i64::from(width) * 8 - 3);
        let negative = self.b.ins().band_imm_u(sign, 4);
        // Bits 3..7 as they are after the result's store (`store` read them again if
        // dst covers the byte).
        let kept = self.b.use_var(self.flags_kept);
        let new = self.b.ins().bor(kept, zero);
        let new = self.b.ins().bor(new, overflow);
        let new = self.b.ins().bor(new, negative);
        let (base, off) = self.addr(self.layout.flags_at);
        self.b.ins().istore8(memory_flags(), new, base, off);
    }

    /// a rel b (0 or 1, i32): width 1 unsigned, 2 and 4 signed.
    fn compare(&mut self, rel: Rel, a: u32, b: u32, width: u8) -> Value {
        let ty = width_type(width);
        let x = self.load(ty, a);
        let y = self.load(ty, b);
        let cc = match (rel, width == 1) {
            (Rel::Eq, _) => IntCC::Equal,
            (Rel::Ne, _) => IntCC::NotEqual,
            (Rel::Lt, true) => IntCC::UnsignedLessThan,
            (Rel::Le, true) => IntCC::UnsignedLessThanOrEqual,
            (Rel::Gt, true) => IntCC::UnsignedGreaterThan,
            (Rel::Ge, true) => IntCC::UnsignedGreaterThanOrEqual,
            (Rel::Lt, false) => IntCC::SignedLessThan,
            (Rel::Le, false) => IntCC::SignedLessThanOrEqual,
            (Rel::Gt, false) => IntCC::SignedGreaterThan,
            (Rel::Ge, false) => IntCC::SignedGreaterThanOrEqual,
        };
        let r = self.b.ins().icmp(cc, x, y);
        self.b.ins().uextend(I32, r)
    }

    /// The pieces (offset, type) a copy of the L bytes marked in `touched` moves: each
    /// run of marked bytes 8 bytes at a time, then 4, 2, 1.
    fn pieces(touched: &[bool]) -> Vec<(u32, Type)> {
        let mut pieces = Vec::new();
        let mut at = 0;
        while at < touched.len() {
            if !touched[at] {
                at += 1;
                continue;
            }
            let end = at + touched[at..].iter().take_while(|t| **t).count();
            for (size, ty) in [(8, I64), (4, I32), (2, I16), (1, I8)] {
                while end - at >= size {
                    pieces.push((at as u32, ty));
                    at += size;
                }
            }
        }
        pieces
    }

    /// vm/src/calls.rs enter_planned + return_planned with the callee run in between:
    /// its steps emitted here (small callees) or a real call. Only the L bytes the callee
    /// can touch are saved, cleared and restored (`Plan::call_touches`).
    fn call(&mut self, callee: usize, args: &[crate::Arg]) {
        let inputs: Vec<Option<Value>> = args
            .iter()
            .map(|a| a.input.then(|| self.arg_load(a, false)))
            .collect();
        let touched = self.plan.call_touches(self.layout, callee, args);
        let pieces = Self::pieces(&touched);
        let start = self.layout.local.map_or(0, |(start, _)| start);
        let saved: Vec<Value> = pieces
            .iter()
            .map(|&(off, ty)| self.load(ty, start + off))
            .collect();
        for &(off, ty) in &pieces {
            let zero = self.b.ins().iconst(ty, 0);
            self.store(zero, start + off);
        }
        for (a, v) in args.iter().zip(&inputs) {
            if let Some(v) = *v {
                self.arg_store(a, true, v);
            }
        }
        self.real_call(callee);
        let outputs: Vec<Option<Value>> = args
            .iter()
            .map(|a| a.output.then(|| self.arg_load(a, true)))
            .collect();
        for (&(off, _), &v) in pieces.iter().zip(&saved) {
            self.store(v, start + off);
        }
        for (a, v) in args.iter().zip(&outputs) {
            if let Some(v) = *v {
                self.arg_store(a, false, v);
            }
        }
    }

    /// A Call argument's value, its variable's (`param` false) or its parameter's:
    /// `width` bytes, or a BOOL's bit as an i32 0 or 1.
    fn arg_load(&mut self, a: &crate::Arg, param: bool) -> Value {
        let at = if param { a.param } else { a.var };
        match a.bits {
            Some((var_bit, param_bit)) => {
                self.bit(at, if param { param_bit } else { var_bit }, false)
            }
            None => self.load(width_type(a.width), at),
        }
    }

    /// Store a Call argument's value (from `arg_load`): `width` bytes, or a BOOL's bit
    /// into its byte, the other bits kept.
    fn arg_store(&mut self, a: &crate::Arg, param: bool, v: Value) {
        let at = if param { a.param } else { a.var };
        match a.bits {
            Some((var_bit, param_bit)) => {
                let bit = if param { param_bit } else { var_bit };
                let byte = self.byte(at);
                let cleared = self.b.ins().band_imm_u(byte, i64::from(!(1u8 << bit)));
                let set = self.b.ins().ishl_imm_u(v, i64::from(bit));
                let new = self.b.ins().bor(cleared, set);
                let (base, off) = self.addr(at);
                self.b.ins().istore8(memory_flags(), new, base, off);
                self.stored(at, 1);
            }
            None => self.store(v, at),
        }
    }

    /// A direct call with an empty logic stack in a stack slot; the count it returns
    /// added to the caller's.
    fn real_call(&mut self, callee: usize) {
        let Some(func) = self.callees.get(callee).copied().flatten() else {
            // `lower` declares every callee of the function; unreachable once checked.
            return;
        };
        let slot = match self.callee_stack {
            Some(slot) => slot,
            None => {
                let slot = self.b.create_sized_stack_slot(StackSlotData::new(
                    StackSlotKind::ExplicitSlot,
                    4,
                    2,
                ));
                self.callee_stack = Some(slot);
                slot
            }
        };
        let empty = self.k(0);
        self.b.ins().stack_store(self.ptr, empty, slot, 0);
        let stack = self.b.ins().stack_addr(self.ptr, slot, 0);
        let call = self.b.ins().call(func, &[self.mem, stack, self.exit_ptr]);
        let executed = self.b.inst_results(call)[0];
        // The callee may have changed it.
        self.reload_flags();
        let count = self.b.use_var(self.count);
        let count = self.b.ins().iadd(count, executed);
        self.b.def_var(self.count, count);
    }
}

// ---- Generic families: `vm/src/ops/{math,shift,convert,moves}.rs` ----------

/// A bool (the i8 of icmp/fcmp) at bit `bit` of an i32.
fn at_bit(e: &mut Emitter<'_, '_>, cond: Value, bit: u8) -> Value {
    let v = e.b.ins().uextend(I32, cond);
    if bit == 0 {
        v
    } else {
        e.b.ins().ishl_imm_u(v, i64::from(bit))
    }
}

/// The low `width` bytes as an i32 mask.
fn mask_of(width: u8) -> u32 {
    if width >= 4 {
        u32::MAX
    } else {
        (1u32 << (u32::from(width) * 8)) - 1
    }
}

impl Emitter<'_, '_> {
    /// The `width` bytes at `at`, zero-extended (or sign-extended) to an i32.
    fn load32(&mut self, at: u32, width: u8, signed: bool) -> Value {
        let (base, off) = self.addr(at);
        let ins = self.b.ins();
        match (width, signed) {
            (1, false) => ins.uload8(I32, memory_flags(), base, off),
            (1, true) => ins.sload8(I32, memory_flags(), base, off),
            (2, false) => ins.uload16(I32, memory_flags(), base, off),
            (2, true) => ins.sload16(I32, memory_flags(), base, off),
            _ => ins.load(I32, memory_flags(), base, off),
        }
    }

    /// Store the low `width` bytes of the i32 `v` at `at`.
    fn store32(&mut self, v: Value, at: u32, width: u8) {
        let (base, off) = self.addr(at);
        match width {
            1 => self.b.ins().istore8(memory_flags(), v, base, off),
            2 => self.b.ins().istore16(memory_flags(), v, base, off),
            _ => self.b.ins().store(memory_flags(), v, base, off),
        };
        self.stored(at, u32::from(width));
    }

    /// The flags byte's bits in `mask` := `bits` (an i32 with only those bits), the
    /// others as they are in memory now (after the result's store).
    fn write_flags(&mut self, mask: u8, bits: Value) {
        let byte = self.byte(self.layout.flags_at);
        let kept = self.b.ins().band_imm_u(byte, i64::from(!mask));
        let new = self.b.ins().bor(kept, bits);
        let (base, off) = self.addr(self.layout.flags_at);
        self.b.ins().istore8(memory_flags(), new, base, off);
        if mask & 0xF8 != 0 {
            self.reload_flags();
        }
    }

    /// Flags 0 zero, 1 overflow, 2 negative from three bools (i8); None: 0.
    fn flags3(&mut self, zero: Value, overflow: Option<Value>, negative: Option<Value>) {
        let mut bits = at_bit(self, zero, 0);
        if let Some(o) = overflow {
            let o = at_bit(self, o, 1);
            bits = self.b.ins().bor(bits, o);
        }
        if let Some(n) = negative {
            let n = at_bit(self, n, 2);
            bits = self.b.ins().bor(bits, n);
        }
        self.write_flags(0x07, bits);
    }

    /// Division by zero: flags 0..2 := 0, 3 := 1.
    fn divide_by_zero(&mut self) {
        let eight = self.k(8);
        self.write_flags(0x0F, eight);
    }

    /// Flag 3 := 0.
    fn clear_divide(&mut self) {
        let zero = self.k(0);
        self.write_flags(0x08, zero);
    }

    /// REAL flags of `r`: 0 == 0, 1 not finite, 2 < 0 (if `negative`).
    fn real_flags(&mut self, r: Value, negative: bool) {
        let zero = self.b.ins().f32const(0.0);
        let is_zero = self.b.ins().fcmp(FloatCC::Equal, r, zero);
        let abs = self.b.ins().fabs(r);
        let inf = self.b.ins().f32const(f32::INFINITY);
        let not_finite = self
            .b
            .ins()
            .fcmp(FloatCC::UnorderedOrGreaterThanOrEqual, abs, inf);
        let neg = negative.then(|| self.b.ins().fcmp(FloatCC::LessThan, r, zero));
        self.flags3(is_zero, Some(not_finite), neg);
    }

    /// `v` (i32) stored at `dst` in `width` bytes when the bool `ok` holds; else the
    /// bytes stay (written back as they were).
    fn store_if(&mut self, ok: Value, v: Value, dst: u32, width: u8) {
        let old = self.load32(dst, width, false);
        let new = self.b.ins().select(ok, v, old);
        self.store32(new, dst, width);
    }

    /// A boxed generic step, power flow known.
    fn generic(&mut self, step: &Step) {
        match *step {
            Step::Logic {
                op,
                src,
                dst,
                width,
            } => {
                let a = self.load32(dst, width, false);
                let b = self.load32(src, width, false);
                let r = match op {
                    Logic::And => self.b.ins().band(a, b),
                    Logic::Or => self.b.ins().bor(a, b),
                    Logic::Xor => self.b.ins().bxor(a, b),
                };
                self.store32(r, dst, width);
                let zero = self.b.ins().icmp_imm_s(IntCC::Equal, r, 0);
                self.flags3(zero, None, None);
            }
            Step::Invert { at, width } => {
                let v = self.load32(at, width, false);
                let r = self.b.ins().bnot(v);
                let r = self.b.ins().band_imm_u(r, i64::from(mask_of(width)));
                self.store32(r, at, width);
                let zero = self.b.ins().icmp_imm_s(IntCC::Equal, r, 0);
                self.flags3(zero, None, None);
            }
            Step::IncDec { at, width: 1, up } => {
                let v = self.load32(at, 1, false);
                let r = self.b.ins().iadd_imm_s(v, if up { 1 } else { -1 });
                let r = self.b.ins().band_imm_u(r, 0xFF);
                self.store32(r, at, 1);
                let zero = self.b.ins().icmp_imm_s(IntCC::Equal, r, 0);
                let wrapped = self
                    .b
                    .ins()
                    .icmp_imm_u(IntCC::Equal, v, if up { 255 } else { 0 });
                self.flags3(zero, Some(wrapped), None);
            }
            Step::IncDec { at, width, up } => {
                let ty = width_type(width);
                let v = self.load(ty, at);
                let one = self.b.ins().iconst(ty, 1);
                let (r, overflow) = if up {
                    self.b.ins().sadd_overflow(v, one)
                } else {
                    self.b.ins().ssub_overflow(v, one)
                };
                self.store(r, at);
                let zero = self.b.ins().icmp_imm_s(IntCC::Equal, r, 0);
                let neg = self.b.ins().icmp_imm_s(IntCC::SignedLessThan, r, 0);
                self.flags3(zero, Some(overflow), Some(neg));
            }
            Step::Divide { src, dst, width } => {
                let a = self.load32(dst, width, true);
                let b = self.load32(src, width, true);
                let min = if width == 2 {
                    i64::from(i16::MIN)
                } else {
                    i64::from(i32::MIN)
                };
                self.divide(a, b, min, |e, a, b| {
                    let q = e.b.ins().sdiv(a, b);
                    e.store32(q, dst, width);
                    let q = if width == 2 {
                        let q16 = e.b.ins().ireduce(I16, q);
                        e.b.ins().sextend(I32, q16)
                    } else {
                        q
                    };
                    let zero = e.b.ins().icmp_imm_s(IntCC::Equal, q, 0);
                    let neg = e.b.ins().icmp_imm_s(IntCC::SignedLessThan, q, 0);
                    e.flags3(zero, None, Some(neg));
                });
            }
            Step::MulWide { src, dst } => {
                let a = self.load32(src, 2, true);
                let b = self.load32(dst, 2, true);
                let p = self.b.ins().imul(a, b);
                self.store32(p, dst, 4);
                let zero = self.b.ins().icmp_imm_s(IntCC::Equal, p, 0);
                let neg = self.b.ins().icmp_imm_s(IntCC::SignedLessThan, p, 0);
                self.flags3(zero, None, Some(neg));
            }
            Step::DivWide { src, dst } => {
                let d = self.load32(src, 2, true);
                let n = self.load32(dst, 2, true);
                self.divide(n, d, i64::from(i16::MIN), |e, n, d| {
                    let q = e.b.ins().sdiv(n, d);
                    let r = e.b.ins().srem(n, d);
                    let high = e.b.ins().ishl_imm_u(r, 16);
                    let low = e.b.ins().band_imm_u(q, 0xFFFF);
                    let v = e.b.ins().bor(high, low);
                    e.store32(v, dst, 4);
                    let zero = e.b.ins().icmp_imm_s(IntCC::Equal, q, 0);
                    let neg = e.b.ins().icmp_imm_s(IntCC::SignedLessThan, q, 0);
                    e.flags3(zero, None, Some(neg));
                });
            }
            Step::Shift {
                op,
                at,
                width,
                count,
            } => self.shift(op, at, width, count),
            Step::Convert { op, src, dst } => self.convert(op, src, dst),
            Step::RealMath { op, src, dst } => {
                let body = |e: &mut Self| {
                    let a = e.load(F32, dst);
                    let b = e.load(F32, src);
                    let r = match op {
                        RealOp::Add => e.b.ins().fadd(a, b),
                        RealOp::Sub => e.b.ins().fsub(a, b),
                        RealOp::Mul => e.b.ins().fmul(a, b),
                        RealOp::Div => e.b.ins().fdiv(a, b),
                    };
                    e.store(r, dst);
                    e.real_flags(r, true);
                };
                if op == RealOp::Div {
                    let b = self.load(F32, src);
                    let zero = self.b.ins().f32const(0.0);
                    let is_zero = self.b.ins().fcmp(FloatCC::Equal, b, zero);
                    self.branch(
                        is_zero,
                        |e| e.divide_by_zero(),
                        |e| {
                            e.clear_divide();
                            body(e);
                        },
                    );
                } else {
                    body(self);
                }
            }
            Step::Sqrt { src, dst } => {
                let x = self.load(F32, src);
                let r = self.b.ins().sqrt(x);
                self.store(r, dst);
                self.real_flags(r, false);
            }
            Step::Const { value, dst, width } => {
                let v = self.k(value);
                self.store32(v, dst, width);
            }
            Step::Swap { at } => {
                let v = self.load(I16, at);
                let r = self.b.ins().bswap(v);
                self.store(r, at);
            }
            _ => {}
        }
    }

    /// A signed division of the i32s `n / d` (both read already): by zero, the
    /// overflow `min / -1`, or `body` after flag 3 is cleared.
    fn divide(&mut self, n: Value, d: Value, min: i64, body: impl FnOnce(&mut Self, Value, Value)) {
        let by_zero = self.b.ins().icmp_imm_s(IntCC::Equal, d, 0);
        self.branch(
            by_zero,
            |e| e.divide_by_zero(),
            |e| {
                e.clear_divide();
                let is_min = e.b.ins().icmp_imm_s(IntCC::Equal, n, min);
                let minus_one = e.b.ins().icmp_imm_s(IntCC::Equal, d, -1);
                let overflow = e.b.ins().band(is_min, minus_one);
                e.branch(
                    overflow,
                    |e| {
                        let two = e.k(2);
                        e.write_flags(0x07, two);
                    },
                    |e| body(e, n, d),
                );
            },
        );
    }

    /// SRx/SLx/RRx/RLx (`Step::Shift`).
    fn shift(&mut self, op: Shift, at: u32, width: u8, count: u32) {
        let w = i64::from(width) * 8;
        let m = i64::from(mask_of(width));
        let v = self.load32(at, width, false);
        let n = self.load32(count, 1, false);
        let zero = self.k(0);
        let (r, out) = match op {
            Shift::Right | Shift::Left => {
                let shifted = if op == Shift::Right {
                    self.b.ins().ushr(v, n)
                } else {
                    let s = self.b.ins().ishl(v, n);
                    self.b.ins().band_imm_u(s, m)
                };
                let over = self
                    .b
                    .ins()
                    .icmp_imm_u(IntCC::UnsignedGreaterThanOrEqual, n, w);
                let r = self.b.ins().select(over, zero, shifted);
                // 1 <= n <= w: n - 1 < w unsigned.
                let n1 = self.b.ins().iadd_imm_s(n, -1);
                let moved = self.b.ins().icmp_imm_u(IntCC::UnsignedLessThan, n1, w);
                let amount = if op == Shift::Right {
                    n1
                } else {
                    let wk = self.k(w as u32);
                    self.b.ins().isub(wk, n)
                };
                let bit = self.b.ins().ushr(v, amount);
                let bit = self.b.ins().band_imm_u(bit, 1);
                (r, self.b.ins().select(moved, bit, zero))
            }
            Shift::RotateRight | Shift::RotateLeft => {
                let n = self.b.ins().band_imm_u(n, w - 1);
                let wk = self.k(w as u32);
                let back = self.b.ins().isub(wk, n);
                let (a, b) = if op == Shift::RotateRight {
                    (self.b.ins().ushr(v, n), self.b.ins().ishl(v, back))
                } else {
                    (self.b.ins().ishl(v, n), self.b.ins().ushr(v, back))
                };
                let r = self.b.ins().bor(a, b);
                let r = self.b.ins().band_imm_u(r, m);
                let bit = if op == Shift::RotateRight {
                    self.b.ins().ushr_imm_u(r, w - 1)
                } else {
                    r
                };
                let bit = self.b.ins().band_imm_u(bit, 1);
                let none = self.b.ins().icmp_imm_s(IntCC::Equal, n, 0);
                (r, self.b.ins().select(none, zero, bit))
            }
        };
        self.store32(r, at, width);
        let is_zero = self.b.ins().icmp_imm_s(IntCC::Equal, r, 0);
        let z = at_bit(self, is_zero, 0);
        let out = self.b.ins().ishl_imm_u(out, 1);
        let bits = self.b.ins().bor(z, out);
        self.write_flags(0x03, bits);
    }

    /// One conversion (`Step::Convert`).
    fn convert(&mut self, op: Convert, src: u32, dst: u32) {
        let (from, to) = op.widths();
        match op {
            Convert::Bti => {
                let v = self.load32(src, 1, false);
                self.store32(v, dst, to);
            }
            Convert::Itd => {
                let v = self.load32(src, 2, true);
                self.store32(v, dst, to);
            }
            Convert::Dtr => {
                let v = self.load32(src, 4, false);
                let r = self.b.ins().fcvt_from_sint(F32, v);
                self.store(r, dst);
            }
            Convert::Itb | Convert::Dti => {
                let v = self.load32(src, from, true);
                let ok = if op == Convert::Itb {
                    self.b.ins().icmp_imm_u(IntCC::UnsignedLessThan, v, 256)
                } else {
                    let v16 = self.b.ins().ireduce(I16, v);
                    let back = self.b.ins().sextend(I32, v16);
                    self.b.ins().icmp(IntCC::Equal, back, v)
                };
                self.store_if(ok, v, dst, to);
                let bad = self.b.ins().bxor_imm_u(ok, 1);
                let bad = at_bit(self, bad, 1);
                self.write_flags(0x02, bad);
            }
            Convert::Round | Convert::Trunc => {
                let x = self.load(F32, src);
                // A DINT holds round(x) and trunc(x) exactly when -2^31 <= x < 2^31
                // (the f32 next to those bounds are integers already): false for NaN.
                let lo = self.b.ins().f32const(-2_147_483_648.0);
                let hi = self.b.ins().f32const(2_147_483_648.0);
                let above = self.b.ins().fcmp(FloatCC::GreaterThanOrEqual, x, lo);
                let below = self.b.ins().fcmp(FloatCC::LessThan, x, hi);
                let ok = self.b.ins().band(above, below);
                // Toward zero, saturating (never traps; the value is used only if ok).
                let mut t = self.b.ins().fcvt_to_sint_sat(I32, x);
                if op == Convert::Round {
                    // x - trunc(x) is exact; halves go away from zero.
                    let tf = self.b.ins().fcvt_from_sint(F32, t);
                    let frac = self.b.ins().fsub(x, tf);
                    let half = self.b.ins().f32const(0.5);
                    let minus_half = self.b.ins().f32const(-0.5);
                    let up = self.b.ins().fcmp(FloatCC::GreaterThanOrEqual, frac, half);
                    let down = self
                        .b
                        .ins()
                        .fcmp(FloatCC::LessThanOrEqual, frac, minus_half);
                    let up = self.b.ins().uextend(I32, up);
                    let down = self.b.ins().uextend(I32, down);
                    t = self.b.ins().iadd(t, up);
                    t = self.b.ins().isub(t, down);
                }
                self.store_if(ok, t, dst, 4);
                let bad = self.b.ins().bxor_imm_u(ok, 1);
                let bad = at_bit(self, bad, 1);
                self.write_flags(0x02, bad);
            }
            Convert::Bcdi => {
                let v = self.load32(src, 2, false);
                let mut bad = None;
                let mut n = self.k(0);
                for shift in [12, 8, 4, 0] {
                    let d = self.b.ins().ushr_imm_u(v, shift);
                    let d = self.b.ins().band_imm_u(d, 0xF);
                    let over = self.b.ins().icmp_imm_u(IntCC::UnsignedGreaterThan, d, 9);
                    bad = Some(match bad {
                        None => over,
                        Some(b) => self.b.ins().bor(b, over),
                    });
                    let ten = self.b.ins().imul_imm_u(n, 10);
                    n = self.b.ins().iadd(ten, d);
                }
                let bad = bad.unwrap_or(n);
                let ok = self.b.ins().bxor_imm_u(bad, 1);
                self.store_if(ok, n, dst, to);
                let bad = at_bit(self, bad, 6);
                self.write_flags(0x40, bad);
            }
            Convert::Ibcd => {
                let v = self.load32(src, 2, true);
                let ok = self
                    .b
                    .ins()
                    .icmp_imm_u(IntCC::UnsignedLessThanOrEqual, v, 9999);
                let thousands = self.b.ins().udiv_imm_u(v, 1000);
                let hundreds = self.b.ins().udiv_imm_u(v, 100);
                let hundreds = self.b.ins().urem_imm_u(hundreds, 10);
                let tens = self.b.ins().udiv_imm_u(v, 10);
                let tens = self.b.ins().urem_imm_u(tens, 10);
                let ones = self.b.ins().urem_imm_u(v, 10);
                let mut bcd = self.b.ins().ishl_imm_u(thousands, 12);
                for (digit, shift) in [(hundreds, 8), (tens, 4), (ones, 0)] {
                    let d = self.b.ins().ishl_imm_u(digit, shift);
                    bcd = self.b.ins().bor(bcd, d);
                }
                self.store_if(ok, bcd, dst, to);
                let bad = self.b.ins().bxor_imm_u(ok, 1);
                let bad = at_bit(self, bad, 6);
                self.write_flags(0x40, bad);
            }
            Convert::Seg => {
                // The 16 patterns in two 64-bit constants, a byte each: no table in
                // memory to bound.
                let v = self.load32(src, 1, false);
                let nibble = self.b.ins().band_imm_u(v, 0xF);
                let low = self.b.ins().icmp_imm_u(IntCC::UnsignedLessThan, nibble, 8);
                let lo = self.b.ins().iconst(I64, SEGMENTS_LO as i64);
                let hi = self.b.ins().iconst(I64, SEGMENTS_HI as i64);
                let table = self.b.ins().select(low, lo, hi);
                let k = self.b.ins().band_imm_u(nibble, 7);
                let k = self.b.ins().ishl_imm_u(k, 3);
                let k = self.b.ins().uextend(I64, k);
                let pattern = self.b.ins().ushr(table, k);
                let pattern = self.b.ins().ireduce(I32, pattern);
                let pattern = self.b.ins().band_imm_u(pattern, 0xFF);
                self.store32(pattern, dst, to);
            }
            Convert::Deco => {
                let v = self.load32(src, 1, false);
                let nibble = self.b.ins().band_imm_u(v, 0xF);
                let one = self.k(1);
                let r = self.b.ins().ishl(one, nibble);
                self.store32(r, dst, to);
            }
            Convert::Enco => {
                let v = self.load32(src, 2, false);
                let zero = self.b.ins().icmp_imm_s(IntCC::Equal, v, 0);
                let ok = self.b.ins().bxor_imm_u(zero, 1);
                let lowest = self.b.ins().ctz(v);
                self.store_if(ok, lowest, dst, to);
                let bad = at_bit(self, zero, 1);
                self.write_flags(0x02, bad);
            }
        }
    }
}

/// SEG's patterns of 0..7 and 8..F, a byte each from the low end (convert.rs SEGMENTS).
const SEGMENTS_LO: u64 = 0x07_7D_6D_66_4F_5B_06_3F;
const SEGMENTS_HI: u64 = 0x71_79_5E_39_7C_77_6F_7F;
