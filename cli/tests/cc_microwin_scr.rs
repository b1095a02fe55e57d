//! The S area of sequence control relays through the real binary (docs/microwin.md,
//! "Sequence control relays"): by default SB0 is the last 32 bytes of M (MB96 on
//! CPU-EC20); `--s-area` and a project's `[microwin] s_area` move it (the image's
//! disassembly says where `S0.1` went, the summary says it too); a value that is no
//! byte address is a usage error, one the target cannot hold is E0224.

mod common;

use common::{cc, cc_in, stderr, stdout};

use std::path::{Path, PathBuf};

/// A fresh directory for this test.
fn scratch(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "gutta-cc-microwin-scr-{tag}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("creates the scratch directory");
    dir
}

const EXPORT: &str = "ORGANIZATION_BLOCK MAIN:OB1\r\nTITLE=SCR\r\nBEGIN\r\n\
Network 1\r\nLD     SM0.1\r\nS      S0.0, 1\r\nNetwork 2\r\nLSCR   S0.0\r\n\
Network 3\r\nLD     I0.0\r\nSCRT   S0.1\r\nNetwork 4\r\nSCRE\r\nEND_ORGANIZATION_BLOCK\r\n";

/// The disassembly of an image.
fn dis(image: &Path) -> String {
    let o = cc(&["dis", image.to_str().expect("path")]);
    assert!(o.status.success(), "{}", stderr(&o));
    stdout(&o)
}

#[test]
fn the_flag_moves_the_s_area_and_a_bad_value_is_refused() {
    let dir = scratch("flag");
    let source = dir.join("main.awl");
    std::fs::write(&source, EXPORT).expect("writes the export");
    let source = source.to_str().expect("path");

    let plain = dir.join("plain");
    let o = cc(&[source, "-o", plain.to_str().expect("path")]);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("S area: S0.0-S0.7 in MB96 (SB0 = MB96; the default: the last 32 bytes of M)"),
        "{err}"
    );
    assert!(dis(&plain).contains("M96.1"), "{}", dis(&plain));

    let moved = dir.join("moved");
    let o = cc(&[
        source,
        "--s-area",
        "MB20",
        "-o",
        moved.to_str().expect("path"),
    ]);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("(SB0 = MB20; as chosen)"), "{err}");
    let text = dis(&moved);
    assert!(text.contains("M20.1") && !text.contains("M96"), "{text}");

    // No byte address: a usage error of the flag.
    let o = cc(&[source, "--s-area", "M20.0"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("not a byte address such as MB96"),
        "{}",
        stderr(&o)
    );
    // A byte address the target cannot hold the S area at: E0224 at the S operand.
    let o = cc(&[source, "--s-area", "IB0"]);
    let err = stderr(&o);
    assert!(!o.status.success());
    assert!(
        err.contains("[E0224]")
            && err.contains("area I is not a writable, bit-addressable global area"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_project_places_the_s_area_from_its_manifest() {
    let dir = scratch("project");
    std::fs::create_dir_all(dir.join("src")).expect("creates src");
    std::fs::write(dir.join("src/main.awl"), EXPORT).expect("writes the export");
    std::fs::write(
        dir.join("gutta.toml"),
        "[program]\nsources = [\"src/main.awl\"]\n\n[microwin]\ns_area = \"MB40\"\n",
    )
    .expect("writes the manifest");
    let o = cc_in(&dir, &["build"]);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("(SB0 = MB40; as chosen)"), "{err}");
    assert!(dis(&dir.join("target/image")).contains("M40.1"));

    // A value that is no byte address is refused where it stands.
    std::fs::write(
        dir.join("gutta.toml"),
        "[program]\nsources = [\"src/main.awl\"]\n\n[microwin]\ns_area = \"M40\"\n",
    )
    .expect("writes the manifest");
    let o = cc_in(&dir, &["build"]);
    let err = stderr(&o);
    assert!(!o.status.success());
    assert!(
        err.contains("[microwin] s_area `M40` is not a byte address"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
