//! The memory-map parts of `docs/targets.md`: one table per PLC type (slots, sizes,
//! addresses, widths, `&`, `*`, writes, Modbus references) with its timers, counters,
//! forcing and serial ports, and the area rules every type shares. Pure text, no I/O.

use std::fmt::Write;

use super::super::yes_no;
use super::bullet;
use crate::modbus::format_reference;
use crate::{Address, Area, MemoryMap, ModbusTable, Target, Width};

/// Widths, `&`, `*` and writes by area name, when every name means the same on every
/// type; otherwise a pointer to the memory maps.
pub(super) fn write_area_rules(out: &mut String, targets: &[Target]) {
    let Some(areas) = areas_by_name(targets) else {
        out.push_str(
            "- Widths, `&`, `*` and program writes differ between types: see the memory maps.\n",
        );
        return;
    };
    let mut by_widths: Vec<(String, Vec<&str>)> = Vec::new();
    for area in &areas {
        let widths: Vec<String> = area
            .widths
            .iter()
            .map(|w| w.keyword().to_ascii_lowercase())
            .collect();
        let widths = widths.join(", ");
        match by_widths.iter_mut().find(|(w, _)| *w == widths) {
            Some((_, names)) => names.push(&area.name),
            None => by_widths.push((widths, vec![&area.name])),
        }
    }
    let widths: Vec<String> = by_widths
        .iter()
        .map(|(widths, names)| format!("{}: {widths}.", names.join(", ")))
        .collect();
    bullet(out, &format!("Widths: {}", widths.join(" ")));
    let names = |keep: fn(&Area) -> bool| -> String {
        let names: Vec<&str> = areas
            .iter()
            .filter(|a| keep(a))
            .map(|a| a.name.as_str())
            .collect();
        names.join(", ")
    };
    bullet(
        out,
        &format!(
            "`&` (address-of a byte): {}. `*` (a dword holding a pointer): {}.",
            names(|a| a.address_of),
            names(|a| a.holds_pointer)
        ),
    );
    bullet(
        out,
        &format!(
            "Programs cannot write {}; all other areas are writable.",
            names(|a| !a.writable)
        ),
    );
}

/// Every area name of the types once, each after the area its first type has before it
/// (`V` after `M`); None when a name has other widths or permissions on another type.
fn areas_by_name(targets: &[Target]) -> Option<Vec<&Area>> {
    let mut areas: Vec<&Area> = Vec::new();
    for target in targets {
        for (i, area) in target.memory.areas.iter().enumerate() {
            match areas.iter().find(|a| a.name == area.name) {
                Some(known) if same_rules(known, area) => {}
                Some(_) => return None,
                None => {
                    let at = i
                        .checked_sub(1)
                        .and_then(|before| {
                            let name = &target.memory.areas[before].name;
                            areas.iter().position(|a| a.name == *name)
                        })
                        .map_or(areas.len(), |p| p + 1);
                    areas.insert(at, area);
                }
            }
        }
    }
    Some(areas)
}

fn same_rules(a: &Area, b: &Area) -> bool {
    a.widths == b.widths
        && a.address_of == b.address_of
        && a.holds_pointer == b.holds_pointer
        && a.writable == b.writable
}

pub(super) fn write_memory_map(out: &mut String, target: &Target) {
    let memory = &target.memory;
    let _ = write!(
        out,
        "\n### {}\n\n`Information`: \"{}\".\n\n",
        target.name(),
        target.plc.information
    );
    out.push_str(
        "| slot | area | size (bytes) | unit | addresses | widths | & | * | program writes | Modbus |\n\
         | ---: | --- | ---: | --- | --- | --- | :-: | :-: | :-: | --- |\n",
    );
    for area in &memory.areas {
        let widths: Vec<String> = area
            .widths
            .iter()
            .map(|w| w.keyword().to_ascii_lowercase())
            .collect();
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            area.slot,
            area.name,
            area.size,
            area.unit.keyword(),
            address_range(memory, area),
            widths.join(" "),
            if area.address_of { "yes" } else { "" },
            if area.holds_pointer { "yes" } else { "" },
            yes_no(area.writable),
            modbus_range(memory, area)
        );
    }
    let _ = writeln!(
        out,
        "\nTimers: {}. Counters count to {}. Forcing: {}. Serial ports: {}.",
        timers(memory),
        memory.counter_max,
        forcing(memory),
        memory.serial_ports
    );
}

/// `` `IB0`..`IB7` ``, `` `T0`..`T15` ``: the first and last address at the area's unit
/// (bytes for areas with several widths).
fn address_range(memory: &MemoryMap, area: &Area) -> String {
    let width = area.fixed_width().unwrap_or(Width::Byte);
    let at = |offset: u32| Address {
        slot: area.slot,
        width,
        offset,
        bit: 0,
    };
    let last = area.size.saturating_sub(width.bytes());
    format!(
        "`{}`..`{}`",
        memory.format_address(&at(0)),
        memory.format_address(&at(last))
    )
}

/// `holding registers 400009-400072`, or `none` off Modbus.
fn modbus_range(memory: &MemoryMap, area: &Area) -> String {
    let Some(span) = memory
        .modbus_spans()
        .into_iter()
        .find(|s| s.slot == area.slot)
    else {
        return "none".to_string();
    };
    let table = match span.table {
        ModbusTable::Coil => "coils",
        ModbusTable::DiscreteInput => "discrete inputs",
        ModbusTable::InputRegister => "input registers",
        ModbusTable::HoldingRegister => "holding registers",
    };
    format!(
        "{table} {}-{}",
        format_reference(span.first_reference()),
        format_reference(span.last_reference())
    )
}

/// `T0-T1 1 ms, T2-T3 10 ms, T4-T15 100 ms`.
fn timers(memory: &MemoryMap) -> String {
    let ranges: Vec<String> = memory
        .timers
        .iter()
        .map(|r| format!("T{}-T{} {} ms", r.first, r.last, r.milliseconds))
        .collect();
    ranges.join(", ")
}

/// `I and Q`: the areas whose bits can be forced.
fn forcing(memory: &MemoryMap) -> String {
    let names: Vec<&str> = memory
        .forcing
        .iter()
        .filter_map(|slot| memory.area_by_slot(*slot))
        .map(|area| area.name.as_str())
        .collect();
    match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        Some((last, _)) => last.to_string(),
        None => "none".to_string(),
    }
}
