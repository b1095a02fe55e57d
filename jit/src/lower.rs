//! Steps to Cranelift IR to machine code: one Cranelift function per `Function`, of
//! signature (mem: ptr, stack: ptr) -> i64 (the instructions executed). The logic stack
//! lives in an SSA variable (loaded from `stack` at entry, stored at return), memory is
//! accessed at compile-time-constant offsets from `mem`, Move/Math/Call run in a block
//! entered only with power flow, a Call is a direct call. It trusts `check.rs`: every
//! offset it emits has been checked against the memory's length. No unsafe code here.

use cranelift_codegen::ir::condcodes::IntCC;
use cranelift_codegen::ir::types::{I16, I32, I64, I8};
use cranelift_codegen::ir::{
    AbiParam, Endianness, FuncRef, InstBuilder, MemFlagsData, StackSlot, StackSlotData,
    StackSlotKind, Type, Value,
};
use cranelift_codegen::isa::TargetFrontendConfig;
use cranelift_codegen::settings::{self, Configurable};
use cranelift_codegen::Context;
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext, Variable};
use cranelift_jit::{JITBuilder, JITModule};
use cranelift_module::{default_libcall_names, FuncId, Linkage, Module as _};

use crate::call::Code;
use crate::{Arith, Combine, Function, JitError, Layout, Rel, Step};

/// The compiled functions and their machine code size.
pub(crate) struct Compiled {
    pub code: Code,
    pub code_bytes: usize,
}

fn cranelift(e: impl std::fmt::Display) -> JitError {
    JitError::Cranelift(e.to_string())
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
    let (mem, stack_ptr) = (params[0], params[1]);
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
    let mut e = Emitter {
        b,
        mem,
        ptr,
        s,
        count,
        layout,
        callees,
        frame: None,
    };
    for step in &function.steps {
        e.step(step);
    }
    let Emitter { mut b, .. } = e;
    let s_end = b.use_var(s);
    b.ins().store(MemFlagsData::trusted(), s_end, stack_ptr, 0);
    let c_end = b.use_var(count);
    b.ins().return_(&[c_end]);
    b.finalize(frontend);
}

/// The stack slots of a function that calls: the callee's logic stack, the caller's L.
#[derive(Clone, Copy)]
struct Frame {
    callee_stack: StackSlot,
    saved_local: Option<StackSlot>,
}

struct Emitter<'a, 'b> {
    b: FunctionBuilder<'a>,
    mem: Value,
    ptr: Type,
    s: Variable,
    count: Variable,
    layout: &'b Layout,
    callees: &'b [Option<FuncRef>],
    frame: Option<Frame>,
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

    fn step(&mut self, step: &Step) {
        let s = self.b.use_var(self.s);
        let new = match *step {
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
            Step::Move { src, dst, width } => {
                self.with_power(s, |e| {
                    let v = e.load(width_type(width), src);
                    e.store(v, dst);
                });
                s
            }
            Step::Math {
                op,
                src,
                dst,
                width,
            } => {
                self.with_power(s, |e| e.math(op, src, dst, width));
                s
            }
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
            Step::Call { callee, ref args } => {
                self.with_power(s, |e| e.call(callee, args));
                s
            }
        };
        self.b.def_var(self.s, new);
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

    /// dst := dst op src (sign-extended to i64), the SM1 flags.
    fn math(&mut self, op: Arith, src: u32, dst: u32, width: u8) {
        let ty = width_type(width);
        let a = self.load(ty, dst);
        let a = self.b.ins().sextend(I64, a);
        let b = self.load(ty, src);
        let b = self.b.ins().sextend(I64, b);
        let exact = match op {
            Arith::Add => self.b.ins().iadd(a, b),
            Arith::Sub => self.b.ins().isub(a, b),
            Arith::Mul => self.b.ins().imul(a, b),
        };
        let wrapped = self.b.ins().ireduce(ty, exact);
        self.store(wrapped, dst);
        let r = self.b.ins().sextend(I64, wrapped);
        let zero = self.b.ins().icmp_imm_s(IntCC::Equal, r, 0);
        let overflow = self.b.ins().icmp(IntCC::NotEqual, r, exact);
        let negative = self.b.ins().icmp_imm_s(IntCC::SignedLessThan, r, 0);
        let zero = self.b.ins().uextend(I32, zero);
        let overflow = self.b.ins().uextend(I32, overflow);
        let overflow = self.b.ins().ishl_imm_u(overflow, 1);
        let negative = self.b.ins().uextend(I32, negative);
        let negative = self.b.ins().ishl_imm_u(negative, 2);
        // Read after the result's store: dst may cover the flags byte.
        let flags_at = self.layout.flags_at;
        let old = self.byte(flags_at);
        let kept = self.b.ins().band_imm_u(old, 0xF8);
        let new = self.b.ins().bor(kept, zero);
        let new = self.b.ins().bor(new, overflow);
        let new = self.b.ins().bor(new, negative);
        let (base, off) = self.addr(flags_at);
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

    /// The stack slots of a calling function, made at its first Call.
    fn frame(&mut self) -> Frame {
        if let Some(frame) = self.frame {
            return frame;
        }
        let callee_stack =
            self.b
                .create_sized_stack_slot(StackSlotData::new(StackSlotKind::ExplicitSlot, 4, 2));
        let saved_local =
            match self.layout.local {
                Some((_, len)) if len > 0 => Some(self.b.create_sized_stack_slot(
                    StackSlotData::new(StackSlotKind::ExplicitSlot, len, 3),
                )),
                _ => None,
            };
        let frame = Frame {
            callee_stack,
            saved_local,
        };
        self.frame = Some(frame);
        frame
    }

    /// The pieces (offset, type) a copy of `len` bytes moves: 8 bytes at a time, then
    /// 4, 2, 1.
    fn pieces(len: u32) -> Vec<(u32, Type)> {
        let mut pieces = Vec::new();
        let mut off = 0;
        for (size, ty) in [(8, I64), (4, I32), (2, I16), (1, I8)] {
            while len - off >= size {
                pieces.push((off, ty));
                off += size;
            }
        }
        pieces
    }

    /// vm/src/calls.rs enter_planned + return_planned, the callee run in between.
    fn call(&mut self, callee: u32, args: &[crate::Arg]) {
        let Some(callee) = self.callees.get(callee as usize).copied().flatten() else {
            // `lower` declares every callee of the function; unreachable once checked.
            return;
        };
        let frame = self.frame();
        let inputs: Vec<Option<Value>> = args
            .iter()
            .map(|a| a.input.then(|| self.load(width_type(a.width), a.var)))
            .collect();
        let local = self.layout.local.filter(|&(_, len)| len > 0);
        if let (Some((start, len)), Some(slot)) = (local, frame.saved_local) {
            let zero = self.b.ins().iconst(I64, 0);
            for (off, ty) in Self::pieces(len) {
                let v = self.load(ty, start + off);
                self.b.ins().stack_store(self.ptr, v, slot, off as i32);
                let z = if ty == I64 {
                    zero
                } else {
                    self.b.ins().ireduce(ty, zero)
                };
                self.store(z, start + off);
            }
        }
        for (a, v) in args.iter().zip(&inputs) {
            if let Some(v) = *v {
                self.store(v, a.param);
            }
        }
        let empty = self.k(0);
        self.b
            .ins()
            .stack_store(self.ptr, empty, frame.callee_stack, 0);
        let stack = self.b.ins().stack_addr(self.ptr, frame.callee_stack, 0);
        let call = self.b.ins().call(callee, &[self.mem, stack]);
        let executed = self.b.inst_results(call)[0];
        let outputs: Vec<Option<Value>> = args
            .iter()
            .map(|a| a.output.then(|| self.load(width_type(a.width), a.param)))
            .collect();
        if let (Some((start, len)), Some(slot)) = (local, frame.saved_local) {
            for (off, ty) in Self::pieces(len) {
                let v = self.b.ins().stack_load(self.ptr, ty, slot, off as i32);
                self.store(v, start + off);
            }
        }
        for (a, v) in args.iter().zip(&outputs) {
            if let Some(v) = *v {
                self.store(v, a.var);
            }
        }
        let count = self.b.use_var(self.count);
        let count = self.b.ins().iadd(count, executed);
        self.b.def_var(self.count, count);
    }
}
