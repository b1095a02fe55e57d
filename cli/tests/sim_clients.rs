//! `gutta-sim` as a process on loopback TCP, with independent Modbus clients: mbpoll
//! (Debian) over Modbus TCP and, through a socat pty, over a serial line bridged to the
//! RTU-over-TCP listener; pymodbus (`tests/clients/pymodbus_check.py`, in a venv) over
//! both framings, with hand-built function 13 frames. `.ci/run` installs the tools; a
//! missing tool fails the test with how to install it, unless GUTTA_SKIP_EXTERNAL=1
//! declares the external tools absent (then the test says it skipped). The robustness
//! tests use plain sockets and always run.

mod common;

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::Duration;

/// A running simulator, killed on drop.
struct Sim {
    child: Child,
    tcp: u16,
    rtu: u16,
}

impl Drop for Sim {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn image_dir(tag: &str) -> PathBuf {
    common::image_dir(tag, &common::example("in1001_pointers.lad"))
}

fn start(dir: &Path) -> Sim {
    let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
        .arg(dir)
        .args(["--tcp", "127.0.0.1:0", "--rtu-tcp", "127.0.0.1:0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("starts gutta-sim");
    let stdout = child.stdout.take().expect("stdout");
    let mut lines = BufReader::new(stdout).lines();
    let mut port = |what: &str| {
        common::listener_port(&lines.next().expect("a listener line").expect("text"), what)
    };
    let tcp = port("modbus-tcp");
    let rtu = port("rtu-over-tcp");
    // Let the first scans run (the pointer example writes MW24/MW26 in scan 1).
    std::thread::sleep(Duration::from_millis(100));
    Sim { child, tcp, rtu }
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
fn mbpoll_reads_and_writes_through_the_mapping() {
    if !common::have("mbpoll") {
        return;
    }
    let sim = start(&image_dir("mbpoll"));
    let port = sim.tcp.to_string();
    // Options, the host, then the values to write (if any).
    let tcp = |opts: &[&str], values: &[&str]| {
        let mut args = vec!["-m", "tcp", "-p", &port, "-a", "1", "-1"];
        args.extend_from_slice(opts);
        args.push("127.0.0.1");
        args.extend_from_slice(values);
        mbpoll(&args)
    };
    // M: MW24, MW26 = 400021, 400022.
    let out = tcp(&["-r", "21", "-c", "2", "-t", "4:hex"], &[]);
    assert!(
        out.contains("[21]: \t0x0E01") && out.contains("[22]: \t0x0E02"),
        "{out}"
    );
    // AQ: write 400001 then read it.
    tcp(&["-r", "1", "-t", "4"], &["4321"]);
    assert!(tcp(&["-r", "1", "-c", "1", "-t", "4"], &[]).contains("[1]: \t4321"));
    // Q: coil 25 is Q3.0.
    tcp(&["-r", "25", "-t", "0"], &["1"]);
    assert!(tcp(&["-r", "25", "-c", "1", "-t", "0"], &[]).contains("[25]: \t1"));
    // I and AI: read-only tables, all zero here.
    assert!(tcp(&["-r", "1", "-c", "8", "-t", "1"], &[]).contains("[8]: \t0"));
    assert!(tcp(&["-r", "1", "-c", "1", "-t", "3"], &[]).contains("[1]: \t0"));
    // RTU through a pty: socat bridges a serial device to the RTU-over-TCP listener.
    if common::have("socat") {
        let pty = std::env::temp_dir().join(format!("gutta-pty-{}", std::process::id()));
        let mut socat = Command::new("socat")
            .arg(format!("pty,link={},raw,echo=0", pty.display()))
            .arg(format!("tcp:127.0.0.1:{}", sim.rtu))
            .spawn()
            .expect("socat");
        for _ in 0..50 {
            if pty.exists() {
                break;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        let device = pty.display().to_string();
        let out = mbpoll(&[
            "-m", "rtu", "-b", "19200", "-P", "even", "-a", "1", "-r", "21", "-c", "2", "-t",
            "4:hex", "-1", &device,
        ]);
        let _ = socat.kill();
        let _ = socat.wait();
        assert!(out.contains("[21]: \t0x0E01"), "{out}");
    }
}

#[test]
fn pymodbus_over_tcp_and_rtu_with_function_13() {
    let Some(python) = common::pymodbus_python() else {
        return;
    };
    let sim = start(&image_dir("pymodbus"));
    common::run_python_client(
        &python,
        "pymodbus_check.py",
        &[sim.tcp.to_string(), sim.rtu.to_string()],
        "0 failures",
    );
}

fn mbap(tid: u16, pdu: &[u8]) -> Vec<u8> {
    let mut f = tid.to_be_bytes().to_vec();
    f.extend([0, 0]);
    f.extend(((pdu.len() + 1) as u16).to_be_bytes());
    f.push(1);
    f.extend(pdu);
    f
}

fn ask(s: &mut TcpStream, tid: u16, pdu: &[u8]) -> Vec<u8> {
    s.write_all(&mbap(tid, pdu)).expect("send");
    let mut head = [0u8; 7];
    s.read_exact(&mut head).expect("answer header");
    let len = usize::from(u16::from_be_bytes([head[4], head[5]])) - 1;
    let mut pdu = vec![0; len];
    s.read_exact(&mut pdu).expect("answer");
    pdu
}

fn connect(port: u16) -> TcpStream {
    let s = TcpStream::connect(("127.0.0.1", port)).expect("connects");
    s.set_read_timeout(Some(Duration::from_secs(5)))
        .expect("timeout");
    s
}

#[test]
fn bad_clients_do_not_wedge_the_server() {
    let sim = start(&image_dir("robust"));
    // Half a frame, then the client goes away.
    {
        let mut s = connect(sim.tcp);
        s.write_all(&mbap(1, &[0x03, 0x00, 0x14, 0x00, 0x02])[..5])
            .expect("send");
    }
    // A malformed MBAP header (protocol id 7) closes that connection only.
    {
        let mut s = connect(sim.tcp);
        s.write_all(&[0, 1, 0, 7, 0, 6, 1, 3, 0, 0, 0, 1])
            .expect("send");
        let mut buf = [0u8; 16];
        assert_eq!(s.read(&mut buf).unwrap_or(0), 0, "closed without an answer");
    }
    // Garbage and a bad CRC on RTU: no answer, and the stream resynchronises.
    {
        let mut s = connect(sim.rtu);
        let good = gutta_protocol::rtu::encode_rtu(1, &[0x03, 0x00, 0x14, 0x00, 0x02]);
        let mut bad = good.clone();
        bad[3] ^= 0xFF;
        s.write_all(&[0xFF, 0x00, 0x13]).expect("send");
        s.write_all(&bad).expect("send");
        s.write_all(&good).expect("send");
        let mut answer = [0u8; 9];
        s.read_exact(&mut answer)
            .expect("the good frame is answered");
        assert_eq!(&answer[..7], &[1, 3, 4, 0x0E, 0x01, 0x0E, 0x02]);
    }
    // A wrong password fails; everything that needs a login is refused; a new client
    // is still served.
    let mut s = connect(sim.tcp);
    let mut attach = vec![0x0D, 0x00, 0x14, 0x01, 0x10, 0x80, 0x00];
    attach.extend([0u8; 16]);
    assert_eq!(
        ask(&mut s, 2, &attach),
        [0x0D, 0x00, 0x04, 0x81, 0x10, 0x80, 0x00]
    );
    let page_write = [0x0D, 0x00, 0x06, 0x03, 0x12, 0x80, 0x00, 1, 2];
    assert_eq!(
        ask(&mut s, 3, &page_write),
        [0x0D, 0x00, 0x04, 0x83, 0x12, 0x80, 0x00]
    );
    // Function 13 with a length field that lies: exception 03, not a crash.
    assert_eq!(
        ask(&mut s, 4, &[0x0D, 0x00, 0x09, 0x0A, 0x00, 0x80, 0x00]),
        [0x8D, 0x03]
    );
    let mut other = connect(sim.tcp);
    assert_eq!(
        ask(&mut other, 5, &[0x03, 0x00, 0x14, 0x00, 0x02]),
        [0x03, 0x04, 0x0E, 0x01, 0x0E, 0x02]
    );
}

#[test]
fn mbpoll_over_a_serial_line() {
    if !common::have("mbpoll") || !common::have("socat") {
        return;
    }
    // A socat pty pair: the simulator opens one end with --serial, mbpoll the other.
    let base = std::env::temp_dir().join(format!("gutta-serial-{}", std::process::id()));
    let (a, b) = (base.with_extension("a"), base.with_extension("b"));
    let mut socat = Command::new("socat")
        .arg(format!("pty,raw,echo=0,link={}", a.display()))
        .arg(format!("pty,raw,echo=0,link={}", b.display()))
        .spawn()
        .expect("socat");
    for _ in 0..100 {
        if a.exists() && b.exists() {
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
        .arg(image_dir("serial"))
        .arg("--serial")
        .arg(&a)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("starts gutta-sim");
    let mut lines = BufReader::new(child.stdout.take().expect("stdout")).lines();
    let line = lines.next().expect("a listener line").expect("text");
    assert!(line.contains("rtu-serial on"), "{line}");
    std::thread::sleep(Duration::from_millis(100));
    let device = b.display().to_string();
    let rtu = |opts: &[&str], values: &[&str]| {
        let mut args = vec!["-m", "rtu", "-b", "19200", "-P", "even", "-a", "1", "-1"];
        args.extend_from_slice(opts);
        args.push(&device);
        args.extend_from_slice(values);
        mbpoll(&args)
    };
    let out = rtu(&["-r", "21", "-c", "2", "-t", "4:hex"], &[]);
    rtu(&["-r", "9", "-t", "4"], &["777"]);
    let back = rtu(&["-r", "9", "-c", "1", "-t", "4"], &[]);
    let _ = child.kill();
    let _ = child.wait();
    let _ = socat.kill();
    let _ = socat.wait();
    assert!(
        out.contains("[21]: \t0x0E01") && out.contains("[22]: \t0x0E02"),
        "{out}"
    );
    assert!(back.contains("[9]: \t777"), "MW0 = 400009: {back}");
}
