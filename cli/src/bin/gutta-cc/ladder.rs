//! `gutta-cc ladder INPUT -o OUT` (docs/ladder.md): the program of a source file, a
//! project (its folder or gutta.toml) or an image directory (through the disassembler:
//! addresses instead of symbols) drawn as ladder diagrams into OUT, an `.svg` (every
//! network stacked) or a self-contained `.html` page, or written as the ladder model's
//! JSON (`.json`, `-` for stdout). A model (`INPUT.json`) is read, checked (its
//! structure, then the compiler on its program, each diagnostic at a JSON path) and
//! written back as a program (`.lad`, `-` for stdout) with its rungs as STL. The model, its JSON,
//! the program text and the drawing are gutta_ladder's; this file reads the input and
//! writes the file atomically.

use std::io::IsTerminal;
use std::path::Path;
use std::process::ExitCode;

use gutta_catalog::TargetOrigin;
use gutta_cli::fatal::{Fatal, MessageFormat};
use gutta_cli::notes::{self, JsonTo};
use gutta_cli::sources::read_program;
use gutta_compiler::diagnostics::render::{render, RenderStyle};
use gutta_compiler::source::SourceFile;
use gutta_compiler::{check_program, CheckedFile, ProgramSources};
use gutta_io::Project;
use gutta_ladder::html::{ladder_html, HtmlOptions};
use gutta_ladder::svg::ladder_svg_with;

use crate::args::{Cli, DrawArgs};

/// What the output file is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum OutputKind {
    Svg,
    Html,
    /// The ladder model's JSON, into a file or (`-`) onto stdout.
    Json,
}

fn output_kind(out: &Path) -> Result<OutputKind, Fatal> {
    if is_stdout(out) {
        return Ok(OutputKind::Json);
    }
    match out.extension().map(|e| e.to_ascii_lowercase()) {
        Some(e) if e == "svg" => Ok(OutputKind::Svg),
        Some(e) if e == "html" || e == "htm" => Ok(OutputKind::Html),
        Some(e) if e == "json" => Ok(OutputKind::Json),
        _ => Err(Fatal::usage(format!(
            "{}: the output ends in .svg (every network in one drawing), .html (a page) or .json (the ladder model), or is - (the model on stdout)",
            out.display()
        ))),
    }
}

/// `-o -`: stdout.
fn is_stdout(out: &Path) -> bool {
    out.as_os_str() == "-"
}

/// An input that is a ladder model (`.json`), not a program.
fn is_model(input: &Path) -> bool {
    input.is_file()
        && input
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"))
}

/// The checked program of `input`: an image directory, a project, or source files.
pub(crate) fn checked_input(cli: &Cli, input: &Path) -> Result<CheckedFile, Fatal> {
    let explicit = cli.target.explicit()?;
    if input.join("manifest.json").is_file() {
        let (image, target) = cli.target.read_image(input)?;
        let text = gutta_format::disasm::disassemble(&image, &target)
            .map_err(|e| Fatal::program(format!("{}: cannot disassemble: {e}", input.display())))?;
        let name = format!("{} (disassembled)", input.display());
        let explicit = gutta_compiler::ExplicitTarget {
            target,
            origin: TargetOrigin::Image(input.to_path_buf()).to_string(),
        };
        return Ok(check_program(
            ProgramSources::single(SourceFile::new(name, text)),
            Some(&explicit),
        ));
    }
    let manifest = if input.is_dir() {
        Some(input.join(gutta_io::MANIFEST))
    } else if input.file_name().is_some_and(|n| n == gutta_io::MANIFEST) {
        Some(input.to_path_buf())
    } else {
        None
    };
    if let Some(manifest) = manifest {
        if !manifest.is_file() {
            return Err(Fatal::usage(format!(
                "{}: neither an image directory (manifest.json) nor a project ({})",
                input.display(),
                gutta_io::MANIFEST
            )));
        }
        let project = Project::load(&manifest).map_err(Fatal::usage)?;
        let mut notes = Vec::new();
        let mut program = read_program(&project.sources, &project.symbols, &mut notes)?;
        notes::print(&notes, cli.message_format, JsonTo::Stderr);
        program.options.scale_timer_presets =
            project.scale_timer_presets || cli.scale_timer_presets;
        program.options.s_area = crate::compile::s_area(cli, &project)?;
        let target = gutta_cli::target::TargetArgs {
            project: project.plc.spec(),
            ..cli.target.clone()
        };
        let explicit = target.explicit()?;
        return Ok(check_program(program, explicit.as_ref()));
    }
    let mut notes = Vec::new();
    let mut program = read_program(&[input.to_path_buf()], &cli.symbols, &mut notes)?;
    notes::print(&notes, cli.message_format, JsonTo::Stderr);
    program.options.scale_timer_presets = cli.scale_timer_presets;
    program.options.s_area = cli.s_area.clone();
    Ok(check_program(program, explicit.as_ref()))
}

pub(crate) fn ladder(
    cli: &Cli,
    input: &Path,
    out: &Path,
    draw: &DrawArgs,
) -> Result<ExitCode, Fatal> {
    if is_model(input) {
        return from_model(cli, input, out);
    }
    let kind = output_kind(out)?;
    let checked = checked_input(cli, input)?;
    let color = gutta_cli::color::use_color(cli.color, std::io::stderr().is_terminal());
    let style = RenderStyle {
        color,
        unicode: color,
    };
    if checked.has_errors() {
        eprint!("{}", render(&checked.file, checked.diagnostics(), style));
        return Ok(ExitCode::from(1));
    }
    let ladder = gutta_ladder::build(&checked);
    let text = match kind {
        OutputKind::Svg => ladder_svg_with(&ladder, &draw.options()),
        OutputKind::Html => ladder_html(
            &ladder,
            &HtmlOptions {
                title: format!("{} ({})", input.display(), ladder.plc),
                live_script: None,
                draw: draw.options(),
            },
        ),
        OutputKind::Json => gutta_ladder::json::model_of(&checked, &ladder).to_json(),
    };
    write_out(out, text.as_bytes(), "the model")?;
    let (drawn, stl) = census(&ladder);
    eprintln!(
        "{}: {} drawn as ladder, {stl} as STL, into {}",
        input.display(),
        gutta_cli::plural::count(drawn, "network"),
        shown(out)
    );
    Ok(ExitCode::SUCCESS)
}

/// `gutta-cc ladder MODEL.json -o OUT.lad`: the model read and checked on its PLC type
/// (`--plc`/`--target` win over its `plc`) by `gutta_ladder::json::check`: a structural
/// fault is its L code with the JSON path, exit 2, nothing written; so is every error
/// of the compiler on the written program, each at the JSON path of the part of the
/// model that caused it, with its help as the hint. Warnings are printed and the
/// program is written (into the .lad file atomically, or onto stdout). With
/// `--message-format json` every diagnostic is one JSON object on stdout (its `file`,
/// `path`, `code`, `severity`, `message`, `help`), before any fatal error.
fn from_model(cli: &Cli, input: &Path, out: &Path) -> Result<ExitCode, Fatal> {
    use gutta_ladder::json::{check, read_model, ModelDiagnostic, ModelError, ModelErrorCode};
    let refused = |e: ModelError| {
        Fatal::program(format!("{}: {e}", input.display()))
            .with_hint(format!("gutta-cc explain {}", e.code))
    };
    let lad = out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("lad"));
    if !is_stdout(out) && !lad {
        return Err(Fatal::usage(format!(
            "{}: a ladder model is written as STL into a .lad file, or - (stdout)",
            out.display()
        )));
    }
    let bytes = std::fs::read(input)
        .map_err(|e| Fatal::io(format!("cannot read {}: {e}", input.display())))?;
    let model = read_model(&bytes).map_err(refused)?;
    let target = match cli.target.explicit()? {
        Some(explicit) => explicit,
        None => gutta_compiler::ExplicitTarget {
            target: std::sync::Arc::new(gutta_catalog::stdlib::load(&model.plc).map_err(|e| {
                refused(ModelError::new(
                    ModelErrorCode::UnknownPlc,
                    "plc",
                    e.to_string(),
                ))
            })?),
            origin: "the model's `plc`".to_string(),
        },
    };
    let checked = check(&model, &target);
    let fault = |d: &ModelDiagnostic| {
        Fatal::program(format!("{}: {d}", input.display())).with_hint(
            d.help
                .clone()
                .unwrap_or_else(|| format!("gutta-cc explain {}", d.code)),
        )
    };
    let Some(program) = &checked.program else {
        // A structural fault stops the check: its L code, as the model's reader says it.
        let first = checked.diagnostics.first();
        return Err(first.map_or_else(
            || Fatal::program(format!("{}: the model was not written", input.display())),
            fault,
        ));
    };
    let tool = env!("CARGO_BIN_NAME");
    let json = cli.message_format == MessageFormat::Json;
    for d in &checked.diagnostics {
        if json {
            let mut object = serde_json::to_value(d).unwrap_or_default();
            object["file"] = input.display().to_string().into();
            println!("{object}");
        } else if !d.is_error() {
            eprintln!("{tool}: warning: {}: {d}", input.display());
            if let Some(help) = &d.help {
                eprintln!("  help: {help}");
            }
        }
    }
    let errors: Vec<&ModelDiagnostic> = checked
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .collect();
    if let Some((last, before)) = errors.split_last() {
        if json {
            return Err(Fatal::program(format!(
                "{}: {} in the model: nothing written",
                input.display(),
                gutta_cli::plural::count(errors.len(), "error")
            )));
        }
        for d in before {
            fault(d).report(tool, cli.message_format);
        }
        return Err(fault(last));
    }
    write_out(out, program.text.as_bytes(), "the program")?;
    let networks: usize = model.blocks.iter().map(|b| b.networks.len()).sum();
    eprintln!(
        "{}: {} written as STL into {}",
        input.display(),
        gutta_cli::plural::count(networks, "network"),
        shown(out)
    );
    Ok(ExitCode::SUCCESS)
}

/// Networks drawn as rungs, and shown as STL.
pub(crate) fn census(ladder: &gutta_ladder::model::Ladder) -> (usize, usize) {
    let nets = ladder.blocks.iter().flat_map(|b| &b.networks);
    let drawn = nets
        .clone()
        .filter(|n| matches!(n.body, gutta_ladder::model::Body::Rung(_)))
        .count();
    (drawn, nets.count() - drawn)
}

/// `bytes` onto stdout (`-`) or into the file `out` atomically; `what` names them in
/// the error.
fn write_out(out: &Path, bytes: &[u8], what: &str) -> Result<(), Fatal> {
    if !is_stdout(out) {
        return write_atomically(out, bytes);
    }
    use std::io::Write;
    let mut stdout = std::io::stdout().lock();
    stdout
        .write_all(bytes)
        .and_then(|()| stdout.flush())
        .map_err(|e| Fatal::io(format!("cannot write {what} to stdout: {e}")))
}

/// Where the output went, for the closing line on stderr.
fn shown(out: &Path) -> String {
    if is_stdout(out) {
        "stdout".to_string()
    } else {
        out.display().to_string()
    }
}

/// The file written atomically (`gutta_io::write_file_atomically`), a failure as I/O.
fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), Fatal> {
    gutta_io::write_file_atomically(path, bytes)
        .map_err(|e| Fatal::io(format!("cannot write {}: {e}", path.display())))
}
