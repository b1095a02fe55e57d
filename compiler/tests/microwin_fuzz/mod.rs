//! One input of the `microwin_front_end` fuzz target (fuzz/fuzz_targets/), shared with
//! its replay in `fuzz_regressions.rs` so that both do exactly the same: bytes decoded
//! as `gutta-cc` decodes a Micro/WIN export (`decode_code_page`: UTF-8, else GBK, else
//! Windows-1252), compiled in the dialect on CPU-EC20. An input whose first byte is odd
//! is a program exported one block per file: the rest split at NUL bytes into
//! `MAIN.awl`, `SBR_0.awl`, `INT_0.awl`, symbol tables (`symbols.csv`, then
//! `symbols.txt`) and a sixth part `DB1.txt`, a source like the first three (a data block
//! export when it starts with `DATA_BLOCK_TAB`, as any source does), each decoded on its
//! own. Panics are the findings; this also asserts
//! that every span lies inside the text on char boundaries and that the diagnostics
//! render. No I/O: the bytes come in as data.

use std::sync::{Arc, OnceLock};

use gutta_catalog::{stdlib, Target};
use gutta_compiler::diagnostics::json::to_json_lines;
use gutta_compiler::diagnostics::render::{render, RenderStyle};
use gutta_compiler::source::{SourceFile, Span};
use gutta_compiler::{compile_program, Compiled, ExplicitTarget, ProgramSources};

/// The names the parts of a split input get, in order: sources, then tables.
const SOURCES: [&str; 3] = ["MAIN.awl", "SBR_0.awl", "INT_0.awl"];
const TABLES: [&str; 2] = ["symbols.csv", "symbols.txt"];
/// The part after the tables: a source under Micro/WIN's name of a data block export.
const DATA_BLOCK: &str = "DB1.txt";

/// CPU-EC20, loaded once (loading it per input would dominate the run).
pub fn cpu_ec20() -> &'static ExplicitTarget {
    static TARGET: OnceLock<ExplicitTarget> = OnceLock::new();
    TARGET.get_or_init(|| {
        let target: Arc<Target> = stdlib::shared("CPU-EC20").expect("CPU-EC20 loads");
        ExplicitTarget {
            target,
            origin: "the fuzzer".to_string(),
        }
    })
}

/// The program an input stands for (see the module comment).
pub fn sources(data: &[u8]) -> ProgramSources {
    let decode =
        |name: &str, bytes: &[u8]| SourceFile::from_code_page_bytes(name, bytes.to_vec()).0;
    let Some((&mode, rest)) = data.split_first() else {
        return ProgramSources::single(decode(SOURCES[0], data));
    };
    if mode % 2 == 0 {
        return ProgramSources::single(decode(SOURCES[0], rest));
    }
    let mut program = ProgramSources::default();
    for (i, part) in rest
        .split(|&b| b == 0)
        .take(SOURCES.len() + TABLES.len() + 1)
        .enumerate()
    {
        match (SOURCES.get(i), TABLES.get(i - i.min(SOURCES.len()))) {
            (Some(name), _) => program.sources.push(decode(name, part)),
            (None, Some(name)) => program.symbol_tables.push(decode(name, part)),
            (None, None) => program.sources.push(decode(DATA_BLOCK, part)),
        }
    }
    program
}

fn assert_span(text: &str, span: Span, what: &str) {
    let (start, end) = (span.start as usize, span.end as usize);
    assert!(
        start <= end && end <= text.len(),
        "{what} span {start}..{end} outside text of {} bytes",
        text.len()
    );
    assert!(
        text.is_char_boundary(start) && text.is_char_boundary(end),
        "{what} span {start}..{end} not on char boundaries"
    );
}

/// Compile one input as the fuzz target does, with its checks; panics where it would.
pub fn run(data: &[u8]) -> Compiled {
    let compiled = compile_program(sources(data), Some(cpu_ec20()));
    let checked = &compiled.checked;
    let text = checked.file.text.as_str();
    for d in checked.diagnostics() {
        assert_span(text, d.primary.span, "primary");
        for s in &d.secondary {
            assert_span(text, s.span, "secondary");
        }
    }
    for def in &checked.output.definitions {
        assert_span(text, def.span, "definition");
    }
    for r in &checked.output.references {
        assert_span(text, r.span, "reference");
    }
    let rendered = render(&checked.file, checked.diagnostics(), RenderStyle::PLAIN);
    assert_eq!(checked.diagnostics().is_empty(), rendered.is_empty());
    let json = to_json_lines(&checked.file, &checked.index, checked.diagnostics());
    assert_eq!(json.lines().count(), checked.diagnostics().len());
    assert_eq!(compiled.image.is_some(), !checked.has_errors());
    let _ = checked.microwin_summary();
    compiled
}
