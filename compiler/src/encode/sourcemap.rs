//! The source map of a lowered program: every instruction record's page, byte offset,
//! network and step, with the file, line, column and text of the source it came from,
//! and the program's symbols. Byte offsets follow the records' encoded lengths, as the
//! encoder lays them out. No I/O.

use gutta_format::{Image, MappedInstruction, Record, SourceMap, SymbolTable};

use crate::lower::Lowered;
use crate::source::{LineIndex, PartKind, SourceFile};

/// The map of `image`, encoded from `lowered`, compiled from `file` (one file or a
/// joined program: instructions name their file's index among its sources), carrying
/// `symbols`.
pub fn source_map(
    lowered: &Lowered,
    image: &Image,
    file: &SourceFile,
    index: &LineIndex,
    symbols: SymbolTable,
) -> SourceMap {
    let parts = file.parts();
    // Sources come before tables, so a source's part index is its index in `files`.
    let files: Vec<String> = parts
        .iter()
        .filter(|p| p.kind == PartKind::Source)
        .map(|p| p.name.clone())
        .collect();
    let mut instructions = Vec::new();
    for unit in &lowered.units {
        let Ok(page) = u8::try_from(unit.page) else {
            continue;
        };
        let (mut byte, mut network, mut step) = (0usize, 0u16, 0u16);
        for (record, span) in &unit.records {
            match record {
                Record::Network(n) => (network, step) = (*n, 0),
                Record::Instruction { .. } => {
                    let at = file.locate(index, span.start as usize);
                    let source = file.part_index(span.start as usize);
                    instructions.push(MappedInstruction {
                        page,
                        byte: u32::try_from(byte).unwrap_or(u32::MAX),
                        network,
                        step,
                        file: u16::try_from(source).unwrap_or(u16::MAX),
                        line: at.line,
                        column: at.column,
                        text: instruction_text(file.slice(*span)),
                    });
                    step = step.saturating_add(1);
                }
            }
            byte += record.len();
        }
    }
    SourceMap::new(file.name.clone(), &image.manifest(), instructions)
        .with_files(files)
        .with_symbols(symbols)
}

/// The instruction's first source line, without a trailing comment or blanks.
fn instruction_text(source: &str) -> String {
    let line = source.lines().next().unwrap_or("");
    let code = line.split("//").next().unwrap_or(line);
    code.trim().to_string()
}
