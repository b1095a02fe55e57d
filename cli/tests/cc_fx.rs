//! `gutta-cc fx` against `gutta-sim --device fx` (and, for retries and silence, against
//! a scripted TCP peer): every subcommand, the program's round trip, clear errors, and
//! a serial line at 7E1 through a socat pty pair, its rate switched by `41`.

mod common;

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpListener;
use std::process::{Child, Command, Output, Stdio};

use gutta_protocol::fx::{FxReply, FxRequest, FxSplitter, FxToken, NAK};

struct Sim(Child, String);

impl Drop for Sim {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn fx_sim() -> Sim {
    let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
        .args(["--device", "fx", "--tcp", "127.0.0.1:0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("gutta-sim starts");
    let line = BufReader::new(child.stdout.take().expect("fx_sim"))
        .lines()
        .next()
        .expect("fx_sim")
        .expect("fx_sim");
    let address = line.rsplit(' ').next().expect("fx_sim").to_string();
    Sim(child, address)
}

fn fx(args: &[&str], address: &str) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gutta-cc"))
        .arg("fx")
        .args(args)
        .args(["--tcp", address])
        .output()
        .expect("fx")
}

fn ok(output: &Output) -> String {
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8(output.stdout.clone()).expect("ok")
}

fn failed(output: &Output) -> String {
    assert_eq!(output.status.code(), Some(2), "{output:?}");
    String::from_utf8_lossy(&output.stderr).into_owned()
}

#[test]
fn read_write_force_config_and_baud() {
    let sim = fx_sim();
    let a = sim.1.as_str();
    assert_eq!(ok(&fx(&["read", "0E02", "2"], a)), "0E02: 00 00\n");
    assert_eq!(
        ok(&fx(&["write", "0x0E02", "B1", "5E"], a)),
        "wrote 2 bytes at 0E02\n"
    );
    assert_eq!(ok(&fx(&["read", "0E02", "2"], a)), "0E02: B1 5E\n");
    // One byte is a byte, not "1 bytes".
    assert_eq!(
        ok(&fx(&["write", "0E04", "07"], a)),
        "wrote 1 byte at 0E04\n"
    );
    assert_eq!(ok(&fx(&["force-on", "0801"], a)), "forced bit 0801 on\n");
    assert_eq!(ok(&fx(&["read", "0100", "1"], a)), "0100: 02\n");
    ok(&fx(&["force-off", "0801"], a));
    assert_eq!(ok(&fx(&["read", "0100", "1"], a)), "0100: 00\n");
    let config = ok(&fx(&["config"], a));
    assert_eq!(config.lines().count(), 16);
    assert!(
        config.starts_with("8000: C8 00 FB 5E 08 00 10 00 00 00 B3 FF 00 00 00 00\n"),
        "{config}"
    );
    assert!(
        config.ends_with("80F0: 01 15 71 3F 10 00 00 00 00 00 00 00 00 00\n"),
        "{config}"
    );
    assert_eq!(
        ok(&fx(&["baud", "38400"], a)),
        "the device now runs at 38400 baud (give --baud 38400 from now on)\n"
    );
    let error = failed(&fx(&["baud", "4800"], a));
    assert!(
        error.contains("4800 baud: the port runs at 9600"),
        "{error}"
    );
}

#[test]
fn program_download_then_upload_round_trip() {
    let sim = fx_sim();
    let dir = std::env::temp_dir().join(format!("gutta-cc-fx-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // 600 bytes: three E11 frames (FE, FE, 5E), read back the same way.
    let program: Vec<u8> = (0..600u32).map(|n| (n * 7 + 3) as u8).collect();
    let file = dir.join("program.bin");
    std::fs::write(&file, &program).unwrap();
    let text = ok(&fx(&["download-program", file.to_str().unwrap()], &sim.1));
    assert_eq!(
        text,
        "downloaded 600 bytes to program memory (805C-82B3), read back and compared, write ended (E87)\n"
    );
    let back = dir.join("back.bin");
    let text = ok(&fx(
        &[
            "upload-program",
            "-o",
            back.to_str().unwrap(),
            "--size",
            "600",
        ],
        &sim.1,
    ));
    assert!(text.starts_with("uploaded 600 bytes"), "{text}");
    assert_eq!(std::fs::read(&back).unwrap(), program);
    // The whole program memory by default: 805C-FFFF.
    let all = dir.join("all.bin");
    ok(&fx(
        &["upload-program", "-o", all.to_str().unwrap()],
        &sim.1,
    ));
    let all = std::fs::read(&all).unwrap();
    assert_eq!(all.len(), 0x1_0000 - 0x805C);
    assert_eq!(all[..600], program[..]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn clear_errors() {
    let sim = fx_sim();
    // The device refuses an address outside the data area: NAK, retried, then an error.
    let error = failed(&fx(&["read", "7FFF", "2"], &sim.1));
    assert!(
        error.contains("read (30) 2 bytes at 7FFF failed after 3 attempts: NAK, NAK, NAK"),
        "{error}"
    );
    assert!(error.contains("check the address range"), "{error}");
    let error = failed(&fx(&["write", "0E02", "1"], &sim.1));
    assert!(error.contains("is not bytes in hex"), "{error}");
    let error = failed(&fx(&["download-program", "/nonexistent/p.bin"], &sim.1));
    assert!(error.contains("cannot read /nonexistent/p.bin"), "{error}");
    let output = Command::new(env!("CARGO_BIN_EXE_gutta-cc"))
        .args(["fx", "read", "0", "1"])
        .output()
        .unwrap();
    assert!(failed(&output).contains("give --tcp HOST:PORT or --serial DEVICE"));
}

/// A peer that answers the first request NAK, the second with data, then stays silent.
#[test]
fn retries_on_nak_and_reports_silence() {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let address = listener.local_addr().unwrap().to_string();
    let peer = std::thread::spawn(move || {
        let mut requests = Vec::new();
        for answers in [vec![vec![NAK], FxReply::Data(vec![0x42]).encode()], vec![]] {
            let (mut stream, _) = listener.accept().unwrap();
            let mut splitter = FxSplitter::new();
            let mut answers = answers.into_iter();
            let mut buf = [0u8; 256];
            loop {
                let n = stream.read(&mut buf).unwrap_or(0);
                if n == 0 {
                    break;
                }
                for token in splitter.push(&buf[..n]) {
                    let FxToken::Frame(frame) = token else {
                        panic!("{token:?}")
                    };
                    requests.push(FxRequest::decode(&frame).unwrap());
                    if let Some(answer) = answers.next() {
                        stream.write_all(&answer).unwrap();
                    }
                }
            }
        }
        requests
    });
    assert_eq!(ok(&fx(&["read", "0010", "1"], &address)), "0010: 42\n");
    let error = failed(&fx(
        &["read", "0010", "1", "--timeout", "100", "--retries", "1"],
        &address,
    ));
    assert!(
        error.contains("failed after 2 attempts: no answer in 100 ms, no answer in 100 ms"),
        "{error}"
    );
    assert!(error.contains("check the endpoint"), "{error}");
    let read = FxRequest::Read {
        address: 0x10,
        len: 1,
    };
    assert_eq!(
        peer.join().unwrap(),
        vec![read.clone(), read.clone(), read.clone(), read]
    );
}

#[test]
fn serial_line_at_7e1_switches_rate_after_the_ack() {
    if !common::have("socat") {
        return;
    }
    let base = std::env::temp_dir().join(format!("gutta-cc-fx-serial-{}", std::process::id()));
    let (device_end, tool_end) = (base.with_extension("dev"), base.with_extension("tool"));
    let socat = Command::new("socat")
        .arg(format!("pty,raw,echo=0,link={}", device_end.display()))
        .arg(format!("pty,raw,echo=0,link={}", tool_end.display()))
        .stderr(Stdio::null())
        .spawn()
        .expect("socat starts");
    let _socat = Sim(socat, String::new());
    for _ in 0..100 {
        if device_end.exists() && tool_end.exists() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
        .args(["--device", "fx", "--serial"])
        .arg(&device_end)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("gutta-sim starts");
    let mut said = BufReader::new(child.stdout.take().unwrap()).lines();
    let _sim = Sim(child, String::new());
    let line = said.next().unwrap().unwrap();
    assert_eq!(
        line,
        format!(
            "gutta-sim: fx-serial on {} (9600 7E1)",
            device_end.display()
        )
    );
    let serial = |args: &[&str], baud: &str| {
        Command::new(env!("CARGO_BIN_EXE_gutta-cc"))
            .arg("fx")
            .args(args)
            .args(["--serial", tool_end.to_str().unwrap(), "--baud", baud])
            .output()
            .unwrap()
    };
    assert_eq!(
        ok(&serial(&["write", "0E02", "B15E"], "9600")),
        "wrote 2 bytes at 0E02\n"
    );
    assert_eq!(ok(&serial(&["read", "0E02", "2"], "9600")), "0E02: B1 5E\n");
    ok(&serial(&["baud", "57600"], "9600"));
    let line = said.next().unwrap().unwrap();
    assert_eq!(
        line,
        format!(
            "gutta-sim: fx-serial on {} now 57600 7E1",
            device_end.display()
        )
    );
    assert_eq!(
        ok(&serial(&["read", "0E02", "2"], "57600")),
        "0E02: B1 5E\n"
    );
}
