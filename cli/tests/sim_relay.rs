//! `gutta-sim --device relay-board` as a process on loopback TCP: a raw TCP client sends
//! the frames of seed document 004 byte for byte (Modbus TCP and the board's own frames
//! on one connection) and sees the automatic report on a second connection; mbpoll
//! (1-based references: channel 1 is reference 513) and pymodbus
//! (`tests/clients/pymodbus_relay.py`) read and switch the board. External tools follow
//! `tests/common`'s rule (missing: fail with how to install, unless GUTTA_SKIP_EXTERNAL=1).

mod common;

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

/// A running board, killed on drop.
struct Board {
    child: Child,
    port: u16,
}

impl Drop for Board {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn start() -> Board {
    let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
        .args(["--device", "relay-board", "--tcp", "127.0.0.1:0"])
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
    let port = common::listener_port(&line, "relay-board");
    Board { child, port }
}

fn connect(board: &Board) -> TcpStream {
    let s = TcpStream::connect(("127.0.0.1", board.port)).expect("connects");
    s.set_read_timeout(Some(Duration::from_secs(5)))
        .expect("timeout");
    s
}

fn hex(text: &str) -> Vec<u8> {
    text.split_whitespace()
        .map(|b| u8::from_str_radix(b, 16).expect("hex byte"))
        .collect()
}

/// Sends `request` and reads exactly `answer.len()` bytes, which must be `answer`.
fn exchange(s: &mut TcpStream, request: &str, answer: &str) {
    s.write_all(&hex(request)).expect("sends");
    let want = hex(answer);
    let mut got = vec![0; want.len()];
    s.read_exact(&mut got).expect("an answer");
    assert_eq!(got, want, "{request}");
}

/// Sends a frame that has no answer (reporting off), then proves nothing came back by
/// the next answer being the next bytes.
fn send(s: &mut TcpStream, request: &str) {
    s.write_all(&hex(request)).expect("sends");
}

#[test]
fn the_documents_frames_over_tcp() {
    let board = start();
    let mut s = connect(&board);
    // Reporting off first, as the document advises for debugging; and on again.
    exchange(
        &mut s,
        "00 00 00 00 00 06 01 05 1D 5C FF 00",
        "00 00 00 00 00 06 01 05 1D 5C FF 00",
    );
    exchange(
        &mut s,
        "00 00 00 00 00 06 01 05 1D 5C 00 00",
        "00 00 00 00 00 06 01 05 1D 5C 00 00",
    );
    for n in 0..10 {
        let frame = format!("00 00 00 00 00 06 01 05 02 {n:02X} FF 00");
        exchange(&mut s, &frame, &frame);
    }
    exchange(
        &mut s,
        "00 00 00 00 00 06 01 01 02 00 00 0A",
        "00 00 00 00 00 05 01 01 02 FF 03",
    );
    exchange(
        &mut s,
        "00 00 00 00 00 06 01 05 02 01 00 00",
        "00 00 00 00 00 06 01 05 02 01 00 00",
    );
    let read32 = "01 01 02 00 00 05 00 20 00 00 00 00";
    exchange(&mut s, read32, "01 01 02 01 05 00 00 10 FD 03 00 00");
    for (frame, status) in [
        ("03 01 02 00 00 05 00 20 FF FF FF FF", "FF FF FF FF"),
        ("03 01 02 00 00 05 00 20 00 00 00 00", "00 00 00 00"),
        ("03 01 02 00 00 05 00 20 03 00 00 00", "03 00 00 00"),
        ("03 01 02 00 00 05 00 20 0C 00 00 00", "0C 00 00 00"),
        ("24 01 02 00 00 05 00 01 00 00 00", "0D 00 00 00"),
        ("24 01 02 00 00 05 00 02 00 00 00", "0F 00 00 00"),
        ("24 01 02 00 00 05 00 04 00 00 00", "0B 00 00 00"),
        ("24 01 02 00 00 05 00 35 00 00 00", "3E 00 00 00"),
    ] {
        send(&mut s, frame);
        exchange(&mut s, read32, &format!("01 01 02 01 05 00 00 10 {status}"));
    }
    // An exception: function 03 is not the board's.
    exchange(
        &mut s,
        "00 01 00 00 00 06 01 03 02 00 00 01",
        "00 01 00 00 00 03 01 83 01",
    );
}

#[test]
fn automatic_report_reaches_every_connection() {
    let board = start();
    let mut a = connect(&board);
    let mut b = connect(&board);
    // Make sure b is being served before a changes anything.
    exchange(
        &mut b,
        "01 01 02 00 00 05 00 20 00 00 00 00",
        "01 01 02 01 05 00 00 10 00 00 00 00",
    );
    // Reporting is on at power-up: a's switch is answered, then reported to a and b.
    exchange(
        &mut a,
        "00 00 00 00 00 06 01 05 02 02 FF 00",
        "00 00 00 00 00 06 01 05 02 02 FF 00",
    );
    let report = hex("01 01 02 01 05 00 00 10 04 00 00 00");
    for s in [&mut a, &mut b] {
        let mut got = vec![0; 12];
        s.read_exact(&mut got).expect("a report");
        assert_eq!(got, report);
    }
    // Off: a toggle is silent, the next bytes on a are the answer to its read.
    exchange(
        &mut a,
        "00 00 00 00 00 06 01 05 1D 5C 00 00",
        "00 00 00 00 00 06 01 05 1D 5C 00 00",
    );
    send(&mut a, "24 01 02 00 00 05 00 01 00 00 00");
    exchange(
        &mut a,
        "01 01 02 00 00 05 00 20 00 00 00 00",
        "01 01 02 01 05 00 00 10 05 00 00 00",
    );
    // b got nothing more: its next bytes are its own answer.
    exchange(
        &mut b,
        "00 02 00 00 00 06 01 01 02 00 00 03",
        "00 02 00 00 00 04 01 01 01 05",
    );
}

#[test]
fn garbage_closes_only_its_connection() {
    let board = start();
    let mut bad = connect(&board);
    bad.write_all(&hex("55 55 55 55 55 55 55 55"))
        .expect("sends");
    let mut rest = Vec::new();
    assert_eq!(bad.read_to_end(&mut rest).expect("closed"), 0);
    let mut good = connect(&board);
    exchange(
        &mut good,
        "01 01 02 00 00 05 00 20 00 00 00 00",
        "01 01 02 01 05 00 00 10 00 00 00 00",
    );
}

#[test]
fn relay_board_takes_only_tcp() {
    let out = Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
        .args(["--device", "relay-board", "--rtu-tcp", "127.0.0.1:0"])
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--device relay-board"), "{err}");
}

fn mbpoll(args: &[&str]) -> String {
    let out = Command::new("mbpoll")
        .args(args)
        .output()
        .expect("runs mbpoll");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(out.status.success(), "mbpoll {args:?}: {text}");
    text
}

#[test]
fn mbpoll_reads_and_switches_channels() {
    if !common::have("mbpoll") {
        return;
    }
    let board = start();
    let port = board.port.to_string();
    let base = ["-m", "tcp", "-a", "1", "-t", "0", "-1", "-p", &port];
    // Reporting off (coil 0x1D5C = reference 7517).
    let mut off = base.to_vec();
    off.extend(["-r", "7517", "127.0.0.1", "0"]);
    assert!(mbpoll(&off).contains("Written 1 references"));
    // Channels 1 and 10 on: references 513 and 522 (mbpoll counts from 1).
    for reference in ["513", "522"] {
        let mut on = base.to_vec();
        on.extend(["-r", reference, "127.0.0.1", "1"]);
        assert!(mbpoll(&on).contains("Written 1 references"));
    }
    let mut read = base.to_vec();
    read.extend(["-r", "513", "-c", "10", "127.0.0.1"]);
    let text = mbpoll(&read);
    for n in 513..=522 {
        let want = if n == 513 || n == 522 { 1 } else { 0 };
        assert!(text.contains(&format!("[{n}]: \t{want}")), "{n}: {text}");
    }
    // The board agrees: channels 1 and 10 in its own read.
    let mut s = connect(&board);
    exchange(
        &mut s,
        "01 01 02 00 00 05 00 20 00 00 00 00",
        "01 01 02 01 05 00 00 10 01 02 00 00",
    );
}

#[test]
fn pymodbus_reads_and_switches_channels() {
    let Some(python) = common::pymodbus_python() else {
        return;
    };
    let board = start();
    common::run_python_client(
        &python,
        "pymodbus_relay.py",
        &[board.port.to_string()],
        "pymodbus_relay: 0 failures",
    );
}
