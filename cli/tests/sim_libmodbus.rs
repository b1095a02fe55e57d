//! libmodbus's `random-test-client` (the example shipped in Debian's libmodbus-dev)
//! against a `gutta-sim` process over Modbus TCP.
//!
//! The client writes random values with functions 05, 15, 06 and 16 to coils and
//! holding registers 0..99 and reads each back with 01 and 03; then it tries function
//! 23 (read/write multiple registers). The simulator runs an empty EC30-EKSTM32, where
//! coils 0..255 are Q and holding registers 0..127 are AQ, so every address the client
//! uses is inside one area. A GUTTA PLC speaks 01-06/15/16 only (AN2002): function 23
//! must get exception 01, which the client counts as one failure per address, and
//! nothing else may fail.
//!
//! The example is compiled from /usr/share/doc/libmodbus-dev/examples with the port it
//! hard-codes (1502) replaced by the simulator's. `.ci/run` installs libmodbus-dev; a
//! missing library, pkg-config or cc fails the test with how to install them, unless
//! GUTTA_SKIP_EXTERNAL=1 declares the external tools absent.

mod common;

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

const EXAMPLES: &str = "/usr/share/doc/libmodbus-dev/examples";

/// The addresses the client walks (`ADDRESS_START`, `ADDRESS_END` in its source).
const ADDRESSES: usize = 99;

struct Sim(Child);

impl Drop for Sim {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// The client compiled for `port`, or None when libmodbus-dev is not there.
fn build_client(port: u16) -> Option<PathBuf> {
    let source = Path::new(EXAMPLES).join("random-test-client.c");
    let Ok(text) = std::fs::read_to_string(&source) else {
        common::tool_missing(&format!("{} is not there", source.display()));
        return None;
    };
    let hard_coded = "modbus_new_tcp(\"127.0.0.1\", 1502)";
    assert!(
        text.contains(hard_coded),
        "the example no longer connects with `{hard_coded}`"
    );
    let text = text.replace(
        hard_coded,
        &format!("modbus_new_tcp(\"127.0.0.1\", {port})"),
    );
    let dir = std::env::temp_dir().join(format!("gutta-libmodbus-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let c = dir.join("random-test-client.c");
    std::fs::write(&c, text).expect("writes the source");
    let flags = match Command::new("pkg-config")
        .args(["--cflags", "--libs", "libmodbus"])
        .output()
    {
        Ok(out) if out.status.success() => String::from_utf8_lossy(&out.stdout).into_owned(),
        _ => {
            common::tool_missing("pkg-config does not know libmodbus");
            return None;
        }
    };
    if !common::have("cc") {
        return None;
    }
    let exe = dir.join("random-test-client");
    let out = Command::new("cc")
        .arg(&c)
        .arg("-o")
        .arg(&exe)
        .args(flags.split_whitespace())
        .output()
        .expect("runs cc");
    assert!(
        out.status.success(),
        "cc: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    Some(exe)
}

fn start_sim() -> (Sim, u16) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
        .args(["--plc", "EC30-EKSTM32", "--tcp", "127.0.0.1:0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("starts gutta-sim");
    let stdout = child.stdout.take().expect("stdout");
    let line = BufReader::new(stdout)
        .lines()
        .next()
        .expect("a listener line")
        .expect("text");
    let port = common::listener_port(&line, "modbus-tcp");
    (Sim(child), port)
}

#[test]
fn random_test_client_passes_everything_but_function_23() {
    let (_sim, port) = start_sim();
    let Some(client) = build_client(port) else {
        return;
    };
    let out = Command::new(&client).output().expect("runs the client");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(out.status.success(), "random-test-client: {text}");
    let errors: Vec<&str> = text.lines().filter(|l| l.starts_with("ERROR")).collect();
    let others: Vec<&&str> = errors
        .iter()
        .filter(|l| !l.starts_with("ERROR modbus_read_and_write_registers"))
        .collect();
    assert!(others.is_empty(), "unexpected failures: {others:?}\n{text}");
    // One failed function 23 per address, and the client's total agrees.
    assert_eq!(errors.len(), ADDRESSES, "{text}");
    assert!(
        text.contains(&format!("Test: {ADDRESSES} FAILS")),
        "{}",
        text.lines().rev().take(5).collect::<Vec<_>>().join("\n")
    );
    // Each function 23 was answered with exception 01: with debug on, libmodbus prints
    // every frame it receives (`<97><01>` is function 0x17 | 0x80 and code 01) and
    // names the exception on stderr.
    assert_eq!(text.matches("><97><01>").count(), ADDRESSES, "{text}");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        stderr.matches("Illegal function").count(),
        ADDRESSES,
        "{stderr}"
    );
}
