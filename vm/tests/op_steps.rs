//! The VM's decoded operations (`vm/src/op.rs`, `Op`) against the compiled tier's steps
//! (`jit/src/lib.rs`, `Step`), so the tiers cannot drift apart (ARCHITECTURE.md,
//! "Invariants"). Two parts:
//!
//! - `every_op_has_a_row_and_every_step_an_op`: both enums read from the sources with
//!   `syn`; `TABLE` says what each `Op` becomes in the tier (`vm/src/tier.rs`), and the
//!   table is checked against the translation itself (`simple_step`, `Builder::step`)
//!   and against `Op::widened` for the per-width forms. A new `Op` or `Step` fails here
//!   until it is given a row.
//! - A differential test per family the tier compiles (integer math with its flags,
//!   moves, compares of BYTE/INT/DINT, bit logic): one program, random and edge
//!   operands, run by the generic semantics (`fast` off), the interpreter and compiled
//!   at load; for math and compares also by gutta-jit's compiled code and its reference
//!   interpreter on the same operands. Random programs mixing the families are
//!   `native_tier.rs`; gutta-jit's steps against its reference, `jit/tests/`.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use syn::visit::Visit;

/// What the compiled tier makes of an `Op`.
enum Tier {
    /// `simple_step` translates it to these steps.
    Direct(&'static [&'static str]),
    /// Never in `simple_step` (it returns None): the tier takes the plain operations
    /// it stands for (`Unit::plain_op`), these `Op`s, whose steps these are.
    Plain(&'static [&'static str], &'static [&'static str]),
    /// `Builder::step` translates it to these steps (a planned CALL whose callee
    /// compiles whole; a timer or counter with its side table; JMP/LBL records).
    Call(&'static [&'static str]),
    /// `Builder::step` translates the first steps itself (JMP/LBL records, and the
    /// boxes it keeps interpreted as escapes) and hands the other generic records to
    /// `tier_generic.rs`, which builds the second.
    Generic(&'static [&'static str], &'static [&'static str]),
    /// The tier never takes it: why.
    Interpreted(&'static str),
}

use Tier::{Call, Direct, Generic, Interpreted, Plain};

const BIT_OPS: &[&str] = &["Network", "Ld", "Ldn", "A", "An", "O", "On", "Assign"];
const BIT_STEPS: &[&str] = BIT_OPS;

/// Every `Op` and what the compiled tier makes of it.
const TABLE: &[(&str, Tier)] = &[
    ("Network", Direct(&["Network"])),
    ("Chain", Plain(BIT_OPS, BIT_STEPS)),
    (
        "NetworkLoad",
        Plain(&["Network", "Ld", "Ldn"], &["Network", "Ld", "Ldn"]),
    ),
    ("Ld", Direct(&["Ld"])),
    ("Ldn", Direct(&["Ldn"])),
    ("A", Direct(&["A"])),
    ("An", Direct(&["An"])),
    ("O", Direct(&["O"])),
    ("On", Direct(&["On"])),
    ("Not", Direct(&["Not"])),
    ("Assign", Direct(&["Assign"])),
    ("Ald", Direct(&["Ald"])),
    ("Old", Direct(&["Old"])),
    ("Lps", Direct(&["Lps"])),
    ("Lrd", Direct(&["Lrd"])),
    ("Lpp", Direct(&["Lpp"])),
    ("Move", Direct(&["Move"])),
    ("Math", Direct(&["Math"])),
    ("Compare", Direct(&["Compare"])),
    ("MoveB", Plain(&["Move"], &["Move"])),
    ("MoveW", Plain(&["Move"], &["Move"])),
    ("MoveD", Plain(&["Move"], &["Move"])),
    ("MathW", Plain(&["Math"], &["Math"])),
    ("MathD", Plain(&["Math"], &["Math"])),
    ("CompareB", Plain(&["Compare"], &["Compare"])),
    ("CompareW", Plain(&["Compare"], &["Compare"])),
    ("CompareD", Plain(&["Compare"], &["Compare"])),
    ("Call", Call(&["Call"])),
    ("Timer", Call(&["Timer"])),
    ("Counter", Call(&["Counter"])),
    ("Edge", Direct(&["Edge"])),
    ("SetBits", Direct(&["SetBits"])),
    // JMP/LBL records (the other generic records: tier_generic.rs).
    (
        "Generic",
        Generic(
            &["Jump", "Label", "Escape"],
            &[
                "CompareReal",
                "Const",
                "Convert",
                "DivWide",
                "Divide",
                "IncDec",
                "Invert",
                "Lds",
                "Logic",
                "MulWide",
                "Nop",
                "Store",
                "RealMath",
                "Shift",
                "Sqrt",
                "Swap",
            ],
        ),
    ),
    (
        "Break",
        Interpreted("a breakpoint: while one is set everything runs interpreted"),
    ),
];

#[allow(
    clippy::disallowed_methods,
    reason = "the table is checked against the tiers' sources"
)]
fn parse(relative: &str) -> syn::File {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(relative);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{relative}: {e}"));
    syn::parse_file(&text).unwrap_or_else(|e| panic!("{relative}: {e}"))
}

fn variants(file: &syn::File, name: &str) -> Vec<String> {
    file.items
        .iter()
        .find_map(|item| match item {
            syn::Item::Enum(e) if e.ident == name => {
                Some(e.variants.iter().map(|v| v.ident.to_string()).collect())
            }
            _ => None,
        })
        .unwrap_or_else(|| panic!("no enum {name}"))
}

/// The `Enum::Variant` paths (exactly two segments) under a node, by enum.
#[derive(Default)]
struct Paths(BTreeMap<String, BTreeSet<String>>, bool);

impl<'a> Visit<'a> for Paths {
    fn visit_path(&mut self, p: &'a syn::Path) {
        if p.segments.len() == 2 && p.leading_colon.is_none() {
            self.0
                .entry(p.segments[0].ident.to_string())
                .or_default()
                .insert(p.segments[1].ident.to_string());
        }
        syn::visit::visit_path(self, p);
    }
    fn visit_expr_return(&mut self, r: &'a syn::ExprReturn) {
        self.1 = true;
        syn::visit::visit_expr_return(self, r);
    }
}

fn paths_of(enum_name: &str, visit: impl FnOnce(&mut Paths)) -> (BTreeSet<String>, bool) {
    let mut p = Paths::default();
    visit(&mut p);
    (p.0.remove(enum_name).unwrap_or_default(), p.1)
}

/// The first `match` in a function body.
#[derive(Default)]
struct FirstMatch(Option<syn::ExprMatch>);

impl<'a> Visit<'a> for FirstMatch {
    fn visit_expr_match(&mut self, m: &'a syn::ExprMatch) {
        if self.0.is_none() {
            self.0 = Some(m.clone());
        }
    }
}

fn function<'f>(file: &'f syn::File, name: &str) -> &'f syn::Block {
    file.items
        .iter()
        .find_map(|item| match item {
            syn::Item::Fn(f) if f.sig.ident == name => Some(&*f.block),
            _ => None,
        })
        .unwrap_or_else(|| panic!("no fn {name}"))
}

fn method<'f>(file: &'f syn::File, ty: &str, name: &str) -> &'f syn::Block {
    file.items
        .iter()
        .filter_map(|item| match item {
            syn::Item::Impl(i) if quote_type(&i.self_ty) == ty => Some(i),
            _ => None,
        })
        .flat_map(|i| &i.items)
        .find_map(|item| match item {
            syn::ImplItem::Fn(f) if f.sig.ident == name => Some(&f.block),
            _ => None,
        })
        .unwrap_or_else(|| panic!("no {ty}::{name}"))
}

fn quote_type(ty: &syn::Type) -> String {
    match ty {
        syn::Type::Path(p) => p
            .path
            .segments
            .last()
            .map(|s| s.ident.to_string())
            .unwrap_or_default(),
        _ => String::new(),
    }
}

/// Per `Op` variant named in a pattern of `block`'s first match: the `Step`s its arm
/// builds, None when the arm returns (the tier cannot take it).
fn arms(block: &syn::Block, from: &str, to: &str) -> BTreeMap<String, Option<BTreeSet<String>>> {
    let mut first = FirstMatch::default();
    first.visit_block(block);
    let m = first.0.expect("a match");
    let mut arms = BTreeMap::new();
    for arm in &m.arms {
        let (ops, _) = paths_of(from, |p| p.visit_pat(&arm.pat));
        let (steps, returns) = paths_of(to, |p| p.visit_expr(&arm.body));
        for op in ops {
            let built = (!returns).then(|| steps.clone());
            assert!(arms.insert(op.clone(), built).is_none(), "{op} in two arms");
        }
    }
    arms
}

fn set(names: &[&str]) -> BTreeSet<String> {
    names.iter().map(|s| s.to_string()).collect()
}

#[test]
fn every_op_has_a_row_and_every_step_an_op() {
    let op_rs = parse("src/op.rs");
    let tier_rs = parse("src/tier.rs");
    let tier_generic_rs = parse("src/tier_generic.rs");
    let (steps_in_generic, _) = paths_of("Step", |p| p.visit_file(&tier_generic_rs));
    let ops = variants(&op_rs, "Op");
    let steps: BTreeSet<String> = variants(&parse("../jit/src/lib.rs"), "Step")
        .into_iter()
        .collect();
    let rows: BTreeMap<&str, &Tier> = TABLE.iter().map(|(op, t)| (*op, t)).collect();
    assert_eq!(rows.len(), TABLE.len(), "an Op with two rows");

    let missing: Vec<_> = ops
        .iter()
        .filter(|o| !rows.contains_key(o.as_str()))
        .collect();
    assert!(
        missing.is_empty(),
        "Op variants without a row in TABLE: {missing:?}"
    );
    let stale: Vec<_> = rows
        .keys()
        .filter(|r| !ops.iter().any(|o| o == *r))
        .collect();
    assert!(
        stale.is_empty(),
        "rows of TABLE that are no Op variant: {stale:?}"
    );

    // The tier's translation: every Op named in simple_step's match (no wildcard may
    // hide a new one), each either built into steps or refused.
    let simple = arms(function(&tier_rs, "simple_step"), "Op", "Step");
    let unnamed: Vec<_> = ops.iter().filter(|o| !simple.contains_key(*o)).collect();
    assert!(
        unnamed.is_empty(),
        "Ops simple_step does not name: {unnamed:?}"
    );
    let widened = arms(method(&op_rs, "Op", "widened"), "Op", "Op");
    let (in_step, _) = paths_of("Op", |p| p.visit_block(method(&tier_rs, "Builder", "step")));
    let (steps_in_step, _) = paths_of("Step", |p| {
        p.visit_block(method(&tier_rs, "Builder", "step"))
    });

    let mut mapped = BTreeSet::new();
    for (op, tier) in TABLE {
        let built = &simple[*op];
        match tier {
            Direct(to) => {
                assert_eq!(built.as_ref(), Some(&set(to)), "simple_step's arm of {op}");
                mapped.extend(set(to));
            }
            Plain(plain, to) => {
                assert_eq!(
                    built, &None,
                    "simple_step must refuse {op}: it is not plain"
                );
                let mut union = BTreeSet::new();
                for p in *plain {
                    match rows.get(p) {
                        Some(Direct(s)) => union.extend(set(s)),
                        _ => panic!("{op}'s plain form {p} is not a Direct row"),
                    }
                }
                assert_eq!(union, set(to), "{op}: the steps of its plain forms");
                mapped.extend(set(to));
            }
            Call(to) => {
                assert_eq!(built, &None, "simple_step must leave {op} to Builder::step");
                for to in *to {
                    assert!(
                        in_step.contains(*op) && steps_in_step.contains(*to),
                        "Builder::step must translate Op::{op} to Step::{to}"
                    );
                    mapped.insert(to.to_string());
                }
            }
            Generic(own, generic) => {
                assert_eq!(built, &None, "simple_step must leave {op} to Builder::step");
                for to in *own {
                    assert!(
                        in_step.contains(*op) && steps_in_step.contains(*to),
                        "Builder::step must translate Op::{op} to Step::{to}"
                    );
                    mapped.insert(to.to_string());
                }
                for to in *generic {
                    assert!(
                        steps_in_generic.contains(*to),
                        "tier_generic.rs must build Step::{to}"
                    );
                    mapped.insert(to.to_string());
                }
            }
            Interpreted(why) => {
                assert!(!why.is_empty());
                assert_eq!(
                    built, &None,
                    "simple_step translates {op}, listed interpreted"
                );
                assert!(!in_step.contains(*op), "Builder::step takes {op}");
            }
        }
    }
    // The per-width forms of op.rs are exactly the Plain rows of one form.
    for (op, w) in &widened {
        if let (Some(w), Some(Plain(plain, _))) = (w, rows.get(op.as_str())) {
            assert_eq!(w, &set(plain), "Op::widened of {op}");
        }
    }
    let unmapped: Vec<_> = steps.difference(&mapped).collect();
    assert!(
        unmapped.is_empty(),
        "Step variants no Op maps to: {unmapped:?}"
    );
    let unknown: Vec<_> = mapped.difference(&steps).collect();
    assert!(
        unknown.is_empty(),
        "TABLE names steps jit has not: {unknown:?}"
    );
}

#[cfg(feature = "jit")]
mod common;

/// The differential tests per family: the tests below run this program with operands
/// they write into the inputs.
#[cfg(feature = "jit")]
mod differential {
    use gutta_jit::{reference, Arith, Combine, Function, Layout, Module, Rel, Step};
    use gutta_vm::{TierState, Vm, VmConfig};
    use proptest::prelude::*;

    use super::common;

    /// Integer math: (mnemonic, jit op, width); each result gets its own OUT, first
    /// loaded with the left operand, and its SMB1 copied right after it.
    const MATH: [(&str, Arith, u8); 6] = [
        ("+I", Arith::Add, 2),
        ("-I", Arith::Sub, 2),
        ("*I", Arith::Mul, 2),
        ("+D", Arith::Add, 4),
        ("-D", Arith::Sub, 4),
        ("*D", Arith::Mul, 4),
    ];
    const RELS: [(&str, Rel); 6] = [
        ("=", Rel::Eq),
        ("<>", Rel::Ne),
        ("<", Rel::Lt),
        ("<=", Rel::Le),
        (">", Rel::Gt),
        (">=", Rel::Ge),
    ];
    /// Compares by width: (letter, width, a, b).
    const COMPARES: [(&str, u8, &str, &str); 3] = [
        ("B", 1, "MB12", "MB13"),
        ("W", 2, "MW0", "MW2"),
        ("D", 4, "MD4", "MD8"),
    ];

    /// The math's OUT and flag copy.
    fn math_out(k: usize) -> (String, String) {
        let out = if k < 3 {
            format!("MW{}", 20 + 2 * k)
        } else {
            format!("MD{}", 60 + 4 * (k - 3))
        };
        (out, format!("MB{}", 40 + k))
    }

    /// The bit a compare (width `w`, relation `r`, combine `c` 0 LD, 1 A, 2 O) writes.
    fn compare_out(w: usize, r: usize, c: usize) -> String {
        let i = (w * 6 + r) * 3 + c;
        format!("M{}.{}", 110 + i / 8, i % 8)
    }

    /// Inputs: INT a, b in MW0, MW2; DINT a, b in MD4, MD8; BYTE a, b in MB12, MB13;
    /// bits in MB14, MB15. MAIN starts and ends with more than `MIN_REGION` compilable
    /// instructions, so one region means every record compiled.
    fn program() -> String {
        let mut s = String::from("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\n");
        for (k, (m, _, width)) in MATH.iter().enumerate() {
            let (out, flags) = math_out(k);
            let (mov, a, b) = if *width == 2 {
                ("MOVW", "MW0", "MW2")
            } else {
                ("MOVD", "MD4", "MD8")
            };
            s += &format!("{mov} {a}, {out}\n{m} {b}, {out}\nMOVB SMB1, {flags}\n");
        }
        // Source and destination the same variable.
        s += "MOVW MW0, MW26\n+I MW26, MW26\nMOVB SMB1, MB46\n";
        s += "MOVD MD4, MD72\n*D MD72, MD72\nMOVB SMB1, MB47\n";
        // Moves of every width, one of them unaligned.
        s += "MOVB MB12, MB80\nMOVW MW2, MW82\nMOVD MD8, MD84\nMOVR MD4, MD88\nMOVD MD1, MD92\n";
        // Boxes with power flow from a bit.
        s += "NETWORK 2\nLD M15.4\nMOVW MW0, MW100\n+I MW2, MW100\nMOVD MD4, MD104\n\
              *D MD8, MD104\nMOVB SMB1, MB108\n";
        let mut n = 3;
        for (w, (letter, _, a, b)) in COMPARES.iter().enumerate() {
            for (r, (rel, _)) in RELS.iter().enumerate() {
                for (c, first) in ["", "LD M14.0\nA", "LD M14.1\nO"].iter().enumerate() {
                    let op = if c == 0 { "LD" } else { "" };
                    s += &format!(
                        "NETWORK {n}\n{first}{op}{letter}{rel} {a}, {b}\n= {}\n",
                        compare_out(w, r, c)
                    );
                    n += 1;
                }
            }
        }
        // Bit logic: every step, the stack operations, a byte written and read back,
        // the logic stack nine deep.
        s += &format!(
            "NETWORK {n}\nLD M14.0\nA M14.1\nON M14.2\nLPS\nAN M14.3\n= M120.0\nLRD\nO M14.4\n\
             = M120.1\nLPP\nNOT\n= M120.2\nLD M14.5\nLDN M14.6\nO M14.7\nALD\nLD M15.0\nA M15.1\n\
             OLD\n= M120.3\nLDN M15.2\nO M15.3\nNOT\n= M120.4\n= M120.5\n\
             NETWORK {}\nLD M14.0\n= M121.0\nLD M121.0\nAN M14.1\n= M121.1\nLD M121.1\nO M14.2\n\
             = M121.2\nNETWORK {}\nLD M14.0\nLD M14.1\nLD M14.2\nLD M14.3\nLD M14.4\nLD M14.5\nLD M14.6\n\
             LD M14.7\nLDN M15.0\nALD\nOLD\nALD\nOLD\nALD\nOLD\nALD\nOLD\n= M122.0\n\
             END_ORGANIZATION_BLOCK\n",
            n + 1,
            n + 2
        );
        s
    }

    /// One case's inputs.
    #[derive(Debug, Clone, Copy)]
    struct Operands {
        w: [i16; 2],
        d: [i32; 2],
        b: [u8; 2],
        bits: [u8; 2],
    }

    const EDGES_16: [i16; 12] = [
        i16::MIN,
        i16::MIN + 1,
        -256,
        -182,
        -1,
        0,
        1,
        2,
        181,
        256,
        i16::MAX - 1,
        i16::MAX,
    ];
    const EDGES_32: [i32; 12] = [
        i32::MIN,
        i32::MIN + 1,
        -65536,
        -46341,
        -1,
        0,
        1,
        2,
        46341,
        65536,
        i32::MAX - 1,
        i32::MAX,
    ];
    const EDGES_8: [u8; 6] = [0, 1, 0x7F, 0x80, 0xFE, 0xFF];

    /// The engines: generic semantics (`fast` off), interpreter, compiled at load.
    struct Engines {
        vms: [Vm; 3],
        layout: Layout,
        /// Math (as `MATH`), then compares (width by `COMPARES`, relation by `RELS`).
        functions: Vec<Function>,
        module: Module,
    }

    fn engines() -> Engines {
        let text = program();
        let vms = common::three_engines(VmConfig::default()).map(|c| common::load(&text, c));
        assert!(
            matches!(vms[2].tier(), TierState::Compiled { regions: 1, .. }),
            "MAIN must compile whole: {:?}",
            vms[2].tier()
        );
        let layout = Layout {
            memory_len: 16,
            flags_at: 8,
            stack_mask: 0x1FF,
            local: None,
        };
        let mut functions: Vec<Function> = MATH
            .iter()
            .map(|&(_, op, width)| Function {
                steps: vec![Step::Math {
                    op,
                    src: 4,
                    dst: 0,
                    width,
                }],
            })
            .collect();
        for (_, width, _, _) in COMPARES {
            for (_, rel) in RELS {
                functions.push(Function {
                    steps: vec![Step::Compare {
                        combine: Combine::Load,
                        rel,
                        a: 0,
                        b: 4,
                        width,
                    }],
                });
            }
        }
        let module = gutta_jit::compile(&layout, &functions).expect("compiles");
        Engines {
            vms,
            layout,
            functions,
            module,
        }
    }

    /// Function `f` of gutta-jit on operands `a`, `b`: compiled and by the reference,
    /// which must agree; returns the memory and the logic stack.
    fn jit(e: &Engines, f: usize, width: u8, a: u32, b: u32, stack: u32) -> (Vec<u8>, u32) {
        let mut mem = vec![0u8; 16];
        reference::store(&mut mem, 0, width, a);
        reference::store(&mut mem, 4, width, b);
        let (mut cm, mut cs) = (mem.clone(), stack);
        e.module.run(f, &mut cm, &mut cs);
        let (mut rm, mut rs) = (mem, stack);
        reference::run(&e.layout, &e.functions, f, &mut rm, &mut rs);
        assert_eq!(
            (&cm, cs),
            (&rm, rs),
            "gutta-jit compiled vs reference, function {f}"
        );
        (cm, cs)
    }

    /// Rust's own result and SM1.0..2 of `a op b` at `width`.
    fn expected(op: Arith, width: u8, a: i32, b: i32) -> (u32, u8) {
        let (r, overflow) = match (op, width) {
            (Arith::Add, 2) => (
                (a as i16).wrapping_add(b as i16) as i32,
                (a as i16).checked_add(b as i16).is_none(),
            ),
            (Arith::Sub, 2) => (
                (a as i16).wrapping_sub(b as i16) as i32,
                (a as i16).checked_sub(b as i16).is_none(),
            ),
            (Arith::Mul, 2) => (
                (a as i16).wrapping_mul(b as i16) as i32,
                (a as i16).checked_mul(b as i16).is_none(),
            ),
            (Arith::Add, _) => (a.wrapping_add(b), a.checked_add(b).is_none()),
            (Arith::Sub, _) => (a.wrapping_sub(b), a.checked_sub(b).is_none()),
            (Arith::Mul, _) => (a.wrapping_mul(b), a.checked_mul(b).is_none()),
        };
        let mask = if width == 2 { 0xFFFF } else { u32::MAX };
        let flags = u8::from(r == 0) | (u8::from(overflow) << 1) | (u8::from(r < 0) << 2);
        (r as u32 & mask, flags)
    }

    /// One scan of every engine on `o`; everything must agree.
    fn check(e: &mut Engines, o: Operands) {
        for vm in &mut e.vms {
            common::set(vm, "MW0", o.w[0] as u16 as u32);
            common::set(vm, "MW2", o.w[1] as u16 as u32);
            common::set(vm, "MD4", o.d[0] as u32);
            common::set(vm, "MD8", o.d[1] as u32);
            common::set(vm, "MB12", o.b[0].into());
            common::set(vm, "MB13", o.b[1].into());
            common::set(vm, "MB14", o.bits[0].into());
            common::set(vm, "MB15", o.bits[1].into());
        }
        let outcomes: Vec<_> = e
            .vms
            .iter_mut()
            .map(|vm| (vm.run_scan(), vm.executed_last_scan()))
            .collect();
        for k in 1..3 {
            assert_eq!(outcomes[k], outcomes[0], "outcome of VM {k} on {o:?}");
            assert!(
                common::areas(&e.vms[k]) == common::areas(&e.vms[0]),
                "memory of VM {k} differs from the generic semantics on {o:?}"
            );
        }
        let vm = &e.vms[2];
        for (k, &(m, op, width)) in MATH.iter().enumerate() {
            let (a, b) = if width == 2 {
                (o.w[0].into(), o.w[1].into())
            } else {
                (o.d[0], o.d[1])
            };
            let (out, flags) = math_out(k);
            let (value, sm1) = expected(op, width, a, b);
            let (mem, _) = jit(e, k, width, a as u32, b as u32, 1);
            let got = (common::read(vm, &out), common::read(vm, &flags) as u8 & 7);
            assert_eq!(got, (value, sm1), "{m} {a}, {b}: VM (value, SM1.0-2)");
            let jit_got = (reference::load(&mem, 0, width), mem[8] & 7);
            assert_eq!(jit_got, (value, sm1), "{m} {a}, {b}: gutta-jit");
        }
        for (w, &(letter, width, a, b)) in COMPARES.iter().enumerate() {
            let (x, y) = (common::read(vm, a), common::read(vm, b));
            for (r, &(rel, _)) in RELS.iter().enumerate() {
                let f = MATH.len() + w * 6 + r;
                let (_, stack) = jit(e, f, width, x, y, 0);
                let got = common::read(vm, &compare_out(w, r, 0));
                assert_eq!(
                    got,
                    stack & 1,
                    "LD{letter}{rel} {x:#x}, {y:#x}: VM vs gutta-jit"
                );
                let [b0, b1] = [o.bits[0] & 1, (o.bits[0] >> 1) & 1].map(u32::from);
                assert_eq!(common::read(vm, &compare_out(w, r, 1)), b0 & got);
                assert_eq!(common::read(vm, &compare_out(w, r, 2)), b1 | got);
            }
        }
    }

    /// Every pair of edge values: INT and DINT math and compares, bytes by index.
    #[test]
    fn every_pair_of_edge_operands_agrees() {
        let mut e = engines();
        for (i, (&a16, &a32)) in EDGES_16.iter().zip(&EDGES_32).enumerate() {
            for (j, (&b16, &b32)) in EDGES_16.iter().zip(&EDGES_32).enumerate() {
                check(
                    &mut e,
                    Operands {
                        w: [a16, b16],
                        d: [a32, b32],
                        b: [EDGES_8[i % 6], EDGES_8[j % 6]],
                        bits: [(i * 37 + j) as u8, ((i * 11) ^ (j * 5)) as u8],
                    },
                );
            }
        }
    }

    fn int() -> impl Strategy<Value = i16> {
        prop_oneof![any::<i16>(), prop::sample::select(&EDGES_16[..])]
    }
    fn dint() -> impl Strategy<Value = i32> {
        prop_oneof![any::<i32>(), prop::sample::select(&EDGES_32[..])]
    }
    fn byte() -> impl Strategy<Value = u8> {
        prop_oneof![any::<u8>(), prop::sample::select(&EDGES_8[..])]
    }
    fn operands() -> impl Strategy<Value = Operands> {
        (
            [int(), int()],
            [dint(), dint()],
            [byte(), byte()],
            any::<[u8; 2]>(),
        )
            .prop_map(|(w, d, b, bits)| Operands { w, d, b, bits })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(16))]

        /// Random operands (half of them edge values), 32 scans per case.
        #[test]
        fn random_operands_agree(cases in prop::collection::vec(operands(), 32)) {
            let mut e = engines();
            for o in cases {
                check(&mut e, o);
            }
        }
    }
}
