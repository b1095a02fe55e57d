//! `gutta-sim --plant` with the real binary (issue 30, "A plant"): the AN2002 sample 3
//! plant reproduces the document's capture between master and slave, byte for byte the
//! same as between two processes (`--trace-ports` on both); the relay-board plant
//! switches a relay from the PLC program; every device answers gutta-cc, mbpoll and
//! pymodbus on its own addresses; two PLCs polling each other do not deadlock; Ctrl-C
//! stops the plant with status 0; bad plant files and a project that does not compile
//! stop the start with their coded errors.

#![cfg(unix)]

mod common;

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{channel, Receiver};
use std::time::{Duration, Instant};

/// A running `gutta-sim`, its stdout lines arriving on a channel; killed when dropped.
struct Running {
    child: Child,
    lines: Receiver<String>,
}

impl Drop for Running {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Running {
    fn start(args: &[&str]) -> Running {
        let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("starts gutta-sim");
        let stdout = child.stdout.take().expect("stdout");
        let (send, lines) = channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { return };
                if send.send(line).is_err() {
                    return;
                }
            }
        });
        Running { child, lines }
    }

    /// The next line, within 20 s.
    fn line(&self) -> String {
        self.lines
            .recv_timeout(Duration::from_secs(20))
            .expect("a line from gutta-sim")
    }

    /// Lines until `done` holds for the ones read, within 10 s; all of them.
    fn lines_until(&self, done: impl Fn(&[String]) -> bool) -> Vec<String> {
        let deadline = Instant::now() + Duration::from_secs(10);
        let mut seen = Vec::new();
        while !done(&seen) {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.lines.recv_timeout(left) {
                Ok(line) => seen.push(line),
                Err(_) => panic!("gave up waiting; saw:\n{}", seen.join("\n")),
            }
        }
        seen
    }
}

/// The addresses of a start line `gutta-sim: NAME: kind on A, kind on B`, by kind.
fn addresses(line: &str, name: &str) -> Vec<(String, String)> {
    let rest = line
        .strip_prefix(&format!("gutta-sim: {name}: "))
        .unwrap_or_else(|| panic!("`{line}` is not {name}'s start line"));
    rest.split(", ")
        .map(|part| {
            let (kind, address) = part.split_once(" on ").expect("KIND on ADDRESS");
            (kind.to_string(), address.to_string())
        })
        .collect()
}

fn address_of(line: &str, name: &str, kind: &str) -> String {
    addresses(line, name)
        .into_iter()
        .find(|(k, _)| k == kind)
        .unwrap_or_else(|| panic!("no {kind} in `{line}`"))
        .1
}

fn examples() -> PathBuf {
    common::root().join("examples/plants")
}

/// A shipped plant file, its listeners moved to free ports (`127.0.0.1:0`) and its
/// project folders named absolutely, written into a scratch folder.
fn shipped_plant(example: &str, tag: &str) -> PathBuf {
    let folder = examples().join(example);
    let text = std::fs::read_to_string(folder.join("plant.toml")).expect("plant.toml");
    let mut out = String::new();
    for line in text.lines() {
        let line = match line.split_once(" = ") {
            Some(("tcp" | "rtu-tcp", _)) => {
                format!("{} = \"127.0.0.1:0\"", line.split(' ').next().unwrap_or(""))
            }
            Some(("project", value)) => format!(
                "project = \"{}\"",
                folder.join(value.trim_matches('"')).display()
            ),
            _ => line.to_string(),
        };
        out.push_str(&line);
        out.push('\n');
    }
    let file = common::scratch(tag).join("plant.toml");
    std::fs::write(&file, out).expect("writes the plant");
    file
}

fn write(address: &str, assignments: &[&str]) {
    let mut args = vec!["write", "--tcp", address];
    args.extend_from_slice(assignments);
    let out = common::cc(&args);
    assert!(out.status.success(), "{}", common::text(&out));
}

fn read(address: &str, var: &str) -> u32 {
    common::read_number(address, var)
}

/// Polls `read` until it gives `want` or 5 s pass; the last value read.
fn settle<T: PartialEq + Copy>(want: T, read: impl Fn() -> T) -> T {
    let deadline = Instant::now() + Duration::from_secs(5);
    loop {
        let now = read();
        if now == want || Instant::now() > deadline {
            return now;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// The port's exchanges in trace lines with `prefix` (`gutta-sim: master: port0`):
/// (request, answer) pairs, in order.
fn exchanges(lines: &[String], prefix: &str) -> Vec<(String, String)> {
    let requests = format!("{prefix} > ");
    let answers = format!("{prefix} < ");
    let mut out = Vec::new();
    let mut pending: Option<String> = None;
    for line in lines {
        if let Some(r) = line.strip_prefix(&requests) {
            pending = Some(r.to_string());
        } else if let (Some(a), Some(r)) = (line.strip_prefix(&answers), pending.take()) {
            out.push((r, a.to_string()));
        }
    }
    out
}

/// The document's capture (GUTTA.md, AN2002 section 5) with the slave's inputs off
/// and AIW0 = 3115.
const CAPTURE: [(&str, &str); 2] = [
    ("01 02 00 04 00 04 38 08", "01 02 01 00 A1 88"),
    (
        "01 03 00 08 00 04 C5 CB",
        "01 03 08 0C 2B 00 00 00 00 00 00 0E 80",
    ),
];

/// With the slave's AIW0 = 3115 and the master polling, the trace until both of the
/// capture's exchanges have shown; the exchanges seen.
fn capture(sim: &Running, slave: &str, master: &str, prefix: &str) -> Vec<(String, String)> {
    write(slave, &["AIW0=3115"]);
    write(master, &["I0.1=1"]);
    let lines = sim.lines_until(|seen| {
        let got = exchanges(seen, prefix);
        CAPTURE
            .iter()
            .all(|(q, a)| got.contains(&(q.to_string(), a.to_string())))
    });
    exchanges(&lines, prefix)
}

#[test]
fn the_an2002_plant_reproduces_the_capture_as_two_processes_do() {
    let plant = shipped_plant("an2002_sample3", "plant-an2002");
    let sim = Running::start(&["--plant", &plant.display().to_string(), "--trace-ports"]);
    let (first, second) = (sim.line(), sim.line());
    let master = address_of(&first, "master", "modbus-tcp");
    let slave = address_of(&second, "slave", "modbus-tcp");
    assert_eq!(
        addresses(&second, "slave")
            .iter()
            .map(|(k, _)| k.as_str())
            .collect::<Vec<_>>(),
        ["modbus-tcp", "rtu-over-tcp"]
    );
    let in_plant = capture(&sim, &slave, &master, "gutta-sim: master: port0");
    // Every exchange before the capture's was one of the two requests, answered.
    for (request, answer) in &in_plant {
        assert!(
            CAPTURE.iter().any(|(q, _)| q == request),
            "{request} / {answer}"
        );
        assert!(!answer.starts_with('('), "{request} got {answer}");
    }

    // The same programs in two processes, the master's port0 a TCP connection to the
    // slave's RTU-over-TCP listener.
    let slave_dir = common::image_dir("plant-slave", &common::example("an2002_sample3_slave.lad"));
    let master_dir = common::image_dir(
        "plant-master",
        &common::example("an2002_sample3_master.lad"),
    );
    let slave_sim = Running::start(&[
        &slave_dir.display().to_string(),
        "--tcp",
        "127.0.0.1:0",
        "--rtu-tcp",
        "127.0.0.1:0",
    ]);
    let slave_tcp = slave_sim
        .line()
        .rsplit(' ')
        .next()
        .expect("address")
        .to_string();
    let slave_rtu = slave_sim
        .line()
        .rsplit(' ')
        .next()
        .expect("address")
        .to_string();
    let master_sim = Running::start(&[
        &master_dir.display().to_string(),
        "--tcp",
        "127.0.0.1:0",
        "--port0",
        &format!("tcp-connect:{slave_rtu}"),
        "--trace-ports",
    ]);
    let master_tcp = master_sim
        .line()
        .rsplit(' ')
        .next()
        .expect("address")
        .to_string();
    let between = capture(&master_sim, &slave_tcp, &master_tcp, "gutta-sim: port0");
    let distinct = |list: &[(String, String)]| {
        let mut set: Vec<(String, String)> = list.to_vec();
        set.sort();
        set.dedup();
        set
    };
    // The same frames: the capture's two exchanges (and, before AIW0 was written,
    // the same exchange with MW0 = 0 in both).
    let tail = |list: &[(String, String)]| distinct(&list[list.len().saturating_sub(2)..]);
    assert_eq!(tail(&in_plant), tail(&between));
    assert_eq!(
        tail(&in_plant),
        distinct(&CAPTURE.map(|(q, a)| (q.to_string(), a.to_string())))
    );

    // The master copies the slave's inputs, as in two processes.
    write(&slave, &["I0.4=1", "I0.6=1"]);
    let copied = settle((0b0101, 3115, 0b010), || {
        (
            read(&master, "QB0") & 0x0F,
            read(&master, "MW110"),
            read(&master, "MB20"),
        )
    });
    assert_eq!(
        copied,
        (0b0101, 3115, 0b010),
        "Q0.0..Q0.3 = the slave's I0.4..I0.7, MW110 = its MW0, table 1 done without error"
    );
    write(&slave, &["I0.7=1", "AIW0=42"]);
    let now = settle((0b1101, 42), || {
        (read(&master, "QB0") & 0x0F, read(&master, "MW110"))
    });
    assert_eq!(now, (0b1101, 42));
}

#[test]
fn the_relay_board_plant_switches_a_relay_from_the_plc_program() {
    if !common::have("mbpoll") {
        return;
    }
    let plant = shipped_plant("relay_board", "plant-relay");
    let sim = Running::start(&["--plant", &plant.display().to_string()]);
    let plc = address_of(&sim.line(), "plc", "modbus-tcp");
    let board = address_of(&sim.line(), "board", "relay-board");
    assert_eq!(common::relay_channels(&board), 0);
    write(&plc, &["I0.0=1", "I0.2=1"]);
    assert_eq!(
        settle((0b0101, 0b0101), || (
            common::relay_channels(&board),
            read(&plc, "MB1")
        )),
        (0b0101, 0b0101),
        "channels 1..4 follow I0.0..I0.3; the PLC reads them back into M1.0..M1.3"
    );
    write(&plc, &["I0.0=0", "I0.1=1", "I0.3=1"]);
    assert_eq!(
        settle((0b1110, 0b1110), || (
            common::relay_channels(&board),
            read(&plc, "MB1")
        )),
        (0b1110, 0b1110)
    );
    // Every exchange answered: the read's and the report switch's error bytes stay 0.
    assert_eq!(read(&plc, "MB81"), 0);
    assert_eq!(read(&plc, "MB113"), 0);
}

/// pymodbus reads holding register 8 (MW0) over Modbus TCP and over RTU over TCP, and
/// the relay board's coil 16#0200; prints them.
const PYMODBUS_READ: &str = r#"
import sys
from pymodbus.client import ModbusTcpClient
from pymodbus.framer import Framer
slave_tcp, slave_rtu, board = (int(p) for p in sys.argv[1:4])
out = []
for port, framer in ((slave_tcp, Framer.SOCKET), (slave_rtu, Framer.RTU)):
    c = ModbusTcpClient("127.0.0.1", port=port, framer=framer, timeout=5)
    c.connect()
    out.append(c.read_holding_registers(8, 1, slave=1).registers[0])
    c.close()
c = ModbusTcpClient("127.0.0.1", port=board, timeout=5)
c.connect()
out.append(int(c.read_coils(0x0200, 1, slave=1).bits[0]))
c.close()
print(" ".join(str(v) for v in out))
"#;

fn port(address: &str) -> &str {
    address.rsplit(':').next().expect("port")
}

#[test]
fn every_device_answers_on_its_own_addresses() {
    if !common::have("mbpoll") {
        return;
    }
    let Some(python) = common::pymodbus_python() else {
        return;
    };
    let dir = common::scratch("plant-reach");
    let slave_dir = common::image_dir(
        "plant-reach-slave",
        &common::example("an2002_sample3_slave.lad"),
    );
    std::fs::write(
        dir.join("plant.toml"),
        format!(
            "[[device]]\nname = \"a\"\nkind = \"plc\"\nimage = \"{}\"\ntcp = [\"127.0.0.1:0\", \"127.0.0.1:0\"]\nrtu-tcp = \"127.0.0.1:0\"\nscan-ms = 5\n\
             [[device]]\nname = \"b\"\nkind = \"plc\"\nimage = \"{}\"\ntcp = \"127.0.0.1:0\"\nscan-ms = 20\n\
             [[device]]\nname = \"board\"\nkind = \"relay-board\"\ntcp = \"127.0.0.1:0\"\n\
             [[device]]\nname = \"fx1\"\nkind = \"fx\"\ntcp = \"127.0.0.1:0\"\n\
             [[device]]\nname = \"quiet\"\nkind = \"plc\"\n",
            slave_dir.display(),
            slave_dir.display()
        ),
    )
    .expect("writes");
    let sim = Running::start(&["--plant", &dir.join("plant.toml").display().to_string()]);
    let a = sim.line();
    let kinds: Vec<String> = addresses(&a, "a").into_iter().map(|(k, _)| k).collect();
    assert_eq!(kinds, ["modbus-tcp", "modbus-tcp", "rtu-over-tcp"]);
    let (a_tcp, a_rtu) = (
        address_of(&a, "a", "modbus-tcp"),
        address_of(&a, "a", "rtu-over-tcp"),
    );
    let b_tcp = address_of(&sim.line(), "b", "modbus-tcp");
    let board = address_of(&sim.line(), "board", "relay-board");
    let fx = address_of(&sim.line(), "fx1", "fx-tcp");
    assert_eq!(sim.line(), "gutta-sim: quiet: no listener");

    // gutta-cc: each PLC is its own.
    write(&a_tcp, &["AIW0=3115"]);
    write(&b_tcp, &["AIW0=7"]);
    assert_eq!(settle(3115, || read(&a_tcp, "MW0")), 3115);
    assert_eq!(settle(7, || read(&b_tcp, "MW0")), 7);
    // mbpoll: the board's channel 1 switched on, read back by mbpoll.
    let mbpoll = |args: &[&str]| {
        let out = Command::new("mbpoll").args(args).output().expect("mbpoll");
        assert!(out.status.success(), "{}", common::text(&out));
        common::stdout(&out)
    };
    mbpoll(&[
        "-m",
        "tcp",
        "-p",
        port(&board),
        "-a",
        "1",
        "-t",
        "0",
        "-r",
        "513",
        "127.0.0.1",
        "1",
    ]);
    let read_back = mbpoll(&[
        "-m",
        "tcp",
        "-p",
        port(&b_tcp),
        "-a",
        "1",
        "-1",
        "-t",
        "4",
        "-r",
        "9",
        "127.0.0.1",
    ]);
    assert!(read_back.contains("[9]: \t7"), "{read_back}");
    // pymodbus: a's MW0 on both of its framings, the board's channel 1.
    let out = Command::new(&python)
        .args([
            "-c",
            PYMODBUS_READ,
            port(&a_tcp),
            port(&a_rtu),
            port(&board),
        ])
        .output()
        .expect("python runs");
    assert_eq!(
        common::stdout(&out).trim(),
        "3115 3115 1",
        "{}",
        common::text(&out)
    );
    // The fx device answers its ENQ with ACK on its raw TCP listener.
    use std::io::{Read, Write};
    let mut s = std::net::TcpStream::connect(&fx).expect("fx connects");
    s.set_read_timeout(Some(Duration::from_secs(5)))
        .expect("timeout");
    s.write_all(&[0x05]).expect("ENQ");
    let mut ack = [0u8; 1];
    s.read_exact(&mut ack).expect("answer");
    assert_eq!(ack, [0x06]);
}

fn stop_with_ctrl_c(mut sim: Running) -> (Option<i32>, Vec<String>) {
    let sent = Command::new("kill")
        .args(["-INT", &sim.child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(sent.success());
    let deadline = Instant::now() + Duration::from_secs(10);
    let status = loop {
        if let Some(status) = sim.child.try_wait().expect("wait") {
            break status;
        }
        assert!(
            Instant::now() < deadline,
            "the plant runs 10 s after SIGINT"
        );
        std::thread::sleep(Duration::from_millis(20));
    };
    let rest: Vec<String> = sim.lines.try_iter().collect();
    (status.code(), rest)
}

#[test]
fn two_plcs_polling_each_other_do_not_deadlock_and_ctrl_c_stops_both() {
    let master = common::root().join("examples/plants/an2002_sample3/master");
    let dir = common::scratch("plant-mutual");
    std::fs::write(
        dir.join("plant.toml"),
        format!(
            "[[device]]\nname = \"left\"\nkind = \"plc\"\nproject = \"{0}\"\ntcp = \"127.0.0.1:0\"\nport0 = \"device:right\"\nscan-ms = 7\n\
             [[device]]\nname = \"right\"\nkind = \"plc\"\nproject = \"{0}\"\ntcp = \"127.0.0.1:0\"\nport0 = \"device:left\"\n",
            master.display()
        ),
    )
    .expect("writes");
    let sim = Running::start(&[
        "--plant",
        &dir.join("plant.toml").display().to_string(),
        "--stats-every",
        "0.5",
    ]);
    let left = address_of(&sim.line(), "left", "modbus-tcp");
    let right = address_of(&sim.line(), "right", "modbus-tcp");
    write(&left, &["I0.1=1", "I0.5=1"]);
    write(&right, &["I0.1=1", "I0.6=1"]);
    // Each reads the other's inputs I0.4..I0.7 into its Q0.0..Q0.3, both scanning and
    // answering all along.
    assert_eq!(settle(0b0100, || read(&left, "QB0") & 0x0F), 0b0100);
    assert_eq!(settle(0b0010, || read(&right, "QB0") & 0x0F), 0b0010);
    let stats = sim.lines_until(|seen| {
        ["left", "right"].iter().all(|n| {
            seen.iter()
                .any(|l| l.starts_with(&format!("gutta-sim: {n}: stats: ")))
        })
    });
    assert!(stats.iter().all(|l| l.contains(": stats: ")), "{stats:?}");
    let (code, rest) = stop_with_ctrl_c(sim);
    assert_eq!(code, Some(0));
    assert_eq!(
        rest.last().map(String::as_str),
        Some("gutta-sim: stopped by Ctrl-C")
    );
}

/// `gutta-sim --plant FILE` with `text` in FILE: it must fail; status and stderr.
fn refused(tag: &str, text: &str) -> (Option<i32>, String, PathBuf) {
    let dir = common::scratch(tag);
    let file = dir.join("plant.toml");
    std::fs::write(&file, text).expect("writes");
    let out = Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
        .args(["--plant", &file.display().to_string()])
        .output()
        .expect("runs");
    (out.status.code(), common::stderr(&out), file)
}

#[test]
fn bad_plant_files_are_refused_with_their_code_and_place() {
    let cases = [
        (
            "[[device]]\nname = \"a\"\nkind = \"plc\"\nscan_ms = 5\n",
            ":4:1: [P0002] unknown key `scan_ms` in a [[device]]; did you mean `scan-ms`?",
        ),
        (
            "[[device]]\nname = \"a\"\nkind = \"plc\"\n[[device]]\nname = \"a\"\nkind = \"plc\"\n",
            ":5:8: [P0005] a second device named `a`",
        ),
        (
            "[[device]]\nname = \"b\"\nkind = \"relay-board\"\nimage = \"x\"\n",
            ":4:9: [P0006] device `b` is a relay-board, which takes no `image`",
        ),
        (
            "[[device]]\nname = \"a\"\nkind = \"plc\"\nport0 = \"device:fx1\"\n[[device]]\nname = \"fx1\"\nkind = \"fx\"\n",
            ":4:9: [P0007] device `a`: port0 = \"device:fx1\": `fx1` is an fx device",
        ),
        ("[[device]]\nname = \"a\"\nkind = \"plc\"\ntcp = 5020\n", ":4:7: [P0001]"),
    ];
    for (n, (text, wanted)) in cases.iter().enumerate() {
        let (code, stderr, file) = refused(&format!("plant-bad-{n}"), text);
        assert_eq!(code, Some(2), "{text}: {stderr}");
        assert!(
            stderr.contains(&format!("gutta-sim: error: {}{wanted}", file.display())),
            "{text}: {stderr}"
        );
    }
    // An image folder that is not there: the device and its place are named.
    let (code, stderr, file) = refused(
        "plant-no-image",
        "[[device]]\nname = \"a\"\nkind = \"plc\"\nimage = \"nowhere\"\n",
    );
    assert_eq!(code, Some(2));
    assert!(
        stderr.contains(&format!("device `a` ({}:1:1): cannot read", file.display())),
        "{stderr}"
    );
}

#[test]
fn a_project_that_does_not_compile_stops_the_start_with_its_first_error() {
    let dir = common::scratch("plant-bad-project");
    std::fs::create_dir_all(dir.join("p")).expect("mkdir");
    std::fs::write(
        dir.join("p/gutta.toml"),
        "[program]\nsources = [\"main.lad\"]\n",
    )
    .expect("writes");
    std::fs::write(
        dir.join("p/main.lad"),
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD I0.0\nNOSUCH Q0.0\nEND_ORGANIZATION_BLOCK\n",
    )
    .expect("writes");
    std::fs::write(
        dir.join("plant.toml"),
        "[[device]]\nname = \"p\"\nkind = \"plc\"\nproject = \"p\"\ntcp = \"127.0.0.1:0\"\n",
    )
    .expect("writes");
    let out = Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
        .args(["--plant", &dir.join("plant.toml").display().to_string()])
        .output()
        .expect("runs");
    let stderr = common::stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    let main = Path::new(&dir).join("p").join("main.lad");
    assert!(
        stderr.contains(&format!("{}:5:", main.display())) && stderr.contains("[E"),
        "{stderr}"
    );
    assert!(stderr.contains("run `gutta-cc build` in"), "{stderr}");
    assert!(!common::stdout(&out).contains(" on "), "no device started");
}

/// A plant device's `flash` is the command line's `--flash`: a program downloaded into
/// it survives kill -9 of the whole plant and a Ctrl-C stop, and comes back running,
/// while the volatile PLC beside it comes back empty.
#[test]
fn a_plant_devices_flash_survives_kill_9_and_ctrl_c() {
    let dir = common::scratch("plant-flash");
    let flash = dir.join("flash-kept");
    std::fs::write(
        dir.join("plant.toml"),
        "[[device]]\nname = \"kept\"\nkind = \"plc\"\nflash = \"flash-kept\"\ntcp = \"127.0.0.1:0\"\n\
         [[device]]\nname = \"volatile\"\nkind = \"plc\"\ntcp = \"127.0.0.1:0\"\n",
    )
    .expect("writes");
    let plant = dir.join("plant.toml").display().to_string();
    let image = common::image_dir("plant-flash-image", &common::example("tank.lad"));
    let start = || {
        let sim = Running::start(&["--plant", &plant]);
        let lines = sim.lines_until(|seen| {
            seen.iter()
                .any(|l| l.starts_with("gutta-sim: volatile: modbus-tcp on "))
        });
        let flash_line = lines
            .iter()
            .find(|l| l.starts_with("gutta-sim: kept: flash "))
            .cloned()
            .unwrap_or_else(|| panic!("no flash line in {lines:?}"));
        let kept = lines
            .iter()
            .find(|l| l.starts_with("gutta-sim: kept: modbus-tcp"))
            .map(|l| address_of(l, "kept", "modbus-tcp"))
            .expect("kept's start line");
        let volatile = address_of(lines.last().expect("a line"), "volatile", "modbus-tcp");
        (sim, flash_line, kept, volatile)
    };
    let (sim, flash_line, kept, volatile) = start();
    assert_eq!(
        flash_line,
        format!("gutta-sim: kept: flash {}: empty", flash.display())
    );
    for address in [&kept, &volatile] {
        let o = common::cc(&["download", &image.display().to_string(), "--tcp", address]);
        assert!(o.status.success(), "{}", common::text(&o));
    }
    drop(sim); // SIGKILL

    let uploaded = |address: &str, tag: &str| {
        let up = common::scratch(tag).join("up");
        let o = common::cc(&["upload", "-o", &up.display().to_string(), "--tcp", address]);
        assert!(o.status.code() != Some(2), "{}", common::text(&o));
        (o.status.code(), up)
    };
    let (sim, flash_line, kept, volatile) = start();
    assert!(
        flash_line.contains(": CPU-EC20 program, ") && flash_line.ends_with(", RUN"),
        "{flash_line}"
    );
    let (code, up) = uploaded(&kept, "plant-flash-up1");
    assert_eq!(code, Some(0));
    assert_eq!(
        common::tree_files(&up),
        common::tree_files(&image),
        "kept's upload"
    );
    let status = common::cc(&["status", "--tcp", &kept]);
    assert!(
        common::stdout(&status).contains(": RUN "),
        "{}",
        common::text(&status)
    );
    let (code, _) = uploaded(&volatile, "plant-flash-up2");
    assert_eq!(code, Some(1), "the volatile PLC comes back empty");

    // Stopped with Ctrl-C in STOP: it comes back stopped, its program kept.
    let o = common::cc(&["stop", "--tcp", &kept]);
    assert!(o.status.success(), "{}", common::text(&o));
    let (code, _) = stop_with_ctrl_c(sim);
    assert_eq!(code, Some(0));
    let (_sim, flash_line, kept, _) = start();
    assert!(flash_line.ends_with(", STOP"), "{flash_line}");
    let (code, up) = uploaded(&kept, "plant-flash-up3");
    assert_eq!(code, Some(0));
    assert_eq!(
        common::tree_files(&up),
        common::tree_files(&image),
        "kept's upload"
    );
}
