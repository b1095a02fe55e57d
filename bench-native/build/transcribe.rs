//! Translates LAD text into the native Rust a careful programmer would write for the
//! same observable behaviour (docs/vm.md): a `LogicStack` per network, operands read
//! from and written to the `Memory` byte arrays, box instructions under `if s.top()`,
//! a subroutine as a plain fn (inputs in, outputs back). It knows exactly the subset
//! the generators in `programs.rs` emit and panics on anything else: it never guesses.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write;

/// Networks per generated function, so no function gets too big to compile quickly.
const NETWORKS_PER_PART: usize = 500;

/// Names the generated code uses itself (besides `in0`.., `out0`).
const RESERVED: [&str; 5] = ["mem", "s", "v", "result", "overflow"];

/// The memory areas the subset touches (fields of `Memory`).
#[derive(Debug, Clone, Copy)]
enum Area {
    I,
    Q,
    M,
    Sm,
}

impl Area {
    fn field(self) -> &'static str {
        match self {
            Area::I => "i",
            Area::Q => "q",
            Area::M => "m",
            Area::Sm => "sm",
        }
    }
}

#[derive(Debug, Clone)]
enum Operand {
    Bit { area: Area, byte: u32, bit: u32 },
    Word { area: Area, byte: u32 },
    Dword { area: Area, byte: u32 },
    Constant(i64),
    Local(String),
    Unit(String),
}

/// Anything outside the subset stops the build.
fn unsupported(what: &str, text: &str) -> ! {
    panic!("{what} outside the transcribed subset: {text:?}")
}

fn parse_operand(text: &str) -> Operand {
    let fail = || -> ! { unsupported("operand", text) };
    if let Some(name) = text.strip_prefix('#') {
        return Operand::Local(name.to_string());
    }
    if let Ok(v) = text.parse::<i64>() {
        return Operand::Constant(v);
    }
    let (area, rest) = if let Some(r) = text.strip_prefix("SM") {
        (Area::Sm, r)
    } else if let Some(r) = text.strip_prefix('I') {
        (Area::I, r)
    } else if let Some(r) = text.strip_prefix('Q') {
        (Area::Q, r)
    } else if let Some(r) = text.strip_prefix('M') {
        (Area::M, r)
    } else if text.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
        return Operand::Unit(text.to_string());
    } else {
        fail()
    };
    let number = |s: &str| s.parse::<u32>().unwrap_or_else(|_| fail());
    if let Some(r) = rest.strip_prefix('W') {
        Operand::Word {
            area,
            byte: number(r),
        }
    } else if let Some(r) = rest.strip_prefix('D') {
        Operand::Dword {
            area,
            byte: number(r),
        }
    } else if let Some((byte, bit)) = rest.split_once('.') {
        let bit = number(bit);
        if bit > 7 {
            fail();
        }
        Operand::Bit {
            area,
            byte: number(byte),
            bit,
        }
    } else {
        fail()
    }
}

/// One parsed instruction line.
#[derive(Debug)]
struct Instruction {
    mnemonic: String,
    operands: Vec<Operand>,
    line: String,
}

/// A parsed block: MAIN or a subroutine with its INT parameters.
#[derive(Debug, Default)]
struct Block {
    name: String,
    is_main: bool,
    inputs: Vec<String>,
    outputs: Vec<String>,
    /// Each network's `NETWORK n` line and instructions.
    networks: Vec<(String, Vec<Instruction>)>,
}

fn parse_blocks(lad: &str) -> Vec<Block> {
    #[derive(PartialEq)]
    enum State {
        Outside,
        Header,
        Inputs,
        Outputs,
        Body,
    }
    let mut blocks = Vec::new();
    let mut state = State::Outside;
    let mut block = Block::default();
    for raw in lad.lines() {
        let line = raw.trim();
        let fail = || -> ! { unsupported("line", raw) };
        match state {
            State::Outside => {
                if let Some(head) = line.strip_prefix("ORGANIZATION_BLOCK ") {
                    block = Block {
                        name: head.split(':').next().unwrap_or_else(|| fail()).to_string(),
                        is_main: head.ends_with(":OB1"),
                        ..Block::default()
                    };
                    if !block.is_main {
                        fail();
                    }
                } else if let Some(head) = line.strip_prefix("SUBROUTINE_BLOCK ") {
                    let (name, unit) = head.split_once(':').unwrap_or_else(|| fail());
                    if !unit.starts_with("SBR") {
                        fail();
                    }
                    block = Block {
                        name: name.to_string(),
                        ..Block::default()
                    };
                } else {
                    fail();
                }
                state = State::Header;
            }
            State::Header => match line {
                "VAR_INPUT" => state = State::Inputs,
                "VAR_OUTPUT" => state = State::Outputs,
                "BEGIN" => state = State::Body,
                _ => fail(),
            },
            State::Inputs | State::Outputs => {
                if line == "END_VAR" {
                    state = State::Header;
                    continue;
                }
                let (name, ty) = line.split_once(':').unwrap_or_else(|| fail());
                if ty.trim() != "INT;" {
                    fail();
                }
                let list = if state == State::Inputs {
                    &mut block.inputs
                } else {
                    &mut block.outputs
                };
                list.push(name.trim().to_string());
            }
            State::Body => {
                if line == "END_ORGANIZATION_BLOCK" || line == "END_SUBROUTINE_BLOCK" {
                    if (line == "END_ORGANIZATION_BLOCK") != block.is_main {
                        fail();
                    }
                    blocks.push(std::mem::take(&mut block));
                    state = State::Outside;
                } else if line.starts_with("NETWORK ") {
                    block.networks.push((line.to_string(), Vec::new()));
                } else {
                    let (mnemonic, rest) = line.split_once(' ').unwrap_or_else(|| fail());
                    let operands = rest.split(',').map(|o| parse_operand(o.trim())).collect();
                    let (_, network) = block.networks.last_mut().unwrap_or_else(|| fail());
                    network.push(Instruction {
                        mnemonic: mnemonic.to_string(),
                        operands,
                        line: line.to_string(),
                    });
                }
            }
        }
    }
    assert!(state == State::Outside, "unterminated block");
    blocks
}

/// Generates one block's body; knows the program's subroutines and the block's locals.
struct Writer<'a> {
    program: &'a str,
    subroutines: &'a BTreeMap<String, (usize, usize)>,
    locals: BTreeSet<String>,
    written_locals: BTreeSet<String>,
}

impl Writer<'_> {
    fn fail(&self, i: &Instruction) -> ! {
        unsupported("instruction", &i.line)
    }

    fn local(&self, name: &str) -> String {
        assert!(self.locals.contains(name), "unknown local #{name}");
        assert!(
            !RESERVED.contains(&name) && !name.starts_with("in") && !name.starts_with("out"),
            "local #{name} would collide with a name of the generated code"
        );
        name.to_string()
    }

    fn bit(&self, op: &Operand) -> String {
        match op {
            Operand::Bit { area, byte, bit } => {
                format!("bit(&mem.{}, {byte}, {bit})", area.field())
            }
            _ => panic!("not a bit operand: {op:?}"),
        }
    }

    /// An INT (i16) or DINT (i32) value; `bits` is 16 or 32.
    fn int(&self, op: &Operand, bits: u32) -> String {
        match (op, bits) {
            (Operand::Word { area, byte }, 16) => format!("word(&mem.{}, {byte})", area.field()),
            (Operand::Dword { area, byte }, 32) => {
                format!("dword(&mem.{}, {byte})", area.field())
            }
            (Operand::Constant(v), 16) if i16::try_from(*v).is_ok() => format!("{v}_i16"),
            (Operand::Constant(v), 32) if i32::try_from(*v).is_ok() => format!("{v}_i32"),
            (Operand::Local(name), 16) => self.local(name),
            _ => panic!("not an operand of {bits} bits: {op:?}"),
        }
    }

    /// The statement storing `value` into an INT/DINT operand.
    fn store(&mut self, op: &Operand, bits: u32, value: &str) -> String {
        match (op, bits) {
            (Operand::Word { area, byte }, 16) => {
                format!("set_word(&mut mem.{}, {byte}, {value});", area.field())
            }
            (Operand::Dword { area, byte }, 32) => {
                format!("set_dword(&mut mem.{}, {byte}, {value});", area.field())
            }
            (Operand::Local(name), 16) => {
                self.written_locals.insert(name.clone());
                format!("{} = {value};", self.local(name))
            }
            _ => panic!("not a writable operand of {bits} bits: {op:?}"),
        }
    }

    /// One instruction as statements (no indentation, one per line).
    fn instruction(&mut self, i: &Instruction) -> Vec<String> {
        let ops = &i.operands;
        let one = |n: usize| {
            if ops.len() != n {
                self.fail(i)
            }
        };
        match i.mnemonic.as_str() {
            "LD" | "A" | "AN" | "O" | "=" => one(1),
            "LDW>=" | "MOVW" | "MOVD" | "+I" | "*I" | "+D" => one(2),
            "CALL" => {}
            _ => self.fail(i),
        }
        let boxed = |body: Vec<String>| {
            let mut lines = vec!["if s.top() {".to_string()];
            lines.extend(body.into_iter().map(|l| format!("    {l}")));
            lines.push("}".to_string());
            lines
        };
        match i.mnemonic.as_str() {
            "LD" => vec![format!("s.push({});", self.bit(&ops[0]))],
            "A" => vec![format!("s.and({});", self.bit(&ops[0]))],
            "AN" => vec![format!("s.and(!{});", self.bit(&ops[0]))],
            "O" => vec![format!("s.or({});", self.bit(&ops[0]))],
            "=" => match &ops[0] {
                Operand::Bit { area, byte, bit } => vec![format!(
                    "set_bit(&mut mem.{}, {byte}, {bit}, s.top());",
                    area.field()
                )],
                _ => self.fail(i),
            },
            "LDW>=" => vec![format!(
                "s.push({} >= {});",
                self.int(&ops[0], 16),
                self.int(&ops[1], 16)
            )],
            "MOVW" | "MOVD" => {
                let bits = if i.mnemonic == "MOVW" { 16 } else { 32 };
                let value = format!("let v = {};", self.int(&ops[0], bits));
                boxed(vec![value, self.store(&ops[1], bits, "v")])
            }
            "+I" | "*I" | "+D" => {
                let bits = if i.mnemonic == "+D" { 32 } else { 16 };
                let method = if i.mnemonic == "*I" {
                    "overflowing_mul"
                } else {
                    "overflowing_add"
                };
                let (out, input) = (self.int(&ops[1], bits), self.int(&ops[0], bits));
                boxed(vec![
                    format!("let (result, overflow) = {out}.{method}({input});"),
                    self.store(&ops[1], bits, "result"),
                    "mem.math_flags(result == 0, overflow, result < 0);".to_string(),
                ])
            }
            "CALL" => self.call(i),
            _ => self.fail(i),
        }
    }

    /// CALL SBR, inputs..., outputs...: inputs read before the call, outputs stored after.
    fn call(&mut self, i: &Instruction) -> Vec<String> {
        let Some(Operand::Unit(name)) = i.operands.first() else {
            self.fail(i)
        };
        let &(inputs, outputs) = self
            .subroutines
            .get(name)
            .unwrap_or_else(|| panic!("CALL of an unknown subroutine: {:?}", i.line));
        let args = &i.operands[1..];
        if args.len() != inputs + outputs || outputs > 1 {
            self.fail(i);
        }
        let mut body = Vec::new();
        let mut names = vec!["mem".to_string()];
        for (k, arg) in args[..inputs].iter().enumerate() {
            body.push(format!("let in{k} = {};", self.int(arg, 16)));
            names.push(format!("in{k}"));
        }
        let callee = format!("{}_sbr_{}", self.program, name.to_lowercase());
        let call = format!("{callee}({})", names.join(", "));
        if let Some(out) = args.get(inputs) {
            body.push(format!("let out0 = {call};"));
            body.push(self.store(out, 16, "out0"));
        } else {
            body.push(format!("{call};"));
        }
        let mut lines = vec!["if s.top() {".to_string()];
        lines.extend(body.into_iter().map(|l| format!("    {l}")));
        lines.push("}".to_string());
        lines
    }

    /// Networks as a function body, each its own scope starting with an empty stack.
    /// With `fenced`, every network ends with `if FENCED { network_boundary(mem) }`
    /// (the function takes `const FENCED: bool`).
    fn networks(
        &mut self,
        networks: &[(String, Vec<Instruction>)],
        fenced: bool,
        out: &mut String,
    ) {
        for (header, network) in networks {
            writeln!(out, "    // {header}").expect("write to String");
            out.push_str("    {\n        let mut s = LogicStack::EMPTY;\n");
            for i in network {
                writeln!(out, "        // {}", i.line).expect("write to String");
                for l in self.instruction(i) {
                    writeln!(out, "        {l}").expect("write to String");
                }
            }
            out.push_str("    }\n");
            if fenced {
                out.push_str("    if FENCED {\n        network_boundary(mem);\n    }\n");
            }
        }
    }
}

/// The transcription of a whole program: `pub fn {program}_scan(mem: &mut Memory)`
/// (system bits, then MAIN in parts), `{program}_scan_fenced` (the same with a
/// `network_boundary` between networks) and one fn per subroutine.
pub fn transcribe(lad: &str, program: &str) -> String {
    let blocks = parse_blocks(lad);
    let subroutines: BTreeMap<String, (usize, usize)> = blocks
        .iter()
        .filter(|b| !b.is_main)
        .map(|b| (b.name.clone(), (b.inputs.len(), b.outputs.len())))
        .collect();
    let mut out = String::new();
    let mut mains = 0;
    for block in &blocks {
        let mut w = Writer {
            program,
            subroutines: &subroutines,
            locals: block.inputs.iter().chain(&block.outputs).cloned().collect(),
            written_locals: BTreeSet::new(),
        };
        if block.is_main {
            mains += 1;
            let parts = block.networks.chunks(NETWORKS_PER_PART);
            let count = parts.len();
            for (k, part) in parts.enumerate() {
                writeln!(
                    out,
                    "fn {program}_part_{k}<const FENCED: bool>(mem: &mut Memory) {{"
                )
                .expect("write");
                w.networks(part, true, &mut out);
                out.push_str("}\n\n");
            }
            let scans = [
                ("", false, "system bits, then MAIN."),
                (
                    "_fenced",
                    true,
                    "system bits, then MAIN with\n/// a `network_boundary` after every network.",
                ),
            ];
            for (suffix, fenced, what) in scans {
                writeln!(
                    out,
                    "/// One scan of the native transcription: {what}\n\
                     pub fn {program}_scan{suffix}(mem: &mut Memory) {{\n    mem.set_system_bits();"
                )
                .expect("write");
                for k in 0..count {
                    writeln!(out, "    {program}_part_{k}::<{fenced}>(mem);").expect("write");
                }
                out.push_str("}\n\n");
            }
        } else {
            let mut body = String::new();
            w.networks(&block.networks, false, &mut body);
            let params: String = block
                .inputs
                .iter()
                .map(|name| format!(", {name}: i16"))
                .collect();
            let ret = match block.outputs.len() {
                0 => "",
                1 => " -> i16",
                _ => panic!("subroutine {} has more than one output", block.name),
            };
            writeln!(
                out,
                "/// Subroutine {} of the {program} program.\n\
                 fn {program}_sbr_{}(mem: &mut Memory{params}){ret} {{",
                block.name,
                block.name.to_lowercase()
            )
            .expect("write");
            for name in block
                .inputs
                .iter()
                .filter(|n| w.written_locals.contains(*n))
            {
                writeln!(out, "    let mut {name} = {name};").expect("write");
            }
            // The VM clears L before a call: outputs start at 0.
            for name in &block.outputs {
                writeln!(out, "    let mut {name}: i16 = 0;").expect("write");
            }
            out.push_str(&body);
            if let Some(name) = block.outputs.first() {
                writeln!(out, "    {name}").expect("write");
            }
            out.push_str("}\n\n");
        }
    }
    assert_eq!(mains, 1, "a program has exactly one MAIN");
    out
}
