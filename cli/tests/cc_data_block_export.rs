//! Micro/WIN data block exports through the real binaries (docs/microwin.md, "Data
//! block exports"): `gutta-cc` takes a `DATA_BLOCK_TAB` file named `.txt` among the
//! sources of a program and of a project (`[program] sources`), reads it in its code
//! page, and `gutta-vm` finds each value at its address after the image is loaded; on a
//! target without V every row is refused at its line.

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{cc, cc_in, scratch, stderr, stdout};

fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/microwin")
}

/// `gutta-vm IMAGE --scans 1 --read ...`: each variable's value as printed.
fn read_after_load(image: &Path, vars: &[&str]) -> Vec<(String, String)> {
    let mut args = vec![
        image.to_str().expect("path").to_string(),
        "--scans".into(),
        "1".into(),
    ];
    for v in vars {
        args.extend(["--read".to_string(), v.to_string()]);
    }
    let o = Command::new(env!("CARGO_BIN_EXE_gutta-vm"))
        .args(&args)
        .output()
        .expect("gutta-vm runs");
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    vars.iter()
        .map(|v| {
            let line = out
                .lines()
                .find(|l| l.starts_with(&format!("{v} ")))
                .unwrap_or_else(|| panic!("no {v} in\n{out}"));
            let value = line.rsplit_once("= ").map(|(_, x)| x).unwrap_or("");
            (v.to_string(), value.to_string())
        })
        .collect()
}

/// After load, each variable of `expected` holds its value (as gutta-vm prints it).
fn assert_values(image: &Path, expected: &[(&str, String)]) {
    let vars: Vec<&str> = expected.iter().map(|(v, _)| *v).collect();
    let want: Vec<(String, String)> = expected
        .iter()
        .map(|(v, x)| (v.to_string(), x.clone()))
        .collect();
    assert_eq!(read_after_load(image, &vars), want);
}

/// `files` of the corpus compiled on EC30-EKSTM32-XC (a target with V) into a scratch
/// image, which must succeed: the scratch folder, the image and gutta-cc's stderr.
fn compile_on_ec30(tag: &str, files: &[&str]) -> (PathBuf, PathBuf, String) {
    let dir = scratch(tag);
    let image = dir.join("image");
    let mut args = files.to_vec();
    args.extend([
        "--plc",
        "EC30-EKSTM32-XC",
        "-o",
        image.to_str().expect("path"),
    ]);
    let o = cc_in(&corpus(), &args);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    (dir, image, err)
}

#[test]
fn every_kind_of_value_is_in_memory_after_load() {
    let (dir, image, err) = compile_on_ec30(
        "data-block-values",
        &["data_block_program.awl", "data_block_utf8_crlf.txt"],
    );
    assert!(err.contains("2 files: wrote"), "{err}");
    // 20 values (a character, a string length one each) in one data block (128 rows on EC30-EKSTM32-XC).
    assert!(err.contains("data 1 page / 16, 20 items"), "{err}");
    let expected = [
        ("VB20", "7".to_string()),
        ("VW28", "15".into()),
        ("VD32", "100000".into()),
        ("VB40", "1".into()),
        ("VB41", "2".into()),
        ("VB42", "3".into()),
        ("VB43", "4".into()),
        // -5 as a byte
        ("VB44", "251".into()),
        ("VW50", "255".into()),
        ("VW52", "10".into()),
        ("VD60", 1.5f32.to_bits().to_string()),
        ("VB70", "65".into()),
        ("VB71", "66".into()),
        // "Hi": length 2, then H and i
        ("VB80", "2".into()),
        ("VB81", "72".into()),
        ("VB82", "105".into()),
        ("VW90", "-2".into()),
        ("VW92", "-1".into()),
        ("VD100", (-1000.0f32).to_bits().cast_signed().to_string()),
        ("VD104", "-1".into()),
        // The program ran its one scan: the data block is no code.
        ("MW0", "1".into()),
    ];
    assert_values(&image, &expected);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_gbk_export_is_read_in_its_code_page() {
    let (dir, image, err) = compile_on_ec30(
        "data-block-gbk",
        &["data_block_gbk_crlf.txt", "data_block_program.awl"],
    );
    assert!(
        err.contains("note: data_block_gbk_crlf.txt is not UTF-8; read as GBK"),
        "{err}"
    );
    let expected = [
        ("VW0", "1000".to_string()),
        ("VW2", "-1".into()),
        ("VB10", "79".into()),
        ("VB11", "75".into()),
        ("VD12", 3.25f32.to_bits().to_string()),
    ];
    assert_values(&image, &expected);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_project_lists_the_export_among_its_sources() {
    let dir = scratch("data-block-project");
    std::fs::create_dir_all(dir.join("src")).expect("src");
    for (from, to) in [
        ("data_block_program.awl", "src/MAIN.awl"),
        ("data_block_utf8_crlf.txt", "src/DB1.txt"),
    ] {
        std::fs::copy(corpus().join(from), dir.join(to)).expect("copy");
    }
    std::fs::write(
        dir.join("gutta.toml"),
        "[program]\nplc = \"EC30-EKSTM32-XC\"\nsources = [\"src/MAIN.awl\", \"src/DB1.txt\"]\n",
    )
    .expect("gutta.toml");
    let o = cc_in(&dir, &["build"]);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    let image = dir.join("target/image");
    assert!(image.is_dir(), "{err}");
    assert_values(
        &image,
        &[("VW28", "15".to_string()), ("VD32", "100000".into())],
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn without_v_every_row_is_refused_at_its_line() {
    let program = corpus().join("data_block_program.awl");
    let export = corpus().join("data_block_cp1252_crlf.txt");
    let dir = scratch("data-block-no-v");
    let image = dir.join("image");
    let o = cc(&[
        program.to_str().expect("path"),
        export.to_str().expect("path"),
        "-o",
        image.to_str().expect("path"),
    ]);
    let err = stderr(&o);
    assert!(!o.status.success(), "{err}");
    assert!(err.contains("read as Windows-1252"), "{err}");
    assert_eq!(
        err.matches("CPU-EC20 has no memory area V").count(),
        2,
        "{err}"
    );
    assert!(err.contains("data_block_cp1252_crlf.txt:8:1"), "{err}");
    assert!(err.contains("data_block_cp1252_crlf.txt:9:1"), "{err}");
    assert!(err.contains("area V exists on EC30-EKSTM32-XC"), "{err}");
    assert!(!image.exists(), "no image with errors");
    let _ = std::fs::remove_dir_all(&dir);
}
