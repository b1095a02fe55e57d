//! Whether human output is coloured: `--color auto|always|never` and the NO_COLOR
//! convention of no-color.org (set and non-empty: no colour by default; an empty value
//! is ignored; `--color always` still wins). It must not print anything itself.

/// The `--color` flag's values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ColorChoice {
    /// Colour on a terminal, unless NO_COLOR is set to a non-empty value.
    Auto,
    Always,
    Never,
}

/// The environment variable of no-color.org.
pub const NO_COLOR: &str = "NO_COLOR";

/// NO_COLOR is set to a non-empty value (an empty one is ignored, as no-color.org says).
pub fn no_color_requested() -> bool {
    std::env::var_os(NO_COLOR).is_some_and(|v| !v.is_empty())
}

/// Whether to colour output for a stream that is (or is not) a terminal.
pub fn use_color(choice: ColorChoice, stream_is_terminal: bool) -> bool {
    match choice {
        ColorChoice::Always => true,
        ColorChoice::Never => false,
        ColorChoice::Auto => stream_is_terminal && !no_color_requested(),
    }
}

/// The same choice for clap's own help and errors.
pub fn clap_color(choice: ColorChoice) -> clap::ColorChoice {
    match choice {
        ColorChoice::Always => clap::ColorChoice::Always,
        ColorChoice::Never => clap::ColorChoice::Never,
        ColorChoice::Auto if no_color_requested() => clap::ColorChoice::Never,
        ColorChoice::Auto => clap::ColorChoice::Auto,
    }
}

/// The `--color` value in the raw arguments (read before clap; the last one wins).
pub fn from_raw_args(args: &[std::ffi::OsString]) -> ColorChoice {
    let mut choice = ColorChoice::Auto;
    let mut words = args.iter().skip(1).map(|a| a.to_string_lossy());
    while let Some(word) = words.next() {
        let value = if word == "--" {
            break;
        } else if word == "--color" {
            words.next().map(|v| v.into_owned())
        } else {
            word.strip_prefix("--color=").map(str::to_string)
        };
        match value.as_deref() {
            Some("always") => choice = ColorChoice::Always,
            Some("never") => choice = ColorChoice::Never,
            Some("auto") => choice = ColorChoice::Auto,
            _ => {}
        }
    }
    choice
}
