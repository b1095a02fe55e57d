//! A typed variable: `NAME` (a symbol) or a direct address, with an optional `:fmt`
//! suffix (`MW2:int`, `Temp:hex`), resolved on a target to an address and the format
//! its values print and parse in. What a [`crate::Session`] reads and writes, and what
//! gutta-vm's `--read`/`--set` name. Plain data: it neither prints nor talks to a PLC,
//! and its errors are plain messages the caller prefixes.

use gutta_catalog::{Address, Target, ValueFormat};
use gutta_format::{Symbol, SymbolTable};

/// Where symbols come from, for the hint of an unknown name.
pub const SYMBOL_SOURCES: &str =
    "symbols come from --symbols FILE (a .lad program or a symbol table) or an image's source map";

/// A resolved variable.
#[derive(Debug, Clone)]
pub struct Var {
    /// The symbol's name as declared, when a symbol was used.
    pub symbol: Option<String>,
    pub address: Address,
    /// The address in canonical form (`MW10`, `Q0.0`).
    pub canonical: String,
    pub format: ValueFormat,
}

impl Var {
    /// `Speed (MW10)` for a symbol, `MW10` for an address.
    pub fn label(&self) -> String {
        match &self.symbol {
            Some(name) => format!("{name} ({})", self.canonical),
            None => self.canonical.clone(),
        }
    }

    /// The symbol's name, else the address: a short name for tables and VCD signals.
    pub fn name(&self) -> &str {
        self.symbol.as_deref().unwrap_or(&self.canonical)
    }

    /// A raw value as text in the variable's format.
    pub fn show(&self, raw: u32) -> String {
        self.format.show(raw, self.address.width)
    }

    /// Text as the raw bits to write.
    pub fn parse(&self, text: &str) -> Result<u32, String> {
        self.format
            .parse(text, self.address.width)
            .map_err(|e| format!("{}: {e}", self.label()))
    }
}

/// `NAME[:fmt]` or `ADDR[:fmt]` on `target`, symbols from `symbols`.
pub fn resolve(text: &str, symbols: &SymbolTable, target: &Target) -> Result<Var, String> {
    let text = text.trim();
    let (name, suffix) = match text.split_once(':') {
        Some((name, suffix)) => (name.trim(), Some(suffix.trim())),
        None => (text, None),
    };
    let (symbol, address) = match symbols.get(name) {
        Some(s) => (Some(s), symbol_address(s, target)?),
        None => (None, address(name, symbols, target)?),
    };
    let canonical = target.memory.format_address(&address);
    let format = match suffix {
        Some(s) => {
            let f = ValueFormat::from_suffix(s).ok_or_else(|| {
                format!("`{text}`: unknown format `:{s}` (bool, int, uint, hex, real, or a type such as DINT)")
            })?;
            if !f.fits(address.width) {
                return Err(format!(
                    "`{text}`: {} ({canonical})",
                    f.misfit(address.width)
                ));
            }
            f
        }
        None => symbol.map_or(ValueFormat::default_for(address.width), |s| {
            s.format(address.width)
        }),
    };
    Ok(Var {
        symbol: symbol.map(|s| s.name.clone()),
        address,
        canonical,
        format,
    })
}

/// `NAME[:fmt]=VALUE`: the variable and the raw bits to write.
pub fn resolve_assignment(
    item: &str,
    symbols: &SymbolTable,
    target: &Target,
) -> Result<(Var, u32), String> {
    let (var, value) = item
        .split_once('=')
        .ok_or_else(|| format!("`{item}`: expected VAR=VALUE (Q0.0=1, Speed=-5, MD8:real=21.5)"))?;
    let var = resolve(var, symbols, target)?;
    let raw = var.parse(value)?;
    Ok((var, raw))
}

fn symbol_address(s: &Symbol, target: &Target) -> Result<Address, String> {
    target.memory.parse_address(&s.address).map_err(|e| {
        format!(
            "symbol `{}` ({}) is {}, not an address on {}: {e}",
            s.name,
            s.origin,
            s.address,
            target.name()
        )
    })
}

/// What can be known of `NAME[:fmt]` (or `NAME[:fmt]=VALUE`) without a target, before
/// connecting to learn the PLC type: a name that is neither a symbol nor shaped like an
/// address, or an unknown `:fmt`, is an error on every target. Addresses, a symbol's
/// address and values wait for the target (`resolve`).
pub fn check_without_target(text: &str, symbols: &SymbolTable) -> Result<(), String> {
    let text = text.split_once('=').map_or(text, |(var, _)| var).trim();
    let (name, suffix) = match text.split_once(':') {
        Some((name, suffix)) => (name.trim(), Some(suffix.trim())),
        None => (text, None),
    };
    if symbols.get(name).is_none() && !gutta_catalog::is_address_shaped(name) {
        return Err(unknown_name(name, symbols, None));
    }
    match suffix {
        Some(s) if ValueFormat::from_suffix(s).is_none() => Err(format!(
            "`{text}`: unknown format `:{s}` (bool, int, uint, hex, real, or a type such as DINT)"
        )),
        _ => Ok(()),
    }
}

/// A direct address, or the error for a name that is neither a symbol nor an address.
fn address(name: &str, symbols: &SymbolTable, target: &Target) -> Result<Address, String> {
    let error = match target.memory.parse_address(name) {
        Ok(a) => return Ok(a),
        Err(e) => e,
    };
    if gutta_catalog::is_address_shaped(name) {
        return Err(format!("`{name}` on {}: {error}", target.name()));
    }
    Err(unknown_name(name, symbols, Some(target.name())))
}

/// The error for a name that is neither a symbol nor an address (on `target`, when
/// known): the symbols it is close to, else where symbols come from.
fn unknown_name(name: &str, symbols: &SymbolTable, target: Option<&str>) -> String {
    let on = target.map(|t| format!(" on {t}")).unwrap_or_default();
    let similar = symbols.similar(name);
    if !similar.is_empty() {
        format!(
            "`{name}` is neither a symbol nor an address: did you mean {}?",
            similar
                .iter()
                .map(|s| format!("`{s}`"))
                .collect::<Vec<_>>()
                .join(" or ")
        )
    } else if symbols.is_empty() {
        format!("`{name}` is not an address{on}, and no symbols are known: {SYMBOL_SOURCES}")
    } else {
        format!(
            "`{name}` is neither a symbol ({} known) nor an address{on}",
            symbols.symbols.len()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table() -> SymbolTable {
        let sym = |name: &str, address: &str, t: Option<&str>| Symbol {
            name: name.into(),
            address: address.into(),
            data_type: t.map(Into::into),
            comment: String::new(),
            origin: "symbols.csv:2".into(),
        };
        SymbolTable::new(vec![
            sym("Temp", "MD8", Some("REAL")),
            sym("Count", "MW10", Some("WORD")),
            sym("Lamp", "Q0.0", None),
        ])
    }

    #[test]
    fn the_suffix_then_the_declared_type_then_the_width_decide_the_format() {
        let target = gutta_catalog::stdlib::shared(gutta_catalog::stdlib::DEFAULT)
            .expect("the default target");
        let symbols = table();
        let format = |text: &str| resolve(text, &symbols, &target).map(|v| v.format);
        assert_eq!(format("temp"), Ok(ValueFormat::Real));
        assert_eq!(format("Temp:hex"), Ok(ValueFormat::Hex));
        assert_eq!(format("Count"), Ok(ValueFormat::Unsigned));
        assert_eq!(format("MW10"), Ok(ValueFormat::Signed));
        assert_eq!(format("Lamp"), Ok(ValueFormat::Bool));
        let temp = resolve("Temp", &symbols, &target).expect("Temp");
        assert_eq!(temp.label(), "Temp (MD8)");
        assert_eq!(temp.parse("-3.5"), Ok((-3.5f32).to_bits()));
        assert_eq!(temp.show(21.5f32.to_bits()), "21.5");
        assert!(format("Count:real").is_err_and(|e| e.contains("double word")));
        assert!(format("Lmap").is_err_and(|e| e.contains("did you mean `Lamp`?")));
        assert!(check_without_target("Lmap=1", &symbols)
            .is_err_and(|e| e.contains("did you mean `Lamp`?")));
        assert!(check_without_target("MW10:hex", &symbols).is_ok());
        assert!(check_without_target("Temp:nope", &symbols).is_err_and(|e| e.contains(":nope")));
        let (var, raw) = resolve_assignment("Count=-1", &symbols, &target).expect("fits");
        assert_eq!((var.canonical.as_str(), raw), ("MW10", 0xFFFF));
    }
}
