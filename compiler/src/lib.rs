//! The GUTTA compiler: .lad source to a checked program and the download image.
//! [`check_source`] reads as the front-end pipeline, [`compile`] as the whole one. The library does
//! no I/O: sources and targets come in as data; the `gutta-cc` binary does the I/O.

pub mod analysis;
pub mod check;
pub mod diagnostics;
pub mod encode;
pub mod lower;
pub mod source;
pub mod syntax;

use std::sync::Arc;

use gutta_catalog::{stdlib, Target};

use crate::check::CheckOutput;
use crate::diagnostics::{Code, Diagnostic};
use crate::source::{LineIndex, SourceFile};
use crate::syntax::ast::Program;

/// Where the target comes from when the command line chose one.
#[derive(Debug, Clone)]
pub struct ExplicitTarget {
    pub target: Arc<Target>,
    /// `--plc NAME` or `--target DIR`, for the W0204 message.
    pub origin: String,
}

/// The result of checking one file: its text, tree, the target used, and every
/// diagnostic (parse and check), sorted by position.
#[derive(Debug, Clone)]
pub struct CheckedFile {
    pub file: SourceFile,
    pub index: LineIndex,
    pub target: Arc<Target>,
    pub ast: Program,
    pub output: CheckOutput,
}

impl CheckedFile {
    pub fn diagnostics(&self) -> &[Diagnostic] {
        &self.output.diagnostics
    }

    pub fn has_errors(&self) -> bool {
        self.output.diagnostics.iter().any(Diagnostic::is_error)
    }
}

/// Parse and check one source file. The target is the explicit one if given, else the
/// file's `PLC_TYPE`, else the stdlib default.
pub fn check_source(file: SourceFile, explicit: Option<&ExplicitTarget>) -> CheckedFile {
    let parsed = syntax::parse(&file.text);
    let mut diagnostics = parsed.diagnostics;
    let target = resolve_target(&parsed.program, explicit, &mut diagnostics);
    let mut output = check::check(&file.text, &parsed.program, &target);
    diagnostics.append(&mut output.diagnostics);
    diagnostics.sort_by_key(|d| (d.primary.span.start, d.primary.span.end));
    if diagnostics.iter().any(Diagnostic::is_error) {
        output.program = None;
    }
    output.diagnostics = diagnostics;
    let index = LineIndex::new(&file.text);
    CheckedFile {
        file,
        index,
        target,
        ast: parsed.program,
        output,
    }
}

fn resolve_target(
    ast: &Program,
    explicit: Option<&ExplicitTarget>,
    diags: &mut Vec<Diagnostic>,
) -> Arc<Target> {
    let written = ast.plc_type.as_ref();
    if let Some(e) = explicit {
        if let Some((name, span)) = written {
            if !name.eq_ignore_ascii_case(e.target.name()) {
                diags.push(
                    Diagnostic::new(
                        Code::PlcTypeOverridden,
                        *span,
                        format!(
                            "the file names {name}; {} selects {}",
                            e.origin,
                            e.target.name()
                        ),
                    )
                    .label("overridden by the command line"),
                );
            }
        }
        return e.target.clone();
    }
    if let Some((name, span)) = written {
        match stdlib::shared(name) {
            Ok(t) => return t,
            Err(_) => {
                let names: Vec<&str> = stdlib::names().collect();
                let hint = names
                    .iter()
                    .find(|n| {
                        n.replace('-', "")
                            .eq_ignore_ascii_case(&name.replace(['-', ' ', '(', ')', ','], ""))
                    })
                    .copied();
                diags.push(
                    Diagnostic::new(
                        Code::BadPlcType,
                        *span,
                        format!("unknown PLC type `{name}`"),
                    )
                    .label("not a stdlib PLC type")
                    .help(match hint {
                        Some(h) => format!("did you mean `{h}`?"),
                        None => format!("known types: {}; or pass --target DIR", names.join(", ")),
                    }),
                );
            }
        }
    }
    // The embedded default always loads (a test pins it); fall back to an empty
    // error only if the build itself is broken.
    stdlib::shared(stdlib::DEFAULT)
        .unwrap_or_else(|e| panic!("embedded default target is invalid: {e}"))
}

/// A checked file and, when it has no errors, its image.
#[derive(Debug, Clone)]
pub struct Compiled {
    pub checked: CheckedFile,
    pub image: Option<gutta_format::Image>,
    /// The lowered program (for listings and the source map), when the program checked.
    pub lowered: Option<lower::Lowered>,
}

impl Compiled {
    /// Where each instruction of `image` comes from; exactly when there is an image.
    /// Built on request (it costs about a sixth of `compile` on a large program, which
    /// the language server and `--check` never need).
    pub fn source_map(&self) -> Option<gutta_format::SourceMap> {
        let (image, lowered) = (self.image.as_ref()?, self.lowered.as_ref()?);
        Some(encode::source_map(
            lowered,
            image,
            &self.checked.file,
            &self.checked.index,
        ))
    }
}

/// The whole pipeline: parse, check, lower, encode. Limit errors of the encoder join the
/// file's diagnostics; `image` is set only when there are no errors at all.
pub fn compile(file: SourceFile, explicit: Option<&ExplicitTarget>) -> Compiled {
    let mut checked = check_source(file, explicit);
    let Some(program) = checked.output.program.take() else {
        return Compiled {
            checked,
            image: None,
            lowered: None,
        };
    };
    let lowered = lower::lower(&program, &checked.target);
    let main_span = program.units.first().map(|u| u.span).unwrap_or_default();
    let image = match encode::encode(&lowered, &checked.target, main_span) {
        Ok(image) => Some(image),
        Err(mut diags) => {
            checked.output.diagnostics.append(&mut diags);
            checked
                .output
                .diagnostics
                .sort_by_key(|d| (d.primary.span.start, d.primary.span.end));
            None
        }
    };
    if image.is_some() {
        checked.output.program = Some(program);
    }
    Compiled {
        checked,
        image,
        lowered: Some(lowered),
    }
}

/// The files of one program: its sources (several files are ONE program, e.g. one block
/// per file) and its symbol tables (CSV `Symbol,Address,Comment` or Micro/WIN's
/// tab-separated rows), whose symbols share one namespace with the `SYMBOLS` blocks.
#[derive(Debug, Clone, Default)]
pub struct ProgramSources {
    pub sources: Vec<SourceFile>,
    pub symbol_tables: Vec<SourceFile>,
}

impl ProgramSources {
    /// One source file and no tables: what `gutta-cc FILE` compiles.
    pub fn single(file: SourceFile) -> ProgramSources {
        ProgramSources {
            sources: vec![file],
            symbol_tables: Vec::new(),
        }
    }
}

/// Parse and check a whole program (see [`ProgramSources`]).
pub fn check_program(program: ProgramSources, explicit: Option<&ExplicitTarget>) -> CheckedFile {
    match <[SourceFile; 1]>::try_from(program.sources) {
        Ok([file]) if program.symbol_tables.is_empty() => check_source(file, explicit),
        _ => unimplemented!("several sources and symbol tables: issue 11's multi-file programs"),
    }
}

/// The whole pipeline on a whole program (see [`ProgramSources`]).
pub fn compile_program(program: ProgramSources, explicit: Option<&ExplicitTarget>) -> Compiled {
    match <[SourceFile; 1]>::try_from(program.sources) {
        Ok([file]) if program.symbol_tables.is_empty() => compile(file, explicit),
        _ => unimplemented!("several sources and symbol tables: issue 11's multi-file programs"),
    }
}

impl CheckedFile {
    /// Every symbol the program declares, for the tools (`gutta_format::SymbolTable`).
    /// Declarations whose address does not parse on the target are left out (the
    /// checker reports them).
    pub fn symbols(&self) -> gutta_format::SymbolTable {
        let text = &self.file.text;
        let slice = |s: source::Span| &text[s.start as usize..s.end as usize];
        let symbols = self
            .ast
            .symbols
            .iter()
            .filter_map(|d| {
                let address = self
                    .target
                    .memory
                    .parse_address(slice(d.address).trim())
                    .ok()?;
                let line = self.index.line_of(d.name.start as usize) + 1;
                Some(gutta_format::Symbol {
                    name: slice(d.name).to_string(),
                    address: self.target.memory.format_address(&address),
                    data_type: None,
                    comment: d
                        .comment
                        .map(|c| slice(c).trim().to_string())
                        .unwrap_or_default(),
                    origin: format!("{}:{line}", self.file.name),
                })
            })
            .collect();
        gutta_format::SymbolTable::new(symbols)
    }
}
