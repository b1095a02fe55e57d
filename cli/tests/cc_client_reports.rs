//! What `gutta-cc download` and `upload` report, against a `gutta-sim` process: the
//! download's summary counts the bytes its progress bar counts (every page byte written
//! and read back, so twice the image's page bytes); an upload from a PLC without a
//! program (fresh, or after PLC_CLEAR) says "no program", exits 1 and writes nothing.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use common::{cc, stderr, stdout, Sim};
use gutta_link::transport::TcpTransport;
use gutta_link::{Client, FACTORY_PASSWORD};

/// A fresh scratch path for this test (not created).
fn scratch(tag: &str) -> PathBuf {
    let path = std::env::temp_dir().join(format!("gutta-cc-reports-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&path);
    path
}

/// An example compiled into an image directory.
fn compiled_example(example: &str, tag: &str) -> PathBuf {
    let dir = scratch(tag);
    let source = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples")
        .join(example);
    let o = cc(&[
        source.to_str().expect("path"),
        "-o",
        dir.to_str().expect("path"),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    dir
}

/// The number after `before` in `text` (`before` must occur).
fn number_after(text: &str, before: &str) -> usize {
    let (_, rest) = text
        .split_once(before)
        .unwrap_or_else(|| panic!("no `{before}` in {text}"));
    let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
    digits
        .parse()
        .unwrap_or_else(|_| panic!("no number after `{before}` in {text}"))
}

#[test]
fn the_download_summary_counts_the_bytes_the_bar_counts() {
    let sim = common::sim("CPU-EC20", None);
    // blink.lad has every kind of page: const, argument and instruction pages of three
    // units, a data block and a system block.
    let dir = compiled_example("blink.lad", "summary");
    let files: BTreeMap<String, Vec<u8>> = gutta_io::directory_files(&dir).expect("image dir");
    let pages: Vec<&Vec<u8>> = files
        .iter()
        .filter(|(name, _)| name.as_str() != "manifest.json")
        .map(|(_, bytes)| bytes)
        .collect();
    let page_bytes: usize = pages.iter().map(|p| p.len()).sum();

    let o = cc(&["download", dir.to_str().expect("path"), "--tcp", &sim.1]);
    assert!(o.status.success(), "{}", stderr(&o));
    let summary = stdout(&o);
    assert!(summary.starts_with("downloaded "), "{summary}");
    assert_eq!(
        number_after(&summary, "downloaded "),
        pages.len(),
        "{summary}"
    );
    assert_eq!(
        number_after(&summary, " pages of "),
        page_bytes,
        "{summary}"
    );
    assert_eq!(
        number_after(&summary, " bytes: "),
        2 * page_bytes,
        "the bar's count: every page byte written, then read back: {summary}"
    );
    assert!(
        summary.contains(" bytes written and read back in "),
        "{summary}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `upload -o dir` against a PLC without a program: status 1, the message, and `dir`
/// exactly as it was (absent, or with its old contents).
fn assert_no_program(sim: &Sim, tag: &str) {
    let absent = scratch(&format!("{tag}-absent"));
    let o = cc(&[
        "upload",
        "-o",
        absent.to_str().expect("path"),
        "--tcp",
        &sim.1,
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert_eq!(
        stderr(&o),
        "gutta-cc: no program: the PLC holds no program to upload\n"
    );
    assert_eq!(stdout(&o), "");
    assert!(!absent.exists(), "no directory was created");

    let existing = scratch(&format!("{tag}-existing"));
    std::fs::create_dir_all(&existing).expect("mkdir");
    std::fs::write(existing.join("keep.txt"), b"old").expect("write");
    let before = gutta_io::directory_files(&existing).expect("dir");
    let o = cc(&[
        "upload",
        "-o",
        existing.to_str().expect("path"),
        "--tcp",
        &sim.1,
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert_eq!(gutta_io::directory_files(&existing).expect("dir"), before);
    let _ = std::fs::remove_dir_all(&existing);
}

#[test]
fn an_empty_plc_has_no_program_to_upload() {
    let sim = common::sim("CPU-EC20", None);
    assert_no_program(&sim, "fresh");

    // A downloaded program uploads; after PLC_CLEAR there is none again.
    let dir = compiled_example("in1001_pointers.lad", "cleared");
    let o = cc(&["download", dir.to_str().expect("path"), "--tcp", &sim.1]);
    assert!(o.status.success(), "{}", stderr(&o));
    let back = scratch("cleared-back");
    let o = cc(&[
        "upload",
        "-o",
        back.to_str().expect("path"),
        "--tcp",
        &sim.1,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(back.join("manifest.json").exists());
    let mut client = Client::new(
        Box::new(TcpTransport::connect(&sim.1, 1000, 2).expect("connects")),
        1,
    );
    client.attach(&FACTORY_PASSWORD).expect("logs in");
    client.clear().expect("PLC_CLEAR");
    drop(client);
    assert_no_program(&sim, "cleared");
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&back);
}
