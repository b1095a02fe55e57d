//! "No I/O in the libraries" is enforced by one clippy configuration that every library
//! package holds a copy of (clippy reads only the clippy.toml of the package it lints).
//! This test keeps the copies equal, keeps the root's shared settings in them, and makes
//! sure a new workspace package is either a library with the copy or named here as one
//! of the packages whose job is I/O.

use std::path::Path;

/// The library packages: no I/O (link's transport module alone allows it).
const LIBRARIES: [&str; 11] = [
    "catalog", "format", "compiler", "analysis", "vm", "protocol", "sim", "link", "gtest",
    "ladder", "jit",
];

/// The packages whose job is I/O: the binaries, the binaries' shared file I/O, and the
/// benchmark programs (their build script writes the generated sources).
const DOING_IO: [&str; 4] = ["cli", "io", "bench-native", "lsp"];

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn every_library_holds_the_same_no_io_configuration() {
    let first = read(&root().join(LIBRARIES[0]).join("clippy.toml"));
    for package in LIBRARIES {
        let text = read(&root().join(package).join("clippy.toml"));
        assert_eq!(
            text, first,
            "{package}/clippy.toml differs from {}/clippy.toml: edit every copy alike",
            LIBRARIES[0]
        );
    }
    for needed in [
        "disallowed-methods",
        "std::fs::read",
        "std::net::TcpStream",
        "std::process::Command",
    ] {
        assert!(
            first.contains(needed),
            "the library clippy.toml lost {needed}"
        );
    }
}

#[test]
fn the_libraries_keep_the_shared_settings_of_the_root() {
    let library = read(&root().join(LIBRARIES[0]).join("clippy.toml"));
    for line in read(&root().join("clippy.toml")).lines() {
        let setting = line.trim();
        if setting.is_empty() || setting.starts_with('#') {
            continue;
        }
        assert!(
            library.lines().any(|l| l.trim() == setting),
            "the library clippy.toml lacks the root's `{setting}`"
        );
    }
}

#[test]
fn every_workspace_package_is_a_library_or_named_as_doing_io() {
    let manifest = read(&root().join("Cargo.toml"));
    let members = manifest
        .lines()
        .find_map(|l| l.trim().strip_prefix("members = ["))
        .expect("the workspace lists its members on one line");
    for member in members.trim_end_matches(']').split(',') {
        let member = member.trim().trim_matches('"');
        assert!(
            LIBRARIES.contains(&member) || DOING_IO.contains(&member),
            "workspace member {member}: add it to LIBRARIES (and copy catalog/clippy.toml \
             into it) or, if its job is I/O, to DOING_IO in {}",
            file!()
        );
        if DOING_IO.contains(&member) {
            assert!(
                !root().join(member).join("clippy.toml").exists(),
                "{member} does I/O by design: it takes the root clippy.toml"
            );
        }
    }
}
