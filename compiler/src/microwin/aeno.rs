//! `AENO` and Micro/WIN's LAD temporaries L60-L63 as the checker's conventions
//! (docs/microwin.md, "AENO" and "LAD temporaries L60-L63"): what `AENO` after each of
//! the target's instructions compiles to, from the catalog's table of S7-200 ENO
//! conditions (`gutta_catalog::s7200_eno`) and the target's flags; and the note that
//! says where the temporaries went. The checker applies both (`check/aeno_lines.rs`,
//! `check/l_temporaries.rs`) without knowing they are Micro/WIN's.

use std::collections::HashMap;

use gutta_catalog::s7200_eno::{s7200_eno, EnoRule};
use gutta_catalog::{Flow, InstrId, Target};

use crate::check::{AenoMeaning, LTemporaryPlacement};

/// What `AENO` after each instruction of the target compiles to.
pub(super) fn meanings(target: &Target) -> HashMap<InstrId, AenoMeaning> {
    let set = &target.instructions;
    let mut out = HashMap::new();
    for (_, id) in set.names() {
        let spec = set.get(id);
        let meaning = match s7200_eno(&spec.mnemonic).map(|r| r.rule) {
            Some(EnoRule::Flags { condition, flags }) => {
                let parsed: Option<Vec<_>> = flags
                    .iter()
                    .map(|f| target.memory.parse_address(f).ok())
                    .collect();
                match parsed {
                    Some(flags) => AenoMeaning::Flags {
                        flags,
                        what: condition.to_string(),
                    },
                    None => AenoMeaning::Unknown(format!(
                        "whose S7-200 ENO is 0 on {condition}, a flag {} does not have ({})",
                        target.name(),
                        flags.join(", ")
                    )),
                }
            }
            Some(EnoRule::CannotFail { .. }) => AenoMeaning::Nothing,
            Some(EnoRule::NoFlag { condition }) => AenoMeaning::Unknown(format!(
                "whose S7-200 ENO is 0 on {condition}: GUTTA cannot tell that error apart"
            )),
            Some(EnoRule::NoEno) => AenoMeaning::Unknown(format!(
                "which is a coil or jump in LAD, not a box with an ENO ({})",
                spec.summary
            )),
            None if spec.flow == Flow::Box => AenoMeaning::Nothing,
            None => AenoMeaning::Unknown(format!("which is no box with an ENO ({})", spec.summary)),
        };
        out.insert(id, meaning);
    }
    out
}

/// The note: `L60-L63 (Micro/WIN's LAD temporaries) in LB28-LB31 in MAIN, SBR_0`; None
/// when no block uses them.
pub fn l_temporaries_summary(placements: &[LTemporaryPlacement]) -> Option<String> {
    let first = placements.first()?;
    let mut units: Vec<&str> = Vec::new();
    for p in placements {
        if !units.contains(&p.unit.as_str()) {
            units.push(&p.unit);
        }
    }
    Some(format!(
        "L60-L63 (Micro/WIN's LAD temporaries) in {} in {}",
        first.bytes,
        units.join(", ")
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::source::Span;

    #[test]
    fn math_boxes_and_the_bit_logic_get_their_meanings() {
        let target = gutta_catalog::stdlib::shared(gutta_catalog::stdlib::DEFAULT).unwrap();
        let m = meanings(&target);
        let of = |mnemonic: &str| m.get(&target.instructions.lookup(mnemonic).unwrap());
        let sm = |a: &str| target.memory.parse_address(a).unwrap();
        assert!(
            matches!(of("+I"), Some(AenoMeaning::Flags { flags, .. }) if *flags == [sm("SM1.1")])
        );
        assert!(
            matches!(of("/I"), Some(AenoMeaning::Flags { flags, .. }) if *flags == [sm("SM1.1"), sm("SM1.3")])
        );
        assert!(
            matches!(of("BCDI"), Some(AenoMeaning::Flags { flags, .. }) if *flags == [sm("SM1.6")])
        );
        assert_eq!(of("MOVW"), Some(&AenoMeaning::Nothing));
        assert_eq!(of("SRW"), Some(&AenoMeaning::Nothing));
        assert!(matches!(of("SHRB"), Some(AenoMeaning::Unknown(_))));
        assert!(matches!(of("LD"), Some(AenoMeaning::Unknown(w)) if w.contains("no box")));
        assert!(matches!(of("JMP"), Some(AenoMeaning::Unknown(w)) if w.contains("coil or jump")));
        assert!(matches!(of("TON"), Some(AenoMeaning::Unknown(_))));
        assert_eq!(m.len(), target.instructions.names().count().min(m.len()));
    }

    #[test]
    fn the_note_names_each_block_once() {
        let p = |unit: &str| LTemporaryPlacement {
            unit: unit.to_string(),
            bytes: "LB28-LB31".to_string(),
            first_use: Span::new(0, 1),
        };
        assert_eq!(l_temporaries_summary(&[]), None);
        assert_eq!(
            l_temporaries_summary(&[p("MAIN"), p("SBR_0"), p("MAIN")]).as_deref(),
            Some("L60-L63 (Micro/WIN's LAD temporaries) in LB28-LB31 in MAIN, SBR_0")
        );
    }
}
