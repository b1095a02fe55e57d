//! `gutta-cc debug ACTION [ARG] [--watch VAR...]`: UM4001's DEBUG_* functions, and the
//! report every action ends with: where the program is (file:line and the instruction
//! text with the image's source map), the logic stack and the watched values in their
//! formats, as text or one JSON object. The connection comes from `client.rs`.

use std::path::Path;
use std::process::ExitCode;

use gutta_cli::fatal::Fatal;
use gutta_cli::vars::VarJson;
use gutta_format::SourceMap;
use gutta_link::message::{debug_state, Breakpoint, DebugStep};
use serde_json::json;

use crate::args::LinkArgs;
use crate::client::{check_early, link_error, login_with_target, resolve_all, Online};

/// The image directory `debug` takes its source map from when `--image` is not given.
const DEFAULT_DEBUG_IMAGE: &str = "image";

/// The source map for `debug`: beside `--image DIR` (an error when it is missing or stale),
/// else beside `image/` when there is one (a warning when it cannot be used).
fn debug_source_map(image: Option<&Path>) -> Result<Option<SourceMap>, Fatal> {
    let (dir, explicit) = match image {
        Some(dir) => (dir, true),
        None => (Path::new(DEFAULT_DEBUG_IMAGE), false),
    };
    let map_path = gutta_io::source_map_path(dir);
    if !explicit && !map_path.is_file() {
        return Ok(None);
    }
    let map = gutta_io::read_image_dir(dir)
        .and_then(|image| gutta_io::read_source_map(dir, &image))
        .and_then(|map| map.ok_or_else(|| format!("no source map {}", map_path.display())));
    match map {
        Ok(map) => Ok(Some(map)),
        Err(e) if explicit => Err(Fatal::io(format!("--image {}: {e}", dir.display()))),
        Err(e) => {
            eprintln!("gutta-cc: warning: {e}; showing positions without source lines");
            Ok(None)
        }
    }
}

/// A `debug` action as the command line gives it.
#[derive(Debug, Clone, Copy)]
enum Action<'a> {
    Break(&'a str),
    Clear,
    Stop,
    Run,
    Reset,
    Step(DebugStep),
    Info,
}

impl<'a> Action<'a> {
    /// The action and its argument, or the usage error that lists them.
    fn parse(words: &'a [String]) -> Result<Action<'a>, Fatal> {
        let first = words.first().map_or("", String::as_str);
        Ok(match (first, words.get(1).map(String::as_str)) {
            ("break", Some(at)) => Action::Break(at),
            ("clear", None) => Action::Clear,
            ("stop", None) => Action::Stop,
            ("run", None) => Action::Run,
            ("reset", None) => Action::Reset,
            ("step", Some(kind)) => Action::Step(match kind {
                "in" => DebugStep::In,
                "over" => DebugStep::Over,
                "out" => DebugStep::Out,
                other => return Err(Fatal::usage(format!("step `{other}`: in, over or out"))),
            }),
            ("info", None) => Action::Info,
            (other, _) => {
                return Err(Fatal::usage(format!(
                    "debug `{other}`: break POSITION, clear, stop, run, step in|over|out, reset or info"
                )))
            }
        })
    }
}

/// `gutta-cc debug ACTION [ARG] [--watch VAR...]`: UM4001's DEBUG_* functions; every
/// action ends with a report of where the program is: file:line and the instruction
/// (with a source map), the logic stack and the watched values.
pub(crate) fn debug(
    online: &Online,
    action: &[String],
    image: Option<&Path>,
    watch: &[String],
    args: &LinkArgs,
) -> Result<ExitCode, Fatal> {
    let map = debug_source_map(image)?;
    // The image's own symbols (its source map's), then --symbols files.
    let symbols = online.symbols(map.iter().map(|m| m.symbols.clone()).collect())?;
    // What the command line names is checked before connecting: the action, the
    // watched variables, and a breakpoint when the PLC type is known.
    let words = action;
    let action = Action::parse(words)?;
    check_early(online, watch, &symbols, false)?;
    if let (Some(e), Action::Break(at)) = (online.targets.explicit()?, action) {
        let map_name = gutta_io::source_map_path(image.unwrap_or(Path::new(DEFAULT_DEBUG_IMAGE)));
        gutta_format::parse_breakpoint(
            at,
            &e.target.plc,
            map.as_ref(),
            &map_name.display().to_string(),
        )
        .map_err(Fatal::usage)?;
    }
    let (mut session, target) = login_with_target(online, args)?;
    let client = session.client();
    let watched = resolve_all(watch, &symbols, &target)?;
    let plc = &target.plc;
    match action {
        Action::Break(at) => {
            let map_name =
                gutta_io::source_map_path(image.unwrap_or(Path::new(DEFAULT_DEBUG_IMAGE)));
            let at = gutta_format::parse_breakpoint(
                at,
                plc,
                map.as_ref(),
                &map_name.display().to_string(),
            )
            .map_err(Fatal::usage)?;
            if let Some(note) = at.note {
                eprintln!("gutta-cc: note: {note}");
            }
            let (index, network, step) = at.position;
            client.set_breakpoint(Some(Breakpoint {
                index,
                network,
                step,
            }))
        }
        Action::Clear => client.set_breakpoint(None),
        Action::Stop => client.debug_run(false),
        Action::Run => client.debug_run(true),
        Action::Reset => client.debug_reset(),
        Action::Step(step) => client.debug_step(step),
        Action::Info => Ok(()),
    }
    .map_err(link_error)?;
    // Every action ends by showing where the program is.
    let (state, info) = client.debug_info().map_err(link_error)?;
    let values = session.read(&watched).map_err(link_error)?;
    let at = |f: u8, n: u16, s: u16| Place {
        position: (f != 0xFF).then(|| format!("{}:{n}:{s}", gutta_format::function_name(f, plc))),
        source: map.as_ref().and_then(|m| {
            let i = m.at_position(f, n, s)?;
            Some((m.file_of(i).to_string(), i.line, i.column, i.text.clone()))
        }),
    };
    let b = info.breakpoint;
    let breakpoint = at(b.index, b.network, b.step);
    let paused = at(info.state_index, info.state_network, info.state_step);
    let mode = if state & debug_state::RUN != 0 {
        "run until a breakpoint"
    } else {
        "single-step stop"
    };
    online.print(
        json!({
            "command": "debug",
            "action": words[0],
            "breakpoint": breakpoint.json(),
            "paused_at": paused.json(),
            "mode": if state & debug_state::RUN != 0 { "run" } else { "step" },
            "logic_stack": info.stack_logic,
            "call_depth": info.sp,
            "saved_l_bytes": info.stack_data,
            "error": info.error,
            "watch": watched.iter().zip(&values).map(|(v, r)| v.json(*r)).collect::<Vec<_>>(),
        }),
        || {
            let mut lines = vec![
                format!("breakpoint: {}", breakpoint.text()),
                format!("paused at:  {}", paused.text()),
                format!(
                    "mode: {mode}; logic stack {:#06X}; call depth {}; saved L {}; error {}",
                    info.stack_logic,
                    info.sp,
                    gutta_cli::plural::count(info.stack_data, "byte"),
                    info.error
                ),
            ];
            lines.extend(
                watched
                    .iter()
                    .zip(&values)
                    .map(|(v, r)| format!("watch: {} = {}", v.label(), v.show(*r))),
            );
            lines.join("\n")
        },
    );
    Ok(ExitCode::SUCCESS)
}

/// A position the debugger reports: `MAIN:2:1` (none when the PLC says 0xFF) and, with
/// the source map, its file, line, column and instruction text.
struct Place {
    position: Option<String>,
    source: Option<(String, u32, u32, String)>,
}

impl Place {
    /// `MAIN:2:1`, or `main.lad:11:1 (MAIN:2:1): MOVW   16#BEEF, MW10`.
    fn text(&self) -> String {
        match (&self.position, &self.source) {
            (None, _) => "none".into(),
            (Some(p), Some((file, line, column, text))) => {
                format!("{file}:{line}:{column} ({p}): {text}")
            }
            (Some(p), None) => p.clone(),
        }
    }

    fn json(&self) -> serde_json::Value {
        match (&self.position, &self.source) {
            (None, _) => serde_json::Value::Null,
            (Some(p), Some((file, line, column, text))) => json!({
                "position": p, "file": file, "line": line, "column": column, "text": text,
            }),
            (Some(p), None) => json!({ "position": p }),
        }
    }
}
