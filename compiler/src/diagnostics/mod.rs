//! The one diagnostic type of the compiler, and its renderers (ariadne text, JSON).
//! Every stage reports through [`Diagnostic`]; only `render` knows ariadne.

mod codes;
pub mod json;
pub mod render;

pub use codes::Code;

use crate::source::Span;

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Severity {
    Error,
    Warning,
}

impl Severity {
    pub fn as_str(self) -> &'static str {
        match self {
            Severity::Error => "error",
            Severity::Warning => "warning",
        }
    }
}

/// A span with an optional message.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Label {
    pub span: Span,
    pub message: Option<String>,
}

/// A change that resolves a diagnostic, for an editor to apply: a title ("replace with
/// `MOVW`") and text edits, each a byte span of the checked text and its replacement.
/// Renderers never show it (the help line says the same in words).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Fix {
    pub title: String,
    pub edits: Vec<(Span, String)>,
}

/// A did-you-mean: the text the help line shows (`#Count`, `PORT0.BAUD`) and the edit
/// that writes it (`Count` over the name without `#`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Suggestion {
    pub shown: String,
    pub span: Span,
    pub replacement: String,
}

impl Suggestion {
    /// `replacement` over `span`, shown as it is written.
    pub fn new(span: Span, replacement: impl Into<String>) -> Suggestion {
        let replacement = replacement.into();
        Suggestion {
            shown: replacement.clone(),
            span,
            replacement,
        }
    }

    /// The help line shows `shown` (e.g. with the `#` the span leaves out).
    pub fn shown_as(mut self, shown: impl Into<String>) -> Suggestion {
        self.shown = shown.into();
        self
    }
}

/// One problem in a program: a code, a message, a primary span on the exact token,
/// secondary spans for context, a help line when a fix is known, and the fixes an
/// editor can apply.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Diagnostic {
    pub code: Code,
    pub severity: Severity,
    pub message: String,
    pub primary: Label,
    pub secondary: Vec<Label>,
    pub help: Option<String>,
    pub fixes: Vec<Fix>,
}

impl Diagnostic {
    pub fn new(code: Code, span: Span, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            code,
            severity: code.severity(),
            message: message.into(),
            primary: Label {
                span,
                message: None,
            },
            secondary: Vec::new(),
            help: None,
            fixes: Vec::new(),
        }
    }

    /// A fix an editor can apply.
    pub fn fix(mut self, fix: Fix) -> Diagnostic {
        self.fixes.push(fix);
        self
    }

    /// Help `did you mean `X`?` and the fix that writes X.
    pub fn suggest(self, s: Suggestion) -> Diagnostic {
        let help = format!("did you mean `{}`?", s.shown);
        self.help(help).fix(Fix {
            title: format!("Replace with `{}`", s.shown),
            edits: vec![(s.span, s.replacement)],
        })
    }

    pub fn maybe_suggest(self, s: Option<Suggestion>) -> Diagnostic {
        match s {
            Some(s) => self.suggest(s),
            None => self,
        }
    }

    /// Text under the primary span.
    pub fn label(mut self, message: impl Into<String>) -> Diagnostic {
        self.primary.message = Some(message.into());
        self
    }

    pub fn with_secondary(mut self, span: Span, message: impl Into<String>) -> Diagnostic {
        self.secondary.push(Label {
            span,
            message: Some(message.into()),
        });
        self
    }

    pub fn help(mut self, help: impl Into<String>) -> Diagnostic {
        self.help = Some(help.into());
        self
    }

    pub fn maybe_help(mut self, help: Option<String>) -> Diagnostic {
        if help.is_some() {
            self.help = help;
        }
        self
    }

    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }
}

/// Collects diagnostics of one file.
#[derive(Debug, Default, Clone)]
pub struct Diagnostics {
    pub items: Vec<Diagnostic>,
}

impl Diagnostics {
    pub fn push(&mut self, d: Diagnostic) {
        self.items.push(d);
    }

    pub fn has_errors(&self) -> bool {
        self.items.iter().any(Diagnostic::is_error)
    }

    /// Sort by position (stable), so output follows the file.
    pub fn sorted(mut self) -> Vec<Diagnostic> {
        self.items
            .sort_by_key(|d| (d.primary.span.start, d.primary.span.end));
        self.items
    }
}

/// docs/diagnostics.md, generated from the code registry (a test keeps the file in sync).
pub fn reference_markdown() -> String {
    let mut out = String::from(
        "# Diagnostic codes\n\n<!-- Generated from compiler/src/diagnostics/codes.rs by `UPDATE_DOCS=1 cargo test -p gutta-compiler --test docs`. Do not edit by hand. -->\n\n\
         Every problem `gutta-cc` reports carries a stable code. `E` codes are errors (exit status 1), \
         `W` codes warnings (the program still compiles). `gutta-cc explain CODE` prints an entry (also for the T codes below \
         and the V codes of image verification, docs/image-format.md). \
         With `--message-format json` each diagnostic is one JSON object per line on stdout with the fields \
         `code`, `severity`, `message`, `file`, `line`, `column`, `end_line`, `end_column` (1-based, columns count characters), \
         `help` (string or null), `start_offset`/`end_offset` (bytes in `file`) and `labels` (secondary spans, each with its own `file`, \
         which differs from the diagnostic's when a program in several files points at another one), \
         and, when the compiler knows one, `fixes`: each a `title` and `edits` (`file`, `line`, `column`, `end_line`, \
         `end_column`, `start_offset`, `end_offset`, `replacement`) that apply the did-you-mean or add the missing `END_` line.\n\n\
         | code | severity | title |\n| --- | --- | --- |\n",
    );
    for c in Code::ALL {
        out.push_str(&format!(
            "| [{0}](#{1}) | {2} | {3} |\n",
            c.as_str(),
            c.as_str().to_ascii_lowercase(),
            c.severity().as_str(),
            c.title()
        ));
    }
    for c in Code::ALL {
        out.push_str(&format!(
            "\n## {}\n\n**{}** ({})\n\n{}\n",
            c.as_str(),
            c.title(),
            c.severity().as_str(),
            c.explanation()
        ));
    }
    out.push_str(
        "\n## Target description errors (T codes)\n\n\
         A malformed `--target` folder stops the compiler with exit status 2 and one of these codes:\n\n\
         | code | meaning |\n| --- | --- |\n",
    );
    for t in gutta_catalog::CatalogErrorCode::ALL {
        out.push_str(&format!("| {} | {} |\n", t.as_str(), t.summary()));
    }
    out
}
