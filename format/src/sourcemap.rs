//! The source map: each instruction of an image, by (unit page, network, step) and by
//! (page, byte offset), to where it is written (file, line, column) and its source text,
//! and the program's symbols. The compiler writes it beside the image directory
//! (docs/image-format.md, "The source map"); it is never downloaded. No I/O here, and
//! nothing about the image's bytes.

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::{crc16, Manifest, Symbol, SymbolTable};

/// The `format` field of `sourcemap.json` (2: several files, `files`, `symbols`).
pub const SOURCE_MAP_FORMAT: u32 = 2;

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
    /// Index into [`SourceMap::files`] of the file the instruction is written in; the
    /// JSON leaves out 0 (the first file).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub file: u16,
    /// 1-based source line and column in that file.
    pub line: u32,
    pub column: u32,
    /// The instruction as written (`MOVW  VW100, VW200`).
    pub text: String,
}

fn is_zero(n: &u16) -> bool {
    *n == 0
}

/// The whole map of one compiled program. Instructions are sorted by (page, byte),
/// so equal programs give byte-identical JSON.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct SourceMap {
    pub format: u32,
    /// The (first) source file's name as given to the compiler (`main.lad`).
    pub file: String,
    /// Every source file of the program, in the order given; `files[0]` is `file`.
    #[serde(default)]
    pub files: Vec<String>,
    /// `crc16` of the image's manifest.json: a map is only used with the image it
    /// was written for (`describes`).
    pub manifest_crc: u16,
    /// The program's symbols (SYMBOLS blocks and symbol tables), a JSON list.
    #[serde(
        default,
        serialize_with = "symbols_as_list",
        deserialize_with = "symbols_from_list"
    )]
    pub symbols: SymbolTable,
    pub instructions: Vec<MappedInstruction>,
}

fn symbols_as_list<S: Serializer>(table: &SymbolTable, s: S) -> Result<S::Ok, S::Error> {
    table.symbols.serialize(s)
}

fn symbols_from_list<'de, D: Deserializer<'de>>(d: D) -> Result<SymbolTable, D::Error> {
    Vec::<Symbol>::deserialize(d).map(SymbolTable::new)
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
    /// A map of one file `file` without symbols; the instructions are sorted here.
    pub fn new(
        file: impl Into<String>,
        manifest: &Manifest,
        instructions: Vec<MappedInstruction>,
    ) -> SourceMap {
        let file = file.into();
        SourceMap::sorted(SourceMap {
            format: SOURCE_MAP_FORMAT,
            files: vec![file.clone()],
            file,
            manifest_crc: crc16(manifest.to_json().as_bytes()),
            symbols: SymbolTable::default(),
            instructions,
        })
    }

    /// The same map for a program of several files: `files[0]` becomes `file`, and each
    /// instruction's `file` indexes `files`.
    pub fn with_files(mut self, files: Vec<String>) -> SourceMap {
        if let Some(first) = files.first() {
            self.file = first.clone();
            self.files = files;
        }
        self
    }

    /// The same map carrying the program's symbols.
    pub fn with_symbols(mut self, symbols: SymbolTable) -> SourceMap {
        self.symbols = symbols;
        self
    }

    fn sorted(mut map: SourceMap) -> SourceMap {
        map.instructions.sort();
        if map.files.is_empty() {
            map.files.push(map.file.clone());
        }
        map
    }

    /// The name of the file `instruction` is written in.
    pub fn file_of(&self, instruction: &MappedInstruction) -> &str {
        self.files
            .get(usize::from(instruction.file))
            .unwrap_or(&self.file)
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
        out.extend_from_slice(b",\"files\":");
        let _ = serde_json::to_writer(&mut out, &self.files);
        out.extend_from_slice(b",\"manifest_crc\":");
        out.extend_from_slice(self.manifest_crc.to_string().as_bytes());
        out.extend_from_slice(b",\"symbols\":[");
        for (k, symbol) in self.symbols.symbols.iter().enumerate() {
            out.extend_from_slice(if k == 0 { b"\n" } else { b",\n" });
            let _ = serde_json::to_writer(&mut out, symbol);
        }
        out.extend_from_slice(b"],\"instructions\":[");
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
        Ok(SourceMap::sorted(map))
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
    /// of that file or on the next line that has one. `Ok(None)` when the text is not of
    /// that form (e.g. `MAIN:2:0`); an error when it is but names no file of the program,
    /// a line past the file's last instruction, or a bare `LINE` when the program has
    /// several files.
    pub fn resolve_line(&self, text: &str) -> Result<Option<LineMatch<'_>>, String> {
        let (file, line) = match text.rsplit_once(':') {
            // A file has a name with a `.` or a directory, or is one of this map's files;
            // `MAIN:1` is a position missing its step.
            Some((file, line))
                if !file.contains(':')
                    && (file.contains(['.', '/', '\\']) || self.file_index(file).is_ok()) =>
            {
                (Some(file), line)
            }
            Some(_) => return Ok(None),
            None => (None, text),
        };
        let Ok(asked) = line.parse::<u32>() else {
            return Ok(None);
        };
        let index = match file {
            Some(file) => self
                .file_index(file)
                .map_err(|why| format!("{text}: {why}"))?,
            None if self.files.len() > 1 => {
                return Err(format!(
                    "{text}: the program has several files ({}); write FILE:LINE, e.g. {}:{asked}",
                    self.files.join(", "),
                    self.files[0]
                ))
            }
            None => 0,
        };
        let name = self.files.get(index).unwrap_or(&self.file);
        let instruction = self
            .instructions
            .iter()
            .filter(|i| usize::from(i.file) == index && i.line >= asked)
            .min_by_key(|i| (i.line, i.page, i.byte))
            .ok_or_else(|| {
                format!("{text}: no instruction on line {asked} or after it in {name}")
            })?;
        Ok(Some(LineMatch { asked, instruction }))
    }

    /// The index in `files` of the file `file` names: the same path, else the only file
    /// with the same last component.
    fn file_index(&self, file: &str) -> Result<usize, String> {
        if let Some(i) = self.files.iter().position(|f| f == file) {
            return Ok(i);
        }
        let last = |p: &str| p.rsplit(['/', '\\']).next().unwrap_or(p).to_string();
        let same: Vec<usize> = (0..self.files.len())
            .filter(|&i| last(&self.files[i]) == last(file))
            .collect();
        match same[..] {
            [i] => Ok(i),
            [] => Err(format!(
                "the image was compiled from {}, not {file}",
                self.files.join(", ")
            )),
            _ => Err(format!(
                "{file} may be any of {}; write the path as compiled",
                same.iter()
                    .map(|&i| self.files[i].as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            )),
        }
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
            file: 0,
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
        let mut other = m.to_json().replace("\"format\":2", "\"format\":9");
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

    fn two_files() -> SourceMap {
        let mut second = instruction(8, 4, 1, 0, 3);
        second.file = 1;
        SourceMap::new(
            "a.lad",
            &manifest("CPU-EC20"),
            vec![instruction(0, 4, 1, 0, 3), second],
        )
        .with_files(vec!["dir/a.lad".into(), "b.lad".into()])
        .with_symbols(SymbolTable::new(vec![Symbol {
            name: "Temp".into(),
            address: "MD8".into(),
            data_type: Some("REAL".into()),
            comment: "tank".into(),
            origin: "s.csv:2".into(),
        }]))
    }

    #[test]
    fn several_files_and_symbols() {
        let m = two_files();
        let json = m.to_json();
        assert!(json.starts_with(
            "{\"format\":2,\"file\":\"dir/a.lad\",\"files\":[\"dir/a.lad\",\"b.lad\"],"
        ));
        assert_eq!(json.matches("\"file\":1").count(), 1, "{json}");
        assert_eq!(SourceMap::from_json(&json), Ok(m.clone()));
        assert_eq!(m.symbols.get("TEMP").map(|s| &*s.address), Some("MD8"));
        let b = m.resolve_line("b.lad:2").expect("ok").expect("a line");
        assert_eq!((b.instruction.page, m.file_of(b.instruction)), (8, "b.lad"));
        let a = m.resolve_line("a.lad:3").expect("ok").expect("a line");
        assert_eq!(
            (a.instruction.page, m.file_of(a.instruction)),
            (0, "dir/a.lad")
        );
        let bare = m.resolve_line("3").expect_err("ambiguous");
        assert!(bare.contains("dir/a.lad, b.lad"), "{bare}");
        assert!(m
            .resolve_line("c.lad:3")
            .is_err_and(|e| e.contains("dir/a.lad, b.lad")));
        assert!(m
            .resolve_line("b.lad:4")
            .is_err_and(|e| e.contains("in b.lad")));
    }
}
