//! The three tools spell their shared flags alike: every flag of the table in
//! gutta_cli::flags (docs/cli.md, "Shared flags") shows in the `--help` of each tool
//! that takes it with the table's value name, and a tool outside the table's list
//! that has the flag anyway spells its value the same.

use std::process::Command;

use gutta_cli::flags::SHARED_FLAGS;

/// Everything `--help` says about a tool's flags: gutta-cc's own and a client
/// command's (the link flags belong to the client commands).
fn help_of(tool: &str) -> String {
    let run = |args: &[&str]| {
        let bin = match tool {
            "gutta-cc" => env!("CARGO_BIN_EXE_gutta-cc"),
            "gutta-vm" => env!("CARGO_BIN_EXE_gutta-vm"),
            _ => env!("CARGO_BIN_EXE_gutta-sim"),
        };
        let out = Command::new(bin).args(args).output().expect("runs");
        assert!(out.status.success(), "{tool} {args:?}");
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    match tool {
        "gutta-cc" => run(&["--help"]) + &run(&["status", "--help"]),
        _ => run(&["--help"]),
    }
}

/// How `--help` shows the flag: `--tcp <HOST:PORT>`, or `--man` alone.
fn shown(long: &str, value_name: Option<&str>) -> String {
    match value_name {
        Some(v) => format!("--{long} <{v}>"),
        None => format!("--{long}\n"),
    }
}

#[test]
fn shared_flags_have_one_spelling() {
    for tool in ["gutta-cc", "gutta-vm", "gutta-sim"] {
        let help = help_of(tool);
        for flag in SHARED_FLAGS {
            let expected = shown(flag.long, flag.value_name);
            if flag.tools.contains(&tool) {
                assert!(
                    help.contains(&expected),
                    "{tool} lacks `{expected}`:\n{help}"
                );
            } else if help.contains(&format!("--{} ", flag.long))
                || help.contains(&format!("--{} <", flag.long))
            {
                assert!(
                    help.contains(&expected),
                    "{tool} spells --{} unlike `{expected}`",
                    flag.long
                );
            }
        }
    }
}

#[test]
fn the_old_json_switch_of_gutta_vm_is_hidden_but_works() {
    let help = help_of("gutta-vm");
    assert!(!help.contains("--json"), "{help}");
    let out = Command::new(env!("CARGO_BIN_EXE_gutta-vm"))
        .args(["/no/such/image", "--json"])
        .output()
        .expect("runs");
    let error: serde_json::Value =
        serde_json::from_slice(&out.stdout).expect("a JSON error with --json");
    assert_eq!(error["type"], "error");
}

#[test]
fn the_table_in_docs_cli_md_is_the_table_in_the_code() {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/cli.md"))
        .expect("docs/cli.md");
    for flag in SHARED_FLAGS {
        let value = flag.value_name.map(|v| format!(" {v}")).unwrap_or_default();
        let row = format!(
            "| `--{}{value}` | {} | {} |",
            flag.long,
            flag.tools.join(", "),
            flag.meaning
        );
        assert!(doc.contains(&row), "docs/cli.md lacks the row\n{row}");
    }
}
