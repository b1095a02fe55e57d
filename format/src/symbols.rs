//! A program's symbols as the tools use them: every name the program declares (its
//! `SYMBOLS` blocks and its symbol tables, one namespace) with its direct address, its
//! declared type and comment, and where it was declared. The compiler builds it; the
//! source map carries it beside the image so `gutta-vm` and the client commands can
//! take symbol names with nothing but the image at hand. No I/O here.

use serde::{Deserialize, Serialize};

use gutta_catalog::{DataType, ValueFormat, Width};

/// One declared symbol.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Symbol {
    /// The name as declared (`Start`, `启动`); looked up case-insensitively.
    pub name: String,
    /// The direct address in canonical form (upper case, no blanks): `I0.0`, `MW10`, `T5`.
    pub address: String,
    /// The declared type's keyword (`REAL`, `INT`), when the declaration names one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub data_type: Option<String>,
    /// The declaration's comment, without `//` (empty when there is none).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub comment: String,
    /// Where it is declared: `main.lad:3` or `symbols.csv:4`.
    pub origin: String,
}

impl Symbol {
    /// The declared type, when there is one and it is a known keyword.
    pub fn declared_type(&self) -> Option<DataType> {
        self.data_type.as_deref().and_then(|t| t.parse().ok())
    }

    /// How the symbol's value prints: its declared type's format, else the width's.
    pub fn format(&self, width: Width) -> ValueFormat {
        self.declared_type()
            .map(ValueFormat::for_type)
            .unwrap_or_else(|| ValueFormat::default_for(width))
    }
}

/// Every symbol of a program, sorted by name (case-insensitively), names unique.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct SymbolTable {
    pub symbols: Vec<Symbol>,
}

impl SymbolTable {
    /// A table of `symbols`, sorted; of two with the same name (which the compiler
    /// refuses), the first is kept.
    pub fn new(mut symbols: Vec<Symbol>) -> SymbolTable {
        symbols.sort_by_key(|s| s.name.to_uppercase());
        symbols.dedup_by(|b, a| a.name.to_uppercase() == b.name.to_uppercase());
        SymbolTable { symbols }
    }

    pub fn is_empty(&self) -> bool {
        self.symbols.is_empty()
    }

    /// The symbol named `name`, case-insensitively.
    pub fn get(&self, name: &str) -> Option<&Symbol> {
        let key = name.to_uppercase();
        self.symbols
            .binary_search_by(|s| s.name.to_uppercase().cmp(&key))
            .ok()
            .map(|i| &self.symbols[i])
    }

    /// The first symbol (by name) standing for `address` (canonical form), to label a
    /// raw address with its name.
    pub fn for_address(&self, address: &str) -> Option<&Symbol> {
        self.symbols
            .iter()
            .find(|s| s.address.eq_ignore_ascii_case(address))
    }

    /// Names close to `name` (edit distance up to 2, or a case-insensitive prefix), for
    /// "did you mean" hints; at most three.
    pub fn similar(&self, name: &str) -> Vec<&str> {
        let key = name.to_uppercase();
        let mut found: Vec<(usize, &str)> = self
            .symbols
            .iter()
            .filter_map(|s| {
                let upper = s.name.to_uppercase();
                let d = gutta_catalog::edit_distance(&key, &upper);
                (d <= 2 || (key.len() >= 3 && upper.starts_with(&key))).then_some((d, &*s.name))
            })
            .collect();
        found.sort();
        found.into_iter().take(3).map(|(_, n)| n).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sym(name: &str, address: &str, t: Option<&str>) -> Symbol {
        Symbol {
            name: name.into(),
            address: address.into(),
            data_type: t.map(Into::into),
            comment: String::new(),
            origin: "main.lad:1".into(),
        }
    }

    #[test]
    fn lookup_is_case_insensitive_and_formats_follow_the_type() {
        let t = SymbolTable::new(vec![
            sym("Lamp", "Q0.0", None),
            sym("Temp", "MD8", Some("REAL")),
            sym("speed", "MW10", None),
        ]);
        assert_eq!(t.get("LAMP").map(|s| &*s.address), Some("Q0.0"));
        assert_eq!(t.get("Speed").map(|s| &*s.address), Some("MW10"));
        assert!(t.get("Pump").is_none());
        let temp = t.get("temp").expect("Temp is declared");
        assert_eq!(temp.format(Width::Dword), ValueFormat::Real);
        let speed = t.get("speed").expect("speed is declared");
        assert_eq!(speed.format(Width::Word), ValueFormat::Signed);
        assert_eq!(t.for_address("q0.0").map(|s| &*s.name), Some("Lamp"));
        assert_eq!(t.similar("Lmap"), vec!["Lamp"]);
        let json = serde_json::to_string(&t).expect("serialises");
        assert_eq!(serde_json::from_str::<SymbolTable>(&json).ok(), Some(t));
    }
}
