//! The flags that several tools take, with the one spelling and value name they share
//! (docs/cli.md, "Shared flags"); cli/tests/cli_shared_flags.rs reads each tool's
//! `--help` against this table. It must not define the flags; each tool's clap
//! attributes do, except `--plc`/`--target`, declared once in `target.rs`.

/// A flag spelt alike wherever it appears.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SharedFlag {
    /// The long name, without `--`.
    pub long: &'static str,
    /// The value name in `--help` (`None`: a switch).
    pub value_name: Option<&'static str>,
    /// The tools that take it.
    pub tools: &'static [&'static str],
    /// What it means, in every tool that takes it.
    pub meaning: &'static str,
}

const CC: &str = "gutta-cc";
const VM: &str = "gutta-vm";
const SIM: &str = "gutta-sim";

/// Every flag that more than one tool takes, or that a tool spells as others expect.
pub const SHARED_FLAGS: &[SharedFlag] = &[
    SharedFlag {
        long: "plc",
        value_name: Some("NAME"),
        tools: &[CC, VM, SIM],
        meaning: "PLC type from the stdlib (gutta-cc list-targets)",
    },
    SharedFlag {
        long: "target",
        value_name: Some("DIR"),
        tools: &[CC, VM, SIM],
        meaning: "a target folder (PlcType.xml, ManagerVar.xml, ManagerFun.xml) instead of --plc",
    },
    SharedFlag {
        long: "symbols",
        value_name: Some("FILE"),
        tools: &[CC],
        meaning: "a symbol table (CSV or Micro/WIN rows) or a .lad source whose symbols to use",
    },
    SharedFlag {
        long: "message-format",
        value_name: Some("FORMAT"),
        tools: &[CC, VM, SIM],
        meaning: "human or json: results and every error (fatal ones too) as JSON lines on stdout",
    },
    SharedFlag {
        long: "color",
        value_name: Some("WHEN"),
        tools: &[CC],
        meaning: "auto, always or never; auto follows NO_COLOR and the terminal",
    },
    SharedFlag {
        long: "tcp",
        value_name: Some("HOST:PORT"),
        tools: &[CC, SIM],
        meaning: "Modbus TCP: the PLC to talk to (gutta-cc), the address to serve (gutta-sim)",
    },
    SharedFlag {
        long: "rtu-tcp",
        value_name: Some("HOST:PORT"),
        tools: &[CC, SIM],
        meaning: "Modbus RTU frames over TCP: to talk to (gutta-cc), to serve (gutta-sim)",
    },
    SharedFlag {
        long: "serial",
        value_name: Some("DEVICE"),
        tools: &[CC, SIM],
        meaning: "Modbus RTU on a serial device: to talk over (gutta-cc), to serve (gutta-sim)",
    },
    SharedFlag {
        long: "baud",
        value_name: Some("BAUD"),
        tools: &[CC, SIM],
        meaning: "the baud rate of --serial",
    },
    SharedFlag {
        long: "parity",
        value_name: Some("PARITY"),
        tools: &[CC],
        meaning: "the parity of --serial (none, even, odd)",
    },
    SharedFlag {
        long: "station",
        value_name: Some("N"),
        tools: &[CC],
        meaning: "the PLC's Modbus station address",
    },
    SharedFlag {
        long: "scan-ms",
        value_name: Some("MS"),
        tools: &[VM, SIM],
        meaning:
            "milliseconds per scan (the VM's virtual time; gutta-sim also runs it in real time)",
    },
    SharedFlag {
        long: "completions",
        value_name: Some("SHELL"),
        tools: &[VM, SIM],
        meaning: "print the shell completion script (gutta-cc: the `completions` command)",
    },
    SharedFlag {
        long: "man",
        value_name: None,
        tools: &[VM, SIM],
        meaning: "print the man page (gutta-cc: the `man` command)",
    },
];

/// The value parser of `--plc`: any text is taken (the tool loads the PLC type and says
/// which stdlib name was meant when none matches), and the stdlib's PLC types are the
/// possible values shell completion offers. `--help` does not list them
/// (`hide_possible_values`); `gutta-cc list-targets` does.
#[derive(Debug, Clone, Copy, Default)]
pub struct PlcName;

impl clap::builder::TypedValueParser for PlcName {
    type Value = String;

    fn parse_ref(
        &self,
        command: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &std::ffi::OsStr,
    ) -> Result<String, clap::Error> {
        clap::builder::StringValueParser::new().parse_ref(command, arg, value)
    }

    fn possible_values(
        &self,
    ) -> Option<Box<dyn Iterator<Item = clap::builder::PossibleValue> + '_>> {
        Some(Box::new(
            gutta_catalog::stdlib::names().map(clap::builder::PossibleValue::new),
        ))
    }
}
