//! Human rendering of diagnostics with ariadne: the only module that knows ariadne.
//! Colour is decided by the caller (off when stderr is not a terminal or NO_COLOR is
//! set); the ASCII style is used for snapshots.

use ariadne::{sources, CharSet, Config, IndexType, Label, Report, ReportKind, Source};

use crate::diagnostics::{Diagnostic, Severity};
use crate::source::SourceFile;

/// How to draw.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RenderStyle {
    pub color: bool,
    /// Box-drawing characters (true) or plain ASCII (false).
    pub unicode: bool,
}

impl RenderStyle {
    /// No colour, ASCII: stable text for tests and logs.
    pub const PLAIN: RenderStyle = RenderStyle {
        color: false,
        unicode: false,
    };
}

fn config(style: RenderStyle) -> Config {
    Config::default()
        .with_color(style.color)
        .with_char_set(if style.unicode {
            CharSet::Unicode
        } else {
            CharSet::Ascii
        })
        .with_index_type(IndexType::Byte)
}

fn kind(d: &Diagnostic) -> ReportKind<'static> {
    match d.severity {
        Severity::Error => ReportKind::Error,
        Severity::Warning => ReportKind::Warning,
    }
}

/// Render diagnostics of one file, or of a program in several files (each label in
/// its own file), to a string.
pub fn render(file: &SourceFile, diagnostics: &[Diagnostic], style: RenderStyle) -> String {
    if file.is_joined() {
        return render_joined(file, diagnostics, style);
    }
    let mut out = Vec::new();
    let name = file.name.as_str();
    let source = Source::from(file.text.as_str());
    let config = config(style);
    let clamp = |r: std::ops::Range<usize>| {
        let end = r.end.min(file.text.len());
        r.start.min(end)..end
    };
    for d in diagnostics {
        let primary = clamp(d.primary.span.range());
        let mut report = Report::build(kind(d), (name, primary.clone()))
            .with_config(config)
            .with_code(d.code.as_str())
            .with_message(&d.message);
        // ariadne underlines only labelled spans: every primary span gets a text.
        let text = d.primary.message.as_deref().unwrap_or("here");
        let label = Label::new((name, primary)).with_message(text);
        report = report.with_label(label.with_order(0));
        for (i, s) in d.secondary.iter().enumerate() {
            let mut label = Label::new((name, clamp(s.span.range()))).with_order(i as i32 + 1);
            if let Some(m) = &s.message {
                label = label.with_message(m);
            }
            report = report.with_label(label);
        }
        if let Some(h) = &d.help {
            report = report.with_help(h);
        }
        // Writing to a Vec cannot fail; a failure would only lose this report's text.
        let _ = report.finish().write((name, &source), &mut out);
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// `render` for a joined text: every span becomes (its file's name, range in that file).
///
/// A report with labels in more than one file is given to ariadne in char offsets
/// (`IndexType::Char`): with byte offsets ariadne 0.6 takes the char offset of the first
/// label in another file than the report's for a byte offset when it prints that file's
/// `name:line:col`, and panics slicing inside a multibyte character (a GBK export's
/// Chinese name before an "also used here" label; tests/data/fuzz/microwin/).
fn render_joined(file: &SourceFile, diagnostics: &[Diagnostic], style: RenderStyle) -> String {
    let parts = file.parts();
    let mut cache = sources(parts.iter().map(|p| {
        let end = (p.end + 1).min(file.text.len());
        (p.name.clone(), file.text.get(p.start..end).unwrap_or(""))
    }));
    let place = |span: crate::source::Span, chars: bool| {
        let range = file.part_range(span.start as usize);
        let end = (span.end as usize).clamp(range.start, range.end);
        let start = (span.start as usize).min(end);
        let offset = |at: usize| match chars {
            true => char_count(&file.text, range.start, at),
            false => at - range.start,
        };
        (
            file.file_name_at(span.start as usize).to_string(),
            offset(start)..offset(end),
        )
    };
    let mut out = Vec::new();
    for d in diagnostics {
        let name = |s: crate::source::Span| file.file_name_at(s.start as usize);
        let chars = d
            .secondary
            .iter()
            .any(|s| name(s.span) != name(d.primary.span));
        let index_type = if chars {
            IndexType::Char
        } else {
            IndexType::Byte
        };
        let primary = place(d.primary.span, chars);
        let mut report = Report::build(kind(d), primary.clone())
            .with_config(config(style).with_index_type(index_type))
            .with_code(d.code.as_str())
            .with_message(&d.message);
        let text = d.primary.message.as_deref().unwrap_or("here");
        report = report.with_label(Label::new(primary).with_message(text).with_order(0));
        for (i, s) in d.secondary.iter().enumerate() {
            let mut label = Label::new(place(s.span, chars)).with_order(i as i32 + 1);
            if let Some(m) = &s.message {
                label = label.with_message(m);
            }
            report = report.with_label(label);
        }
        if let Some(h) = &d.help {
            report = report.with_help(h);
        }
        let _ = report.finish().write(&mut cache, &mut out);
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// The number of chars in `text[from..to]`, `to` rounded down to a char boundary.
fn char_count(text: &str, from: usize, to: usize) -> usize {
    let mut to = to.min(text.len());
    while !text.is_char_boundary(to) {
        to -= 1;
    }
    text.get(from..to).map_or(0, |t| t.chars().count())
}
