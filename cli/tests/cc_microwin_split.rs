//! A Micro/WIN program exported one block per file (tests/data/microwin/split_program,
//! docs/microwin.md "One block per file") through the real binaries: `gutta-cc` takes
//! the block files and both symbol tables (`--symbols`, each in its own code page) as
//! one program and writes one image; `gutta-vm` runs it and reads what the `EXPECTED`
//! file announces (the subroutine called, the S7-200 interrupt running as GUTTA's INT1).

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{cc_in, stderr, stdout};

fn program_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/microwin/split_program")
}

/// The values of the `// KEY: value` lines of `EXPECTED`, in order.
fn directives<'t>(text: &'t str, key: &str) -> Vec<&'t str> {
    text.lines()
        .filter_map(|l| l.trim().strip_prefix("//")?.trim().strip_prefix(key))
        .filter_map(|rest| rest.strip_prefix(':'))
        .map(str::trim)
        .collect()
}

#[test]
fn a_program_exported_one_block_per_file_compiles() {
    let dir = program_dir();
    let expected = std::fs::read_to_string(dir.join("EXPECTED")).expect("EXPECTED");
    let one = |key: &str| -> &str {
        let found = directives(&expected, key);
        assert_eq!(found.len(), 1, "EXPECTED: one `// {key}:` line");
        found[0]
    };
    let scratch =
        std::env::temp_dir().join(format!("gutta-cc-microwin-split-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&scratch);
    std::fs::create_dir_all(&scratch).expect("scratch directory");
    let image = scratch.join("image");
    let image = image.to_str().expect("path");

    let files: Vec<&str> = one("files").split_whitespace().collect();
    let mut args: Vec<&str> = files.clone();
    for table in one("tables").split_whitespace() {
        args.extend(["--symbols", table]);
    }
    args.extend(["-o", image]);
    let o = cc_in(&dir, &args);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("MAIN.awl is not UTF-8; read as GBK"), "{err}");
    assert!(err.contains("SBR_0.awl is not UTF-8; read as GBK"), "{err}");
    assert!(
        err.contains("symbols_gbk.txt is not UTF-8; read as GBK"),
        "{err}"
    );
    assert!(!err.contains("INT_0.awl is not UTF-8"), "{err}");
    assert!(!err.contains("warning"), "{err}");
    assert!(
        err.contains(&format!(
            "{} files: wrote {image} for CPU-EC20",
            files.len()
        )),
        "{err}"
    );
    assert!(err.contains(" in 3 blocks;"), "{err}");
    assert!(err.contains(one("summary")), "{err}");
    let map = std::fs::read_to_string(format!("{image}.map.json")).expect("the source map");
    assert!(
        map.contains("\"files\":[\"MAIN.awl\",\"SBR_0.awl\",\"INT_0.awl\"]"),
        "{map}"
    );

    let mut vm = vec![image.to_string(), "--scans".into(), one("scans").into()];
    for set in directives(&expected, "set") {
        vm.extend(["--set".to_string(), set.replace(' ', "")]);
    }
    let expects = directives(&expected, "expect");
    assert!(expects.len() >= 3, "EXPECTED announces too little");
    for e in &expects {
        let (var, _) = e.split_once('=').expect("`VAR = VALUE`");
        vm.extend(["--read".to_string(), var.trim().to_string()]);
    }
    let o = Command::new(env!("CARGO_BIN_EXE_gutta-vm"))
        .args(&vm)
        .output()
        .expect("gutta-vm runs");
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    for e in expects {
        let (var, value) = e.split_once('=').expect("`VAR = VALUE`");
        let (var, value) = (var.trim(), value.trim());
        let line = out
            .lines()
            .find(|l| l.starts_with(&format!("{var} ")) || l.contains(&format!("({var})")))
            .unwrap_or_else(|| panic!("no {var} in\n{out}"));
        assert!(
            line.ends_with(&format!("= {value}")),
            "{var}: {line}, expected {value}"
        );
    }
    let _ = std::fs::remove_dir_all(&scratch);
}
