//! Renders the stdlib PLC types as `docs/targets.md`: each type's memory map with its
//! Modbus references, limits, timers, counters, forcing, serial ports, system memory and
//! interrupt events, all from the loaded tables: no table cell is written by hand. The
//! prose here says only what the files cannot (the document's names, the reasons for
//! our decisions). Pure text, no I/O.

use std::fmt::Write;

use super::cell;
use crate::{InterruptEvent, MemoryMap, PlcType, SystemBit, Target};

mod memory_maps;

use memory_maps::{write_area_rules, write_memory_map};

/// What IN1001 calls each stdlib PLC type and the CPU its name implies: facts of the
/// document that the target files do not hold.
const DOCUMENT_NAMES: &[(&str, &str, &str)] = &[
    ("CPU-EC20", "CPU-EC20 (8051,Compile)", "8051"),
    (
        "CPU-EC20-AVR",
        "CPU-EC20 (AVR) and CPU-EC20 (AVR,Compile): same map",
        "AVR",
    ),
    (
        "CPU-EC20-M3",
        "CPU-EC20 (Cortex-M3) and (Cortex-M3,Compile): same map",
        "Cortex-M3",
    ),
    ("EC30-EK51", "EC30-EK51", "8051"),
    ("EC30-EKSTM32", "EC30-EKSTM32: adds HC", "STM32"),
    (
        "EC30-EKSTM32-XC",
        "EC30-EKSTM32-XC: adds V to EC30-EKSTM32",
        "STM32",
    ),
];

const INTRO: &str = "\
The PLC types of IN1001, as shipped in `stdlib/targets/<Name>/` (PlcType.xml and
ManagerVar.xml; all share `stdlib/ManagerFun.xml`); each file exists once. The file
schema is in [target-schema.md](target-schema.md); the memory facts come from IN1001,
the GUTTA memory manual ([sources.md](sources.md)). Every table below is generated from the files;
`catalog/tests/targets.rs` checks the files against a table transcribed by hand from
that section.
";

const SHARED_FROM_THE_DOCUMENT: &str = "\
## What every type shares

From the document:

- Offsets count in bytes, except T and C (words: `T5` is bytes 10..11) and HC (double
  words: `HC1` is bytes 4..7). T, C, J and HC have one width and take no width letter
  (`T5`, `C3`, `J2`, `HC1`); every other area needs `B`, `W`, `D` or a `.bit`.
";

const SHARED_MODBUS: &str = "\
- Modbus: I = discrete inputs from 100001, Q = coils from 000001 (one object per bit,
  `Q3.0` = 000025, `I0.4` = 100005), AI = input registers from 300001, AQ = holding
  registers from 400001, then M, (V), T, C, (HC), SM, J continue the holding registers
  in that order, each taking size/2 registers. A register is two consecutive bytes,
  the even one its low half (memory is little-endian): `MW20` = 400019, `MB31` = high
  byte of 400024 on CPU-EC20. K and L are not on Modbus. See `gutta_catalog::modbus`.

Decided by us (the documents do not say):

- Timer resolutions: the low timers count in 1 ms and 10 ms, T4 and up in 100 ms
  (AN2002 uses T4 as a 100 ms timer); each type's ranges are under its memory map.
";

const SHARED_DECISIONS_END: &str = "- The system memory layout and the interrupt events below.\n";

const SYSTEM_MEMORY: &str = "\
### System memory (SM)

The named bits and bytes at the start of SM; the bytes after them are reserved. The
runtime fault codes of `ERROR_CODE` are the VM's to define (docs of the VM). The
Micro/WIN name is STEP 7-Micro/WIN's system symbol for the same meaning, usable in a
Micro/WIN export (docs/microwin.md); S7-200 system memory without a GUTTA equivalent
has none.
";

const EVENTS: &str = "\
### Interrupt events (`ATCH`)

The S7-200 column is the S7-200 event number that means the same (`MicroWin`
attribute): `ATCH`, `DTCH` and `CEVNT` of a Micro/WIN export name events by it
(docs/microwin.md, \"Interrupt events\").
";

/// The largest event number: `ATCH`'s event operand is a byte.
const LAST_EVENT: u32 = 255;

const LIMITS: &str = "\
## Limits (PlcType.xml)

CPU-EC20's values are the document's example (UM4001) exactly. The other types' are
our decision, chosen to fit their memory:

- `ProgramBlockConstBinarySize` = the size of K (the const page fills K).
- `ProgramBlockPageArgIntSize` and `ProgramBlockPageArgSbrSize` equal the size of L:
  arguments live in L.
- `DataBlockPageSize` stays 16, the protocol's maximum (data pages 022X..024X, X one
  hex digit); items per page grow with the writable memory (M, V) to initialise.
- `SystemBlockBinarySize` grows where there are two serial ports (room for the second
  port's settings; the system block layout is the encoder's).
- Instruction bytes, interrupt routines (MAIN is INT0) and subroutines: the document's
  numbers on CPU-EC20, more on the bigger chips.
- `ExchPackSize` (64 <= n < 1024): the document's 64 on CPU-EC20, more on the bigger
  chips.
- `ExchSupport` `0000|0000` allows every function.
";

const MEMORY_MAPS: &str = "\
## Memory maps

Columns: *addresses* is the first and last address of the area at its unit; *&* may
take the address of a byte; *\\** a dword may hold a pointer; *program writes* says
whether a program may write the area; *Modbus* the first and last reference.
";

/// The whole page for `targets`, the default first.
pub fn target_reference(targets: &[Target]) -> String {
    let mut out = String::new();
    out.push_str("# The stdlib PLC types\n\n");
    out.push_str(
        "<!-- Generated from stdlib/targets/ by gutta_catalog::docs::target_reference.\n\
         Do not edit: run `UPDATE_DOCS=1 cargo test -p gutta-catalog --test targets`. -->\n\n",
    );
    out.push_str(INTRO);
    write_names(&mut out, targets);
    out.push('\n');
    out.push_str(SHARED_FROM_THE_DOCUMENT);
    write_area_rules(&mut out, targets);
    out.push_str(SHARED_MODBUS);
    write_serial_ports(&mut out, targets);
    out.push_str(SHARED_DECISIONS_END);
    out.push('\n');
    out.push_str(SYSTEM_MEMORY);
    for (names, memory) in groups(targets, |m| &m.system_bits) {
        write_group_heading(&mut out, &names, targets.len());
        write_system_bits(&mut out, &memory.system_bits);
    }
    out.push('\n');
    out.push_str(EVENTS);
    for (names, memory) in groups(targets, |m| &m.events) {
        write_group_heading(&mut out, &names, targets.len());
        write_events(&mut out, &memory.events);
    }
    out.push('\n');
    out.push_str(LIMITS);
    write_limits(&mut out, targets);
    out.push('\n');
    out.push_str(MEMORY_MAPS);
    for target in targets {
        write_memory_map(&mut out, target);
    }
    out
}

fn write_names(out: &mut String, targets: &[Target]) {
    out.push_str(
        "\n| Name (PlcType.xml `Name`, GET_PLC_NAME) | document's name | CPU (from the name) |\n\
         | --- | --- | --- |\n",
    );
    for (i, target) in targets.iter().enumerate() {
        let (document, cpu) = DOCUMENT_NAMES
            .iter()
            .find(|(name, _, _)| *name == target.name())
            .map_or((target.plc.information.as_str(), "-"), |(_, d, c)| (*d, *c));
        let default = if i == 0 { " (default)" } else { "" };
        let _ = writeln!(
            out,
            "| `{}`{default} | {} | {} |",
            target.name(),
            cell(document),
            cell(cpu)
        );
    }
}

fn write_serial_ports(out: &mut String, targets: &[Target]) {
    let counts: Vec<String> = groups(targets, |m| &m.serial_ports)
        .into_iter()
        .map(|(names, memory)| format!("{} on {}", memory.serial_ports, names.join(", ")))
        .collect();
    bullet(out, &format!("Serial ports: {}.", counts.join("; ")));
}

/// A list item wrapped at [`LINE`] columns, continuation lines indented.
fn bullet(out: &mut String, text: &str) {
    let mut line = String::from("-");
    for word in text.split(' ') {
        if line.len() + 1 + word.len() > LINE && line.len() > 2 {
            out.push_str(&line);
            out.push('\n');
            line = String::from(" ");
        }
        line.push(' ');
        line.push_str(word);
    }
    out.push_str(&line);
    out.push('\n');
}

/// The width the prose of the page is wrapped at.
const LINE: usize = 88;

/// Targets grouped by equal `part` of their memory map, in order of first appearance:
/// the names of each group and the first member's map.
fn groups<T: PartialEq>(
    targets: &[Target],
    part: impl Fn(&MemoryMap) -> &T,
) -> Vec<(Vec<&str>, &MemoryMap)> {
    let mut groups: Vec<(Vec<&str>, &MemoryMap)> = Vec::new();
    for target in targets {
        match groups
            .iter_mut()
            .find(|(_, memory)| part(memory) == part(&target.memory))
        {
            Some((names, _)) => names.push(target.name()),
            None => groups.push((vec![target.name()], &target.memory)),
        }
    }
    groups
}

fn write_group_heading(out: &mut String, names: &[&str], all: usize) {
    if names.len() == all {
        out.push_str("\nThe same on every type.\n");
    } else {
        let _ = writeln!(out, "\nOn {}:", names.join(", "));
    }
}

fn write_system_bits(out: &mut String, bits: &[SystemBit]) {
    out.push_str("\n| address | name | Micro/WIN name | meaning |\n| --- | --- | --- | --- |\n");
    for bit in bits {
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} |",
            bit.address,
            bit.name,
            bit.microwin.as_deref().unwrap_or(""),
            cell(&bit.description)
        );
    }
}

fn write_events(out: &mut String, events: &[InterruptEvent]) {
    out.push_str(
        "\n| event | name | kind | input or period | meaning | S7-200 |\n| ---: | --- | --- | --- | --- | --- |\n",
    );
    for event in events {
        let source = event
            .input
            .as_deref()
            .or(event.period.as_deref())
            .unwrap_or("");
        let s7200 = event
            .microwin
            .and_then(|n| crate::s7200::s7200_event(i64::from(n)))
            .map(|e| format!("{} ({})", e.number, e.meaning))
            .unwrap_or_default();
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} |",
            event.number,
            event.name,
            event.kind,
            source,
            cell(&event.description),
            cell(&s7200)
        );
    }
    let unassigned = unassigned_events(events);
    if !unassigned.is_empty() {
        let _ = writeln!(out, "\nEvents {unassigned} are unassigned.");
    }
}

/// The event numbers up to [`LAST_EVENT`] no event has: `8, 9 and 12..255`.
fn unassigned_events(events: &[InterruptEvent]) -> String {
    let mut runs: Vec<(u32, u32)> = Vec::new();
    for n in (0..=LAST_EVENT).filter(|n| !events.iter().any(|e| e.number == *n)) {
        match runs.last_mut() {
            Some((_, last)) if *last + 1 == n => *last = n,
            _ => runs.push((n, n)),
        }
    }
    let mut parts: Vec<String> = Vec::new();
    for (first, last) in runs {
        match last - first {
            0 => parts.push(first.to_string()),
            1 => parts.extend([first.to_string(), last.to_string()]),
            _ => parts.push(format!("{first}..{last}")),
        }
    }
    match parts.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        Some((last, _)) => last.clone(),
        None => String::new(),
    }
}

/// One row per PlcType.xml limit, one column per target.
fn write_limits(out: &mut String, targets: &[Target]) {
    type Limit = (&'static str, fn(&PlcType) -> String);
    const ROWS: &[Limit] = &[
        ("SystemBlockBinarySize", |p| {
            p.system_block_binary_size.to_string()
        }),
        ("DataBlockPageSize", |p| p.data_block_page_size.to_string()),
        ("DataBlockPageItemSize", |p| {
            p.data_block_page_item_size.to_string()
        }),
        ("ProgramBlockPageIntSize", |p| {
            p.program_block_page_int_size.to_string()
        }),
        ("ProgramBlockPageSbrSize", |p| {
            p.program_block_page_sbr_size.to_string()
        }),
        ("ProgramBlockPageArgIntSize", |p| {
            p.program_block_page_arg_int_size.to_string()
        }),
        ("ProgramBlockPageArgSbrSize", |p| {
            p.program_block_page_arg_sbr_size.to_string()
        }),
        ("ProgramBlockConstBinarySize", |p| {
            p.program_block_const_binary_size.to_string()
        }),
        ("ProgramBlockInstructionBinarySize", |p| {
            p.program_block_instruction_binary_size.to_string()
        }),
        ("ExchPackSize", |p| p.exch_pack_size.to_string()),
        ("ExchSupport", |p| {
            let rules: Vec<String> = p
                .exch_support
                .rules
                .iter()
                .map(|(mask, value)| format!("{mask:04X}|{value:04X}"))
                .collect();
            format!("`{}`", cell(&rules.join("|")))
        }),
        ("data block bytes (pages x items x 8)", |p| {
            p.data_block_bytes().to_string()
        }),
    ];
    let names: Vec<&str> = targets.iter().map(Target::name).collect();
    let _ = writeln!(out, "\n| limit | {} |", names.join(" | "));
    let _ = writeln!(out, "| --- |{}", " ---: |".repeat(targets.len()));
    for (limit, value) in ROWS {
        let values: Vec<String> = targets.iter().map(|t| value(&t.plc)).collect();
        let _ = writeln!(out, "| {limit} | {} |", values.join(" | "));
    }
}
