//! Encoding: lowered structures to page bytes (docs/image-format.md), with every
//! PlcType size limit checked and reported as a diagnostic that names the limit, the
//! size and the target. Takes only lowered output of a checked program.

use std::collections::BTreeMap;

use gutta_catalog::{plural, AreaKind, Target};
use gutta_format::{encode_data, encode_instructions, Image, PageId, PageKind, Record};

mod listing;
mod sourcemap;

pub use listing::listing;
pub use sourcemap::source_map;

use crate::diagnostics::{Code, Diagnostic};
use crate::lower::Lowered;
use crate::source::Span;

/// `12,345`.
pub fn thousands(n: usize) -> String {
    let s = n.to_string();
    let mut out = String::new();
    for (i, c) in s.chars().enumerate() {
        if i > 0 && (s.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// Encode, or say which limits the program exceeds.
pub fn encode(
    lowered: &Lowered,
    target: &Target,
    main_span: Span,
) -> Result<Image, Vec<Diagnostic>> {
    let plc = &target.plc;
    let mut diags = Vec::new();
    let mut pages = BTreeMap::new();

    let k_size = target
        .memory
        .area_of_kind(AreaKind::Constant)
        .map(|a| a.size)
        .unwrap_or(0);
    let const_limit = plc.program_block_const_binary_size.min(k_size) as usize;
    if lowered.consts.bytes.len() > const_limit {
        diags.push(
            Diagnostic::new(
                Code::ConstPageTooLarge,
                main_span,
                format!(
                    "constants need {} bytes; {} allows {} (ProgramBlockConstBinarySize, K)",
                    thousands(lowered.consts.bytes.len()),
                    plc.name,
                    thousands(const_limit)
                ),
            )
            .label("in this program"),
        );
    }
    pages.insert(
        PageId::new(PageKind::Const, 0),
        lowered.consts.bytes.clone(),
    );

    let mut instruction_total = 0usize;
    for u in &lowered.units {
        let Ok(page) = u8::try_from(u.page) else {
            continue;
        };
        let records: Vec<Record> = u.records.iter().map(|(r, _)| r.clone()).collect();
        let bytes = encode_instructions(&records);
        instruction_total += bytes.len();
        pages.insert(PageId::new(PageKind::Argument, page), u.arguments.encode());
        pages.insert(PageId::new(PageKind::Instruction, page), bytes);
    }
    let limit = plc.program_block_instruction_binary_size as usize;
    if instruction_total > limit {
        // Point at the instruction where the pages overflow.
        let mut running = 0usize;
        let mut at = main_span;
        'outer: for u in &lowered.units {
            for (r, span) in &u.records {
                running += r.len();
                if running > limit {
                    at = *span;
                    break 'outer;
                }
            }
        }
        diags.push(
            Diagnostic::new(
                Code::InstructionsTooLarge,
                at,
                format!(
                    "instruction pages {} bytes, {} allows {} (ProgramBlockInstructionBinarySize)",
                    thousands(instruction_total),
                    plc.name,
                    thousands(limit)
                ),
            )
            .label("the program passes the limit here"),
        );
    }

    for d in &lowered.data {
        let Ok(n) = u8::try_from(d.number) else {
            continue;
        };
        pages.insert(PageId::new(PageKind::Data, n), encode_data(&d.items));
    }

    if let Some(system) = &lowered.system {
        let bytes = system.encode();
        let limit = plc.system_block_binary_size as usize;
        if bytes.len() > limit {
            diags.push(Diagnostic::new(
                Code::SystemPageTooLarge,
                main_span,
                format!(
                    "the system page needs {} bytes; {} allows {} (SystemBlockBinarySize)",
                    bytes.len(),
                    plc.name,
                    limit
                ),
            ));
        }
        pages.insert(PageId::new(PageKind::System, 0), bytes);
    }

    if !diags.is_empty() {
        return Err(diags);
    }
    Ok(Image {
        plc_type: plc.name.clone(),
        pages,
    })
}

/// One line per page kind against the target's limits:
/// `instructions 1,204 / 10,752 bytes; const 18 / 128; ...`.
pub fn summary(image: &Image, target: &Target) -> String {
    let plc = &target.plc;
    let k_size = target
        .memory
        .area_of_kind(AreaKind::Constant)
        .map(|a| a.size)
        .unwrap_or(0);
    let count = |k: PageKind| image.pages.keys().filter(|id| id.kind == k).count();
    let arguments = image.total(PageKind::Argument);
    let mut parts = vec![
        format!(
            "instructions {} / {} bytes in {}",
            thousands(image.total(PageKind::Instruction)),
            thousands(plc.program_block_instruction_binary_size as usize),
            plural::count(count(PageKind::Instruction), "block"),
        ),
        format!(
            "const {} / {}",
            thousands(image.total(PageKind::Const)),
            thousands(plc.program_block_const_binary_size.min(k_size) as usize)
        ),
        format!(
            "arguments {} {}",
            thousands(arguments),
            plural::noun_for(arguments as u64, "byte")
        ),
    ];
    let data_pages = count(PageKind::Data);
    if data_pages > 0 {
        let items = image.total(PageKind::Data) / 8;
        parts.push(format!(
            "data {} / {}, {}",
            plural::count(data_pages, "page"),
            plc.data_block_page_size,
            plural::count(items, "item"),
        ));
    }
    if count(PageKind::System) > 0 {
        parts.push(format!(
            "system {} / {}",
            image.total(PageKind::System),
            plc.system_block_binary_size
        ));
    }
    parts.join("; ")
}

#[cfg(test)]
mod tests {
    #[test]
    fn thousands_separators() {
        assert_eq!(super::thousands(10752), "10,752");
        assert_eq!(super::thousands(18), "18");
        assert_eq!(super::thousands(1_000_000), "1,000,000");
    }
}
