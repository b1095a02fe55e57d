//! The session's program as something to run (docs/studio.md, "Simulate"): every open
//! file's buffer, saved or not, compiled as one program with the project's tables,
//! target and options (as `gutta-cc build` compiles the files), to an image the VM
//! loads, with what power flow needs: the networks as the page draws them, the
//! program's symbols and its target. A program with errors is refused with the first
//! error's code, message and place.

use std::sync::Arc;

use gutta_catalog::Target;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile_program, ProgramSources};
use gutta_format::{Image, SymbolTable};
use gutta_ladder::model::Ladder;

use super::Session;

/// The session's program compiled: what the simulator runs and paints.
#[derive(Debug, Clone)]
pub struct RunProgram {
    /// The compiled image (what `gutta-cc build` would write for these buffers).
    pub image: Image,
    /// The target the program was compiled for.
    pub target: Arc<Target>,
    /// Every symbol of the program (SYMBOLS blocks and the project's tables).
    pub symbols: SymbolTable,
    /// The blocks of every open file, as the page draws them (`data-block`,
    /// `data-network`, element ids `data-id`).
    pub ladder: Ladder,
}

/// Why the program does not run: its first error (`code` is the compiler's, `E0101`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ProgramError {
    pub code: String,
    pub message: String,
    /// Where the error is: the file as the session names it, line and column (1-based).
    pub file: String,
    pub line: u32,
    pub column: u32,
}

impl std::fmt::Display for ProgramError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}:{}:{}: [{}] {} (the program must compile to run)",
            self.file, self.line, self.column, self.code, self.message
        )
    }
}

impl std::error::Error for ProgramError {}

impl Session {
    /// The current program (every buffer, saved or not) compiled with the project's
    /// tables, target and options; refused with its first error when it does not
    /// compile.
    pub fn run_program(&self) -> Result<RunProgram, ProgramError> {
        let sources = ProgramSources {
            sources: self
                .files
                .iter()
                .map(|f| SourceFile::new(&f.name, &f.text))
                .collect(),
            symbol_tables: self.tables.clone(),
            options: self.options.clone(),
        };
        let compiled = compile_program(sources, self.target.as_ref());
        let checked = &compiled.checked;
        let first_error = checked.diagnostics().iter().find(|d| d.is_error());
        let image = match (&compiled.image, first_error) {
            (Some(image), None) => image.clone(),
            (_, error) => {
                let (code, message, offset) = error.map_or_else(
                    || {
                        (
                            "E0000".to_string(),
                            "the program has no image".to_string(),
                            0,
                        )
                    },
                    |d| {
                        (
                            d.code.as_str().to_string(),
                            d.message.clone(),
                            d.primary.span.start as usize,
                        )
                    },
                );
                let at = checked.file.locate(&checked.index, offset);
                return Err(ProgramError {
                    code,
                    message,
                    file: at.file.to_string(),
                    line: at.line,
                    column: at.column,
                });
            }
        };
        let ladder = Ladder {
            plc: checked.target.name().to_string(),
            blocks: self
                .files
                .iter()
                .flat_map(|f| f.ladder.blocks.iter().cloned())
                .collect(),
        };
        Ok(RunProgram {
            image,
            target: checked.target.clone(),
            symbols: checked.symbols(),
            ladder,
        })
    }
}
