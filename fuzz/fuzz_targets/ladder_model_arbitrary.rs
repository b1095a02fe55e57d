//! Fuzz target of the checks on the ladder model (docs/ladder.md, "Checks on the
//! model"): models built from the fuzzer's bytes with `arbitrary::Unstructured` (the
//! default target's contacts, coils and boxes with mostly the right operand and input
//! counts, operands mostly of the kind, area and width the catalog's operand spec
//! takes, else from a pool of good and bad texts and symbols, rungs mostly in the
//! shapes ladder has and sometimes any shape, symbols, blocks of the three kinds with
//! variables, networks given as `stl` lines) through `gutta_ladder::json::check`
//! (validate -> written program -> compile). It must never panic; every diagnostic and
//! note names a part of the model; a structural fault is one L code; and a model that
//! validates (no error) has a program that compiles on its own, as `gutta-cc -o` does
//! it, to an image that verifies, and JSON that reads back to the same model.
#![no_main]

use std::sync::{Arc, OnceLock};

use gutta_catalog::{stdlib, Join, LadderClass, OperandKind, OperandSpec, Target};
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};
use gutta_ladder::json::{
    check, names_a_part, program_of, read_model, BlockJson, Element, Model, NetworkBody,
    NetworkJson, SymbolJson, VarJson,
};
use libfuzzer_sys::arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;

/// Operand texts: good ones of every area and width, constants, locals, pointers,
/// symbols the pool of symbol names defines, block names, and bad ones.
#[rustfmt::skip]
const OPERANDS: &[&str] = &[
    "I0.0", "I0.1", "I1.7", "Q0.0", "Q0.1", "Q1.0", "M0.0", "M1.7", "SM0.0", "SM0.1",
    "V0.0", "MB0", "MB1", "MW0", "MW2", "MD4", "VB10", "VW100", "VD200", "IB0", "IW0",
    "QB0", "QW0", "AIW0", "AQW0", "T37", "T5", "T0", "C0", "C5", "0", "1", "3", "10", "100",
    "-5", "32767", "70000", "3.5", "16#FF", "#a", "#b", "#level", "&VB0", "*VD0", "Start",
    "Stop", "Motor", "Level", "FILL", "ADD3", "INT_A", "SBR0", "Q99.9", "MW99999", "I0.8",
    "bad operand", "", "Undefined",
];

/// Symbol names (good, clashing with keywords, malformed).
const SYMBOL_NAMES: &[&str] = &[
    "Start", "Stop", "Motor", "Level", "Start", "LD", "1abc", "bad name", "a", "X_1",
];

/// Symbol addresses.
#[rustfmt::skip]
const ADDRESSES: &[&str] = &[
    "I0.0", "I0.1", "Q0.0", "M0.0", "MW10", "VD100", "T37", "C5", "Q99.9", "AIW0", "SM0.0",
    "IB0", "X1", "",
];

/// Data types for symbols and variables (and a bad one).
#[rustfmt::skip]
const TYPES: &[&str] = &[
    "BOOL", "BYTE", "WORD", "INT", "DWORD", "DINT", "REAL", "WORDY",
];

/// Free text: titles and comments, some with what a line cannot hold.
#[rustfmt::skip]
const TEXTS: &[&str] = &[
    "", "motor", "start/stop latch", "a // b", "two\nlines", "x\ry",
    "END_ORGANIZATION_BLOCK",
];

/// STL lines of networks shown as STL.
const STL: &[&str] = &[
    "LD     SM0.0",
    "LD     I0.0",
    "A      I0.1",
    "=      Q0.0",
    "MOVW   1, MW0",
    "TON    T37, 10",
    "ALD",
    "OLD",
    "LPS",
    "LPP",
    "NOT",
    "RET",
    "CALL   FILL",
    "xyz",
    "// a comment",
    "",
    "NETWORK 9",
    "END_ORGANIZATION_BLOCK",
];

/// Block names and ids.
const BLOCK_NAMES: &[&str] = &["MAIN", "FILL", "ADD3", "INT_A", "SBR_0"];
const BLOCK_IDS: &[&str] = &["OB1", "SBR0", "SBR1", "INT0", "INT1", "SBR99", "X"];
const KINDS: &[&str] = &[
    "ORGANIZATION_BLOCK",
    "SUBROUTINE_BLOCK",
    "INTERRUPT_BLOCK",
    "DATA_BLOCK",
];

/// Local variable names.
const VAR_NAMES: &[&str] = &["a", "b", "level", "tmp", "a"];

/// Mnemonics no target has, or of the wrong form.
const BAD_MNEMONICS: &[&str] = &["XYZ", "", "ld"];

/// The default target's mnemonics by the element they make.
struct Pools {
    target: Arc<Target>,
    explicit: ExplicitTarget,
    contacts: Vec<String>,
    coils: Vec<String>,
    boxes: Vec<String>,
    /// Boxes with a power output: they can stand in a power path.
    passing: Vec<String>,
    /// Every mnemonic, for a wrong element.
    all: Vec<String>,
}

fn pools() -> &'static Pools {
    static POOLS: OnceLock<Pools> = OnceLock::new();
    POOLS.get_or_init(|| {
        let target = stdlib::shared(stdlib::DEFAULT).expect("the embedded default target loads");
        let set = &target.instructions;
        let of = |keep: &dyn Fn(&gutta_catalog::Instruction) -> bool| -> Vec<String> {
            set.instructions
                .iter()
                .filter(|i| keep(i))
                .map(|i| i.mnemonic.clone())
                .collect()
        };
        Pools {
            contacts: of(&|i| {
                (i.ladder.is_contact() && i.join() == Some(Join::Load))
                    || matches!(
                        i.ladder,
                        LadderClass::Not | LadderClass::RisingEdge | LadderClass::FallingEdge
                    )
            }),
            coils: of(&|i| i.ladder.is_coil()),
            boxes: of(&|i| i.ladder == LadderClass::Box),
            passing: of(&|i| i.ladder == LadderClass::Box && i.power_output.is_some()),
            all: of(&|_| true),
            explicit: ExplicitTarget {
                target: target.clone(),
                origin: "the fuzzer's target".to_string(),
            },
            target,
        }
    })
}

fn text(u: &mut Unstructured, pool: &[&str]) -> Result<String> {
    Ok(u.choose(pool)?.to_string())
}

/// Up to `max` items of `make`.
fn list<T>(
    u: &mut Unstructured,
    max: u32,
    mut make: impl FnMut(&mut Unstructured) -> Result<T>,
) -> Result<Vec<T>> {
    let n = u.int_in_range(0..=max)?;
    (0..n).map(|_| make(u)).collect()
}

/// A mnemonic of `pool`, now and then one of another kind or none at all.
fn mnemonic(u: &mut Unstructured, pool: &[String]) -> Result<String> {
    if u.ratio(1, 32)? {
        return Ok(u.choose(&pools().all)?.clone());
    }
    if u.ratio(1, 64)? {
        return text(u, BAD_MNEMONICS);
    }
    Ok(u.choose(pool)?.clone())
}

/// As many operands as the instruction takes (CALL: and some arguments), now and then
/// one more or one fewer; each mostly of the kind its operand takes.
fn operands(u: &mut Unstructured, mnemonic: &str) -> Result<Vec<String>> {
    let set = &pools().target.instructions;
    let spec = set.lookup(mnemonic).map(|id| set.get(id));
    let mut n = spec.map_or(1, |i| {
        i.operands.len() + if i.call_arguments { 2 } else { 0 }
    });
    if u.ratio(1, 32)? {
        n = n.saturating_sub(1);
    } else if u.ratio(1, 32)? {
        n += 1;
    }
    (0..n)
        .map(|i| operand(u, spec.and_then(|s| s.operands.get(i))))
        .collect()
}

/// An operand: one of the kind `spec` takes (a label, a block, a literal in range, an
/// address of an allowed area and width, a constant), or (a quarter of the time, or
/// without a spec) any text of the pool.
fn operand(u: &mut Unstructured, spec: Option<&OperandSpec>) -> Result<String> {
    let typed = !u.ratio(1, 4)?;
    let Some(spec) = spec.filter(|s| typed && !s.types.is_empty()) else {
        return text(u, OPERANDS);
    };
    Ok(match spec.kind {
        OperandKind::Label => u.int_in_range(0..=3u8)?.to_string(),
        OperandKind::Block => text(u, BLOCK_NAMES)?,
        OperandKind::Literal => {
            let (min, max) = (spec.min.unwrap_or(0), spec.max.unwrap_or(0));
            u.int_in_range(min.min(max)..=max.max(min))?.to_string()
        }
        OperandKind::Data => {
            let ty = *u.choose(&spec.types)?;
            if spec.constant && u.ratio(1, 3)? {
                let (min, max) = ty.integer_range().unwrap_or((0, 1));
                return Ok(u.int_in_range(min.max(-1000)..=max.min(1000))?.to_string());
            }
            let area = match &spec.areas {
                Some(areas) => u.choose(areas)?.clone(),
                None => u.choose(&["I", "Q", "M", "V", "SM"])?.to_string(),
            };
            let byte = u.int_in_range(0..=7u8)?;
            match ty.width().letter() {
                _ if area == "T" || area == "C" => format!("{area}{}", u.choose(&[0, 5, 37, 64])?),
                None => format!("{area}{byte}.{}", u.int_in_range(0..=7u8)?),
                Some(letter) => format!("{area}{letter}{}", byte * 4),
            }
        }
    })
}

fn contact(u: &mut Unstructured) -> Result<Element> {
    let contact = mnemonic(u, &pools().contacts)?;
    let operands = operands(u, &contact)?;
    Ok(Element::Contact { contact, operands })
}

fn coil(u: &mut Unstructured) -> Result<Element> {
    let coil = mnemonic(u, &pools().coils)?;
    let operands = operands(u, &coil)?;
    Ok(Element::Coil { coil, operands })
}

/// A box of `pool`, with its power inputs after the first as paths.
fn boxed(u: &mut Unstructured, pool: &[String], depth: u32) -> Result<Element> {
    let mnemonic = self::mnemonic(u, pool)?;
    let operands = operands(u, &mnemonic)?;
    let set = &pools().target.instructions;
    let mut n = set
        .lookup(&mnemonic)
        .map_or(0, |id| set.get(id).power_inputs.len().saturating_sub(1));
    if u.ratio(1, 32)? {
        n += 1;
    }
    let inputs = (0..n)
        .map(|_| path(u, depth.saturating_sub(1)))
        .collect::<Result<_>>()?;
    Ok(Element::Box {
        mnemonic,
        operands,
        inputs,
    })
}

/// A power path: contacts, paths in series or in parallel, a box passing power on.
fn path(u: &mut Unstructured, depth: u32) -> Result<Element> {
    let choice = if depth == 0 {
        0
    } else {
        u.int_in_range(0..=9)?
    };
    match choice {
        0..=4 => contact(u),
        5 | 6 => Ok(Element::Parallel {
            parallel: (0..u.int_in_range(1..=3u32)?)
                .map(|_| path(u, depth - 1))
                .collect::<Result<_>>()?,
        }),
        7 | 8 => Ok(Element::Series {
            series: (0..u.int_in_range(1..=3u32)?)
                .map(|_| path(u, depth - 1))
                .collect::<Result<_>>()?,
        }),
        _ => boxed(u, &pools().passing, depth),
    }
}

/// Outputs: a coil, a box, or branches in parallel (each its contacts, then outputs).
fn outputs(u: &mut Unstructured, depth: u32) -> Result<Element> {
    let choice = if depth == 0 {
        0
    } else {
        u.int_in_range(0..=5)?
    };
    match choice {
        0..=2 => coil(u),
        3 => boxed(u, &pools().boxes, depth),
        _ => Ok(Element::Parallel {
            parallel: (0..u.int_in_range(1..=3u32)?)
                .map(|_| {
                    let mut series = list(u, 2, |u| path(u, depth - 1))?;
                    series.push(outputs(u, depth - 1)?);
                    Ok(if series.len() == 1 {
                        series.remove(0)
                    } else {
                        Element::Series { series }
                    })
                })
                .collect::<Result<_>>()?,
        }),
    }
}

/// Any element in any place: what ladder cannot draw too.
fn any(u: &mut Unstructured, depth: u32) -> Result<Element> {
    let choice = if depth == 0 {
        0
    } else {
        u.int_in_range(0..=4)?
    };
    match choice {
        0 => contact(u),
        1 => coil(u),
        2 => boxed(u, &pools().boxes, depth),
        3 => Ok(Element::Series {
            series: list(u, 3, |u| any(u, depth - 1))?,
        }),
        _ => Ok(Element::Parallel {
            parallel: list(u, 3, |u| any(u, depth - 1))?,
        }),
    }
}

/// A rung: mostly a path from the rail then outputs, sometimes any shape.
fn rung(u: &mut Unstructured) -> Result<Element> {
    if u.ratio(1, 8)? {
        return any(u, 4);
    }
    let mut series = list(u, 3, |u| path(u, 3))?;
    series.push(outputs(u, 3)?);
    Ok(Element::Series { series })
}

fn network(u: &mut Unstructured) -> Result<NetworkJson> {
    let body = if u.ratio(1, 6)? {
        NetworkBody::Stl {
            stl: list(u, 5, |u| text(u, STL))?,
            reason: text(u, TEXTS)?,
        }
    } else {
        NetworkBody::Rung { rung: rung(u)? }
    };
    Ok(NetworkJson {
        number: if u.ratio(1, 16)? {
            Some(u.int_in_range(0..=9)?)
        } else {
            None
        },
        title: if u.ratio(1, 4)? {
            text(u, TEXTS)?
        } else {
            String::new()
        },
        comment: if u.ratio(1, 4)? {
            text(u, TEXTS)?
        } else {
            String::new()
        },
        body,
    })
}

fn var(u: &mut Unstructured) -> Result<VarJson> {
    Ok(VarJson {
        name: text(u, VAR_NAMES)?,
        data_type: text(u, TYPES)?,
        comment: if u.ratio(1, 4)? {
            Some(text(u, TEXTS)?)
        } else {
            None
        },
    })
}

/// A block: the first mostly MAIN, the others of any kind; variables mostly in
/// subroutines.
fn block(u: &mut Unstructured, first: bool) -> Result<BlockJson> {
    let main = first && !u.ratio(1, 8)?;
    let (kind, name, id) = if main {
        (
            "ORGANIZATION_BLOCK".to_string(),
            "MAIN".to_string(),
            "OB1".to_string(),
        )
    } else {
        let kind = if u.ratio(1, 32)? {
            KINDS[3]
        } else {
            u.choose(&KINDS[..3])?
        };
        (kind.to_string(), text(u, BLOCK_NAMES)?, text(u, BLOCK_IDS)?)
    };
    let vars = !main || u.ratio(1, 8)?;
    let section = |u: &mut Unstructured| -> Result<Vec<VarJson>> {
        if vars {
            list(u, 2, var)
        } else {
            Ok(Vec::new())
        }
    };
    Ok(BlockJson {
        kind,
        name,
        id,
        title: if u.ratio(1, 4)? {
            Some(text(u, TEXTS)?)
        } else {
            None
        },
        var_input: section(u)?,
        var_in_out: section(u)?,
        var_output: section(u)?,
        var: section(u)?,
        networks: list(u, 4, network)?,
    })
}

fn symbol(u: &mut Unstructured) -> Result<SymbolJson> {
    Ok(SymbolJson {
        name: text(u, SYMBOL_NAMES)?,
        address: text(u, ADDRESSES)?,
        data_type: if u.ratio(1, 3)? {
            Some(text(u, TYPES)?)
        } else {
            None
        },
        comment: if u.ratio(1, 4)? {
            Some(text(u, TEXTS)?)
        } else {
            None
        },
    })
}

fn model(u: &mut Unstructured) -> Result<Model> {
    let plc = if u.ratio(1, 16)? {
        u.choose(&["CPU-EC20", "cpu-ec20", "CPU-EC30", "NONE"])?
            .to_string()
    } else {
        stdlib::DEFAULT.to_string()
    };
    let symbols = list(u, 4, symbol)?;
    let blocks = (0..u.int_in_range(1..=3u32)?)
        .map(|b| block(u, b == 0))
        .collect::<Result<_>>()?;
    Ok(Model {
        format: "gutta-ladder".to_string(),
        version: 1,
        plc,
        symbols,
        blocks,
    })
}

fuzz_target!(|data: &[u8]| {
    let mut u = Unstructured::new(data);
    let Ok(model) = model(&mut u) else {
        return;
    };
    let pools = pools();
    let checked = check(&model, &pools.explicit);
    let json = || model.to_json();
    for d in &checked.diagnostics {
        for path in std::iter::once(&d.path).chain(d.notes.iter().map(|n| &n.path)) {
            assert!(
                names_a_part(&model, path),
                "{d}: `{path}` names no part of\n{}",
                json()
            );
        }
    }
    let Some(program) = &checked.program else {
        // A structural fault: one L code, nothing written.
        assert_eq!(checked.diagnostics.len(), 1, "{:?}", checked.diagnostics);
        assert!(checked.diagnostics[0].code.starts_with('L'));
        return;
    };
    assert_eq!(program.text.lines().count(), program.paths.len());
    assert_eq!(
        program_of(&model, &pools.target.instructions).as_deref(),
        Ok(program.text.as_str())
    );
    if checked.has_errors() {
        return;
    }
    // The model validates: its program compiles on its own to an image that verifies.
    let compiled = compile(
        SourceFile::new("model.lad", program.text.clone()),
        Some(&pools.explicit),
    );
    assert!(
        !compiled.checked.has_errors(),
        "{:?}\n{}\n{}",
        compiled.checked.diagnostics(),
        program.text,
        json()
    );
    let image = compiled
        .image
        .unwrap_or_else(|| panic!("no image\n{}\n{}", program.text, json()));
    if let Err(e) = gutta_format::verify(&image, &pools.target) {
        panic!(
            "the image does not verify: {e}\n{}\n{}",
            program.text,
            json()
        );
    }
    let again = read_model(json().as_bytes())
        .unwrap_or_else(|e| panic!("its own JSON does not read: {e}\n{}", json()));
    assert_eq!(again, model, "{}", json());
});
