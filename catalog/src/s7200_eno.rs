//! What `AENO` means after each S7-200 box (docs/microwin.md, "AENO"): on an S7-200 a
//! box's ENO is 0 when the box ran into an error (the system manual's "error conditions
//! that set ENO = 0" of each instruction), and Micro/WIN writes `AENO` after a box when
//! it turns chained LAD boxes into STL. This is the table of those conditions and of
//! the GUTTA flag (SM1.x, ManagerFun.xml's `Flags:` text) that says the box failed;
//! plain data, which the compiler's Micro/WIN stage applies. Boxes GUTTA has that are
//! absent from the table cannot fail (their `Flags:` text says none); a test holds the
//! table to the shipped instruction set.

use crate::s7200::S7200Instruction;

/// What ENO is after an S7-200 box, and how GUTTA knows it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EnoRule {
    /// ENO = 0 on `condition`, which GUTTA reports by setting one of `flags` (SM bits,
    /// as the target's memory map writes them) when the box runs; every run writes
    /// them, so `AN` of each is the ENO.
    Flags {
        condition: &'static str,
        flags: &'static [&'static str],
    },
    /// The box sets SM flags but has no error of its own on an S7-200 (only an
    /// indirect address past its area, which GUTTA faults on): ENO is its power flow.
    CannotFail { why: &'static str },
    /// ENO = 0 on `condition`, which GUTTA sets no flag of its own for.
    NoFlag { condition: &'static str },
    /// A coil or jump in LAD, with no ENO output.
    NoEno,
}

/// One instruction's row of the table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct S7200Eno {
    /// The GUTTA mnemonic (as in ManagerFun.xml), upper case.
    pub mnemonic: &'static str,
    pub rule: EnoRule,
}

const fn flags(
    mnemonic: &'static str,
    condition: &'static str,
    flags: &'static [&'static str],
) -> S7200Eno {
    S7200Eno {
        mnemonic,
        rule: EnoRule::Flags { condition, flags },
    }
}

const fn cannot_fail(mnemonic: &'static str, why: &'static str) -> S7200Eno {
    S7200Eno {
        mnemonic,
        rule: EnoRule::CannotFail { why },
    }
}

const fn no_eno(mnemonic: &'static str) -> S7200Eno {
    S7200Eno {
        mnemonic,
        rule: EnoRule::NoEno,
    }
}

const OVERFLOW: &str = "overflow (SM1.1)";
const DIVISION: &str = "overflow (SM1.1) or division by zero (SM1.3)";
const SM11: &[&str] = &["SM1.1"];
const SM11_SM13: &[&str] = &["SM1.1", "SM1.3"];
const LOGIC: &str = "SM1.0 only says the result is zero";
const SHIFT: &str = "SM1.1 holds the last bit shifted out, which is no error";

/// Every GUTTA box with SM flags whose S7-200 counterpart has an ENO, and the jumps and
/// coils GUTTA models as boxes. Source: the S7-200 system manual's error conditions
/// per instruction.
pub const S7200_ENO: &[S7200Eno] = &[
    // Integer math.
    flags("+I", OVERFLOW, SM11),
    flags("-I", OVERFLOW, SM11),
    flags("*I", OVERFLOW, SM11),
    flags("/I", DIVISION, SM11_SM13),
    flags("+D", OVERFLOW, SM11),
    flags("-D", OVERFLOW, SM11),
    flags("*D", OVERFLOW, SM11),
    flags("/D", DIVISION, SM11_SM13),
    flags("MUL", OVERFLOW, SM11),
    flags("DIV", DIVISION, SM11_SM13),
    flags("INCB", OVERFLOW, SM11),
    flags("INCW", OVERFLOW, SM11),
    flags("INCD", OVERFLOW, SM11),
    flags("DECB", OVERFLOW, SM11),
    flags("DECW", OVERFLOW, SM11),
    flags("DECD", OVERFLOW, SM11),
    // Real math.
    flags("+R", OVERFLOW, SM11),
    flags("-R", OVERFLOW, SM11),
    flags("*R", OVERFLOW, SM11),
    flags("/R", DIVISION, SM11_SM13),
    flags("SQRT", OVERFLOW, SM11),
    flags("SIN", OVERFLOW, SM11),
    flags("COS", OVERFLOW, SM11),
    flags("TAN", OVERFLOW, SM11),
    flags("LN", OVERFLOW, SM11),
    flags("EXP", OVERFLOW, SM11),
    // Logic.
    cannot_fail("ANDB", LOGIC),
    cannot_fail("ANDW", LOGIC),
    cannot_fail("ANDD", LOGIC),
    cannot_fail("ORB", LOGIC),
    cannot_fail("ORW", LOGIC),
    cannot_fail("ORD", LOGIC),
    cannot_fail("XORB", LOGIC),
    cannot_fail("XORW", LOGIC),
    cannot_fail("XORD", LOGIC),
    cannot_fail("INVB", LOGIC),
    cannot_fail("INVW", LOGIC),
    cannot_fail("INVD", LOGIC),
    // Block moves: a block past the end of its area (S7-200 error 0091).
    flags("BMB", "a block past the end of its area (0091)", SM11),
    flags("BMW", "a block past the end of its area (0091)", SM11),
    flags("BMD", "a block past the end of its area (0091)", SM11),
    flags("FILL", "a block past the end of its area (0091)", SM11),
    // Shift and rotate.
    cannot_fail("SRB", SHIFT),
    cannot_fail("SRW", SHIFT),
    cannot_fail("SRD", SHIFT),
    cannot_fail("SLB", SHIFT),
    cannot_fail("SLW", SHIFT),
    cannot_fail("SLD", SHIFT),
    cannot_fail("RRB", SHIFT),
    cannot_fail("RRW", SHIFT),
    cannot_fail("RRD", SHIFT),
    cannot_fail("RLB", SHIFT),
    cannot_fail("RLW", SHIFT),
    cannot_fail("RLD", SHIFT),
    S7200Eno {
        mnemonic: "SHRB",
        rule: EnoRule::NoFlag {
            condition: "an illegal length (0091, 0092), which GUTTA reports in SM1.1 together with the bit shifted out",
        },
    },
    // Conversions.
    flags("ITB", "a value outside 0..255 (SM1.1)", SM11),
    flags("DTI", OVERFLOW, SM11),
    flags("ROUND", OVERFLOW, SM11),
    flags("TRUNC", OVERFLOW, SM11),
    flags("BCDI", "an invalid BCD value (SM1.6)", &["SM1.6"]),
    flags("IBCD", "an invalid BCD value (SM1.6)", &["SM1.6"]),
    cannot_fail("ENCO", "an input of 0 is no S7-200 error"),
    flags("ATH", "an illegal ASCII character (SM1.7) or a buffer past its area (0091)", SM11),
    flags("HTA", "a buffer past its area (0091)", SM11),
    flags("ITA", "an illegal format or a buffer past its area (0091)", SM11),
    flags("DTA", "an illegal format or a buffer past its area (0091)", SM11),
    flags("RTA", "an illegal format or a buffer past its area (0091)", SM11),
    // Tables.
    flags("ATT", "a full table (SM1.4) or an illegal table (0091)", &["SM1.4", "SM1.1"]),
    flags("FIFO", "an empty table (SM1.5) or an illegal table (0091)", &["SM1.5", "SM1.1"]),
    flags("LIFO", "an empty table (SM1.5) or an illegal table (0091)", &["SM1.5", "SM1.1"]),
    flags("FND=", "an illegal table (0091)", SM11),
    flags("FND<>", "an illegal table (0091)", SM11),
    flags("FND<", "an illegal table (0091)", SM11),
    flags("FND>", "an illegal table (0091)", SM11),
    // Coils and jumps in LAD.
    no_eno("JMP"),
    no_eno("END"),
    no_eno("STOP"),
    no_eno("CRET"),
    no_eno("CRETI"),
    no_eno("WDR"),
];

/// `AENO` as an S7-200 instruction outside the Micro/WIN dialect, where GUTTA's own
/// language has no such line (E0220).
pub const AENO: S7200Instruction = S7200Instruction {
    mnemonic: "AENO",
    what: "and ENO of the previous box",
    instead: Some(
        "compile the file as a Micro/WIN export (`.awl`, or the `// dialect: microwin` line), where AENO is the previous box's ENO, or `AN` the flag the box sets (`AN SM1.1` after `+I`)",
    ),
};

/// The table's row for a GUTTA mnemonic (any case).
pub fn s7200_eno(mnemonic: &str) -> Option<&'static S7200Eno> {
    S7200_ENO
        .iter()
        .find(|e| e.mnemonic.eq_ignore_ascii_case(mnemonic))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stdlib;
    use crate::Flow;

    /// The `Flags:` sentence of an instruction's description.
    fn flags_text(description: &str) -> String {
        let joined = description.split_whitespace().collect::<Vec<_>>().join(" ") + " ";
        let rest = joined.split_once("Flags:").map_or("", |(_, r)| r);
        rest.split_once(". ")
            .map_or(rest, |(f, _)| f)
            .trim()
            .to_string()
    }

    #[test]
    fn the_table_holds_to_every_targets_instruction_set() {
        for name in stdlib::names() {
            let target = stdlib::shared(name).expect("stdlib target loads");
            let set = &target.instructions;
            for row in S7200_ENO {
                let id = set.lookup(row.mnemonic).unwrap_or_else(|| {
                    panic!("{} is not in {name}'s ManagerFun.xml", row.mnemonic)
                });
                let spec = set.get(id);
                assert_eq!(
                    spec.flow,
                    Flow::Box,
                    "{}: only boxes have an ENO row",
                    row.mnemonic
                );
                let text = flags_text(&spec.description);
                if let EnoRule::Flags { flags, .. } = row.rule {
                    for f in flags {
                        assert!(
                            format!("{text},").contains(&format!("{f} ")),
                            "{}: the table relies on {f}, which its Flags text `{text}` does not name",
                            row.mnemonic
                        );
                        assert!(target.memory.parse_address(f).is_ok(), "{f} on {name}");
                    }
                }
            }
            for (mnemonic, id) in set.names() {
                let spec = set.get(id);
                if spec.flow != Flow::Box || s7200_eno(&spec.mnemonic).is_some() {
                    continue;
                }
                let text = flags_text(&spec.description);
                assert!(
                    text.starts_with("none"),
                    "{mnemonic} sets `{text}` but has no row in S7200_ENO: say when its ENO is 0 or that it cannot fail"
                );
            }
        }
    }

    #[test]
    fn rows_are_listed_once_and_math_names_its_flags() {
        let mut seen = std::collections::BTreeSet::new();
        for row in S7200_ENO {
            assert!(seen.insert(row.mnemonic), "{} twice", row.mnemonic);
        }
        assert!(matches!(
            s7200_eno("/i").map(|r| r.rule),
            Some(EnoRule::Flags {
                flags: ["SM1.1", "SM1.3"],
                ..
            })
        ));
        assert!(matches!(
            s7200_eno("BCDI").map(|r| r.rule),
            Some(EnoRule::Flags {
                flags: ["SM1.6"],
                ..
            })
        ));
        assert!(matches!(
            s7200_eno("SRW").map(|r| r.rule),
            Some(EnoRule::CannotFail { .. })
        ));
        assert_eq!(s7200_eno("MOVW"), None);
        assert!(crate::s7200::s7200_instruction("AENO").is_some());
    }
}
