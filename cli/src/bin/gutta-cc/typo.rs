//! Mistyped subcommands. `gutta-cc` takes source files without a subcommand
//! (`gutta-cc main.lad -o image/`), so clap reads any unknown first word as a file and
//! its own did-you-mean never fires; this looks at the first positional word before
//! clap does. For the same reason clap takes a command after a global flag
//! (`gutta-cc --plc X modbus MW0`) for a file, so such flags move after the command. It
//! must not reject a word that names an existing path or looks like a
//! file (an extension or a path separator).

use std::ffi::OsString;
use std::path::Path;

use clap::Command;
use gutta_cli::fatal::Fatal;

/// Check the first positional word of `args` (the program name first) against the
/// subcommands of `command`: a word close to one is `unknown command 'donwload'; did you
/// mean 'download'?`, a word far from all and not a file `no such file or command`.
/// After `help`, the next word is checked the same way (`help donwload`).
pub(crate) fn check_first_word(command: &Command, args: &[OsString]) -> Result<(), Fatal> {
    let mut command = command.clone();
    command.build();
    let Some(i) = first_positional(&command, args) else {
        return Ok(());
    };
    let word = args[i].to_string_lossy().into_owned();
    let names: Vec<&str> = command.get_subcommands().map(|s| s.get_name()).collect();
    let is_command = |word: &str| {
        command
            .get_subcommands()
            .any(|s| s.get_name() == word || s.get_all_aliases().any(|a| a == word))
    };
    // `help WORD`: WORD must be a command, with the same did-you-mean.
    if word == "help" && is_command("help") {
        return match args.get(i + 1).map(|a| a.to_string_lossy()) {
            Some(topic) if !topic.starts_with('-') && !is_command(&topic) => {
                Err(unknown(&topic, &names, true))
            }
            _ => Ok(()),
        };
    }
    if is_command(&word) || looks_like_a_file(&word) {
        return Ok(());
    }
    Err(unknown(&word, &names, false))
}

/// The error for `word`, which is no command: did-you-mean for a near miss; else the
/// commands (`help` takes only those), or a note on source files.
fn unknown(word: &str, names: &[&str], after_help: bool) -> Fatal {
    let lower = word.to_lowercase();
    let closest = names
        .iter()
        .map(|name| (gutta_catalog::edit_distance(&lower, name), *name))
        .min();
    match closest {
        Some((distance, name)) if distance <= allowed_distance(word) => Fatal::usage(format!(
            "unknown command '{word}'; did you mean '{name}'?"
        ))
        .with_hint(if after_help {
            format!("`gutta-cc help {name}` shows its usage")
        } else {
            format!("`gutta-cc {name} --help` shows its usage")
        }),
        _ if after_help => Fatal::usage(format!("no such command '{word}'"))
            .with_hint(format!("commands: {}", names.join(", "))),
        _ => Fatal::usage(format!("no such file or command '{word}'")).with_hint(format!(
            "commands: {}; a source file needs its path or extension (main.lad)",
            names.join(", ")
        )),
    }
}

/// A word that is a path, or could only be one.
fn looks_like_a_file(word: &str) -> bool {
    Path::new(word).exists() || word.contains(['/', '\\', '.']) || word == "-" || word.is_empty()
}

/// How many edits a typo may have: one in a short word, two in a longer one.
fn allowed_distance(word: &str) -> usize {
    if word.chars().count() <= 4 {
        1
    } else {
        2
    }
}

/// `args` with the global flags before a subcommand moved after it (`--plc X modbus
/// MW0` becomes `modbus --plc X MW0`), since clap takes a top-level flag to rule out a
/// subcommand; other arguments as they are.
pub(crate) fn subcommand_first(command: &Command, args: &[OsString]) -> Vec<OsString> {
    let mut command = command.clone();
    command.build();
    let Some(i) = first_positional(&command, args) else {
        return args.to_vec();
    };
    let word = args[i].to_string_lossy();
    let is_command = command
        .get_subcommands()
        .any(|s| s.get_name() == word || s.get_all_aliases().any(|a| a == word));
    // Only global flags may come before a command; anything else (`--check stop`, a
    // file named like a command) stays for clap to judge.
    let all_global = args[1..i].iter().all(|a| {
        let a = a.to_string_lossy();
        match a.strip_prefix("--") {
            Some(long) => {
                let long = long.split('=').next().unwrap_or(long);
                command
                    .get_arguments()
                    .any(|arg| arg.get_long() == Some(long) && arg.is_global_set())
            }
            // An option's value.
            None => !a.starts_with('-'),
        }
    });
    if i <= 1 || !is_command || !all_global {
        return args.to_vec();
    }
    let mut moved = vec![args[0].clone(), args[i].clone()];
    moved.extend_from_slice(&args[1..i]);
    moved.extend_from_slice(&args[i + 1..]);
    moved
}

/// The index in `args` of the first argument that is neither an option nor an option's
/// value (the word after a `--` counts).
fn first_positional(command: &Command, args: &[OsString]) -> Option<usize> {
    let takes_value = |arg: &clap::Arg| arg.get_action().takes_values();
    let mut words = args
        .iter()
        .enumerate()
        .skip(1)
        .map(|(i, a)| (i, a.to_string_lossy().into_owned()));
    while let Some((i, word)) = words.next() {
        if word == "--" {
            return words.next().map(|(i, _)| i);
        }
        if let Some(long) = word.strip_prefix("--") {
            let wants_value = !long.contains('=')
                && command
                    .get_arguments()
                    .any(|a| a.get_long() == Some(long) && takes_value(a));
            if wants_value {
                words.next();
            }
        } else if let Some(shorts) = word.strip_prefix('-').filter(|s| !s.is_empty()) {
            let mut chars = shorts.chars();
            let wants_value = chars.next().is_some_and(|c| {
                command
                    .get_arguments()
                    .any(|a| a.get_short() == Some(c) && takes_value(a))
            }) && chars.next().is_none();
            if wants_value {
                words.next();
            }
        } else {
            return Some(i);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_swap_is_one_edit() {
        assert_eq!(gutta_catalog::edit_distance("donwload", "download"), 1);
        assert_eq!(gutta_catalog::edit_distance("stats", "status"), 1);
        assert_eq!(gutta_catalog::edit_distance("xyz", "dis"), 3);
    }

    #[test]
    fn option_values_are_not_the_first_word() {
        let command = clap::Command::new("t")
            .arg(clap::Arg::new("plc").long("plc"))
            .arg(clap::Arg::new("o").short('o'))
            .arg(
                clap::Arg::new("check")
                    .long("check")
                    .action(clap::ArgAction::SetTrue),
            )
            .arg(clap::Arg::new("files").num_args(0..));
        let args = |s: &str| -> Vec<OsString> { s.split(' ').map(OsString::from).collect() };
        let first = |s: &str| first_positional(&command, &args(s));
        assert_eq!(first("t --plc X donwload"), Some(3));
        assert_eq!(first("t -o DIR --check main"), Some(4));
        assert_eq!(first("t --plc=X -- file"), Some(3));
        assert_eq!(first("t --check"), None);
    }
}
