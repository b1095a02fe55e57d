//! What `gutta-cc` says when the way to a PLC or a name on the command line is wrong,
//! through the real binary: a refused connection says whether a PLC or gutta-sim
//! listens there and how to start one (text and the JSON error's `hint`), a missing
//! serial device says so, and a misspelt symbol gets its did-you-mean before any
//! connection is tried, so even with nothing listening. Counts agree with their nouns
//! (`1 network`, `1 error`).

mod common;

use common::{cc, cc_in, stderr, stdout};

/// A loopback address nothing listens at: a port the system just handed out, closed.
fn refused_address() -> String {
    let listener = std::net::TcpListener::bind("127.0.0.1:0").expect("binds");
    let address = listener.local_addr().expect("address").to_string();
    drop(listener);
    address
}

fn temp_dir(tag: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("gutta-cli-messages-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

#[test]
fn a_refused_connection_says_how_to_start_a_simulator() {
    let at = refused_address();
    for flag in ["--tcp", "--rtu-tcp"] {
        let out = cc(&["status", flag, &at]);
        assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
        let text = stderr(&out);
        assert!(
            text.contains(&format!(
                "gutta-cc: error: cannot connect to {at}: connection refused\n"
            )),
            "{text}"
        );
        assert!(
            text.contains(&format!(
                "  hint: is a PLC or gutta-sim listening at {at}? Check the address, or start a simulated PLC there: `gutta-sim {flag} {at}`"
            )),
            "{text}"
        );
        let out = cc(&["status", flag, &at, "--message-format", "json"]);
        assert_eq!(out.status.code(), Some(2));
        let error: serde_json::Value = serde_json::from_str(stdout(&out).trim()).expect("JSON");
        assert_eq!(error["kind"], "link", "{error}");
        assert_eq!(
            error["message"],
            format!("cannot connect to {at}: connection refused")
        );
        let hint = error["hint"].as_str().expect("a hint");
        assert!(hint.contains(&format!("`gutta-sim {flag} {at}`")), "{hint}");
    }
}

#[test]
fn a_missing_serial_device_says_so() {
    let device = temp_dir("serial").join("ttyNOPE");
    let device = device.to_str().expect("path");
    let out = cc(&["status", "--serial", device]);
    assert_eq!(out.status.code(), Some(2));
    let text = stderr(&out);
    assert!(
        text.contains(&format!("cannot open {device}: no such device")),
        "{text}"
    );
    assert!(
        text.contains(&format!(
            "hint: {device} does not exist: check the device name"
        )),
        "{text}"
    );
}

#[test]
fn a_misspelt_symbol_is_reported_before_connecting() {
    let dir = temp_dir("project");
    let out = cc_in(&dir, &["new", "demo"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let project = dir.join("demo");
    let at = refused_address();
    let commands: [&[&str]; 6] = [
        &["read", "Lamp", "Runing"],
        &["write", "Runing=1"],
        &["force", "Runing=1"],
        &["unforce", "Runing"],
        &["watch", "Runing", "--once"],
        &["debug", "info", "--watch", "Runing"],
    ];
    for args in commands {
        let mut args = args.to_vec();
        args.extend(["--tcp", &at]);
        let out = cc_in(&project, &args);
        let text = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {text}");
        assert!(
            text.contains("`Runing` is neither a symbol nor an address: did you mean `Running`?"),
            "{args:?}: {text}"
        );
        assert!(!text.contains("cannot connect"), "{args:?}: {text}");
    }
    // Outside a project and without --plc, the PLC type is not known before
    // connecting: a name that is no address on any PLC is refused all the same.
    let table = dir.join("symbols.csv");
    std::fs::write(&table, "Symbol,Address,Comment\nLamp,Q0.0,\n").expect("writes");
    let table = table.to_str().expect("path");
    let out = cc(&["read", "Lmap", "--symbols", table, "--tcp", &at]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("`Lmap` is neither a symbol nor an address: did you mean `Lamp`?"),
        "{}",
        stderr(&out)
    );
    // A well-formed address still needs the PLC: the connection error comes.
    let out = cc(&["read", "Q0.0", "--tcp", &at]);
    assert!(
        stderr(&out).contains("connection refused"),
        "{}",
        stderr(&out)
    );
    // A debug action that does not exist is refused before connecting too.
    let out = cc(&["debug", "jump", "--tcp", &at]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("debug `jump`: break POSITION, clear"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn counts_agree_with_their_nouns() {
    let dir = temp_dir("counts");
    let one = dir.join("one.lad");
    std::fs::write(
        &one,
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nNOP\nEND_ORGANIZATION_BLOCK\n",
    )
    .expect("writes");
    let out = cc_in(&dir, &["--check", "one.lad"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(
        stderr(&out),
        "one.lad: ok on CPU-EC20 (1 block, 1 instruction, 0 data blocks)\n"
    );
    std::fs::write(
        dir.join("lamp.lad"),
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\n= Q0.0\nEND_ORGANIZATION_BLOCK\n",
    )
    .expect("writes");
    let out = cc_in(&dir, &["ladder", "lamp.lad", "-o", "lamp.svg"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(
        stderr(&out),
        "lamp.lad: 1 network drawn as ladder, 0 as STL, into lamp.svg\n"
    );
    std::fs::write(
        dir.join("bad.lad"),
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nNOP 0\nEND_ORGANIZATION_BLOCK\n",
    )
    .expect("writes");
    let out = cc_in(&dir, &["--check", "bad.lad"]);
    assert!(
        stderr(&out).ends_with("bad.lad: 1 error, 0 warnings\n"),
        "{}",
        stderr(&out)
    );
    let out = cc_in(&dir, &["monitor", "bad.lad", "--tcp", &refused_address()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("bad.lad has 1 error: `gutta-cc --check bad.lad` shows it;"),
        "{}",
        stderr(&out)
    );
}
