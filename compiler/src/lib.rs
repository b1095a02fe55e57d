//! The GUTTA compiler: .lad source to a checked program and the download image.
//! [`check_source`] reads as the front-end pipeline, [`compile`] as the whole one; a
//! program of several files and symbol tables ([`check_program`], [`compile_program`]) is
//! one joined text with a file table (`SourceFile::join`) through the same pipeline. The
//! library does no I/O: sources and targets come in as data; `gutta-cc` does the I/O.
//!
//! The stages, in order: `syntax` (text -> tree; a Micro/WIN export with its dialect's
//! line rules), the target (`PLC_TYPE` or the command line), `microwin::desugar` (only
//! for an export: interrupt blocks placed, template blocks dropped, S7-200 event
//! numbers translated, system symbols predefined; the checker gets what it must apply
//! as plain data, `check::Conventions`), `check` (names, operands, limits: the checked
//! program), `microwin::Desugared::after_check` (an export's timer and counter bits given
//! their instructions), then `lower` and `encode`. Only this file and `microwin/` know
//! whether a program is an export.

pub mod check;
pub mod diagnostics;
pub mod encode;
pub mod lower;
pub mod microwin;
pub mod source;
pub mod suggest;
pub mod syntax;

use std::sync::Arc;

use gutta_catalog::{choose_target, stdlib, OwnName, Target, TargetInputs, TargetSpec};

use crate::check::CheckOutput;
use crate::diagnostics::{Code, Diagnostic, Suggestion};
use crate::microwin::Desugared;
use crate::source::{LineIndex, PartKind, SourceFile};
use crate::syntax::ast::Program;

/// A target the caller chose (`gutta_catalog::choose_target`: the command line, a test
/// file or a project), loaded, with where it came from.
#[derive(Debug, Clone)]
pub struct ExplicitTarget {
    pub target: Arc<Target>,
    /// Where it came from, for the W0204 message: `gutta_catalog::TargetOrigin`'s
    /// wording (`--plc NAME`).
    pub origin: String,
}

/// Choices that change what a program compiles to, beyond its text and target.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct CompileOptions {
    /// In a Micro/WIN export, scale the constant presets of timers whose S7-200
    /// resolution differs from the target's, so that the program keeps its S7-200
    /// timing (`--scale-timer-presets`; docs/microwin.md, "Timer resolutions").
    pub scale_timer_presets: bool,
    /// In a Micro/WIN export, where SB0 of the S area goes (`--s-area MB96`, `[microwin]
    /// s_area`); None: the last 32 bytes of M (docs/microwin.md, "Sequence control
    /// relays").
    pub s_area: Option<microwin::SAreaBase>,
}

/// The result of checking one file or program: its text (joined, for several files),
/// tree, the target used, and every diagnostic (parse and check), sorted by position.
#[derive(Debug, Clone)]
pub struct CheckedFile {
    pub file: SourceFile,
    pub index: LineIndex,
    pub target: Arc<Target>,
    pub ast: Program,
    pub output: CheckOutput,
    /// Set for a Micro/WIN export: what the dialect's stage did to it (docs/microwin.md).
    pub microwin: Option<microwin::Export>,
}

impl CheckedFile {
    pub fn diagnostics(&self) -> &[Diagnostic] {
        &self.output.diagnostics
    }

    pub fn has_errors(&self) -> bool {
        self.output.diagnostics.iter().any(Diagnostic::is_error)
    }

    /// In a Micro/WIN export, where its S7-200 interrupt blocks went and the S7-200
    /// event numbers that compile to another GUTTA number, as one line for the compile
    /// summary and the listing (docs/microwin.md); None when there is nothing to show.
    pub fn microwin_summary(&self) -> Option<String> {
        self.microwin.as_ref()?.summary(&self.target)
    }

    /// In a Micro/WIN export, the dialect's notes one by one (the parts of
    /// [`CheckedFile::microwin_summary`]); empty otherwise.
    pub fn microwin_notes(&self) -> Vec<microwin::Note> {
        self.microwin
            .as_ref()
            .map_or_else(Vec::new, |e| e.notes(&self.target))
    }
}

/// Parse and check one source file. The target is the explicit one if given, else the
/// file's `PLC_TYPE`, else the stdlib default.
///
/// ```rust
/// use gutta_compiler::{check_source, source::SourceFile};
///
/// let text = "\
/// ORGANIZATION_BLOCK MAIN:OB1
/// BEGIN
/// NETWORK 1
/// LD     SM0.0
/// MOVB   MB0, IB0
/// END_ORGANIZATION_BLOCK
/// ";
/// let checked = check_source(SourceFile::new("main.lad", text), None);
/// assert_eq!(checked.target.plc.name, gutta_catalog::stdlib::DEFAULT);
/// let codes: Vec<&str> = checked.diagnostics().iter().map(|d| d.code.as_str()).collect();
/// assert_eq!(codes, ["E0308"]); // inputs are read-only for programs
/// ```
pub fn check_source(file: SourceFile, explicit: Option<&ExplicitTarget>) -> CheckedFile {
    check_source_with(file, explicit, CompileOptions::default())
}

/// [`check_source`] with [`CompileOptions`].
pub fn check_source_with(
    file: SourceFile,
    explicit: Option<&ExplicitTarget>,
    options: CompileOptions,
) -> CheckedFile {
    let microwin = microwin::is_export(&file);
    let mut parsed = parse(&file, microwin);
    let mut diagnostics = std::mem::take(&mut parsed.diagnostics);
    let target = resolve_target(&parsed.program, explicit, &mut diagnostics);
    let mut desugared = Desugared::default();
    if microwin {
        desugared = microwin::desugar(&mut parsed.program, &file, &target, &options);
    }
    diagnostics.append(&mut desugared.diagnostics);
    let mut output = check::check(&file.text, &parsed.program, &target, &desugared.conventions);
    diagnostics.append(&mut output.diagnostics);
    diagnostics.extend(desugared.after_check(&mut output, &file.text, &target, options));
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
        microwin: desugared.export,
    }
}

/// The sources of a text (one file, or several joined) parsed as one program, with the
/// dialect's line rules when it is a Micro/WIN export, then its symbol tables' rows
/// added to its symbols (after the SYMBOLS blocks', as they follow in the text) and its
/// data block exports (`DATA_BLOCK_TAB` files) to its data block exports.
fn parse(file: &SourceFile, microwin: bool) -> syntax::ParseOutput {
    let parts = file.parts();
    let ends: Vec<usize> = parts
        .iter()
        .filter(|p| p.kind == PartKind::Source)
        .map(|p| p.end)
        .collect();
    let mut parsed = if microwin {
        syntax::parse_microwin_files(&file.text, &ends)
    } else {
        syntax::parse_files(&file.text, &ends)
    };
    for part in &parts {
        match part.kind {
            PartKind::Source => {}
            PartKind::SymbolTable => {
                let (decls, mut diags) =
                    syntax::table::parse_table(&file.text, part.start, part.end);
                parsed.program.symbols.extend(decls);
                parsed.diagnostics.append(&mut diags);
            }
            PartKind::DataBlockTab => {
                let (block, mut diags) =
                    syntax::data_block_tab::parse_data_block_tab(&file.text, part.start, part.end);
                parsed.program.data_block_tabs.extend(block);
                parsed.diagnostics.append(&mut diags);
            }
        }
    }
    parsed
}

/// The program's target: the caller's explicit one (chosen by
/// `gutta_catalog::choose_target` from the command line, a test file or a project; W0204
/// when the program's `PLC_TYPE` names another), else the rule applied to the program's
/// own `PLC_TYPE` (an unknown name is reported with its did-you-mean, then the default).
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
    let chosen = choose_target(&TargetInputs {
        own: written.map(|(name, _)| OwnName::Source(name)),
        ..TargetInputs::default()
    });
    if let (TargetSpec::Stdlib(name), Some((_, span))) = (&chosen.spec, written) {
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
                let d = Diagnostic::new(
                    Code::BadPlcType,
                    *span,
                    format!("unknown PLC type `{name}`"),
                )
                .label("not a stdlib PLC type");
                diags.push(match hint {
                    Some(h) => d.suggest(Suggestion::new(*span, h)),
                    None => d.help(format!(
                        "known types: {}; or pass --target DIR",
                        names.join(", ")
                    )),
                });
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
            self.checked.symbols(),
        ))
    }
}

/// The whole pipeline: parse, check, lower, encode. Limit errors of the encoder join the
/// file's diagnostics; `image` is set only when there are no errors at all.
///
/// ```rust
/// use gutta_compiler::{compile, source::SourceFile};
///
/// let text = "\
/// ORGANIZATION_BLOCK MAIN:OB1
/// BEGIN
/// NETWORK 1
/// LD     SM0.0
/// MOVW   3585, MW24
/// END_ORGANIZATION_BLOCK
/// ";
/// // No PLC_TYPE line and no explicit target: the stdlib default (CPU-EC20).
/// let compiled = compile(SourceFile::new("main.lad", text), None);
/// assert!(!compiled.checked.has_errors(), "{:?}", compiled.checked.diagnostics());
/// let image = compiled.image.expect("a program without errors has an image");
/// assert_eq!(image.plc_type, "CPU-EC20");
/// assert!(!image.pages.is_empty());
/// ```
pub fn compile(file: SourceFile, explicit: Option<&ExplicitTarget>) -> Compiled {
    compile_with(file, explicit, CompileOptions::default())
}

/// [`compile`] with [`CompileOptions`].
pub fn compile_with(
    file: SourceFile,
    explicit: Option<&ExplicitTarget>,
    options: CompileOptions,
) -> Compiled {
    let mut checked = check_source_with(file, explicit, options);
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
    pub options: CompileOptions,
}

impl ProgramSources {
    /// One source file and no tables: what `gutta-cc FILE` compiles.
    pub fn single(file: SourceFile) -> ProgramSources {
        ProgramSources {
            sources: vec![file],
            symbol_tables: Vec::new(),
            options: CompileOptions::default(),
        }
    }
}

impl ProgramSources {
    /// The program as one text with a file table; one source alone stays as it is.
    pub fn join(self) -> SourceFile {
        SourceFile::join(self.sources, self.symbol_tables)
    }
}

/// Parse and check a whole program (see [`ProgramSources`]): its files are one program
/// (one namespace, MAIN once, one PLC type), each diagnostic in its own file.
pub fn check_program(
    mut program: ProgramSources,
    explicit: Option<&ExplicitTarget>,
) -> CheckedFile {
    let options = std::mem::take(&mut program.options);
    check_source_with(program.join(), explicit, options)
}

/// The whole pipeline on a whole program (see [`ProgramSources`]).
pub fn compile_program(mut program: ProgramSources, explicit: Option<&ExplicitTarget>) -> Compiled {
    let options = std::mem::take(&mut program.options);
    compile_with(program.join(), explicit, options)
}

impl CheckedFile {
    /// Every symbol the program declares (SYMBOLS blocks and symbol tables), for the
    /// tools (`gutta_format::SymbolTable`), with its declared type and `file:line`.
    /// Declarations whose address does not parse on the target are left out (the
    /// checker reports them), and so is a type that is not a known keyword.
    pub fn symbols(&self) -> gutta_format::SymbolTable {
        let text = &self.file.text;
        let slice = |s: source::Span| text.get(s.range()).unwrap_or("");
        let symbols = self
            .ast
            .symbols
            .iter()
            .filter_map(|d| {
                // A symbol of an S bit (`Step1 : S0.1`, in a Micro/WIN export) is at the
                // address its S operand went to.
                let s_address = || {
                    let export = self.microwin.as_ref()?;
                    let s = export.s_operands.iter().find(|s| s.0 == d.address)?;
                    Some(s.2)
                };
                let address = self
                    .target
                    .memory
                    .parse_address(slice(d.address).trim())
                    .ok()
                    .or_else(s_address)?;
                let at = self.file.locate(&self.index, d.name.start as usize);
                let data_type = d
                    .data_type
                    .and_then(|t| slice(t).parse::<gutta_catalog::DataType>().ok())
                    .map(|t| t.keyword().to_string());
                Some(gutta_format::Symbol {
                    name: slice(d.name).to_string(),
                    address: self.target.memory.format_address(&address),
                    data_type,
                    comment: d.comment_text(text).unwrap_or_default(),
                    origin: format!("{}:{}", at.file, at.line),
                })
            })
            .collect();
        gutta_format::SymbolTable::new(symbols)
    }
}
