//! `ManagerVar.xml`: the memory areas (slots) of a PLC type, with widths, offset
//! units, permissions, Modbus mapping, timer resolutions, forcing, serial ports,
//! system bits and interrupt events. Schema: docs/target-schema.md.

use std::collections::BTreeSet;
use std::str::FromStr;

use serde::Deserialize;

use crate::text::decode_xml_text;
use crate::xml_util::{attr_bool, attr_int, from_xml};
use crate::{CatalogError, CatalogErrorCode, Width};

const FILE: &str = "ManagerVar.xml";

/// What an area is for; the compiler and the VM find K, L, I, Q, T, C ... by kind,
/// never by name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum AreaKind {
    DigitalInput,
    DigitalOutput,
    AnalogInput,
    AnalogOutput,
    Memory,
    Timer,
    Counter,
    HighSpeedCounter,
    System,
    Flow,
    Constant,
    Local,
}

impl AreaKind {
    const NAMES: [(&'static str, AreaKind); 12] = [
        ("DigitalInput", AreaKind::DigitalInput),
        ("DigitalOutput", AreaKind::DigitalOutput),
        ("AnalogInput", AreaKind::AnalogInput),
        ("AnalogOutput", AreaKind::AnalogOutput),
        ("Memory", AreaKind::Memory),
        ("Timer", AreaKind::Timer),
        ("Counter", AreaKind::Counter),
        ("HighSpeedCounter", AreaKind::HighSpeedCounter),
        ("System", AreaKind::System),
        ("Flow", AreaKind::Flow),
        ("Constant", AreaKind::Constant),
        ("Local", AreaKind::Local),
    ];

    pub fn keyword(self) -> &'static str {
        Self::NAMES
            .iter()
            .find(|(_, k)| *k == self)
            .map(|(n, _)| *n)
            .unwrap_or("?")
    }
}

impl FromStr for AreaKind {
    type Err = ();
    fn from_str(s: &str) -> Result<Self, ()> {
        Self::NAMES
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(s))
            .map(|(_, k)| *k)
            .ok_or(())
    }
}

/// The four Modbus tables.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum ModbusTable {
    /// 0x references (000001...), functions 01, 05, 15.
    Coil,
    /// 1x references (100001...), function 02.
    DiscreteInput,
    /// 3x references (300001...), function 04.
    InputRegister,
    /// 4x references (400001...), functions 03, 06, 16.
    HoldingRegister,
}

impl ModbusTable {
    /// The leading digit of the six-digit reference number.
    pub fn prefix(self) -> u32 {
        match self {
            ModbusTable::Coil => 0,
            ModbusTable::DiscreteInput => 1,
            ModbusTable::InputRegister => 3,
            ModbusTable::HoldingRegister => 4,
        }
    }

    pub fn is_bits(self) -> bool {
        matches!(self, ModbusTable::Coil | ModbusTable::DiscreteInput)
    }

    pub fn keyword(self) -> &'static str {
        match self {
            ModbusTable::Coil => "Coil",
            ModbusTable::DiscreteInput => "DiscreteInput",
            ModbusTable::InputRegister => "InputRegister",
            ModbusTable::HoldingRegister => "HoldingRegister",
        }
    }
}

impl FromStr for ModbusTable {
    type Err = ();
    fn from_str(s: &str) -> Result<Self, ()> {
        [
            ModbusTable::Coil,
            ModbusTable::DiscreteInput,
            ModbusTable::InputRegister,
            ModbusTable::HoldingRegister,
        ]
        .into_iter()
        .find(|t| t.keyword().eq_ignore_ascii_case(s))
        .ok_or(())
    }
}

/// Where an area appears in Modbus: its table and the six-digit reference number of
/// its first bit (bit tables) or first register (register tables).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ModbusMapping {
    pub table: ModbusTable,
    /// e.g. 400009 for M on CPU-EC20.
    pub start: u32,
}

impl ModbusMapping {
    /// The 0-based address on the wire of the area's first bit or register.
    pub fn wire_start(&self) -> u32 {
        self.start - self.table.prefix() * 100_000 - 1
    }
}

/// One memory area (slot).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Area {
    /// Area prefix in addresses: `I`, `AI`, `SM`, ...
    pub name: String,
    /// SLOT field of the packed operand, 0..15.
    pub slot: u8,
    pub kind: AreaKind,
    /// Size in bytes.
    pub size: u32,
    /// Unit the offset in an address counts in (`T5` is word 5 = byte 10).
    pub unit: Width,
    /// Widths a program may access the area with.
    pub widths: BTreeSet<Width>,
    /// Whether `&` may take the address of a byte in this area.
    pub address_of: bool,
    /// Whether a DWORD of this area may hold a pointer used with `*`.
    pub holds_pointer: bool,
    /// Whether a program may write it (K and input areas may not).
    pub writable: bool,
    pub modbus: Option<ModbusMapping>,
    pub description: String,
}

impl Area {
    /// Whether the width letter is left out of addresses: areas with one width only
    /// (`T5`, `C3`, `J2`, `HC1`); their offset counts in `unit`.
    pub fn fixed_width(&self) -> Option<Width> {
        if self.widths.len() == 1 {
            self.widths.iter().next().copied()
        } else {
            None
        }
    }

    pub fn allows(&self, width: Width) -> bool {
        self.widths.contains(&width)
    }

    /// Number of addressable units (`T0..T15` on CPU-EC20 gives 16).
    pub fn unit_count(&self) -> u32 {
        self.size / self.unit.bytes()
    }
}

/// Timers `first..=last` count in steps of `milliseconds`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TimerResolution {
    pub first: u32,
    pub last: u32,
    pub milliseconds: u32,
}

/// A documented system-memory bit or byte (`SM0.0` always on, ...), for hover and docs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SystemBit {
    pub address: String,
    pub name: String,
    pub description: String,
    /// STEP 7-Micro/WIN's system symbol for the same bit or byte (`Always_On`), where
    /// the GUTTA one means the same (attribute `MicroWin`; docs/microwin.md).
    pub microwin: Option<String>,
}

/// An interrupt event number usable with `ATCH`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InterruptEvent {
    pub number: u32,
    pub name: String,
    /// `Timed`, `RisingEdge`, `FallingEdge`, `Communication`, ...
    pub kind: String,
    /// For timed events: the SM byte holding the period in milliseconds.
    pub period: Option<String>,
    /// For edge events: the input bit whose rising or falling edge raises the event.
    pub input: Option<String>,
    pub description: String,
    /// The S7-200 event number that means the same (attribute `MicroWin`; one of
    /// `s7200::S7200_EVENTS`): what `ATCH` of a Micro/WIN export names this event by.
    pub microwin: Option<u32>,
}

/// The whole memory description of a PLC type.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MemoryMap {
    /// `PlcType` attribute of the root, when present (must match PlcType.xml).
    pub plc_type: Option<String>,
    /// Areas sorted by slot.
    pub areas: Vec<Area>,
    pub timers: Vec<TimerResolution>,
    /// Largest counter value (counters stop there).
    pub counter_max: i32,
    /// Slots whose bits can be forced (I and Q).
    pub forcing: Vec<u8>,
    pub serial_ports: u8,
    pub system_bits: Vec<SystemBit>,
    pub events: Vec<InterruptEvent>,
}

#[derive(Deserialize)]
struct Raw {
    #[serde(rename = "@PlcType")]
    plc_type: Option<String>,
    #[serde(rename = "Area", default)]
    areas: Vec<RawArea>,
    #[serde(rename = "Timers")]
    timers: Option<RawTimers>,
    #[serde(rename = "Counters")]
    counters: Option<RawCounters>,
    #[serde(rename = "Forcing")]
    forcing: Option<RawForcing>,
    #[serde(rename = "SerialPorts")]
    serial_ports: Option<RawSerialPorts>,
    #[serde(rename = "SystemBit", default)]
    system_bits: Vec<RawSystemBit>,
    #[serde(rename = "Event", default)]
    events: Vec<RawEvent>,
}

#[derive(Deserialize)]
struct RawArea {
    #[serde(rename = "@Name")]
    name: String,
    #[serde(rename = "@Slot")]
    slot: String,
    #[serde(rename = "@Kind")]
    kind: String,
    #[serde(rename = "@Size")]
    size: String,
    #[serde(rename = "@Unit")]
    unit: String,
    #[serde(rename = "@Access")]
    access: String,
    #[serde(rename = "@AddressOf")]
    address_of: Option<String>,
    #[serde(rename = "@Pointer")]
    pointer: Option<String>,
    #[serde(rename = "@Writable")]
    writable: Option<String>,
    #[serde(rename = "@Modbus")]
    modbus: Option<String>,
    #[serde(rename = "@ModbusStart")]
    modbus_start: Option<String>,
    #[serde(rename = "@Description", default)]
    description: String,
}

#[derive(Deserialize)]
struct RawTimers {
    #[serde(rename = "Resolution", default)]
    resolutions: Vec<RawResolution>,
}

#[derive(Deserialize)]
struct RawResolution {
    #[serde(rename = "@First")]
    first: String,
    #[serde(rename = "@Last")]
    last: String,
    #[serde(rename = "@Milliseconds")]
    milliseconds: String,
}

#[derive(Deserialize)]
struct RawCounters {
    #[serde(rename = "@Max")]
    max: String,
}

#[derive(Deserialize)]
struct RawForcing {
    #[serde(rename = "@Areas")]
    areas: String,
}

#[derive(Deserialize)]
struct RawSerialPorts {
    #[serde(rename = "@Count")]
    count: String,
}

#[derive(Deserialize)]
struct RawSystemBit {
    #[serde(rename = "@Address")]
    address: String,
    #[serde(rename = "@Name")]
    name: String,
    #[serde(rename = "@Description", default)]
    description: String,
    #[serde(rename = "@MicroWin", default)]
    microwin: Option<String>,
}

#[derive(Deserialize)]
struct RawEvent {
    #[serde(rename = "@Number")]
    number: String,
    #[serde(rename = "@Name")]
    name: String,
    #[serde(rename = "@Kind")]
    kind: String,
    #[serde(rename = "@Period")]
    period: Option<String>,
    #[serde(rename = "@Input")]
    input: Option<String>,
    #[serde(rename = "@Description", default)]
    description: String,
    #[serde(rename = "@MicroWin")]
    microwin: Option<String>,
}

fn err(code: CatalogErrorCode, msg: String) -> CatalogError {
    CatalogError::new(code, FILE, msg)
}

fn parse_area(raw: RawArea) -> Result<Area, CatalogError> {
    let name = raw.name.trim().to_string();
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_uppercase()) {
        return Err(err(
            CatalogErrorCode::Value,
            format!("area name `{name}` must be upper-case letters"),
        ));
    }
    let ctx = |attr: &str| format!("{attr} of area {name}");
    let slot = attr_int(FILE, &ctx("Slot"), &raw.slot, 0, 15)? as u8;
    let kind = raw.kind.parse::<AreaKind>().map_err(|_| {
        err(
            CatalogErrorCode::Value,
            format!("unknown Kind `{}` of area {name}", raw.kind),
        )
    })?;
    let unit = raw
        .unit
        .parse::<Width>()
        .ok()
        .filter(|w| *w != Width::Bit)
        .ok_or_else(|| {
            err(
                CatalogErrorCode::Value,
                format!(
                    "Unit of area {name} must be BYTE, WORD or DWORD, not `{}`",
                    raw.unit
                ),
            )
        })?;
    let size = attr_int(FILE, &ctx("Size"), &raw.size, 1, 65536)? as u32;
    if !size.is_multiple_of(unit.bytes()) {
        return Err(err(
            CatalogErrorCode::Value,
            format!("Size {size} of area {name} is not a whole number of {unit}s"),
        ));
    }
    let mut widths = BTreeSet::new();
    for word in raw.access.split_whitespace() {
        let w = word.parse::<Width>().map_err(|_| {
            err(
                CatalogErrorCode::Value,
                format!("unknown width `{word}` in Access of area {name}"),
            )
        })?;
        if w != Width::Bit && w.bytes() < unit.bytes() {
            return Err(err(
                CatalogErrorCode::Value,
                format!("area {name} counts in {unit}s and cannot allow {w} access"),
            ));
        }
        widths.insert(w);
    }
    if widths.is_empty() {
        return Err(err(
            CatalogErrorCode::Value,
            format!("area {name} allows no access width"),
        ));
    }
    if widths.contains(&Width::Bit) && unit != Width::Byte {
        return Err(err(
            CatalogErrorCode::Value,
            format!("area {name} has bit access but counts in {unit}s"),
        ));
    }
    let modbus = match (raw.modbus, raw.modbus_start) {
        (None, None) => None,
        (Some(table), Some(start)) => {
            let table = table.parse::<ModbusTable>().map_err(|_| {
                err(
                    CatalogErrorCode::Value,
                    format!("unknown Modbus table `{table}` of area {name}"),
                )
            })?;
            let lo = table.prefix() * 100_000 + 1;
            let start = attr_int(
                FILE,
                &ctx("ModbusStart"),
                &start,
                lo as i64,
                (lo + 65_535) as i64,
            )? as u32;
            Some(ModbusMapping { table, start })
        }
        _ => {
            return Err(err(
                CatalogErrorCode::Syntax,
                format!("area {name} needs both Modbus and ModbusStart, or neither"),
            ))
        }
    };
    Ok(Area {
        slot,
        kind,
        size,
        unit,
        widths,
        address_of: attr_bool(FILE, &ctx("AddressOf"), raw.address_of.as_deref(), false)?,
        holds_pointer: attr_bool(FILE, &ctx("Pointer"), raw.pointer.as_deref(), false)?,
        writable: attr_bool(FILE, &ctx("Writable"), raw.writable.as_deref(), true)?,
        modbus,
        description: raw.description,
        name,
    })
}

impl MemoryMap {
    /// The system bit or byte whose Micro/WIN system symbol is `name` (case-insensitive,
    /// as symbols are).
    pub fn microwin_system_bit(&self, name: &str) -> Option<&SystemBit> {
        self.system_bits.iter().find(|b| {
            b.microwin
                .as_deref()
                .is_some_and(|m| m.eq_ignore_ascii_case(name))
        })
    }

    /// The target's event that S7-200 event `n` means (the one whose `MicroWin` is
    /// `n`), if the target has one.
    pub fn event_for_s7200(&self, n: u32) -> Option<&InterruptEvent> {
        self.events.iter().find(|e| e.microwin == Some(n))
    }

    pub fn parse(bytes: &[u8]) -> Result<MemoryMap, CatalogError> {
        let text = decode_xml_text(bytes, FILE)?;
        let raw: Raw = from_xml(&text, FILE)?;
        let mut areas = raw
            .areas
            .into_iter()
            .map(parse_area)
            .collect::<Result<Vec<_>, _>>()?;
        areas.sort_by_key(|a| a.slot);
        for pair in areas.windows(2) {
            if pair[0].slot == pair[1].slot {
                return Err(err(
                    CatalogErrorCode::Duplicate,
                    format!(
                        "areas {} and {} share slot {}",
                        pair[0].name, pair[1].name, pair[0].slot
                    ),
                ));
            }
        }
        let mut names = BTreeSet::new();
        for a in &areas {
            if !names.insert(a.name.as_str()) {
                return Err(err(
                    CatalogErrorCode::Duplicate,
                    format!("area {} is described twice", a.name),
                ));
            }
        }
        crate::modbus::check_layout(&areas, FILE)?;
        for kind in [
            AreaKind::Constant,
            AreaKind::Local,
            AreaKind::Timer,
            AreaKind::Counter,
        ] {
            let n = areas.iter().filter(|a| a.kind == kind).count();
            if n != 1 {
                return Err(err(
                    CatalogErrorCode::Value,
                    format!(
                        "exactly one area of Kind {} is required, found {n}",
                        kind.keyword()
                    ),
                ));
            }
        }
        let map_partial = MemoryMap {
            plc_type: raw.plc_type.map(|s| s.trim().to_string()),
            areas,
            timers: Vec::new(),
            counter_max: 32767,
            forcing: Vec::new(),
            serial_ports: 1,
            system_bits: Vec::new(),
            events: Vec::new(),
        };
        let mut map = map_partial;
        let timer_count = map
            .area_of_kind(AreaKind::Timer)
            .map(Area::unit_count)
            .unwrap_or(0);
        if let Some(t) = raw.timers {
            for r in t.resolutions {
                let first = attr_int(FILE, "First", &r.first, 0, timer_count as i64 - 1)? as u32;
                let last =
                    attr_int(FILE, "Last", &r.last, first as i64, timer_count as i64 - 1)? as u32;
                let ms = attr_int(FILE, "Milliseconds", &r.milliseconds, 1, 60_000)? as u32;
                map.timers.push(TimerResolution {
                    first,
                    last,
                    milliseconds: ms,
                });
            }
        }
        map.timers.sort_by_key(|t| t.first);
        for pair in map.timers.windows(2) {
            if pair[1].first <= pair[0].last {
                return Err(err(
                    CatalogErrorCode::Duplicate,
                    format!("timer resolutions overlap at T{}", pair[1].first),
                ));
            }
        }
        if let Some(uncovered) = (0..timer_count).find(|n| map.timer_resolution(*n).is_none()) {
            return Err(err(
                CatalogErrorCode::Value,
                format!("timer T{uncovered} has no <Resolution>"),
            ));
        }
        if let Some(c) = raw.counters {
            map.counter_max = attr_int(FILE, "Counters Max", &c.max, 1, i32::MAX as i64)? as i32;
        }
        if let Some(f) = raw.forcing {
            for name in f.areas.split_whitespace() {
                let area = map.area(name).ok_or_else(|| {
                    err(
                        CatalogErrorCode::Mismatch,
                        format!("<Forcing> names unknown area `{name}`"),
                    )
                })?;
                map.forcing.push(area.slot);
            }
        }
        if let Some(p) = raw.serial_ports {
            map.serial_ports = attr_int(FILE, "SerialPorts Count", &p.count, 0, 16)? as u8;
        }
        for b in raw.system_bits {
            map.system_bits.push(SystemBit {
                address: b.address.trim().to_string(),
                name: b.name,
                description: b.description,
                microwin: b
                    .microwin
                    .map(|n| n.trim().to_string())
                    .filter(|n| !n.is_empty()),
            });
        }
        for e in raw.events {
            let number = attr_int(FILE, "Event Number", &e.number, 0, 255)? as u32;
            let last_s7200 = crate::s7200::S7200_EVENTS.len() as i64 - 1;
            let microwin = match e.microwin.as_deref().map(str::trim) {
                None | Some("") => None,
                Some(n) => Some(attr_int(
                    FILE,
                    &format!("MicroWin of event {number}"),
                    n,
                    0,
                    last_s7200,
                )? as u32),
            };
            map.events.push(InterruptEvent {
                number,
                name: e.name,
                kind: e.kind,
                period: e.period,
                input: e.input,
                description: e.description,
                microwin,
            });
        }
        // Edge events name an input bit of this target; timed events a period byte.
        for e in &map.events {
            if let Some(input) = &e.input {
                let ok = map
                    .parse_address(input)
                    .ok()
                    .filter(|a| a.width == Width::Bit)
                    .and_then(|a| map.area_by_slot(a.slot))
                    .is_some_and(|a| a.kind == AreaKind::DigitalInput);
                if !ok {
                    return Err(err(
                        CatalogErrorCode::Value,
                        format!(
                            "Input `{input}` of event {} is not a bit of a digital input area",
                            e.number
                        ),
                    ));
                }
            }
            if let Some(period) = &e.period {
                if map.parse_address(period).is_err() {
                    return Err(err(
                        CatalogErrorCode::Value,
                        format!(
                            "Period `{period}` of event {} is not an address of this target",
                            e.number
                        ),
                    ));
                }
            }
        }
        map.events.sort_by_key(|e| e.number);
        for pair in map.events.windows(2) {
            if pair[0].number == pair[1].number {
                return Err(err(
                    CatalogErrorCode::Duplicate,
                    format!("interrupt event {} is described twice", pair[0].number),
                ));
            }
        }
        let mut s7200 = BTreeSet::new();
        for e in &map.events {
            if let Some(n) = e.microwin.filter(|n| !s7200.insert(*n)) {
                return Err(err(
                    CatalogErrorCode::Duplicate,
                    format!("S7-200 event {n} is the MicroWin of two events"),
                ));
            }
        }
        Ok(map)
    }

    /// Area by its name, case-insensitively.
    pub fn area(&self, name: &str) -> Option<&Area> {
        self.areas
            .iter()
            .find(|a| a.name.eq_ignore_ascii_case(name))
    }

    pub fn area_by_slot(&self, slot: u8) -> Option<&Area> {
        self.areas.iter().find(|a| a.slot == slot)
    }

    pub fn area_of_kind(&self, kind: AreaKind) -> Option<&Area> {
        self.areas.iter().find(|a| a.kind == kind)
    }

    /// The resolution of timer `Tn` in milliseconds.
    pub fn timer_resolution(&self, n: u32) -> Option<u32> {
        self.timers
            .iter()
            .find(|t| (t.first..=t.last).contains(&n))
            .map(|t| t.milliseconds)
    }

    pub fn can_force(&self, slot: u8) -> bool {
        self.forcing.contains(&slot)
    }
}

#[cfg(test)]
mod microwin_tests {
    use crate::stdlib;

    /// The S7-200 meanings (Micro/WIN's system symbol table) the stdlib targets map.
    const S7_200: [(&str, &str); 19] = [
        ("Always_On", "SM0.0"),
        ("First_Scan_On", "SM0.1"),
        ("Retentive_Lost", "SM0.2"),
        ("RUN_Power_Up", "SM0.3"),
        ("Clock_60s", "SM0.4"),
        ("Clock_1s", "SM0.5"),
        ("Clock_Scan", "SM0.6"),
        ("Result_0", "SM1.0"),
        ("Overflow_Illegal", "SM1.1"),
        ("Neg_Result", "SM1.2"),
        ("Divide_By_0", "SM1.3"),
        ("Table_Overflow", "SM1.4"),
        ("Table_Empty", "SM1.5"),
        ("Not_BCD", "SM1.6"),
        ("Last_Scan_Time", "SMW4"),
        ("Minimum_Scan_Time", "SMW6"),
        ("Maximum_Scan_Time", "SMW8"),
        ("Time_0_Intrvl", "SMB10"),
        ("Time_1_Intrvl", "SMB11"),
    ];

    #[test]
    fn every_stdlib_target_maps_micro_win_system_symbols_once_each() {
        for name in stdlib::names() {
            let target = stdlib::shared(name).expect("stdlib target loads");
            let memory = &target.memory;
            let mapped: Vec<&str> = memory
                .system_bits
                .iter()
                .filter_map(|b| b.microwin.as_deref())
                .collect();
            assert_eq!(mapped.len(), S7_200.len(), "{name}: {mapped:?}");
            for (symbol, address) in S7_200 {
                let bit = memory
                    .microwin_system_bit(&symbol.to_ascii_uppercase())
                    .unwrap_or_else(|| panic!("{name}: no {symbol}"));
                assert_eq!(bit.address, address, "{name}: {symbol}");
            }
            assert!(memory.microwin_system_bit("Mode_Switch").is_none());
        }
    }

    /// Every `<Event MicroWin=n>` of every stdlib target means what S7-200 event n
    /// means: an edge of the same kind on the same input, or the timed interrupt whose
    /// period byte is Micro/WIN's `Time_n_Intrvl` on this target; and the stdlib
    /// targets map all their events.
    #[test]
    fn every_micro_win_event_means_the_s7_200_event() {
        use crate::s7200::{s7200_event, S7200EventSource};
        for name in stdlib::names() {
            let target = stdlib::shared(name).expect("stdlib target loads");
            let memory = &target.memory;
            for event in &memory.events {
                let n = event
                    .microwin
                    .unwrap_or_else(|| panic!("{name}: event {} has no MicroWin", event.number));
                let s7 = s7200_event(i64::from(n))
                    .unwrap_or_else(|| panic!("{name}: MicroWin {n} is no S7-200 event"));
                let same = match s7.source {
                    S7200EventSource::Edge { input, rising } => {
                        let kind = if rising { "RisingEdge" } else { "FallingEdge" };
                        event.kind == kind && event.input.as_deref() == Some(input)
                    }
                    S7200EventSource::Timed { interval } => {
                        let byte = memory.microwin_system_bit(interval).map(|b| &b.address);
                        event.kind == "Timed" && byte.is_some() && event.period.as_ref() == byte
                    }
                    S7200EventSource::Other => false,
                };
                assert!(
                    same,
                    "{name}: event {} ({}) is not S7-200's {n} ({})",
                    event.number, event.description, s7.meaning
                );
                assert_eq!(memory.event_for_s7200(n), Some(event), "{name}");
            }
            assert!(memory.event_for_s7200(12).is_none(), "{name}: HSC0");
        }
    }

    #[test]
    fn micro_win_event_numbers_are_checked_on_load() {
        let xml = |events: &str| {
            format!(
                r#"<ManagerVar>
  <Area Name="I" Slot="0" Kind="DigitalInput" Size="8" Unit="BYTE" Access="BIT BYTE" Writable="false"/>
  <Area Name="T" Slot="5" Kind="Timer" Size="32" Unit="WORD" Access="WORD"/>
  <Area Name="C" Slot="6" Kind="Counter" Size="16" Unit="WORD" Access="WORD"/>
  <Area Name="K" Slot="9" Kind="Constant" Size="128" Unit="BYTE" Access="BIT BYTE WORD DWORD" Writable="false"/>
  <Area Name="L" Slot="10" Kind="Local" Size="32" Unit="BYTE" Access="BIT BYTE WORD DWORD"/>
  <Timers><Resolution First="0" Last="15" Milliseconds="100"/></Timers>
  {events}
</ManagerVar>"#
            )
        };
        let ok =
            xml(r#"<Event Number="20" Name="R" Kind="RisingEdge" Input="I0.0" MicroWin="0"/>"#);
        let map = crate::MemoryMap::parse(ok.as_bytes()).expect("loads");
        assert_eq!(map.event_for_s7200(0).map(|e| e.number), Some(20));
        let past =
            xml(r#"<Event Number="20" Name="R" Kind="RisingEdge" Input="I0.0" MicroWin="34"/>"#);
        assert!(crate::MemoryMap::parse(past.as_bytes()).is_err());
        let twice = xml(
            r#"<Event Number="20" Name="R" Kind="RisingEdge" Input="I0.0" MicroWin="0"/>
  <Event Number="21" Name="S" Kind="RisingEdge" Input="I0.0" MicroWin="0"/>"#,
        );
        let e = crate::MemoryMap::parse(twice.as_bytes()).expect_err("a duplicate");
        assert!(e.to_string().contains("S7-200 event 0"), "{e}");
    }
}
