//! Projects on the command line (docs/projects.md): `gutta-cc new` (a project from the
//! templates in cli/templates/), `gutta-cc build`, and a found gutta.toml's values put
//! into a parsed command line where the user gave none. Reading and validating
//! gutta.toml is gutta_io::Project's; compiling is compile.rs's.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::parser::ValueSource;
use clap::ArgMatches;
use gutta_catalog::{stdlib, TargetOrigin};
use gutta_cli::fatal::Fatal;
use gutta_cli::target::TargetArgs;
use gutta_io::{Connection, Endpoint, Project};

use crate::args::{Cli, Command, LinkArgs};

/// The files `gutta-cc new` writes: path in the project, template text.
const TEMPLATES: &[(&str, &str)] = &[
    ("gutta.toml", include_str!("../../../templates/gutta.toml")),
    ("src/main.lad", include_str!("../../../templates/main.lad")),
    (
        "symbols.csv",
        include_str!("../../../templates/symbols.csv"),
    ),
    (
        "tests/main.gtest",
        include_str!("../../../templates/main.gtest"),
    ),
    (".gitignore", include_str!("../../../templates/gitignore")),
    ("README.md", include_str!("../../../templates/README.md")),
];

/// The project around the current directory, if any.
pub(crate) fn find() -> Result<Option<Project>, Fatal> {
    Project::find(&current_dir()?).map_err(Fatal::usage)
}

/// The project a project command needs: found, or an error saying how to make one.
pub(crate) fn required(project: Option<&Project>, command: &str) -> Result<Project, Fatal> {
    match project {
        Some(p) => Ok(p.clone()),
        None => {
            let cwd = std::env::current_dir()
                .map(|d| d.display().to_string())
                .unwrap_or_else(|_| ".".into());
            Err(Fatal::usage(format!(
                "`gutta-cc {command}` needs a project, and no {} was found in {cwd} or any folder above it; \
                 create one with `gutta-cc new NAME`, or compile a file with `gutta-cc FILE.lad -o DIR`",
                gutta_io::MANIFEST
            )))
        }
    }
}

/// `gutta-cc new NAME [--plc PLC]`: a project that builds, runs and passes its tests as
/// created.
pub(crate) fn new(path: &Path, target: &TargetArgs) -> Result<ExitCode, Fatal> {
    if target.target.is_some() {
        return Err(Fatal::usage(format!(
            "`gutta-cc new` takes --plc NAME; for a target folder, set {}",
            TargetOrigin::ProjectFolder
        )));
    }
    let plc = target.plc.as_deref();
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    if name.is_empty() {
        return Err(Fatal::usage(
            "`gutta-cc new` takes the new project's folder, e.g. `gutta-cc new blinky`",
        ));
    }
    check_name(&name)?;
    let plc = plc.unwrap_or(stdlib::DEFAULT);
    stdlib::load(plc).map_err(|e| {
        Fatal::target(format!(
            "--plc {plc}: {e} (`gutta-cc list-targets` lists them)"
        ))
    })?;
    if let Ok(mut entries) = std::fs::read_dir(path) {
        if entries.next().is_some() {
            return Err(Fatal::usage(format!(
                "{} already exists and is not empty: `gutta-cc new` creates a new folder",
                path.display()
            )));
        }
    } else if path.exists() {
        return Err(Fatal::usage(format!(
            "{} exists and is not a folder",
            path.display()
        )));
    }
    for (file, template) in TEMPLATES {
        let text = template.replace("{name}", &name).replace("{plc}", plc);
        let target = path.join(file);
        if let Some(dir) = target.parent() {
            std::fs::create_dir_all(dir)
                .map_err(|e| Fatal::io(format!("cannot create {}: {e}", dir.display())))?;
        }
        std::fs::write(&target, text)
            .map_err(|e| Fatal::io(format!("cannot write {}: {e}", target.display())))?;
    }
    println!("created project `{name}` for {plc} in {}:", path.display());
    for (file, _) in TEMPLATES {
        println!("  {}", path.join(file).display());
    }
    println!(
        "next:\n  cd {}\n  gutta-cc build                     # compile into target/image/\n  \
         gutta-cc test                      # run tests/main.gtest on the VM\n  \
         gutta-sim --tcp 127.0.0.1:5020 &   # a simulated PLC at gutta.toml's [connection]\n  \
         gutta-cc download                  # build and download\n  \
         gutta-cc force Start=1             # Lamp blinks; `gutta-cc watch Lamp` shows it",
        path.display()
    );
    Ok(ExitCode::SUCCESS)
}

/// A project name: a letter, then letters, digits, `-` or `_` (it names a folder and
/// appears in gutta.toml and its README).
fn check_name(name: &str) -> Result<(), Fatal> {
    let mut chars = name.chars();
    let valid = chars.next().is_some_and(|c| c.is_ascii_alphabetic())
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_');
    if valid {
        Ok(())
    } else {
        Err(Fatal::usage(format!(
            "`{name}` is not a project name: use a letter, then letters, digits, `-` or `_` (e.g. `blinky`)"
        )))
    }
}

/// `gutta-cc build [--output DIR]`: the project's sources as one program, its tables
/// then `user_tables` (the user's --symbols) as symbol tables, into the output directory.
/// Files are named as gutta.toml names them (`src/main.lad`: relative to the project
/// folder, as cargo names its workspace's files), in diagnostics, the summary and the
/// source map, wherever in the project the command was given; paths from the command
/// line keep meaning what they meant where it was given.
pub(crate) fn build(
    cli: &Cli,
    project: &Project,
    output: Option<&Path>,
    user_tables: &[PathBuf],
) -> Result<ExitCode, Fatal> {
    let cwd = current_dir()?;
    let output = output.map_or_else(|| project.output.clone(), |o| cwd.join(o));
    let in_project = |p: &PathBuf| {
        p.strip_prefix(&project.root)
            .map(Path::to_path_buf)
            .unwrap_or_else(|_| p.clone())
    };
    let files: Vec<PathBuf> = project.sources.iter().map(in_project).collect();
    let user_tables: Vec<PathBuf> = user_tables.iter().map(|s| cwd.join(s)).collect();
    let tables: Vec<PathBuf> = project
        .symbols
        .iter()
        .chain(&user_tables)
        .map(in_project)
        .collect();
    // --target DIR as the user gave it, made absolute (W0204 names it so).
    let target = TargetArgs {
        target: cli.target.target.as_ref().map(|dir| cwd.join(dir)),
        ..cli.target.clone()
    };
    crate::compile::compile(
        cli,
        &crate::compile::Job {
            base: &project.root,
            files: &files,
            tables: &tables,
            output: Some(&in_project(&output)),
            emit: None,
            scale_timer_presets: cli.scale_timer_presets || project.scale_timer_presets,
            s_area: crate::compile::s_area(cli, project)?,
            target: &target,
        },
    )
}

fn current_dir() -> Result<PathBuf, Fatal> {
    std::env::current_dir()
        .map_err(|e| Fatal::io(format!("cannot read the current directory: {e}")))
}

/// A project path as diagnostics and summaries show it: relative to the current
/// directory when it is inside it or the project is above it (`src/main.lad`,
/// `../src/main.lad`), else absolute.
pub(crate) fn shown(path: &Path) -> PathBuf {
    let Ok(cwd) = std::env::current_dir() else {
        return path.to_path_buf();
    };
    for (up, base) in cwd.ancestors().enumerate() {
        if let Ok(rest) = path.strip_prefix(base) {
            let mut relative: PathBuf = std::iter::repeat_n("..", up).collect();
            relative.push(rest);
            return relative;
        }
    }
    path.to_path_buf()
}

/// The files a client command resolves symbols from: the project's sources (one
/// program) and tables.
pub(crate) fn context_files(project: &Project) -> Vec<PathBuf> {
    project
        .sources
        .iter()
        .chain(&project.symbols)
        .map(|p| shown(p))
        .collect()
}

/// `[connection]` into the link flags the command line did not give (`matches`: the
/// subcommand's own), so a flag always wins over gutta.toml.
pub(crate) fn apply_connection(link: &mut LinkArgs, matches: &ArgMatches, c: &Connection) {
    let unset = |id: &str| matches.value_source(id) != Some(ValueSource::CommandLine);
    if unset("tcp") && unset("rtu_tcp") && unset("serial") {
        match &c.endpoint {
            Some(Endpoint::Tcp(a)) => link.tcp = Some(a.clone()),
            Some(Endpoint::RtuTcp(a)) => link.rtu_tcp = Some(a.clone()),
            Some(Endpoint::Serial(d)) => link.serial = Some(d.clone()),
            None => {}
        }
    }
    if let (Some(baud), true) = (c.baud, unset("baud")) {
        link.baud = baud;
    }
    if let (Some(parity), true) = (c.parity, unset("parity")) {
        link.parity = parity;
    }
    if let (Some(station), true) = (c.station, unset("station")) {
        link.station = station;
    }
    if let (Some(timeout), true) = (c.timeout_ms, unset("timeout")) {
        link.timeout = timeout;
    }
    if let (Some(retries), true) = (c.retries, unset("retries")) {
        link.retries = retries;
    }
}

/// The project's image for `download` without IMAGE: built first, like `cargo run`
/// (the build's diagnostics and summary printed); `None` when the build failed, so the
/// PLC is never touched.
pub(crate) fn build_for_download(cli: &Cli, project: &Project) -> Result<Option<PathBuf>, Fatal> {
    // The client's symbol context holds the project's files; the build takes only the
    // user's own --symbols and the project's tables.
    let user_tables: Vec<PathBuf> = cli
        .symbols
        .iter()
        .filter(|s| {
            !project
                .sources
                .iter()
                .chain(&project.symbols)
                .any(|p| shown(p) == **s)
        })
        .cloned()
        .collect();
    let code = build(cli, project, None, &user_tables)?;
    Ok((code == ExitCode::SUCCESS).then(|| project.output.clone()))
}

/// Inside a project (docs/projects.md), what the command line leaves out comes from
/// gutta.toml: the link flags not given on the command line from `[connection]`,
/// --plc/--target from `[program]` (the target resolver's project input), the symbol
/// context (--symbols) from the project's sources and tables, and `debug`'s image from
/// the build output. Compiling files, `new`, `dis`, `explain` and `list-targets` do not
/// look for a project; outside one, nothing changes.
pub(crate) fn apply(cli: &mut Cli, matches: &ArgMatches) -> Result<(), Fatal> {
    let uses_project = !matches!(
        cli.command,
        None | Some(
            Command::New { .. }
                | Command::Dis { .. }
                | Command::Ladder { .. }
                | Command::Explain { .. }
                | Command::ListTargets
                | Command::Completions { .. }
                | Command::Man { .. }
        )
    );
    if !uses_project {
        return Ok(());
    }
    let Some(project) = find()? else {
        return Ok(());
    };
    if matches!(cli.command, Some(Command::Test { .. })) {
        // `test` takes each test file's program, target and symbols itself.
        cli.project = Some(project);
        return Ok(());
    }
    cli.target.project = project.plc.spec();
    let link = cli.command.as_mut().and_then(Command::link_mut);
    if let (Some(link), Some((_, sub))) = (link, matches.subcommand()) {
        apply_connection(link, sub, &project.connection);
    }
    let building = matches!(cli.command, Some(Command::Build { .. }));
    if cli.symbols.is_empty() && !building {
        cli.symbols = context_files(&project);
    }
    if let Some(Command::Debug {
        image: image @ None,
        ..
    }) = &mut cli.command
    {
        if project.output.is_dir() {
            *image = Some(shown(&project.output));
        }
    }
    cli.project = Some(project);
    Ok(())
}
