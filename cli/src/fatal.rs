//! A fatal error of a command-line tool (exit status 2): its kind, message and hint,
//! printed as one `tool: error: ...` line or as one JSON object on stdout with
//! `--message-format json` (docs/cli.md, "Errors as JSON"), clap's usage errors
//! included. It must not decide what is an error; the tools do.

use std::ffi::OsString;
use std::io::Write;
use std::process::ExitCode;

/// What went wrong, for scripts: the `kind` field of the JSON error object. The names
/// are stable (docs/cli.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// Arguments that do not make sense: an unknown command or flag, a bad value.
    Usage,
    /// A file or directory that cannot be read or written.
    Io,
    /// Talking to a PLC: cannot connect, no answer, the PLC refused.
    Link,
    /// An image or program that does not verify, load or fit the PLC.
    Program,
    /// A PLC type or target folder that cannot be loaded.
    Target,
    /// Not yet classified (the `Fatal(message)` shorthand).
    Other,
}

impl ErrorKind {
    /// The stable name in JSON.
    pub fn name(self) -> &'static str {
        match self {
            ErrorKind::Usage => "usage",
            ErrorKind::Io => "io",
            ErrorKind::Link => "link",
            ErrorKind::Program => "program",
            ErrorKind::Target => "target",
            ErrorKind::Other => "other",
        }
    }
}

/// A fatal error: printed, exit status 2.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Fatal {
    pub kind: ErrorKind,
    pub message: String,
    /// What to try next, when the tool knows.
    pub hint: Option<String>,
}

/// `Fatal(message)`: the shorthand older call sites use (`Fatal(format!(..))`,
/// `.map_err(Fatal)`), of kind `other`. New code names the kind: `Fatal::usage(..)`,
/// `Fatal::io(..)`, `Fatal::link(..)`, `Fatal::program(..)`, `Fatal::target(..)`.
#[allow(non_snake_case)]
pub fn Fatal(message: String) -> Fatal {
    Fatal::new(ErrorKind::Other, message)
}

impl Fatal {
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Fatal {
        Fatal {
            kind,
            message: message.into(),
            hint: None,
        }
    }
    pub fn usage(message: impl Into<String>) -> Fatal {
        Fatal::new(ErrorKind::Usage, message)
    }
    pub fn io(message: impl Into<String>) -> Fatal {
        Fatal::new(ErrorKind::Io, message)
    }
    pub fn link(message: impl Into<String>) -> Fatal {
        Fatal::new(ErrorKind::Link, message)
    }
    pub fn program(message: impl Into<String>) -> Fatal {
        Fatal::new(ErrorKind::Program, message)
    }
    pub fn target(message: impl Into<String>) -> Fatal {
        Fatal::new(ErrorKind::Target, message)
    }

    /// The same error with a hint (`hint: ...` under the message; `"hint"` in JSON).
    pub fn with_hint(mut self, hint: impl Into<String>) -> Fatal {
        self.hint = Some(hint.into());
        self
    }

    /// The JSON object: `{"type":"error","tool":..,"kind":..,"message":..,"hint":..}`.
    pub fn to_json(&self, tool: &str) -> serde_json::Value {
        serde_json::json!({
            "type": "error",
            "tool": tool,
            "kind": self.kind.name(),
            "message": self.message,
            "hint": self.hint,
        })
    }

    /// Print the error as `format` asks (human text on stderr, JSON on stdout) and give
    /// the exit status: 2.
    pub fn report(&self, tool: &str, format: MessageFormat) -> ExitCode {
        match format {
            MessageFormat::Json => {
                let mut out = std::io::stdout().lock();
                let _ = writeln!(out, "{}", self.to_json(tool));
                let _ = out.flush();
            }
            MessageFormat::Human => {
                let mut err = std::io::stderr().lock();
                let _ = writeln!(err, "{tool}: error: {}", self.message);
                if let Some(hint) = &self.hint {
                    let _ = writeln!(err, "  hint: {hint}");
                }
            }
        }
        ExitCode::from(2)
    }
}

/// How a tool prints its results, diagnostics and errors (`--message-format`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum MessageFormat {
    /// Text for people: results on stdout, errors on stderr.
    Human,
    /// One JSON object per line on stdout, errors included.
    Json,
}

impl MessageFormat {
    /// The format the raw arguments ask for, read before (or without) clap: JSON when
    /// `--message-format json` (or `=json`) or one of `json_flags` (gutta-vm's `--json`)
    /// comes before a `--`; the last `--message-format` wins.
    pub fn from_raw_args(args: &[OsString], json_flags: &[&str]) -> MessageFormat {
        let mut format = MessageFormat::Human;
        let mut words = args.iter().skip(1).map(|a| a.to_string_lossy());
        while let Some(word) = words.next() {
            let value = if word == "--" {
                break;
            } else if word == "--message-format" {
                words.next().map(|v| v.into_owned())
            } else if let Some(v) = word.strip_prefix("--message-format=") {
                Some(v.to_string())
            } else if json_flags.contains(&word.as_ref()) {
                Some("json".to_string())
            } else {
                None
            };
            match value.as_deref() {
                Some("json") => format = MessageFormat::Json,
                Some(_) => format = MessageFormat::Human,
                None => {}
            }
        }
        format
    }
}

/// A clap parse failure as a usage error: `--help` and `--version` print and exit 0;
/// an error prints as clap renders it (human) or as one JSON object of kind `usage`;
/// exit status 2.
pub fn report_clap_error(error: clap::Error, tool: &str, format: MessageFormat) -> ExitCode {
    use clap::error::ErrorKind as Clap;
    match error.kind() {
        Clap::DisplayHelp | Clap::DisplayVersion => {
            let _ = error.print();
            ExitCode::SUCCESS
        }
        Clap::DisplayHelpOnMissingArgumentOrSubcommand => {
            let _ = error.print();
            ExitCode::from(2)
        }
        _ if format == MessageFormat::Human => {
            let _ = error.print();
            ExitCode::from(2)
        }
        _ => usage_from_clap(&error).report(tool, format),
    }
}

/// clap's rendered error as a `Fatal`: its first paragraph (after `error: `) is the
/// message; its tips, or else its usage line, the hint.
pub fn usage_from_clap(error: &clap::Error) -> Fatal {
    let text = error.render().to_string();
    let mut paragraphs = text.split("\n\n").map(|p| {
        p.lines()
            .map(str::trim)
            .filter(|l| !l.is_empty())
            .collect::<Vec<_>>()
            .join(" ")
    });
    let first = paragraphs.next().unwrap_or_default();
    let message = first.strip_prefix("error: ").unwrap_or(&first).to_string();
    let rest: Vec<String> = paragraphs.filter(|p| !p.is_empty()).collect();
    let tips: Vec<&str> = rest
        .iter()
        .filter_map(|p| p.strip_prefix("tip: "))
        .collect();
    let hint = if tips.is_empty() {
        rest.iter().find(|p| p.starts_with("Usage:")).cloned()
    } else {
        Some(tips.join("; "))
    };
    Fatal {
        kind: ErrorKind::Usage,
        message,
        hint,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(line: &str) -> Vec<OsString> {
        line.split(' ').map(OsString::from).collect()
    }

    #[test]
    fn the_raw_flag_is_found_anywhere_before_a_double_dash() {
        let format = |line: &str| MessageFormat::from_raw_args(&args(line), &["--json"]);
        assert_eq!(format("t read --message-format json"), MessageFormat::Json);
        assert_eq!(format("t --message-format=json x"), MessageFormat::Json);
        assert_eq!(format("t --json x"), MessageFormat::Json);
        assert_eq!(
            format("t --message-format json --message-format human"),
            MessageFormat::Human
        );
        assert_eq!(format("t -- --message-format json"), MessageFormat::Human);
        assert_eq!(format("t x"), MessageFormat::Human);
    }

    #[test]
    fn a_clap_error_becomes_a_usage_error_with_a_hint() {
        let error = clap::Command::new("t")
            .try_get_matches_from(["t", "--bogus"])
            .expect_err("unknown flag");
        let fatal = usage_from_clap(&error);
        assert_eq!(fatal.kind, ErrorKind::Usage);
        assert_eq!(fatal.message, "unexpected argument '--bogus' found");
        assert!(fatal.hint.is_some_and(|h| h.starts_with("Usage: t")));
        let json = Fatal::io("cannot read x")
            .with_hint("check the path")
            .to_json("t");
        assert_eq!(json["type"], "error");
        assert_eq!(json["kind"], "io");
        assert_eq!(json["hint"], "check the path");
    }
}
