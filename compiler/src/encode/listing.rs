//! `--emit listing`: every source line that produced bytes, with the page, offset and
//! bytes, in source order (a `; file NAME` line where the next file of a program in
//! several files starts), plus the const page. For reading what the encoder did.

use gutta_format::Record;

use crate::lower::Lowered;
use crate::source::{LineIndex, SourceFile, Span};

struct Entry {
    span: Span,
    page: String,
    offset: usize,
    bytes: Vec<u8>,
}

fn hex(bytes: &[u8]) -> String {
    bytes
        .iter()
        .map(|b| format!("{b:02X}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// The listing text.
pub fn listing(lowered: &Lowered, file: &SourceFile, index: &LineIndex, plc_type: &str) -> String {
    let mut entries = Vec::new();
    for u in &lowered.units {
        let page = format!("I{:02X}", u.page);
        entries.push(Entry {
            span: u.span,
            page: format!("A{:02X}", u.page),
            offset: 0,
            bytes: u.arguments.encode(),
        });
        let mut offset = 0;
        for (record, span) in &u.records {
            let mut bytes = Vec::with_capacity(record.len());
            record.encode_into(&mut bytes);
            let span = match record {
                Record::Network(_) => *span,
                Record::Instruction { .. } => *span,
            };
            entries.push(Entry {
                span,
                page: page.clone(),
                offset,
                bytes,
            });
            offset += record.len();
        }
    }
    for d in &lowered.data {
        for (i, (item, span)) in d.items.iter().zip(&d.spans).enumerate() {
            let mut bytes = item.operand.to_le_bytes().to_vec();
            bytes.extend(item.value.to_le_bytes());
            entries.push(Entry {
                span: *span,
                page: format!("D{:X}", d.number),
                offset: 8 * i,
                bytes,
            });
        }
    }
    if let (Some(system), Some(span)) = (&lowered.system, lowered.system_span) {
        entries.push(Entry {
            span,
            page: "S0".into(),
            offset: 0,
            bytes: system.encode(),
        });
    }
    entries.sort_by_key(|e| (e.span.start, e.page.clone(), e.offset));
    let names: Vec<String> = file.parts().into_iter().map(|p| p.name).collect();
    let mut out = format!(
        "; listing of {} for {plc_type}\n; page offset  bytes{}line  source\n",
        names.join(", "),
        " ".repeat(32)
    );
    out.push_str(&format!(
        "; K    0000    {}\n",
        if lowered.consts.bytes.is_empty() {
            "(no constants)".to_string()
        } else {
            hex(&lowered.consts.bytes)
        }
    ));
    let mut current_file = None;
    for e in entries {
        let lc = index.line_col(&file.text, e.span.start as usize);
        let line_start = index.line_start(lc.line as usize - 1);
        if file.is_joined() {
            let part = file.part_index(e.span.start as usize);
            if current_file != Some(part) {
                current_file = Some(part);
                out.push_str(&format!("; file {}\n", names[part]));
            }
        }
        let lc = file.locate(index, e.span.start as usize);
        let source = file.text[line_start..]
            .lines()
            .next()
            .unwrap_or("")
            .trim_end();
        let chunks: Vec<&[u8]> = e.bytes.chunks(12).collect();
        for (i, chunk) in chunks.iter().enumerate() {
            if i == 0 {
                out.push_str(&format!(
                    "  {:<4} {:04X}    {:<36} {:>5}  {}\n",
                    e.page,
                    e.offset,
                    hex(chunk),
                    lc.line,
                    source
                ));
            } else {
                out.push_str(&format!(
                    "  {:<4} {:04X}    {}\n",
                    "",
                    e.offset + 12 * i,
                    hex(chunk)
                ));
            }
        }
    }
    out
}
