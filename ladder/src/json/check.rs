//! Checks on the model (docs/ladder.md, "Checks on the model"): a model's structural
//! check (`validate`, then `written_program`: an L code at its JSON path), then the
//! compiler's whole pipeline on the program written from it (`gutta_compiler::compile`,
//! as `gutta-cc -o` runs it, so the encoder's limits count too), every diagnostic
//! mapped through the written program's source map to the JSON path of the part of
//! the model that caused it, so an editor can mark the contact. A model *validates*
//! when this check reports no error; then its program compiles to an image. Plain data:
//! no I/O, no rendering.

use gutta_compiler::diagnostics::{Diagnostic, Severity};
use gutta_compiler::source::{LineIndex, SourceFile, Span};
use gutta_compiler::{compile, ExplicitTarget};
use serde::{Serialize, Serializer};

use super::codes::ModelError;
use super::to_program::{written_program, WrittenProgram};
use super::validate::validate;
use super::Model;

/// The name the written program is compiled under.
const PROGRAM_NAME: &str = "model.lad";

/// One diagnostic of a model: the JSON path of the part at fault (`""`: the whole
/// model), the code (`L0007`, `E0301`, `W0204`), and what the compiler says.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ModelDiagnostic {
    pub path: String,
    pub code: String,
    #[serde(serialize_with = "severity_name")]
    pub severity: Severity,
    pub message: String,
    /// The text under the compiler's primary span, when it has one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub label: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub help: Option<String>,
    /// The compiler's secondary labels (an earlier definition, the other half of a
    /// pair), each at the part of the model its line was written for.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<ModelNote>,
}

/// A secondary label of a diagnostic, at its own part of the model.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ModelNote {
    pub path: String,
    pub message: String,
}

impl ModelDiagnostic {
    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }

    /// A structural fault of the model: its L code, an error.
    fn structural(e: &ModelError) -> ModelDiagnostic {
        ModelDiagnostic {
            path: e.path.clone(),
            code: e.code.as_str().to_string(),
            severity: Severity::Error,
            message: e.message.clone(),
            label: None,
            help: None,
            notes: Vec::new(),
        }
    }
}

impl std::fmt::Display for ModelDiagnostic {
    /// `E0301 at blocks[0].networks[2].rung.series[1]: ...`, as `ModelError` shows.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.path.is_empty() {
            write!(f, "{}: {}", self.code, self.message)
        } else {
            write!(f, "{} at {}: {}", self.code, self.path, self.message)
        }
    }
}

fn severity_name<S: Serializer>(severity: &Severity, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(severity.as_str())
}

/// What [`check`] found: the diagnostics in the program's order, and the written
/// program when the model's structure let it be written.
#[derive(Debug, Clone)]
pub struct ModelCheck {
    pub diagnostics: Vec<ModelDiagnostic>,
    /// `None` when a structural L code stopped the check before the compiler.
    pub program: Option<WrittenProgram>,
}

impl ModelCheck {
    /// Whether the model has an error: it does not validate.
    pub fn has_errors(&self) -> bool {
        self.diagnostics.iter().any(ModelDiagnostic::is_error)
    }

    /// The diagnostics as a JSON array (pretty, with a final newline).
    pub fn to_json(&self) -> String {
        let mut text = serde_json::to_string_pretty(&self.diagnostics).unwrap_or_default();
        text.push('\n');
        text
    }
}

/// Every diagnostic of `model` on `target` (the caller's choice: the model's `plc`, or
/// `--plc`; W0204 when they differ), each at the JSON path of its cause.
pub fn check(model: &Model, target: &ExplicitTarget) -> ModelCheck {
    let written = validate(model, &target.target.instructions)
        .and_then(|()| written_program(model, &target.target.instructions));
    let written = match written {
        Ok(w) => w,
        Err(e) => {
            return ModelCheck {
                diagnostics: vec![ModelDiagnostic::structural(&e)],
                program: None,
            }
        }
    };
    let compiled = compile(
        SourceFile::new(PROGRAM_NAME, written.text.clone()),
        Some(target),
    );
    let index = LineIndex::new(&written.text);
    let diagnostics = compiled
        .checked
        .diagnostics()
        .iter()
        .map(|d| mapped(d, &written, &index))
        .collect();
    ModelCheck {
        diagnostics,
        program: Some(written),
    }
}

/// A compiler diagnostic at the part of the model its line was written for.
fn mapped(d: &Diagnostic, written: &WrittenProgram, index: &LineIndex) -> ModelDiagnostic {
    // An empty span at the start is the compiler's "no place" (no MAIN); past the end
    // of the text is no line either: both are the whole model.
    let path = |span: Span| {
        let offset = span.start as usize;
        if offset >= written.text.len() || (span.is_empty() && offset == 0) {
            return String::new();
        }
        written.path_of_line(index.line_of(offset)).to_string()
    };
    ModelDiagnostic {
        path: path(d.primary.span),
        code: d.code.as_str().to_string(),
        severity: d.severity,
        message: d.message.clone(),
        label: d.primary.message.clone(),
        help: d.help.clone(),
        notes: d
            .secondary
            .iter()
            .map(|l| ModelNote {
                path: path(l.span),
                message: l.message.clone().unwrap_or_default(),
            })
            .collect(),
    }
}

/// Whether `path` names a part of `model`: `""` the whole model, else fields and list
/// indices as the model's JSON has them (`blocks[0].networks[2].rung.series[1]`,
/// `symbols[3]`, `blocks[1].VAR[0]`).
pub fn names_a_part(model: &Model, path: &str) -> bool {
    let Ok(mut at) = serde_json::to_value(model) else {
        return false;
    };
    if path.is_empty() {
        return true;
    }
    for segment in path.split('.') {
        let (field, indices) = match segment.find('[') {
            Some(i) => (&segment[..i], &segment[i..]),
            None => (segment, ""),
        };
        let Some(next) = at.get_mut(field).map(std::mem::take) else {
            return false;
        };
        at = next;
        for index in indices.split_terminator(']') {
            let Some(Ok(i)) = index.strip_prefix('[').map(str::parse::<usize>) else {
                return false;
            };
            let Some(next) = at.get_mut(i).map(std::mem::take) else {
                return false;
            };
            at = next;
        }
    }
    true
}
