//! Instruction positions as users write them: `FUNCTION:NETWORK:STEP`, the function
//! being `MAIN` (or `OB1`), `INTn`, `SBRn` or a unit page number (docs/image-format.md:
//! MAIN and INTn are pages 0..IntSize-1, SBRn is page IntSize + n), the network its
//! number in the source and the step the instruction's 0-based index in the network.

/// (unit page, network, step) from `MAIN:2:0`, `SBR0:1:3`, `INT1:1:0`, `8:1:0`.
/// `int_size` is the target's ProgramBlockPageIntSize.
pub fn parse_position(text: &str, int_size: u32) -> Result<(u8, u16, u16), String> {
    let bad = |why: &str| {
        format!("{text}: {why} (expected FUNCTION:NETWORK:STEP, e.g. MAIN:2:0 or SBR0:1:3)")
    };
    let parts: Vec<&str> = text.split(':').collect();
    let [function, network, step] = parts[..] else {
        return Err(bad("three parts separated by `:`"));
    };
    let upper = function.to_ascii_uppercase();
    let page = if upper == "MAIN" || upper == "OB1" {
        Some(0)
    } else if let Some(n) = upper.strip_prefix("SBR") {
        n.parse::<u32>().ok().map(|n| int_size + n)
    } else if let Some(n) = upper.strip_prefix("INT") {
        n.parse::<u32>().ok().filter(|&n| n < int_size.max(1))
    } else {
        upper.parse::<u32>().ok()
    };
    let function = page
        .and_then(|p| u8::try_from(p).ok())
        .ok_or_else(|| bad("FUNCTION is MAIN, INTn, SBRn or a page number below 256"))?;
    let network = network
        .parse()
        .map_err(|_| bad("NETWORK is a network number"))?;
    let step = step
        .parse()
        .map_err(|_| bad("STEP is the instruction's 0-based index in its network"))?;
    Ok((function, network, step))
}

/// MAIN, INTn or SBRn for a unit page.
pub fn function_name(page: u8, int_size: u32) -> String {
    match u32::from(page) {
        0 => "MAIN".into(),
        p if p < int_size => format!("INT{p}"),
        p => format!("SBR{}", p - int_size),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions() {
        assert_eq!(parse_position("MAIN:2:0", 8), Ok((0, 2, 0)));
        assert_eq!(parse_position("sbr1:1:3", 8), Ok((9, 1, 3)));
        assert_eq!(parse_position("INT7:1:0", 8), Ok((7, 1, 0)));
        assert!(parse_position("INT8:1:0", 8).is_err());
        assert!(parse_position("MAIN:1", 8).is_err());
        assert!(parse_position("300:1:0", 8).is_err());
        assert_eq!(function_name(9, 8), "SBR1");
        assert_eq!(function_name(0, 8), "MAIN");
        assert_eq!(function_name(3, 8), "INT3");
    }
}
