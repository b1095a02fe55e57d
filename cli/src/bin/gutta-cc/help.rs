//! `gutta-cc --help` grouped by task: one table gives each subcommand its group, and the
//! help lists the groups with each command's one-line about from its clap metadata. It
//! must not describe a command itself (that is the command's doc comment and examples).

use clap::Command;

/// The tasks the help groups commands by, in the order it shows them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Group {
    Build,
    Online,
    Inspect,
    Shell,
}

impl Group {
    const ALL: [Group; 4] = [Group::Build, Group::Online, Group::Inspect, Group::Shell];

    fn heading(self) -> &'static str {
        match self {
            Group::Build => "Build",
            Group::Online => "Online (talk to a PLC: --tcp, --rtu-tcp or --serial)",
            Group::Inspect => "Inspect",
            Group::Shell => "Shell",
        }
    }
}

/// Every subcommand and its group: a new subcommand is one line here (a test fails when
/// a subcommand is in no group). Rows of commands this build lacks are skipped.
pub(crate) const COMMAND_GROUPS: &[(&str, Group)] = &[
    ("new", Group::Build),
    ("build", Group::Build),
    ("test", Group::Build),
    ("studio", Group::Build),
    ("download", Group::Online),
    ("upload", Group::Online),
    ("status", Group::Online),
    ("run", Group::Online),
    ("stop", Group::Online),
    ("read", Group::Online),
    ("write", Group::Online),
    ("force", Group::Online),
    ("unforce", Group::Online),
    ("watch", Group::Online),
    ("monitor", Group::Online),
    ("debug", Group::Online),
    ("fx", Group::Online),
    ("dis", Group::Inspect),
    ("ladder", Group::Inspect),
    ("modbus", Group::Inspect),
    ("explain", Group::Inspect),
    ("list-targets", Group::Inspect),
    ("completions", Group::Shell),
    ("man", Group::Shell),
    ("help", Group::Shell),
];

/// The pseudo-command of the Build group: source files given without a subcommand.
const FILES_ENTRY: (&str, &str) = (
    "FILE.lad...",
    "Check source files (--check), or compile one into an image (-o DIR, --emit listing)",
);

/// An about's first clause (up to ` (`, `: ` or `. `), for a one-line list.
fn first_clause(about: &str) -> String {
    let end = [" (", ": ", ". "]
        .iter()
        .filter_map(|stop| about.find(stop))
        .min()
        .unwrap_or(about.len());
    about[..end].trim_end_matches('.').to_string()
}

/// The subcommands of `command` that no row of `COMMAND_GROUPS` names.
pub(crate) fn ungrouped(command: &Command) -> Vec<String> {
    let mut command = command.clone();
    command.build();
    command
        .get_subcommands()
        .map(|s| s.get_name().to_string())
        .filter(|name| !COMMAND_GROUPS.iter().any(|(n, _)| n == name))
        .collect()
}

/// `command` whose help lists its subcommands by group (a help template); a subcommand
/// in no group shows under "Other" so it is never hidden.
pub(crate) fn grouped(command: Command) -> Command {
    let mut built = command.clone();
    built.build();
    let about = |name: &str| {
        built
            .find_subcommand(name)
            .and_then(|s| s.get_about())
            .map(|a| first_clause(&a.to_string()))
            .unwrap_or_default()
    };
    let mut sections: Vec<(String, Vec<(String, String)>)> = Vec::new();
    for group in Group::ALL {
        let mut rows: Vec<(String, String)> = Vec::new();
        if group == Group::Build {
            rows.push((FILES_ENTRY.0.to_string(), FILES_ENTRY.1.to_string()));
        }
        for (name, _) in COMMAND_GROUPS.iter().filter(|(_, g)| *g == group) {
            if built.find_subcommand(name).is_some() {
                rows.push((name.to_string(), about(name)));
            }
        }
        sections.push((group.heading().to_string(), rows));
    }
    let other: Vec<(String, String)> = ungrouped(&built)
        .into_iter()
        .map(|name| {
            let text = about(&name);
            (name, text)
        })
        .collect();
    if !other.is_empty() {
        sections.push(("Other".to_string(), other));
    }
    let width = sections
        .iter()
        .flat_map(|(_, rows)| rows.iter().map(|(n, _)| n.len()))
        .max()
        .unwrap_or(0);
    let mut list = String::new();
    for (heading, rows) in sections.iter().filter(|(_, rows)| !rows.is_empty()) {
        list.push_str(&format!("{heading}:\n"));
        for (name, text) in rows {
            list.push_str(&format!("  {name:<width$}  {text}\n"));
        }
        list.push('\n');
    }
    // Braces in an about would read as template tags: none of ours has any.
    let template = format!(
        "{{about-with-newline}}\n{{usage-heading}} {{usage}}\n\n{list}\
         Arguments:\n{{positionals}}\n\nOptions:\n{{options}}{{after-help}}"
    );
    command.help_template(template)
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn every_subcommand_is_in_a_group() {
        let missing = ungrouped(&crate::args::Cli::command());
        assert!(
            missing.is_empty(),
            "subcommands in no group of help.rs COMMAND_GROUPS: {missing:?}"
        );
    }

    #[test]
    fn the_help_lists_each_group_with_its_commands() {
        let help = grouped(crate::args::Cli::command())
            .render_help()
            .to_string();
        for heading in ["Build:", "Online", "Inspect:", "Shell:"] {
            assert!(help.contains(heading), "{heading} missing from:\n{help}");
        }
        assert!(!help.contains("Other:"), "{help}");
        let online = help.find("Online").expect("online");
        let inspect = help.find("Inspect:").expect("inspect");
        let download = help.find("  download").expect("download listed");
        assert!(online < download && download < inspect, "{help}");
    }
}
