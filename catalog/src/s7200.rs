//! What S7-200 programs (STEP 7-Micro/WIN, MicroWIN SMART) use that GUTTA targets do
//! not have: instruction mnemonics, memory areas and the SM names of Micro/WIN's system
//! symbol table, each with what to use instead where GUTTA has an equivalent; and
//! S7-200's interrupt event numbers with their meaning (`S7200_EVENTS`), which a
//! target's `<Event MicroWin=>` attributes map onto its own events. Plain
//! data (source: the public S7-200 and S7-200 SMART system manuals); the compiler's
//! checker turns a match into a diagnostic. A test keeps every mnemonic here absent
//! from the shipped ManagerFun.xml.

use crate::Width;

/// An S7-200 instruction GUTTA lacks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct S7200Instruction {
    /// The STL mnemonic (or LAD box name) as Micro/WIN writes it, upper case.
    pub mnemonic: &'static str,
    /// What it does on an S7-200, a few words.
    pub what: &'static str,
    /// What to write on a GUTTA target instead, when there is an equivalent.
    pub instead: Option<&'static str>,
}

const fn ins(
    mnemonic: &'static str,
    what: &'static str,
    instead: Option<&'static str>,
) -> S7200Instruction {
    S7200Instruction {
        mnemonic,
        what,
        instead,
    }
}

const SCR_INSTEAD: Option<&str> =
    Some("keep each step in an M bit: `S`/`R` the step bits and guard each step's networks with `LD` of its bit (or `JMP`/`LBL` around it)");
const COMM_INSTEAD: Option<&str> = Some(
    "`EXCH` makes the PLC a Modbus RTU master on a serial port (docs/instructions.md); the ports are set up in the SYSTEM_BLOCK",
);
const NO_STRINGS: Option<&str> = None;

/// The S7-200 instructions GUTTA targets do not have, by mnemonic.
pub const S7200_INSTRUCTIONS: &[S7200Instruction] = &[
    // Sequence control relays.
    ins("LSCR", "load sequence control relay (start of an SCR step)", SCR_INSTEAD),
    ins("SCRT", "sequence control relay transition", SCR_INSTEAD),
    ins("SCRE", "end of an SCR step", SCR_INSTEAD),
    ins("CSCRE", "conditional end of an SCR step", SCR_INSTEAD),
    // Communication.
    ins("XMT", "freeport transmit", COMM_INSTEAD),
    ins("RCV", "freeport receive", COMM_INSTEAD),
    ins("NETR", "PPI network read", COMM_INSTEAD),
    ins("NETW", "PPI network write", COMM_INSTEAD),
    ins("GET", "S7-200 SMART Ethernet read from a remote CPU", COMM_INSTEAD),
    ins("PUT", "S7-200 SMART Ethernet write to a remote CPU", COMM_INSTEAD),
    ins(
        "GPA",
        "get port address",
        Some("the port address is fixed by `PORTn.ADDRESS` in the SYSTEM_BLOCK"),
    ),
    ins(
        "SPA",
        "set port address",
        Some("set `PORTn.ADDRESS` in the SYSTEM_BLOCK"),
    ),
    ins("GIP", "S7-200 SMART get IP address", None),
    ins("SIP", "S7-200 SMART set IP address", None),
    // Strings (STL mnemonics and their LAD box names).
    ins("SLEN", "string length", NO_STRINGS),
    ins("SCPY", "string copy", NO_STRINGS),
    ins("SSCPY", "substring copy", NO_STRINGS),
    ins("SCAT", "string concatenate", NO_STRINGS),
    ins("SFND", "find string in string", NO_STRINGS),
    ins("CFND", "find first character in string", NO_STRINGS),
    ins("STR_LEN", "string length", NO_STRINGS),
    ins("STR_CPY", "string copy", NO_STRINGS),
    ins("SSTR_CPY", "substring copy", NO_STRINGS),
    ins("STR_CAT", "string concatenate", NO_STRINGS),
    ins("STR_FIND", "find string in string", NO_STRINGS),
    ins("CHR_FIND", "find first character in string", NO_STRINGS),
    ins("LDS=", "load string compare equal", NO_STRINGS),
    ins("LDS<>", "load string compare not equal", NO_STRINGS),
    ins("AS=", "and string compare equal", NO_STRINGS),
    ins("AS<>", "and string compare not equal", NO_STRINGS),
    ins("OS=", "or string compare equal", NO_STRINGS),
    ins("OS<>", "or string compare not equal", NO_STRINGS),
    // Conversions to and from strings.
    ins(
        "ITS",
        "integer to string",
        Some("`ITA` writes the ASCII digits without the string's length byte"),
    ),
    ins(
        "DTS",
        "double integer to string",
        Some("`DTA` writes the ASCII digits without the string's length byte"),
    ),
    ins(
        "RTS",
        "real to string",
        Some("`RTA` writes the ASCII digits without the string's length byte"),
    ),
    ins("STI", "substring to integer", None),
    ins("STD", "substring to double integer", None),
    ins("STR", "substring to real", None),
    ins(
        "I_S",
        "integer to string",
        Some("`ITA` writes the ASCII digits without the string's length byte"),
    ),
    ins(
        "DI_S",
        "double integer to string",
        Some("`DTA` writes the ASCII digits without the string's length byte"),
    ),
    ins(
        "R_S",
        "real to string",
        Some("`RTA` writes the ASCII digits without the string's length byte"),
    ),
    ins("S_I", "substring to integer", None),
    ins("S_DI", "substring to double integer", None),
    ins("S_R", "substring to real", None),
    // Real-time clock.
    ins("TODR", "read the real-time clock", None),
    ins("TODW", "set the real-time clock", None),
    ins("TODRX", "read the real-time clock, extended", None),
    ins("TODWX", "set the real-time clock, extended", None),
    ins("READ_RTC", "read the real-time clock", None),
    ins("SET_RTC", "set the real-time clock", None),
    ins("READ_RTCX", "read the real-time clock, extended", None),
    ins("SET_RTCX", "set the real-time clock, extended", None),
    // High-speed counters and pulse outputs.
    ins(
        "HDEF",
        "define a high-speed counter's mode",
        Some("the high-speed counters run without a definition; read their current values in the HC area (`HC0`) where the target has one"),
    ),
    ins(
        "HSC",
        "start or update a high-speed counter",
        Some("read the current value in the HC area (`HC0`) where the target has one"),
    ),
    ins("PLS", "pulse train or pulse width modulation output", None),
    // Control loops and diagnostics.
    ins(
        "PID",
        "PID loop",
        Some("write the loop with REAL arithmetic (`+R`, `-R`, `*R`, `/R`) in a timed interrupt routine"),
    ),
    ins(
        "MEND",
        "unconditional end of the main program",
        Some("nothing: the scan ends after MAIN's last network (`END` ends it early under a condition)"),
    ),
    ins(
        "GERR",
        "get the non-fatal error code",
        Some("read the error code byte of the SM area (see the target's SM table, docs/targets.md)"),
    ),
    ins("DLED", "set the diagnostic LED", None),
];

/// An S7-200 memory area GUTTA targets do not have.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum S7200AreaKind {
    /// The S area (sequence control relay bits: `S0.0`, `SB0`, `SW0`, `SD0`).
    SequenceRelay,
    /// The accumulators `AC0`..`AC3`.
    Accumulator,
}

/// A name of Micro/WIN's system symbol table (an SM address of the S7-200).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct S7200SystemSymbol {
    /// The name as Micro/WIN writes it.
    pub name: &'static str,
    /// Its S7-200 address.
    pub s7200_address: &'static str,
    /// The GUTTA SM address that means the same, if there is one.
    pub gutta_address: Option<&'static str>,
    /// What the S7-200 keeps there, a few words.
    pub what: &'static str,
}

const fn sym(
    name: &'static str,
    s7200_address: &'static str,
    gutta_address: Option<&'static str>,
    what: &'static str,
) -> S7200SystemSymbol {
    S7200SystemSymbol {
        name,
        s7200_address,
        gutta_address,
        what,
    }
}

/// An S7-200 SM name GUTTA has no register for.
const fn sm(
    name: &'static str,
    s7200_address: &'static str,
    what: &'static str,
) -> S7200SystemSymbol {
    sym(name, s7200_address, None, what)
}

/// Micro/WIN's system symbols (SM names, S7-200 CPU 22x and the S7-200 SMART's same
/// addresses) with their GUTTA equivalents: the status bits, the freeport ports, the
/// timed interrupts, the high-speed counters and the pulse outputs.
pub const S7200_SYSTEM_SYMBOLS: &[S7200SystemSymbol] = &[
    // SMB0, SMB1: status bits.
    sym("Always_On", "SM0.0", Some("SM0.0"), "always on"),
    sym(
        "First_Scan_On",
        "SM0.1",
        Some("SM0.1"),
        "on in the first scan",
    ),
    sym(
        "Retentive_Lost",
        "SM0.2",
        Some("SM0.2"),
        "on for one scan when retentive data was lost",
    ),
    sym(
        "RUN_Power_Up",
        "SM0.3",
        Some("SM0.3"),
        "on for one scan when RUN is entered at power-up",
    ),
    sym("Clock_60s", "SM0.4", Some("SM0.4"), "60 s clock"),
    sym("Clock_1s", "SM0.5", Some("SM0.5"), "1 s clock"),
    sym(
        "Clock_Scan",
        "SM0.6",
        Some("SM0.6"),
        "on and off on alternate scans",
    ),
    sm("Mode_Switch", "SM0.7", "the mode switch is in TERM"),
    sym("Result_0", "SM1.0", Some("SM1.0"), "the result was zero"),
    sym(
        "Overflow_Illegal",
        "SM1.1",
        Some("SM1.1"),
        "overflow or illegal value",
    ),
    sym(
        "Neg_Result",
        "SM1.2",
        Some("SM1.2"),
        "the result was negative",
    ),
    sym("Divide_By_0", "SM1.3", Some("SM1.3"), "division by zero"),
    sym(
        "Table_Overflow",
        "SM1.4",
        Some("SM1.4"),
        "the table is full (ATT)",
    ),
    sym(
        "Table_Empty",
        "SM1.5",
        Some("SM1.5"),
        "the table is empty (LIFO, FIFO)",
    ),
    sym(
        "Not_BCD",
        "SM1.6",
        Some("SM1.6"),
        "BCD conversion: an illegal digit",
    ),
    sm(
        "Not_Hex",
        "SM1.7",
        "ASCII to hex conversion: an illegal character",
    ),
    // Freeport: the received character, errors, transmitters.
    sm(
        "Receive_Char",
        "SMB2",
        "the character freeport received last",
    ),
    sm(
        "Parity_Err",
        "SM3.0",
        "freeport parity, framing or overrun error",
    ),
    sm(
        "Comm_Int_Ovr",
        "SM4.0",
        "the communication interrupt queue overflowed",
    ),
    sm(
        "Input_Int_Ovr",
        "SM4.1",
        "the input interrupt queue overflowed",
    ),
    sm(
        "Timed_Int_Ovr",
        "SM4.2",
        "the timed interrupt queue overflowed",
    ),
    sm("Xmt0_Idle", "SM4.5", "port 0's transmitter is idle"),
    sm("Xmt1_Idle", "SM4.6", "port 1's transmitter is idle"),
    // Scan times.
    sym(
        "Scan_Time",
        "SMW22",
        Some("SMW4"),
        "the last scan's time in ms",
    ),
    sym(
        "Scan_Time_Min",
        "SMW24",
        Some("SMW6"),
        "the shortest scan time in ms",
    ),
    sym(
        "Scan_Time_Max",
        "SMW26",
        Some("SMW8"),
        "the longest scan time in ms",
    ),
    // Port 0 and port 1: freeport control and receive message control.
    sm(
        "P0_Config",
        "SMB30",
        "port 0's freeport mode: protocol, bit rate, parity",
    ),
    sm(
        "P1_Config",
        "SMB130",
        "port 1's freeport mode: protocol, bit rate, parity",
    ),
    sm("P0_Stat_Rcv", "SMB86", "port 0's receive message status"),
    sm("P0_Ctrl_Rcv", "SMB87", "port 0's receive message control"),
    sm(
        "P0_Start_Char",
        "SMB88",
        "port 0's start-of-message character",
    ),
    sm("P0_End_Char", "SMB89", "port 0's end-of-message character"),
    sm("P0_Idle_Time", "SMW90", "port 0's idle line time in ms"),
    sm(
        "P0_Timeout",
        "SMW92",
        "port 0's inter-character or message timeout in ms",
    ),
    sm(
        "P0_Max_Char",
        "SMB94",
        "the most characters port 0 receives in a message",
    ),
    sm("P1_Stat_Rcv", "SMB186", "port 1's receive message status"),
    sm("P1_Ctrl_Rcv", "SMB187", "port 1's receive message control"),
    sm(
        "P1_Start_Char",
        "SMB188",
        "port 1's start-of-message character",
    ),
    sm("P1_End_Char", "SMB189", "port 1's end-of-message character"),
    sm("P1_Idle_Time", "SMW190", "port 1's idle line time in ms"),
    sm(
        "P1_Timeout",
        "SMW192",
        "port 1's inter-character or message timeout in ms",
    ),
    sm(
        "P1_Max_Char",
        "SMB194",
        "the most characters port 1 receives in a message",
    ),
    // Timed interrupts.
    sym(
        "Time_0_Intrvl",
        "SMB34",
        Some("SMB10"),
        "timed interrupt 0's period in ms",
    ),
    sym(
        "Time_1_Intrvl",
        "SMB35",
        Some("SMB11"),
        "timed interrupt 1's period in ms",
    ),
    // High-speed counters: status, control, current and preset value.
    sm("HSC0_Status", "SMB36", "high-speed counter 0's status"),
    sm("HSC0_Ctrl", "SMB37", "high-speed counter 0's control"),
    sm(
        "HSC0_CV",
        "SMD38",
        "high-speed counter 0's new current value",
    ),
    sm(
        "HSC0_PV",
        "SMD42",
        "high-speed counter 0's new preset value",
    ),
    sm("HSC1_Status", "SMB46", "high-speed counter 1's status"),
    sm("HSC1_Ctrl", "SMB47", "high-speed counter 1's control"),
    sm(
        "HSC1_CV",
        "SMD48",
        "high-speed counter 1's new current value",
    ),
    sm(
        "HSC1_PV",
        "SMD52",
        "high-speed counter 1's new preset value",
    ),
    sm("HSC2_Status", "SMB56", "high-speed counter 2's status"),
    sm("HSC2_Ctrl", "SMB57", "high-speed counter 2's control"),
    sm(
        "HSC2_CV",
        "SMD58",
        "high-speed counter 2's new current value",
    ),
    sm(
        "HSC2_PV",
        "SMD62",
        "high-speed counter 2's new preset value",
    ),
    sm("HSC3_Status", "SMB136", "high-speed counter 3's status"),
    sm("HSC3_Ctrl", "SMB137", "high-speed counter 3's control"),
    sm(
        "HSC3_CV",
        "SMD138",
        "high-speed counter 3's new current value",
    ),
    sm(
        "HSC3_PV",
        "SMD142",
        "high-speed counter 3's new preset value",
    ),
    sm("HSC4_Status", "SMB146", "high-speed counter 4's status"),
    sm("HSC4_Ctrl", "SMB147", "high-speed counter 4's control"),
    sm(
        "HSC4_CV",
        "SMD148",
        "high-speed counter 4's new current value",
    ),
    sm(
        "HSC4_PV",
        "SMD152",
        "high-speed counter 4's new preset value",
    ),
    sm("HSC5_Status", "SMB156", "high-speed counter 5's status"),
    sm("HSC5_Ctrl", "SMB157", "high-speed counter 5's control"),
    sm(
        "HSC5_CV",
        "SMD158",
        "high-speed counter 5's new current value",
    ),
    sm(
        "HSC5_PV",
        "SMD162",
        "high-speed counter 5's new preset value",
    ),
    // Pulse outputs Q0.0 (PTO0/PWM0) and Q0.1 (PTO1/PWM1): Micro/WIN's PLS names,
    // and the PTO and PWM names of MicroWIN SMART's table for the same bytes.
    sm("PLS0_Status", "SMB66", "pulse output 0's (Q0.0) PTO status"),
    sm(
        "PLS0_Ctrl",
        "SMB67",
        "pulse output 0's (Q0.0) PTO/PWM control",
    ),
    sm("PLS0_Cycle", "SMW68", "pulse output 0's (Q0.0) cycle time"),
    sm("PLS0_PW", "SMW70", "pulse output 0's (Q0.0) pulse width"),
    sm(
        "PLS0_Pulse_Cnt",
        "SMD72",
        "pulse output 0's (Q0.0) PTO pulse count",
    ),
    sm("PLS1_Status", "SMB76", "pulse output 1's (Q0.1) PTO status"),
    sm(
        "PLS1_Ctrl",
        "SMB77",
        "pulse output 1's (Q0.1) PTO/PWM control",
    ),
    sm("PLS1_Cycle", "SMW78", "pulse output 1's (Q0.1) cycle time"),
    sm("PLS1_PW", "SMW80", "pulse output 1's (Q0.1) pulse width"),
    sm(
        "PLS1_Pulse_Cnt",
        "SMD82",
        "pulse output 1's (Q0.1) PTO pulse count",
    ),
    sm("PTO0_Status", "SMB66", "PTO0's (Q0.0) status"),
    sm("PTO0_Ctrl", "SMB67", "PTO0's (Q0.0) control"),
    sm("PTO0_Cycle", "SMW68", "PTO0's (Q0.0) cycle time"),
    sm("PTO0_PC", "SMD72", "PTO0's (Q0.0) pulse count"),
    sm("PTO1_Status", "SMB76", "PTO1's (Q0.1) status"),
    sm("PTO1_Ctrl", "SMB77", "PTO1's (Q0.1) control"),
    sm("PTO1_Cycle", "SMW78", "PTO1's (Q0.1) cycle time"),
    sm("PTO1_PC", "SMD82", "PTO1's (Q0.1) pulse count"),
    sm("PWM0_Ctrl", "SMB67", "PWM0's (Q0.0) control"),
    sm("PWM0_Cycle", "SMW68", "PWM0's (Q0.0) cycle time"),
    sm("PWM0_PW", "SMW70", "PWM0's (Q0.0) pulse width"),
    sm("PWM1_Ctrl", "SMB77", "PWM1's (Q0.1) control"),
    sm("PWM1_Cycle", "SMW78", "PWM1's (Q0.1) cycle time"),
    sm("PWM1_PW", "SMW80", "PWM1's (Q0.1) pulse width"),
    sm("PTO0_Step", "SMB166", "PTO0's (Q0.0) current profile step"),
    sm(
        "PTO0_Profile",
        "SMW168",
        "PTO0's (Q0.0) profile table address in V",
    ),
    sm("PTO1_Step", "SMB176", "PTO1's (Q0.1) current profile step"),
    sm(
        "PTO1_Profile",
        "SMW178",
        "PTO1's (Q0.1) profile table address in V",
    ),
];

/// What raises an S7-200 interrupt event, as far as a GUTTA target's events can mean
/// the same: an input edge, a timed interrupt, or something GUTTA events never are.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum S7200EventSource {
    /// A rising (`rising`) or falling edge of the input bit `input` (`I0.0`).
    Edge { input: &'static str, rising: bool },
    /// A timed interrupt whose period byte is Micro/WIN's system symbol `interval`
    /// (`Time_0_Intrvl`, SMB34 on an S7-200).
    Timed { interval: &'static str },
    /// Communication, high-speed counters, pulse outputs, timers T32/T96.
    Other,
}

/// An S7-200 (CPU 22x) interrupt event number, what raises it, in a few words.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct S7200Event {
    pub number: u32,
    pub meaning: &'static str,
    pub source: S7200EventSource,
}

const fn edge(number: u32, meaning: &'static str, input: &'static str, rising: bool) -> S7200Event {
    S7200Event {
        number,
        meaning,
        source: S7200EventSource::Edge { input, rising },
    }
}

const fn timed(number: u32, meaning: &'static str, interval: &'static str) -> S7200Event {
    S7200Event {
        number,
        meaning,
        source: S7200EventSource::Timed { interval },
    }
}

const fn other(number: u32, meaning: &'static str) -> S7200Event {
    S7200Event {
        number,
        meaning,
        source: S7200EventSource::Other,
    }
}

/// Every S7-200 interrupt event, 0..33, in number order (the S7-200 system manual's
/// table of interrupt events).
pub const S7200_EVENTS: &[S7200Event] = &[
    edge(0, "I0.0 rising edge", "I0.0", true),
    edge(1, "I0.0 falling edge", "I0.0", false),
    edge(2, "I0.1 rising edge", "I0.1", true),
    edge(3, "I0.1 falling edge", "I0.1", false),
    edge(4, "I0.2 rising edge", "I0.2", true),
    edge(5, "I0.2 falling edge", "I0.2", false),
    edge(6, "I0.3 rising edge", "I0.3", true),
    edge(7, "I0.3 falling edge", "I0.3", false),
    other(8, "port 0 receive character"),
    other(9, "port 0 transmit complete"),
    timed(10, "timed interrupt 0 (SMB34)", "Time_0_Intrvl"),
    timed(11, "timed interrupt 1 (SMB35)", "Time_1_Intrvl"),
    other(12, "HSC0 CV=PV"),
    other(13, "HSC1 CV=PV"),
    other(14, "HSC1 direction changed"),
    other(15, "HSC1 external reset"),
    other(16, "HSC2 CV=PV"),
    other(17, "HSC2 direction changed"),
    other(18, "HSC2 external reset"),
    other(19, "PLS0 pulse count complete"),
    other(20, "PLS1 pulse count complete"),
    other(21, "timer T32 CT=PT"),
    other(22, "timer T96 CT=PT"),
    other(23, "port 0 receive message complete"),
    other(24, "port 1 receive message complete"),
    other(25, "port 1 receive character"),
    other(26, "port 1 transmit complete"),
    other(27, "HSC0 direction changed"),
    other(28, "HSC0 external reset"),
    other(29, "HSC4 CV=PV"),
    other(30, "HSC4 direction changed"),
    other(31, "HSC4 external reset"),
    other(32, "HSC3 CV=PV"),
    other(33, "HSC5 CV=PV"),
];

/// The S7-200 interrupt event `number`, if the S7-200 has one.
pub fn s7200_event(number: i64) -> Option<&'static S7200Event> {
    S7200_EVENTS.iter().find(|e| i64::from(e.number) == number)
}

/// What an operand name means on an S7-200 when GUTTA has no such area or name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum S7200Name {
    Area(S7200AreaKind),
    SystemSymbol(&'static S7200SystemSymbol),
    /// MicroWIN SMART's default name of an onboard input or output (`CPU_Input0`).
    SmartIo(crate::s7200_io::SmartIoName),
}

/// The S7-200 instruction `mnemonic` names (any case), if GUTTA lacks it: a row of
/// [`S7200_INSTRUCTIONS`], or `AENO`, which only the Micro/WIN dialect accepts
/// ([`crate::s7200_eno::AENO`]).
pub fn s7200_instruction(mnemonic: &str) -> Option<&'static S7200Instruction> {
    S7200_INSTRUCTIONS
        .iter()
        .chain(std::iter::once(&crate::s7200_eno::AENO))
        .find(|i| i.mnemonic.eq_ignore_ascii_case(mnemonic))
}

/// What `name` (an operand as written) is on an S7-200, when it is an area GUTTA
/// lacks (`S0.0`, `SB2`, `AC0`), a Micro/WIN system symbol (`Always_On`) or one of
/// MicroWIN SMART's default I/O names (`CPU_Input0`).
pub fn s7200_name(name: &str) -> Option<S7200Name> {
    if let Some(s) = S7200_SYSTEM_SYMBOLS
        .iter()
        .find(|s| s.name.eq_ignore_ascii_case(name))
    {
        return Some(S7200Name::SystemSymbol(s));
    }
    if let Some(io) = crate::s7200_io::smart_io_name(name) {
        return Some(S7200Name::SmartIo(io));
    }
    let upper = name.to_ascii_uppercase();
    if let Some(n) = upper.strip_prefix("AC") {
        if matches!(n, "0" | "1" | "2" | "3") {
            return Some(S7200Name::Area(S7200AreaKind::Accumulator));
        }
    }
    let rest = upper.strip_prefix('S')?;
    let rest = rest
        .strip_prefix(['B', 'W', 'D'])
        .filter(|_| !rest.contains('.'))
        .unwrap_or(rest);
    let mut parts = rest.splitn(2, '.');
    let byte = parts.next().unwrap_or("");
    let byte_ok = !byte.is_empty() && byte.bytes().all(|b| b.is_ascii_digit());
    let bit_ok = match parts.next() {
        None => rest.len() != upper.len() - 1,
        Some(bit) => bit.len() == 1 && (b'0'..=b'7').contains(&bit.as_bytes()[0]),
    };
    (byte_ok && bit_ok).then_some(S7200Name::Area(S7200AreaKind::SequenceRelay))
}

/// The SCR instructions, which the Micro/WIN dialect compiles (docs/microwin.md,
/// "Sequence control relays"): E0220 only outside it, so the "lacks" table leaves them out.
pub const SCR_MNEMONICS: [&str; 4] = ["LSCR", "SCRT", "SCRE", "CSCRE"];

/// The S area of the S7-200 holds S0.0-S31.7: this many bytes.
pub const S_AREA_BYTES: u32 = 32;

/// An operand of the S7-200's S area as written (`S0.1`, `SB2`, `SW0`, `SD4`): its width,
/// byte and bit (0 unless a bit). The byte is as written, not checked against
/// [`S_AREA_BYTES`].
pub fn s_operand(name: &str) -> Option<(Width, u32, u8)> {
    if s7200_name(name) != Some(S7200Name::Area(S7200AreaKind::SequenceRelay)) {
        return None;
    }
    let rest = &name[1..];
    let (width, rest) = match rest.as_bytes().first()?.to_ascii_uppercase() {
        b'B' => (Width::Byte, &rest[1..]),
        b'W' => (Width::Word, &rest[1..]),
        b'D' => (Width::Dword, &rest[1..]),
        _ => (Width::Bit, rest),
    };
    match rest.split_once('.') {
        Some((byte, bit)) if width == Width::Bit => {
            Some((width, byte.parse().ok()?, bit.parse().ok()?))
        }
        None if width != Width::Bit => Some((width, rest.parse().ok()?, 0)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stdlib;

    #[test]
    fn no_listed_instruction_is_in_the_shipped_instruction_set() {
        for name in stdlib::names() {
            let target = stdlib::shared(name).expect("stdlib target loads");
            for i in S7200_INSTRUCTIONS {
                assert!(
                    target.instructions.lookup(i.mnemonic).is_none(),
                    "{} is in {name}'s ManagerFun.xml; remove it from the S7-200 table",
                    i.mnemonic
                );
            }
        }
    }

    #[test]
    fn every_gutta_equivalent_is_a_system_entry_of_every_target() {
        for name in stdlib::names() {
            let target = stdlib::shared(name).expect("stdlib target loads");
            for s in S7200_SYSTEM_SYMBOLS {
                if let Some(a) = s.gutta_address {
                    assert!(
                        target
                            .memory
                            .system_bits
                            .iter()
                            .any(|b| b.address.eq_ignore_ascii_case(a)),
                        "{}: {a} is not in {name}'s SM table",
                        s.name
                    );
                }
            }
        }
    }

    #[test]
    fn mnemonics_and_symbols_are_listed_once() {
        let mut seen = std::collections::BTreeSet::new();
        for i in S7200_INSTRUCTIONS {
            assert!(seen.insert(i.mnemonic), "{} twice", i.mnemonic);
            assert_eq!(i.mnemonic, i.mnemonic.to_ascii_uppercase());
        }
        let mut seen = std::collections::BTreeSet::new();
        for s in S7200_SYSTEM_SYMBOLS {
            assert!(seen.insert(s.name.to_ascii_uppercase()), "{} twice", s.name);
        }
    }

    #[test]
    fn events_are_numbered_0_to_33_in_order() {
        for (i, e) in S7200_EVENTS.iter().enumerate() {
            assert_eq!(e.number as usize, i, "{}", e.meaning);
        }
        assert_eq!(S7200_EVENTS.len(), 34);
        assert_eq!(s7200_event(12).map(|e| e.meaning), Some("HSC0 CV=PV"));
        assert_eq!(s7200_event(34), None);
        assert_eq!(s7200_event(-1), None);
    }

    #[test]
    fn s_operands() {
        assert_eq!(s_operand("S0.1"), Some((Width::Bit, 0, 1)));
        assert_eq!(s_operand("sb2"), Some((Width::Byte, 2, 0)));
        assert_eq!(s_operand("SW30"), Some((Width::Word, 30, 0)));
        assert_eq!(s_operand("SD4"), Some((Width::Dword, 4, 0)));
        assert_eq!(s_operand("SM0.0"), None);
        assert_eq!(s_operand("S0"), None);
        assert_eq!(s_operand("AC0"), None);
    }

    #[test]
    fn areas_by_name() {
        let relay = Some(S7200Name::Area(S7200AreaKind::SequenceRelay));
        let acc = Some(S7200Name::Area(S7200AreaKind::Accumulator));
        assert_eq!(s7200_name("S0.0"), relay);
        assert_eq!(s7200_name("s3.7"), relay);
        assert_eq!(s7200_name("SB2"), relay);
        assert_eq!(s7200_name("SW4"), relay);
        assert_eq!(s7200_name("SD0"), relay);
        assert_eq!(s7200_name("AC0"), acc);
        assert_eq!(s7200_name("ac3"), acc);
        assert_eq!(s7200_name("AC4"), None);
        assert_eq!(s7200_name("S0"), None);
        assert_eq!(s7200_name("S0.8"), None);
        assert_eq!(s7200_name("SB0.1"), None);
        assert_eq!(s7200_name("Start"), None);
        assert_eq!(s7200_name("SMB0"), None);
        assert!(matches!(
            s7200_name("always_on"),
            Some(S7200Name::SystemSymbol(s)) if s.gutta_address == Some("SM0.0")
        ));
    }
}
