//! Instruction positions as users write them: `FUNCTION:NETWORK:STEP`, the function
//! being `MAIN` (or `OB1`), `INTn`, `SBRn` or a unit page number, the network its
//! number in the source and the step the instruction's 0-based index in the network.
//! Unit pages are `UnitRef`'s (docs/image-format.md); this file computes none.

use gutta_catalog::PlcType;

use crate::UnitRef;

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
}
