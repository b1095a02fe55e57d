//! The typed variables of the command-line tools: gutta-link's [`Var`] (a symbol or an
//! address with its format, resolved on a target) with its JSON form, and the symbol
//! context variable names come from (program sources and symbol tables, checked by the
//! compiler). gutta-cc and gutta-vm both use it; it neither prints nor talks to a PLC,
//! and its errors are plain messages the caller prefixes.

use std::path::PathBuf;

use gutta_compiler::diagnostics::Code;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{check_program, ExplicitTarget, ProgramSources};
use gutta_format::{Symbol, SymbolTable};

pub use gutta_link::var::{check_without_target, resolve, resolve_assignment, Var, SYMBOL_SOURCES};

/// A variable's values as JSON.
pub trait VarJson {
    /// The value as JSON: a number when the text is one (`-1`, `21.5`), else the text
    /// (`16#00FF`, `nan`).
    fn json_value(&self, raw: u32) -> serde_json::Value;

    /// `{"name", "address", "format", "value", "raw"}`: one value in JSON output.
    fn json(&self, raw: u32) -> serde_json::Value;
}

impl VarJson for Var {
    fn json_value(&self, raw: u32) -> serde_json::Value {
        let text = self.show(raw);
        match serde_json::from_str::<serde_json::Value>(&text) {
            Ok(v @ serde_json::Value::Number(_)) => v,
            _ => serde_json::Value::String(text),
        }
    }

    fn json(&self, raw: u32) -> serde_json::Value {
        serde_json::json!({
            "name": self.symbol,
            "address": self.canonical,
            "format": self.format.name(),
            "value": self.json_value(raw),
            "raw": raw,
        })
    }
}

/// The symbols of `files` (program sources `.lad`, whose SYMBOLS blocks count; any other
/// file a symbol table) and of `tables` (e.g. an image's source map), one namespace. A
/// source with errors is refused: its symbols may be wrong.
/// The errors of symbol declarations and tables: these make a symbol context wrong.
const SYMBOL_CODES: [Code; 6] = [
    Code::BadSymbolTable,
    Code::BadSymbolTableRow,
    Code::DuplicateSymbol,
    Code::BadSymbolName,
    Code::UnknownDataType,
    Code::SymbolTypeWidth,
];

pub fn symbol_context(
    files: &[PathBuf],
    tables: Vec<SymbolTable>,
    explicit: Option<&ExplicitTarget>,
) -> Result<SymbolTable, String> {
    let mut symbols: Vec<Symbol> = tables.into_iter().flat_map(|t| t.symbols).collect();
    // The .lad files are one program (a project's sources), the others its tables: they
    // are checked together, as `gutta-cc build` compiles them, so a symbol declared in one
    // file and a duplicate in another are seen. Only the declarations' own errors stop the
    // command; a program being edited still lends its symbols.
    let mut program = ProgramSources::default();
    for path in files {
        let name = path.display().to_string();
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("--symbols {name}: cannot read it: {e}"))?;
        let file = SourceFile::new(&name, &text);
        if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("lad"))
        {
            program.sources.push(file);
        } else {
            program.symbol_tables.push(file);
        }
    }
    if !files.is_empty() {
        let checked = check_program(program, explicit);
        if let Some(d) = checked
            .diagnostics()
            .iter()
            .find(|d| d.is_error() && SYMBOL_CODES.contains(&d.code))
        {
            let at = checked
                .file
                .locate(&checked.index, d.primary.span.start as usize);
            return Err(format!(
                "{}:{}:{}: [{}] {} (`gutta-cc --check` shows every error)",
                at.file,
                at.line,
                at.column,
                d.code.as_str(),
                d.message
            ));
        }
        symbols.extend(checked.symbols().symbols);
    }
    Ok(SymbolTable::new(symbols))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_values_are_numbers_when_the_text_is_one() {
        let target = gutta_catalog::stdlib::shared(gutta_catalog::stdlib::DEFAULT)
            .expect("the default target");
        let symbols = SymbolTable::new(vec![Symbol {
            name: "Temp".into(),
            address: "MD8".into(),
            data_type: Some("REAL".into()),
            comment: String::new(),
            origin: "symbols.csv:2".into(),
        }]);
        let temp = resolve("Temp", &symbols, &target).expect("Temp");
        assert_eq!(temp.json_value(21.5f32.to_bits()), serde_json::json!(21.5));
        let hex = resolve("MW10:hex", &symbols, &target).expect("MW10");
        assert_eq!(hex.json_value(255), serde_json::json!("16#00FF"));
        assert_eq!(hex.json(255)["raw"], serde_json::json!(255));
    }
}
