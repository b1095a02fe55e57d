//! Which PLC type applies is decided once, by `gutta_catalog::choose_target`, whose
//! `TargetOrigin` words where the choice came from (issue 25, point 1). This test keeps
//! it so: outside catalog/src/choice.rs no source of a tool, the language server or the
//! compiler spells an origin ("in gutta.toml", "in the test file", "the image in") or
//! declares `--plc`/`--target` itself.

use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

fn sources(dir: &Path, into: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            sources(&path, into);
        } else if path.extension().is_some_and(|x| x == "rs") {
            into.push(path);
        }
    }
}

/// The words only `TargetOrigin`'s Display may write, and the clap declaration of
/// `--plc` only `gutta_cli::target::TargetArgs` may hold.
const ONE_HOME: [(&str, &str); 5] = [
    (" in gutta.toml\"", "catalog/src/choice.rs"),
    ("] {key} in gutta.toml", "catalog/src/choice.rs"),
    ("in the test file\"", "catalog/src/choice.rs"),
    ("\"the image in ", "catalog/src/choice.rs"),
    ("value_parser = crate::flags::PlcName", "cli/src/target.rs"),
];

#[test]
fn the_target_rule_and_its_wording_live_in_one_place() {
    let mut files = Vec::new();
    for dir in [
        "catalog/src",
        "compiler/src",
        "cli/src",
        "lsp/src",
        "gtest/src",
        "io/src",
    ] {
        sources(&root().join(dir), &mut files);
    }
    for (needle, home) in ONE_HOME {
        let found: Vec<String> = files
            .iter()
            .filter(|f| {
                std::fs::read_to_string(f)
                    .unwrap_or_else(|e| panic!("{}: {e}", f.display()))
                    .contains(needle)
            })
            .map(|f| f.strip_prefix(root()).unwrap_or(f).display().to_string())
            .collect();
        assert!(
            found.iter().all(|f| f == home),
            "`{needle}` belongs in {home} only, and is also in {found:?}"
        );
    }
    let plc_flags = files
        .iter()
        .filter(|f| {
            std::fs::read_to_string(f)
                .unwrap_or_default()
                .contains("flags::PlcName")
        })
        .count();
    assert_eq!(plc_flags, 1, "--plc is declared once, in cli/src/target.rs");
}
