//! Shared helpers of the edit tests (`edit.rs`, `edit_props.rs`): the corpora's models
//! with their targets, and the round trip an edited network must pass (the model ->
//! its program -> compiled -> built -> the model again: the same network).

use std::sync::Arc;

use gutta_catalog::Target;
use gutta_compiler::source::{is_microwin, SourceFile, MARKER};
use gutta_compiler::{check_source, ExplicitTarget};
use gutta_ladder::json::{model_of, program_of, Model, NetworkBody, NetworkJson};

use super::{checked_file, files, CORPORA};

/// A corpus program's model, the target it is checked on, and its dialect.
pub struct CorpusModel {
    pub name: String,
    pub model: Model,
    pub target: Arc<Target>,
    pub microwin: bool,
}

/// The model of every program of the corpora that compiles without errors.
pub fn corpus_models() -> Vec<CorpusModel> {
    let mut out = Vec::new();
    for (dir, exts) in CORPORA {
        for path in files(dir, exts) {
            let checked = checked_file(&path);
            if checked.has_errors() {
                continue;
            }
            let model = model_of(&checked, &gutta_ladder::build(&checked));
            let original = std::fs::read_to_string(&path).unwrap_or_default();
            out.push(CorpusModel {
                name: path.display().to_string(),
                microwin: is_microwin(&path.display().to_string(), &original),
                model,
                target: checked.target.clone(),
            });
        }
    }
    out
}

/// `model` written as its program, compiled on `target` and built into a model again;
/// each network of `networks` (block, network) must come back the same, its `number`
/// aside (the written program numbers networks by position).
pub fn round_trip(
    model: &Model,
    target: &Arc<Target>,
    microwin: bool,
    networks: &[(usize, usize)],
) -> Result<(), RoundTrip> {
    let text = program_of(model, &target.instructions)
        .map_err(|e| RoundTrip::Differs(format!("not written: {e}")))?;
    let text = if microwin {
        format!("{MARKER}\n{text}")
    } else {
        text
    };
    let explicit = ExplicitTarget {
        target: target.clone(),
        origin: "the model's plc".to_string(),
    };
    let again = check_source(SourceFile::new("edited.lad", text.clone()), Some(&explicit));
    if again.has_errors() {
        let errors: Vec<_> = again
            .diagnostics()
            .iter()
            .filter(|d| d.is_error())
            .collect();
        let (code, message) = errors
            .first()
            .map(|d| (d.code.as_str().to_string(), d.message.clone()))
            .unwrap_or_default();
        return Err(RoundTrip::NotCompiled {
            code,
            codes: errors.iter().map(|d| d.code.as_str().to_string()).collect(),
            message,
            text,
        });
    }
    let back = model_of(&again, &gutta_ladder::build(&again));
    for &(b, n) in networks {
        let want = model.blocks.get(b).and_then(|x| x.networks.get(n));
        let got = back.blocks.get(b).and_then(|x| x.networks.get(n));
        let (Some(want), Some(got)) = (want, got) else {
            return Err(RoundTrip::Differs(format!(
                "network {n} of block {b} is missing"
            )));
        };
        if unnumbered(want) != unnumbered(got) {
            return Err(RoundTrip::Differs(format!(
                "blocks[{b}].networks[{n}] differs:\n  edited {}\n  built  {}\n{text}",
                serde_json::to_string(want).unwrap_or_default(),
                serde_json::to_string(got).unwrap_or_default()
            )));
        }
    }
    Ok(())
}

/// Why a round trip failed.
#[derive(Debug)]
pub enum RoundTrip {
    /// The written program has errors: the first one's code and message, and every
    /// error's code.
    NotCompiled {
        code: String,
        codes: Vec<String>,
        message: String,
        text: String,
    },
    /// A network came back different (or the model was not written).
    Differs(String),
}

impl std::fmt::Display for RoundTrip {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RoundTrip::NotCompiled {
                code,
                message,
                text,
                ..
            } => write!(
                f,
                "the written program does not compile: {code} {message}\n{text}"
            ),
            RoundTrip::Differs(what) => f.write_str(what),
        }
    }
}

/// A network without its number, and an STL network's reason without its source line.
fn unnumbered(net: &NetworkJson) -> NetworkJson {
    let mut net = net.clone();
    net.number = None;
    if let NetworkBody::Stl { reason, .. } = &mut net.body {
        reason.clear();
    }
    net
}
