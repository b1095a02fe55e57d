//! The source map: each instruction of an image, by (unit page, network, step) and by
//! (page, byte offset), to where it is written (file, line, column) and its source text.
//! The compiler writes it beside the image directory (docs/image-format.md, "The source
//! map"); it is never downloaded. No I/O here, and nothing about the image's bytes.

use serde::{Deserialize, Serialize};

use crate::{crc16, Manifest};

/// The `format` field of `sourcemap.json`.
pub const SOURCE_MAP_FORMAT: u32 = 1;

/// One instruction of an instruction page and where its source is.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
pub struct MappedInstruction {
    /// Unit page (function index): 0 MAIN, n INTn, IntSize + n SBRn.
    pub page: u8,
    /// Byte offset of the instruction record in its instruction page.
    pub byte: u32,
    /// Network number, as written in the source.
    pub network: u16,
    /// 0-based index of the instruction in its network.
    pub step: u16,
    /// 1-based source line and column.
    pub line: u32,
    pub column: u32,
    /// The instruction as written (`MOVW  VW100, VW200`).
    pub text: String,
}

/// The whole map of one compiled source file. Instructions are sorted by (page, byte),
/// so equal programs give byte-identical JSON.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct SourceMap {
    pub format: u32,
    /// The source file's name as given to the compiler (`main.lad`).
    pub file: String,
    /// `crc16` of the image's manifest.json: a map is only used with the image it
    /// was written for (`describes`).
    pub manifest_crc: u16,
    pub instructions: Vec<MappedInstruction>,
}

/// What a `FILE:LINE` or `LINE` breakpoint resolved to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LineMatch<'a> {
    /// The line asked for.
    pub asked: u32,
    /// The first instruction on that line or, when it has none, on the next line that has one.
    pub instruction: &'a MappedInstruction,
}

impl LineMatch<'_> {
    /// The line asked for had no instruction; a later line was taken.
    pub fn moved(&self) -> bool {
        self.instruction.line != self.asked
    }
}

impl SourceMap {
    /// A map of `file`; the instructions are sorted here.
    pub fn new(
        file: impl Into<String>,
        manifest: &Manifest,
        instructions: Vec<MappedInstruction>,
    ) -> SourceMap {
        SourceMap::sorted(
            file.into(),
            crc16(manifest.to_json().as_bytes()),
            instructions,
        )
    }

    fn sorted(
        file: String,
        manifest_crc: u16,
        mut instructions: Vec<MappedInstruction>,
    ) -> SourceMap {
        instructions.sort();
        SourceMap {
            format: SOURCE_MAP_FORMAT,
            file,
            manifest_crc,
            instructions,
        }
    }

    /// Whether this map was written for the image with that manifest.
    pub fn describes(&self, manifest: &Manifest) -> bool {
        self.manifest_crc == crc16(manifest.to_json().as_bytes())
    }

    /// JSON with one instruction per line (compact, so a large program's map stays
    /// small and quick to write, yet a diff shows which instructions moved) and a final
    /// newline.
    pub fn to_json(&self) -> String {
        let mut out: Vec<u8> = Vec::with_capacity(96 * self.instructions.len() + 128);
        out.extend_from_slice(b"{\"format\":");
        out.extend_from_slice(self.format.to_string().as_bytes());
        out.extend_from_slice(b",\"file\":");
        let _ = serde_json::to_writer(&mut out, &self.file);
        out.extend_from_slice(b",\"manifest_crc\":");
        out.extend_from_slice(self.manifest_crc.to_string().as_bytes());
        out.extend_from_slice(b",\"instructions\":[");
        for (k, instruction) in self.instructions.iter().enumerate() {
            out.extend_from_slice(if k == 0 { b"\n" } else { b",\n" });
            let _ = serde_json::to_writer(&mut out, instruction);
        }
        out.extend_from_slice(b"\n]}\n");
        String::from_utf8(out).unwrap_or_default()
    }

    /// Parse `sourcemap.json`; refuses another format version.
    pub fn from_json(text: &str) -> Result<SourceMap, String> {
        let map: SourceMap =
            serde_json::from_str(text).map_err(|e| format!("not a source map: {e}"))?;
        if map.format != SOURCE_MAP_FORMAT {
            return Err(format!(
                "source map format {} (this tool reads {SOURCE_MAP_FORMAT})",
                map.format
            ));
        }
        Ok(SourceMap::sorted(
            map.file,
            map.manifest_crc,
            map.instructions,
        ))
    }

    /// The instruction at (unit page, network, step).
    pub fn at_position(&self, page: u8, network: u16, step: u16) -> Option<&MappedInstruction> {
        self.instructions
            .iter()
            .find(|i| i.page == page && i.network == network && i.step == step)
    }

    /// The instruction whose record holds byte `byte` of instruction page `page`.
    pub fn at_byte(&self, page: u8, byte: u32) -> Option<&MappedInstruction> {
        self.instructions
            .iter()
            .filter(|i| i.page == page && i.byte <= byte)
            .max_by_key(|i| i.byte)
    }

    /// `FILE:LINE` or `LINE`: the first instruction (lowest page, then byte) on that line
    /// or on the next line that has one. `Ok(None)` when the text is not of that form
    /// (e.g. `MAIN:2:0`); an error when it is but names another file or a line past the
    /// last instruction.
    pub fn resolve_line(&self, text: &str) -> Result<Option<LineMatch<'_>>, String> {
        let (file, line) = match text.rsplit_once(':') {
            // A file has a name with a `.` or a directory, or is this map's file; `MAIN:1`
            // is a position missing its step.
            Some((file, line))
                if !file.contains(':') && (file.contains(['.', '/', '\\']) || self.names(file)) =>
            {
                (Some(file), line)
            }
            Some(_) => return Ok(None),
            None => (None, text),
        };
        let Ok(asked) = line.parse::<u32>() else {
            return Ok(None);
        };
        if let Some(file) = file {
            if !self.names(file) {
                return Err(format!(
                    "{text}: the image was compiled from {}, not {file}",
                    self.file
                ));
            }
        }
        let instruction = self
            .instructions
            .iter()
            .filter(|i| i.line >= asked)
            .min_by_key(|i| (i.line, i.page, i.byte))
            .ok_or_else(|| {
                format!(
                    "{text}: no instruction on line {asked} or after it in {}",
                    self.file
                )
            })?;
        Ok(Some(LineMatch { asked, instruction }))
    }

    /// Whether `file` names this map's source: the same path, or the same last component.
    fn names(&self, file: &str) -> bool {
        let last = |p: &str| p.rsplit(['/', '\\']).next().unwrap_or(p).to_string();
        file == self.file || last(file) == last(&self.file)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn instruction(page: u8, byte: u32, network: u16, step: u16, line: u32) -> MappedInstruction {
        MappedInstruction {
            page,
            byte,
            network,
            step,
            line,
            column: 5,
            text: format!("LD I0.{step}"),
        }
    }

    fn manifest(plc_type: &str) -> Manifest {
        crate::Image {
            plc_type: plc_type.into(),
            pages: Default::default(),
        }
        .manifest()
    }

    fn map() -> SourceMap {
        SourceMap::new(
            "dir/main.lad",
            &manifest("CPU-EC20"),
            vec![
                instruction(0, 11, 1, 1, 5),
                instruction(0, 4, 1, 0, 4),
                instruction(0, 22, 2, 0, 8),
            ],
        )
    }

    #[test]
    fn sorted_and_round_trips() {
        let m = map();
        assert_eq!(
            m.instructions.iter().map(|i| i.byte).collect::<Vec<_>>(),
            [4, 11, 22]
        );
        assert_eq!(SourceMap::from_json(&m.to_json()), Ok(m.clone()));
        assert!(m.describes(&manifest("CPU-EC20")));
        assert!(!m.describes(&manifest("CPU-EC30")));
        let mut other = m.to_json().replace("\"format\":1", "\"format\":9");
        assert_ne!(other, m.to_json(), "the edit took");
        assert!(SourceMap::from_json(&other).is_err());
        other.clear();
        assert!(SourceMap::from_json(&other).is_err());
    }

    #[test]
    fn lookups() {
        let m = map();
        assert_eq!(m.at_position(0, 1, 1).map(|i| i.line), Some(5));
        assert_eq!(m.at_position(0, 3, 0), None);
        assert_eq!(m.at_byte(0, 12).map(|i| i.line), Some(5));
        assert_eq!(m.at_byte(0, 3), None);
        assert_eq!(m.at_byte(1, 12), None);
    }

    #[test]
    fn lines() {
        let m = map();
        let exact = m.resolve_line("main.lad:5").expect("ok").expect("a line");
        assert_eq!((exact.instruction.byte, exact.moved()), (11, false));
        let next = m.resolve_line("6").expect("ok").expect("a line");
        assert_eq!((next.instruction.line, next.moved()), (8, true));
        assert!(m.resolve_line("main.lad:9").is_err());
        assert!(m.resolve_line("other.lad:5").is_err());
        assert_eq!(m.resolve_line("MAIN:2:0"), Ok(None));
        assert_eq!(m.resolve_line("MAIN"), Ok(None));
        assert_eq!(m.resolve_line("MAIN:1"), Ok(None));
        assert!(m.resolve_line("dir/other.lad:1").is_err());
    }
}
