//! Instruction positions as users write them: `FUNCTION:NETWORK:STEP`, the function
//! being `MAIN` (or `OB1`), `INTn`, `SBRn` or a unit page number, the network its
//! number in the source and the step the instruction's 0-based index in the network.
//! Unit pages are `UnitRef`'s (docs/image-format.md); this file computes none. With a
//! source map, a breakpoint may also be `FILE:LINE` or `LINE` (`parse_breakpoint`).

use gutta_catalog::PlcType;

use crate::{SourceMap, UnitRef};

/// Where a breakpoint goes: (unit page, network, step), and a note when a line without
/// an instruction was moved to the next line that has one.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Breakpoint {
    pub position: (u8, u16, u16),
    pub note: Option<String>,
}

/// A breakpoint as users write it: `FUNCTION:NETWORK:STEP` always; `FILE:LINE` or
/// `LINE` through `map`. Without a map, a line is refused with a message naming
/// `map_name`, the file that would hold the map.
pub fn parse_breakpoint(
    text: &str,
    plc: &PlcType,
    map: Option<&SourceMap>,
    map_name: &str,
) -> Result<Breakpoint, String> {
    match map {
        Some(map) => {
            if let Some(found) = map.resolve_line(text)? {
                let i = found.instruction;
                return Ok(Breakpoint {
                    position: (i.page, i.network, i.step),
                    note: found.moved().then(|| {
                        format!(
                            "{text}: line {} has no instruction; breaking at line {}",
                            found.asked, i.line
                        )
                    }),
                });
            }
        }
        None if names_a_line(text) => {
            return Err(format!(
                "{text}: a source line needs the source map {map_name} that `gutta-cc -o` writes beside the image; without it give FUNCTION:NETWORK:STEP"
            ))
        }
        None => {}
    }
    Ok(Breakpoint {
        position: parse_position(text, plc)?,
        note: None,
    })
}

/// `12` or `main.lad:12` (a file has a `.` or a directory in its name).
fn names_a_line(text: &str) -> bool {
    let (file, line) = text.rsplit_once(':').unwrap_or(("", text));
    line.parse::<u32>().is_ok() && (file.is_empty() || file.contains(['.', '/', '\\']))
}

/// (unit page, network, step) from `MAIN:2:0`, `SBR0:1:3`, `INT1:1:0`, `8:1:0` on a
/// target: a named unit must be one the target can have.
pub fn parse_position(text: &str, plc: &PlcType) -> Result<(u8, u16, u16), String> {
    let bad = |why: &str| {
        format!("{text}: {why} (expected FUNCTION:NETWORK:STEP, e.g. MAIN:2:0 or SBR0:1:3)")
    };
    let parts: Vec<&str> = text.split(':').collect();
    let [function, network, step] = parts[..] else {
        return Err(bad("three parts separated by `:`"));
    };
    let upper = function.to_ascii_uppercase();
    let numbered = |prefix: &str, unit: fn(u16) -> UnitRef| {
        upper
            .strip_prefix(prefix)
            .map(|n| n.parse::<u16>().ok().and_then(|n| unit(n).page(plc)))
    };
    let page = if upper == "MAIN" || upper == "OB1" {
        UnitRef::MAIN.page(plc)
    } else if let Some(page) = numbered("SBR", UnitRef::subroutine) {
        page
    } else if let Some(page) = numbered("INT", UnitRef::interrupt) {
        page
    } else {
        upper.parse::<u8>().ok()
    };
    let function =
        page.ok_or_else(|| bad("FUNCTION is MAIN, INTn, SBRn or a page number below 256"))?;
    let network = network
        .parse()
        .map_err(|_| bad("NETWORK is a network number"))?;
    let step = step
        .parse()
        .map_err(|_| bad("STEP is the instruction's 0-based index in its network"))?;
    Ok((function, network, step))
}

/// MAIN, INTn or SBRn for a unit page; the page number for a page that is no unit of
/// the target.
pub fn function_name(page: u8, plc: &PlcType) -> String {
    match UnitRef::from_page(page, plc) {
        Some(unit) => unit.to_string(),
        None => page.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions() {
        // CPU-EC20: 8 interrupt routines (MAIN included), 8 subroutines.
        let plc = gutta_catalog::stdlib::default_target()
            .expect("the default target loads")
            .plc;
        assert_eq!(parse_position("MAIN:2:0", &plc), Ok((0, 2, 0)));
        assert_eq!(parse_position("sbr1:1:3", &plc), Ok((9, 1, 3)));
        assert_eq!(parse_position("INT7:1:0", &plc), Ok((7, 1, 0)));
        assert_eq!(parse_position("12:1:0", &plc), Ok((12, 1, 0)));
        assert!(parse_position("INT8:1:0", &plc).is_err());
        assert!(parse_position("SBR8:1:0", &plc).is_err());
        assert!(parse_position("MAIN:1", &plc).is_err());
        assert!(parse_position("300:1:0", &plc).is_err());
        assert_eq!(function_name(9, &plc), "SBR1");
        assert_eq!(function_name(0, &plc), "MAIN");
        assert_eq!(function_name(3, &plc), "INT3");
        assert_eq!(function_name(200, &plc), "200");
    }

    #[test]
    fn breakpoints() {
        let plc = gutta_catalog::stdlib::default_target()
            .expect("the default target loads")
            .plc;
        let at =
            |text: &str, map: Option<&SourceMap>| parse_breakpoint(text, &plc, map, "x.map.json");
        assert_eq!(at("MAIN:2:0", None).map(|b| b.position), Ok((0, 2, 0)));
        assert!(at("main.lad:3", None).is_err_and(|e| e.contains("x.map.json")));
        assert!(at("3", None).is_err_and(|e| e.contains("x.map.json")));
        assert!(at("MAIN:1", None).is_err_and(|e| e.contains("three parts")));
        let manifest = crate::Image {
            plc_type: "CPU-EC20".into(),
            pages: Default::default(),
        }
        .manifest();
        let map = SourceMap::new(
            "main.lad",
            &manifest,
            vec![crate::MappedInstruction {
                page: 0,
                byte: 4,
                network: 1,
                step: 0,
                file: 0,
                line: 6,
                column: 1,
                text: "LD I0.0".into(),
            }],
        );
        let moved = at("main.lad:4", Some(&map)).expect("the next line");
        assert_eq!(moved.position, (0, 1, 0));
        assert!(moved.note.is_some_and(|n| n.contains("breaking at line 6")));
        assert_eq!(at("6", Some(&map)).map(|b| b.note), Ok(None));
        assert_eq!(
            at("SBR1:1:3", Some(&map)).map(|b| b.position),
            Ok((9, 1, 3))
        );
    }
}
