//! `manifest.json`: the image's PLC type and every page's length and CRC-16/MODBUS,
//! written in one fixed layout (byte-identical for the same image) and read back with
//! coded errors. It holds nothing the PLC does not hold (no tool, no source path), so
//! an uploaded image writes the same manifest as the one downloaded.

use std::fmt;

use serde::Deserialize;

use crate::PageKind;

pub const FORMAT_VERSION: u32 = 1;

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ManifestPage {
    pub kind: PageKind,
    pub number: u8,
    pub file: String,
    pub length: u32,
    pub crc: u16,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Manifest {
    pub format: u32,
    pub plc_type: String,
    pub pages: Vec<ManifestPage>,
}

/// Why a manifest does not read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ManifestError(pub String);

impl fmt::Display for ManifestError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ManifestError {}

/// The manifest as JSON. Unknown keys are ignored (no `deny_unknown_fields`), so
/// manifests of earlier versions, which also held `tool` and `source`, still read.
#[derive(Deserialize)]
struct RawManifest {
    format: u32,
    plc_type: String,
    pages: Vec<RawPage>,
}

#[derive(Deserialize)]
struct RawPage {
    kind: String,
    number: u32,
    file: String,
    length: u32,
    crc: String,
}

fn json_string(s: &str) -> String {
    serde_json::to_string(s).unwrap_or_else(|_| "\"\"".to_string())
}

impl Manifest {
    /// The fixed JSON layout of docs/image-format.md.
    pub fn to_json(&self) -> String {
        let mut out = String::from("{\n");
        out.push_str(&format!("  \"format\": {},\n", self.format));
        out.push_str(&format!(
            "  \"plc_type\": {},\n",
            json_string(&self.plc_type)
        ));
        out.push_str("  \"pages\": [\n");
        for (i, p) in self.pages.iter().enumerate() {
            out.push_str(&format!(
                "    {{ \"kind\": \"{}\", \"number\": {}, \"file\": {}, \"length\": {}, \"crc\": \"0x{:04X}\" }}{}\n",
                p.kind.keyword(),
                p.number,
                json_string(&p.file),
                p.length,
                p.crc,
                if i + 1 < self.pages.len() { "," } else { "" }
            ));
        }
        out.push_str("  ]\n}\n");
        out
    }

    pub fn parse(text: &str) -> Result<Manifest, ManifestError> {
        let raw: RawManifest =
            serde_json::from_str(text).map_err(|e| ManifestError(format!("manifest.json: {e}")))?;
        if raw.format != FORMAT_VERSION {
            return Err(ManifestError(format!(
                "manifest.json: format {} is not {FORMAT_VERSION}",
                raw.format
            )));
        }
        let mut pages = Vec::with_capacity(raw.pages.len());
        for p in raw.pages {
            let kind = PageKind::from_keyword(&p.kind).ok_or_else(|| {
                ManifestError(format!("manifest.json: unknown page kind `{}`", p.kind))
            })?;
            if p.number > kind.max_number() as u32 {
                return Err(ManifestError(format!(
                    "manifest.json: {} page number {} is out of range",
                    p.kind, p.number
                )));
            }
            let crc = p
                .crc
                .strip_prefix("0x")
                .and_then(|h| u16::from_str_radix(h, 16).ok())
                .ok_or_else(|| {
                    ManifestError(format!(
                        "manifest.json: crc `{}` is not 0x and 4 hex digits",
                        p.crc
                    ))
                })?;
            pages.push(ManifestPage {
                kind,
                number: p.number as u8,
                file: p.file,
                length: p.length,
                crc,
            });
        }
        Ok(Manifest {
            format: raw.format,
            plc_type: raw.plc_type,
            pages,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn manifest_round_trips() {
        let m = Manifest {
            format: 1,
            plc_type: "CPU-EC20 \"b\"".into(),
            pages: vec![ManifestPage {
                kind: PageKind::Const,
                number: 0,
                file: "const.bin".into(),
                length: 3,
                crc: 0xABCD,
            }],
        };
        assert_eq!(Manifest::parse(&m.to_json()), Ok(m));
        assert!(Manifest::parse("{}").is_err());
    }

    #[test]
    fn manifests_of_earlier_versions_with_tool_and_source_still_read() {
        let old = r#"{
  "format": 1,
  "plc_type": "CPU-EC20",
  "tool": "gutta-cc 0.1.0",
  "source": "examples/blink.lad",
  "pages": [
    { "kind": "const", "number": 0, "file": "const.bin", "length": 18, "crc": "0x1F2E" }
  ]
}
"#;
        let m = Manifest::parse(old).expect("an old-style manifest reads");
        assert_eq!(
            m,
            Manifest {
                format: 1,
                plc_type: "CPU-EC20".into(),
                pages: vec![ManifestPage {
                    kind: PageKind::Const,
                    number: 0,
                    file: "const.bin".into(),
                    length: 18,
                    crc: 0x1F2E,
                }],
            }
        );
        // Written again, it holds only what the PLC holds.
        assert!(!m.to_json().contains("tool"));
        assert!(!m.to_json().contains("source"));
    }
}
