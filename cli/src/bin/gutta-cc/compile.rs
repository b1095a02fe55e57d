//! Checking and compiling: `gutta-cc FILE... [--check | -o DIR] [--emit listing]` and
//! `gutta-cc build` (project.rs says which files a project compiles). It reads the
//! program, checks or compiles it on the target `--plc`/`--target` (or the project, or
//! the program's PLC_TYPE) choose, writes the image with its source map, and prints the
//! diagnostics and one summary line. The pipeline itself is gutta_compiler's.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use gutta_cli::fatal::{Fatal, MessageFormat};
use gutta_cli::notes::{self, JsonTo};
use gutta_cli::plural::count;
use gutta_cli::sources::read_program_in;
use gutta_cli::target::TargetArgs;
use gutta_compiler::diagnostics::json;
use gutta_compiler::diagnostics::render::{render, RenderStyle};
use gutta_compiler::encode::{listing, summary};
use gutta_compiler::{check_program, compile_program, CheckedFile, Compiled};

use crate::args::{Cli, Emit};

/// What to check or compile. The paths are relative to `base` (a project's folder, or
/// the current directory when empty) and named as given in diagnostics, the summary and
/// the source map.
pub(crate) struct Job<'a> {
    pub base: &'a Path,
    pub files: &'a [PathBuf],
    pub tables: &'a [PathBuf],
    /// The image directory to write; none: check only.
    pub output: Option<&'a Path>,
    pub emit: Option<Emit>,
    pub scale_timer_presets: bool,
    /// `--s-area`, or the project's `[microwin] s_area`.
    pub s_area: Option<gutta_compiler::microwin::SAreaBase>,
    pub target: &'a TargetArgs,
}

/// `gutta-cc FILE...`: the files on the command line, with its --symbols tables.
pub(crate) fn files(cli: &Cli) -> Result<ExitCode, Fatal> {
    let _ = cli.check; // Without -o, checking is all there is to do.
    compile(
        cli,
        &Job {
            base: Path::new(""),
            files: &cli.files,
            tables: &cli.symbols,
            output: cli.output.as_deref(),
            emit: cli.emit,
            scale_timer_presets: cli.scale_timer_presets,
            s_area: cli.s_area.clone(),
            target: &cli.target,
        },
    )
}

/// Check or compile `job`, write its image, print the diagnostics and the summary
/// (`--message-format` and `--color` from `cli`). Exit 1 when the program has errors.
pub(crate) fn compile(cli: &Cli, job: &Job) -> Result<ExitCode, Fatal> {
    if job.files.is_empty() {
        return Err(Fatal::usage("no input files").with_hint(
            "try `gutta-cc main.lad -o image/`, `gutta-cc --check main.lad`, or --help",
        ));
    }
    let compiling = job.output.is_some() || job.emit.is_some();
    let mut notes = Vec::new();
    let mut program = read_program_in(job.base, job.files, job.tables, &mut notes)?;
    notes::print(&notes, cli.message_format, JsonTo::Stdout);
    program.options.scale_timer_presets = job.scale_timer_presets;
    program.options.s_area = job.s_area.clone();
    let name = match program.sources.len() {
        1 => program.sources[0].name.clone(),
        n => count(n, "file"),
    };
    let explicit = job.target.explicit()?;
    let (checked, image) = if compiling {
        let compiled = compile_program(program, explicit.as_ref());
        if job.emit == Some(Emit::Listing) {
            print_listing(&compiled);
        }
        let map = compiled.source_map();
        (compiled.checked, compiled.image.zip(map))
    } else {
        (check_program(program, explicit.as_ref()), None)
    };
    let written = match (&image, job.output) {
        (Some((image, map)), Some(dir)) => {
            gutta_io::write_image_with_map(&job.base.join(dir), image, map)
                .map_err(|e| Fatal::io(e.0))?;
            Some((image, dir))
        }
        _ => None,
    };
    match cli.message_format {
        MessageFormat::Json => {
            let text = json::to_json_lines(&checked.file, &checked.index, checked.diagnostics());
            let _ = std::io::stdout().lock().write_all(text.as_bytes());
            // The summary line's notes (an export's interrupts, events, ...), one object
            // each; the human summary below says them in one line.
            let summary = notes::program_notes(&checked);
            notes::print(&summary, MessageFormat::Json, JsonTo::Stdout);
        }
        MessageFormat::Human => {
            let color = gutta_cli::color::use_color(cli.color, std::io::stderr().is_terminal());
            let style = RenderStyle {
                color,
                unicode: color,
            };
            eprint!("{}", render(&checked.file, checked.diagnostics(), style));
            print_summary(&name, &checked, written);
        }
    }
    Ok(if checked.has_errors() {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

/// `--emit listing`: every source line with its page, offset and bytes, on stdout, when
/// the program compiled.
fn print_listing(compiled: &Compiled) {
    let (Some(lowered), Some(_)) = (&compiled.lowered, &compiled.image) else {
        return;
    };
    let checked = &compiled.checked;
    let mut text = listing(
        lowered,
        &checked.file,
        &checked.index,
        checked.target.name(),
    );
    if let Some(line) = checked.microwin_summary() {
        text = format!("// {line}\n{text}");
    }
    let _ = std::io::stdout().lock().write_all(text.as_bytes());
}

/// The human summary on stderr: the counts of errors, or what was written, or what the
/// check found (and the Micro/WIN line of an export).
fn print_summary(
    name: &str,
    checked: &CheckedFile,
    written: Option<(&gutta_format::Image, &Path)>,
) {
    let errors = checked
        .diagnostics()
        .iter()
        .filter(|d| d.is_error())
        .count();
    let warnings = checked.diagnostics().len() - errors;
    if errors > 0 {
        eprintln!(
            "{name}: {}, {}",
            count(errors, "error"),
            count(warnings, "warning")
        );
        return;
    }
    if let Some((image, dir)) = written {
        eprintln!(
            "{name}: wrote {} for {}: {}",
            dir.display(),
            image.plc_type,
            summary(image, &checked.target)
        );
    } else if let Some(p) = &checked.output.program {
        let instructions: usize = p
            .units
            .iter()
            .flat_map(|u| &u.networks)
            .map(|n| n.instructions.len())
            .sum();
        eprintln!(
            "{name}: ok on {} ({}, {}, {}{})",
            p.target_name,
            count(p.units.len(), "block"),
            count(instructions, "instruction"),
            count(p.data_blocks.len(), "data block"),
            if warnings > 0 {
                format!(", {}", count(warnings, "warning"))
            } else {
                String::new()
            }
        );
    } else {
        return;
    }
    if let Some(line) = checked.microwin_summary() {
        eprintln!("{name}: {line}");
    }
}

/// `--s-area`, else the project's `[microwin] s_area`.
pub(crate) fn s_area(
    cli: &Cli,
    project: &gutta_io::Project,
) -> Result<Option<gutta_compiler::microwin::SAreaBase>, Fatal> {
    match (cli.s_area.clone(), &project.s_area) {
        (Some(chosen), _) => Ok(Some(chosen)),
        (None, Some(text)) => text.parse().map(Some).map_err(|e: String| {
            Fatal::usage(format!(
                "{}: [microwin] s_area: {e}",
                project.manifest.display()
            ))
        }),
        (None, None) => Ok(None),
    }
}
