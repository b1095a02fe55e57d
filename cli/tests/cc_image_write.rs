//! Writing images as users run it: `gutta-cc FILE -o DIR`. Output is byte-identical from
//! run to run; a failed compile leaves the previous image untouched; a directory that is
//! not an image is never overwritten; limits give coded diagnostics naming the limit.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn gutta_cc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gutta-cc"))
        .args(args)
        .current_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join(".."))
        .output()
        .expect("run gutta-cc")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gutta-image-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

/// Every file of a directory tree with its bytes, sorted by relative path.
fn snapshot(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).expect("read dir") {
            let p = e.expect("entry").path();
            if p.is_dir() {
                stack.push(p);
            } else {
                let rel = p
                    .strip_prefix(dir)
                    .expect("prefix")
                    .to_string_lossy()
                    .into_owned();
                out.push((rel, std::fs::read(&p).expect("read")));
            }
        }
    }
    out.sort();
    out
}

#[test]
fn images_are_byte_identical_across_runs() {
    let root = scratch("determinism");
    let (a, b) = (root.join("a"), root.join("b"));
    for dir in [&a, &b] {
        let out = gutta_cc(&[
            "examples/an2002_sample3_master.lad",
            "-o",
            dir.to_str().expect("utf-8"),
        ]);
        assert_eq!(
            out.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let (sa, sb) = (snapshot(&a), snapshot(&b));
    assert!(
        sa.iter().any(|(f, _)| f == "manifest.json") && sa.len() >= 5,
        "{:?}",
        sa.iter().map(|x| &x.0).collect::<Vec<_>>()
    );
    assert_eq!(sa, sb);
    // No temporary directories are left next to the image.
    let leftovers: Vec<_> = std::fs::read_dir(&root)
        .expect("read")
        .map(|e| e.expect("entry").file_name())
        .filter(|n| n.to_string_lossy().starts_with('.'))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

#[test]
fn a_failed_compile_leaves_the_previous_image() {
    let root = scratch("atomic");
    let image = root.join("image");
    let dir = image.to_str().expect("utf-8");
    assert_eq!(
        gutta_cc(&["examples/blink.lad", "-o", dir]).status.code(),
        Some(0)
    );
    let before = snapshot(&image);
    let broken = root.join("broken.lad");
    std::fs::write(&broken, "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\nLD SM0.0\nMOVW MB0, MW2\nEND_ORGANIZATION_BLOCK\n").expect("write");
    let out = gutta_cc(&[broken.to_str().expect("utf-8"), "-o", dir]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(snapshot(&image), before, "the old image changed");
    // A good compile of another program replaces it completely: no stale pages remain.
    assert_eq!(
        gutta_cc(&["examples/an2002_sample1_slave.lad", "-o", dir])
            .status
            .code(),
        Some(0)
    );
    let after = snapshot(&image);
    assert_ne!(after, before);
    assert!(
        !after.iter().any(|(f, _)| f.contains("08.bin")),
        "stale subroutine page of the old image: {:?}",
        after.iter().map(|x| &x.0).collect::<Vec<_>>()
    );
}

#[test]
fn a_directory_that_is_not_an_image_is_not_overwritten() {
    let root = scratch("refuse");
    let precious = root.join("docs");
    std::fs::create_dir_all(&precious).expect("dir");
    std::fs::write(precious.join("notes.txt"), "keep me").expect("write");
    let out = gutta_cc(&[
        "examples/blink.lad",
        "-o",
        precious.to_str().expect("utf-8"),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("refusing to overwrite"));
    assert_eq!(
        std::fs::read_to_string(precious.join("notes.txt")).expect("read"),
        "keep me"
    );
    assert_eq!(snapshot(&precious).len(), 1);
}

#[test]
fn an_unwritable_destination_is_an_io_error_and_leaves_nothing() {
    let root = scratch("unwritable");
    let file = root.join("a-file");
    std::fs::write(&file, "x").expect("write");
    let out = gutta_cc(&[
        "examples/blink.lad",
        "-o",
        file.join("image").to_str().expect("utf-8"),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(std::fs::read_to_string(&file).expect("read"), "x");
}

#[test]
fn limits_name_the_limit_the_size_and_the_target() {
    let root = scratch("limits");
    // A network (4 bytes), LD (7) and 1,200 MOVW of 11 bytes each (13,211) pass CPU-EC20's 10,752 instruction bytes.
    let mut text = String::from("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\nLD SM0.0\n");
    for i in 0..1200 {
        text.push_str(&format!(
            "MOVW MW{}, MW{}\n",
            (i * 2) % 120,
            (i * 2 + 2) % 120
        ));
    }
    text.push_str("END_ORGANIZATION_BLOCK\n");
    let src = root.join("big.lad");
    std::fs::write(&src, &text).expect("write");
    let out = gutta_cc(&[
        src.to_str().expect("utf-8"),
        "-o",
        root.join("img").to_str().expect("utf-8"),
        "--message-format",
        "json",
    ]);
    assert_eq!(out.status.code(), Some(1));
    let json = String::from_utf8_lossy(&out.stdout);
    assert!(json.contains("E0702"), "{json}");
    assert!(
        json.contains("13,211 bytes, CPU-EC20 allows 10,752 (ProgramBlockInstructionBinarySize)"),
        "{json}"
    );
    assert!(!root.join("img").exists());
    // The same program fits the AVR's 32,768 bytes.
    assert_eq!(
        gutta_cc(&[
            src.to_str().expect("utf-8"),
            "--plc",
            "CPU-EC20-AVR",
            "-o",
            root.join("img").to_str().expect("utf-8")
        ])
        .status
        .code(),
        Some(0)
    );
    // 40 distinct DWORD constants need 160 bytes of K; CPU-EC20 has 128.
    let mut text = String::from("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\nLD SM0.0\n");
    for i in 0..40 {
        text.push_str(&format!("MOVD {}, MD0\n", 100_000 + i * 7919));
    }
    text.push_str("END_ORGANIZATION_BLOCK\n");
    std::fs::write(&src, &text).expect("write");
    let out = gutta_cc(&[
        src.to_str().expect("utf-8"),
        "-o",
        root.join("img2").to_str().expect("utf-8"),
        "--message-format",
        "json",
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stdout).contains("E0701"));
}

#[test]
fn a_system_block_too_large_for_the_target_is_e0703() {
    let root = scratch("system");
    let stdlib = Path::new(env!("CARGO_MANIFEST_DIR")).join("../stdlib/targets/CPU-EC20");
    let target = root.join("target");
    std::fs::create_dir_all(&target).expect("dir");
    std::fs::copy(stdlib.join("ManagerVar.xml"), target.join("ManagerVar.xml")).expect("copy");
    let plc = std::fs::read_to_string(stdlib.join("PlcType.xml")).expect("read");
    std::fs::write(
        target.join("PlcType.xml"),
        plc.replace(
            "SystemBlockBinarySize=\"50\"",
            "SystemBlockBinarySize=\"20\"",
        ),
    )
    .expect("write");
    let out = gutta_cc(&[
        "examples/blink.lad",
        "--target",
        target.to_str().expect("utf-8"),
        "-o",
        root.join("img").to_str().expect("utf-8"),
        "--message-format",
        "json",
    ]);
    assert_eq!(out.status.code(), Some(1));
    let json = String::from_utf8_lossy(&out.stdout);
    assert!(
        json.contains("E0703")
            && json.contains("needs 26 bytes; CPU-EC20 allows 20 (SystemBlockBinarySize)"),
        "{json}"
    );
}

#[test]
fn dis_prints_stl_that_compiles_back_to_the_same_image() {
    let root = scratch("dis");
    let (a, b) = (root.join("a"), root.join("b"));
    assert_eq!(
        gutta_cc(&[
            "examples/an2002_sample3_master.lad",
            "-o",
            a.to_str().expect("utf-8")
        ])
        .status
        .code(),
        Some(0)
    );
    let out = gutta_cc(&["dis", a.to_str().expect("utf-8")]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("EXCH   MB20, 0") && text.contains("DATA_BLOCK DAT1:DAT1"),
        "{text}"
    );
    let src = root.join("dis.lad");
    std::fs::write(&src, text.as_bytes()).expect("write");
    assert_eq!(
        gutta_cc(&[
            src.to_str().expect("utf-8"),
            "-o",
            b.to_str().expect("utf-8")
        ])
        .status
        .code(),
        Some(0)
    );
    let pages = |d: &Path| {
        snapshot(d)
            .into_iter()
            .filter(|(f, _)| f != "manifest.json")
            .collect::<Vec<_>>()
    };
    assert_eq!(pages(&a), pages(&b));
    // A corrupted page is a clean error, exit 2, no panic.
    std::fs::write(a.join("instruction/00.bin"), b"\x01").expect("corrupt");
    let out = gutta_cc(&["dis", a.to_str().expect("utf-8")]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("instruction/00.bin"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
