//! `gutta-sim --device fx --tcp`: a raw TCP client speaks the FX-style port's bytes
//! (seed 001) to the process: ENQ, the document's read, a write, NAK for a bad
//! checksum, the factory E00 answer, and the baud switch announced on stdout.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use gutta_protocol::fx::{FxReply, FxRequest, ACK, ENQ, NAK};

struct Sim(Child);

impl Drop for Sim {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn bytes(text: &str) -> Vec<u8> {
    text.split_whitespace()
        .map(|pair| u8::from_str_radix(pair, 16).expect("bytes"))
        .collect()
}

fn exchange(stream: &mut TcpStream, request: &[u8], answer_len: usize) -> Vec<u8> {
    stream.write_all(request).expect("exchange");
    let mut answer = vec![0u8; answer_len];
    stream.read_exact(&mut answer).expect("exchange");
    answer
}

#[test]
fn raw_tcp_client_speaks_the_documents_frames() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
        .args(["--device", "fx", "--tcp", "127.0.0.1:0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("gutta-sim starts");
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    let _sim = Sim(child);
    let line = lines.next().unwrap().unwrap();
    assert!(line.starts_with("gutta-sim: fx-tcp on "), "{line}");
    let address = line.rsplit(' ').next().unwrap();
    let mut stream = TcpStream::connect(address).unwrap();
    stream
        .set_read_timeout(Some(Duration::from_secs(10)))
        .unwrap();

    assert_eq!(exchange(&mut stream, &[ENQ], 1), vec![ACK]);
    // Factory data area: zeros at 0E02.
    let read = bytes("02 30 30 45 30 32 30 32 03 36 43");
    assert_eq!(
        exchange(&mut stream, &read, 8),
        FxReply::Data(vec![0, 0]).encode()
    );
    let write = FxRequest::Write {
        address: 0x0E02,
        data: vec![0xB1, 0x5E],
    };
    assert_eq!(
        exchange(&mut stream, &write.encode().unwrap(), 1),
        vec![ACK]
    );
    // The document's answer, byte for byte, from the process.
    assert_eq!(
        exchange(&mut stream, &read, 8),
        bytes("02 42 31 35 45 03 46 30")
    );
    // A bad checksum: NAK, and the connection goes on.
    let bad = bytes("02 30 30 45 30 32 30 32 03 36 44");
    assert_eq!(exchange(&mut stream, &bad, 1), vec![NAK]);
    // E00 8000 FE: 0xFE bytes of configuration, starting as the document's does.
    let config = exchange(
        &mut stream,
        &bytes("02 45 30 30 38 30 30 30 46 45 03 46 42"),
        1 + 508 + 3,
    );
    assert_eq!(&config[..9], b"\x02C800FB5E");
    // The frame in two writes, split mid-address.
    stream.write_all(&read[..4]).unwrap();
    stream.flush().unwrap();
    std::thread::sleep(Duration::from_millis(50));
    assert_eq!(
        exchange(&mut stream, &read[4..], 8),
        bytes("02 42 31 35 45 03 46 30")
    );
    // 41 35: ACK, then the new rate on stdout.
    assert_eq!(
        exchange(&mut stream, &bytes("02 41 35 03 37 39"), 1),
        vec![ACK]
    );
    let line = lines.next().unwrap().unwrap();
    assert_eq!(line, "gutta-sim: fx-tcp baud rate now 115200");
}

#[test]
fn fx_device_refuses_plc_options() {
    for extra in [["--rtu-tcp", "127.0.0.1:0"], ["--plc", "CPU-EC20"]] {
        let output = Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
            .args(["--device", "fx", "--tcp", "127.0.0.1:0"])
            .args(extra)
            .output()
            .unwrap();
        assert_eq!(output.status.code(), Some(2), "{extra:?}");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(stderr.contains("--device fx takes --tcp"), "{stderr}");
    }
}
