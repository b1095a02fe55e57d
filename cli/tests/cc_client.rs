//! `gutta-cc download|upload|status|run|stop|read|write|force|debug` against a
//! `gutta-sim` process (this package's binary). The serial-line test needs socat.

mod common;

use common::{cc, stdout, text, Sim};

use std::collections::BTreeMap;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

fn compile(plc: &str, tag: &str) -> PathBuf {
    compile_example(plc, "in1001_pointers.lad", tag)
}

fn compile_example(plc: &str, example: &str, tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gutta-cc-client-{tag}-{}", std::process::id()));
    let example = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples")
        .join(example);
    let o = cc(&[
        example.to_str().expect("path"),
        "--plc",
        plc,
        "-o",
        dir.to_str().expect("path"),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    dir
}

/// Every file under `dir`, by its path relative to `dir` with `/` separators.
fn files_under(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    gutta_io::directory_files(dir).expect("a readable directory")
}

#[test]
fn download_then_operate_the_plc() {
    let sim = common::sim("CPU-EC20", None);
    let image = compile("CPU-EC20", "ok");
    let at = ["--tcp", sim.1.as_str()];
    let run = |args: &[&str]| {
        let mut all = args.to_vec();
        all.extend_from_slice(&at);
        cc(&all)
    };
    let o = run(&["download", image.to_str().expect("path")]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("downloaded 3 pages"), "{}", text(&o));
    std::thread::sleep(std::time::Duration::from_millis(100));
    let o = run(&["status"]);
    assert!(text(&o).starts_with("CPU-EC20: RUN"), "{}", text(&o));
    let o = run(&["read", "MW24", "MW26", "Q0.0"]);
    assert_eq!(
        String::from_utf8_lossy(&o.stdout),
        "MW24 = 3585\nMW26 = 3586\nQ0.0 = 0\n"
    );
    // run and stop say what they did, and when the PLC already was so.
    let o = run(&["stop"]);
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(stdout(&o), "the PLC is stopped (it was running)\n");
    assert!(text(&run(&["status"])).starts_with("CPU-EC20: STOP"));
    assert_eq!(stdout(&run(&["stop"])), "the PLC was already stopped\n");
    let o = run(&["stop", "--message-format", "json"]);
    let v: serde_json::Value = serde_json::from_str(stdout(&o).trim()).expect("JSON");
    assert_eq!(
        v,
        serde_json::json!({"command": "stop", "ok": true, "run": false, "changed": false})
    );
    let o = run(&["write", "MW40=16#BEEF", "AIW0=100", "Q0.1=1"]);
    assert!(o.status.success(), "{}", text(&o));
    // Words read signed (issue 11): 16#BEEF is -16657; `:hex` shows the bits.
    let o = run(&["read", "MW40", "AIW0", "Q0.1", "MW40:hex"]);
    assert_eq!(
        String::from_utf8_lossy(&o.stdout),
        "MW40 = -16657\nAIW0 = 100\nQ0.1 = 1\nMW40 = 16#BEEF\n"
    );
    // Forcing M is refused; a bad value is a usage error before anything is sent.
    let o = run(&["force", "MW0=1"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o).contains("only I and Q can be forced"),
        "{}",
        text(&o)
    );
    let o = run(&["write", "MB0=300"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).contains("does not fit"), "{}", text(&o));
    let o = run(&["run"]);
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(stdout(&o), "the PLC runs (it was stopped)\n");
    let o = run(&["run", "--message-format", "json"]);
    let v: serde_json::Value = serde_json::from_str(stdout(&o).trim()).expect("JSON");
    assert_eq!(
        v,
        serde_json::json!({"command": "run", "ok": true, "run": true, "changed": false})
    );
    assert_eq!(stdout(&run(&["run"])), "the PLC already runs\n");
    // Inputs are terminals: written while the PLC runs, they hold across scans (about
    // ten in 100 ms at the simulator's 10 ms period) until written again.
    assert!(run(&["write", "AIW0=1234", "I0.3=1"]).status.success());
    std::thread::sleep(std::time::Duration::from_millis(100));
    assert_eq!(
        String::from_utf8_lossy(&run(&["read", "AIW0", "I0.3"]).stdout),
        "AIW0 = 1234\nI0.3 = 1\n"
    );
    assert!(run(&["write", "AIW0=100", "I0.3=0"]).status.success());
    // Upload: the directory gutta-cc wrote for the download, every file byte for byte,
    // manifest.json included, and no file more or less.
    let back = std::env::temp_dir().join(format!("gutta-cc-upload-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&back);
    let o = run(&["upload", "-o", back.to_str().expect("path")]);
    assert!(o.status.success(), "{}", text(&o));
    let sent = files_under(&image);
    let got = files_under(&back);
    let _ = std::fs::remove_dir_all(&back);
    assert_eq!(
        sent.keys().collect::<Vec<_>>(),
        [
            "argument/00.bin",
            "const.bin",
            "instruction/00.bin",
            gutta_format::MANIFEST_FILE
        ]
    );
    assert_eq!(
        got.keys().collect::<Vec<_>>(),
        sent.keys().collect::<Vec<_>>(),
        "the same files"
    );
    assert_eq!(
        String::from_utf8_lossy(&got[gutta_format::MANIFEST_FILE]),
        String::from_utf8_lossy(&sent[gutta_format::MANIFEST_FILE])
    );
    for (name, bytes) in &sent {
        assert_eq!(&got[name], bytes, "{name}");
    }
    // Force an input, release it: the terminal (0) shows again.
    assert!(run(&["force", "I0.2=1"]).status.success());
    std::thread::sleep(std::time::Duration::from_millis(50));
    assert_eq!(
        String::from_utf8_lossy(&run(&["read", "I0.2"]).stdout),
        "I0.2 = 1\n"
    );
    assert!(run(&["unforce", "I0.2"]).status.success());
    std::thread::sleep(std::time::Duration::from_millis(50));
    assert_eq!(
        String::from_utf8_lossy(&run(&["read", "I0.2"]).stdout),
        "I0.2 = 0\n"
    );
    // Debug: reset into single-step stop, run to a breakpoint before the second
    // pointer write (network 1 step 4), step over it.
    assert!(run(&["debug", "break", "MAIN:1:4"]).status.success());
    let o = run(&["debug", "reset"]);
    assert!(text(&o).contains("paused at:  MAIN:1:0"), "{}", text(&o));
    assert!(run(&["debug", "run"]).status.success());
    std::thread::sleep(std::time::Duration::from_millis(100));
    let o = run(&["debug", "info"]);
    assert!(text(&o).contains("paused at:  MAIN:1:4"), "{}", text(&o));
    assert_eq!(
        String::from_utf8_lossy(&run(&["read", "MW24", "MW26"]).stdout),
        "MW24 = 3585\nMW26 = 0\n"
    );
    assert!(run(&["debug", "step", "over"]).status.success());
    assert_eq!(
        String::from_utf8_lossy(&run(&["read", "MW26"]).stdout),
        "MW26 = 3586\n"
    );
    assert!(run(&["debug", "clear"]).status.success());
    assert!(run(&["debug", "run"]).status.success());
    let o = run(&["debug", "step", "sideways"]);
    assert_eq!(o.status.code(), Some(2));
    // A wrong password: refused, exit 2.
    let o = run(&["status", "--password", "wrong"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).contains("wrong password"), "{}", text(&o));
}

#[test]
fn a_download_for_another_plc_type_changes_nothing() {
    let sim = common::sim("CPU-EC20", None);
    let image = compile("EC30-EK51", "other");
    let o = cc(&["download", image.to_str().expect("path"), "--tcp", &sim.1]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o).contains("the PLC is a CPU-EC20, the image is for EC30-EK51"),
        "{}",
        text(&o)
    );
    // Nothing to reach: a clear usage error.
    let o = cc(&["status"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).contains("--tcp HOST:PORT"), "{}", text(&o));
}

#[test]
fn download_and_operate_over_a_serial_line() {
    if !common::have("socat") {
        return;
    }
    // A socat pty pair is the serial cable: gutta-sim on one end, gutta-cc on the other.
    let base = std::env::temp_dir().join(format!("gutta-cc-serial-{}", std::process::id()));
    let (plc_end, tool_end) = (base.with_extension("plc"), base.with_extension("tool"));
    let mut socat = Command::new("socat")
        .arg(format!("pty,raw,echo=0,link={}", plc_end.display()))
        .arg(format!("pty,raw,echo=0,link={}", tool_end.display()))
        .stderr(Stdio::null())
        .spawn()
        .expect("socat starts");
    for _ in 0..100 {
        if plc_end.exists() && tool_end.exists() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
        .args(["--plc", "CPU-EC20", "--serial"])
        .arg(&plc_end)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("gutta-sim starts");
    let mut said = BufReader::new(child.stdout.take().expect("stdout")).lines();
    let line = said.next().expect("listener").expect("text");
    // Later lines arrive on a thread, so a missing one fails the test instead of
    // hanging it.
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in said.map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    let sim = Sim(child, line);
    assert!(sim.1.ends_with("(19200 8E1)"), "{}", sim.1);
    let image = compile("CPU-EC20", "serial");
    let device = tool_end.to_str().expect("path").to_string();
    let run = |args: &[&str]| {
        let mut all = args.to_vec();
        all.extend_from_slice(&["--serial", &device]);
        cc(&all)
    };
    let o = run(&["download", image.to_str().expect("path")]);
    let status = run(&["status"]);
    let read = run(&["read", "MW24", "MW26"]);
    // blink's system block: station 20, 38400 8E1, password 1234. After its reset the
    // simulator's end of the line runs at 38400; gutta-cc says how to reach it.
    let blink = compile_example("CPU-EC20", "blink.lad", "serial-blink");
    let moved = run(&["download", blink.to_str().expect("path")]);
    // The simulator reports each switch of its end of the line.
    let switched = || {
        rx.recv_timeout(std::time::Duration::from_secs(10))
            .unwrap_or_default()
    };
    let after_blink = switched();
    let at_20 = ["--station", "20", "--baud", "38400", "--password", "1234"];
    let blink_status = run(&[&["status"][..], &at_20].concat());
    // Downloading again from there: PLC_CLEAR sends the PLC back to station 1 at 19200
    // 8E1, the client follows, and the pointer example (no system block) stays there.
    let back = run(&[&["download", image.to_str().expect("path")][..], &at_20].concat());
    let after_clear = switched();
    let final_status = run(&["status"]);
    drop(sim);
    let _ = socat.kill();
    let _ = socat.wait();
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&status).starts_with("CPU-EC20: RUN"),
        "{}",
        text(&status)
    );
    assert_eq!(
        String::from_utf8_lossy(&read.stdout),
        "MW24 = 3585\nMW26 = 3586\n",
        "{}",
        text(&read)
    );
    assert!(moved.status.success(), "{}", text(&moved));
    assert!(
        text(&moved).contains(
            "the PLC now answers as station 20 on a 38400 8E1 line (its system block): \
             use --station 20 --baud 38400 --parity even"
        ),
        "{}",
        text(&moved)
    );
    assert!(after_blink.ends_with("now 38400 8E1"), "{after_blink}");
    assert!(
        text(&blink_status).starts_with("CPU-EC20: RUN"),
        "{}",
        text(&blink_status)
    );
    assert!(back.status.success(), "{}", text(&back));
    assert!(after_clear.ends_with("now 19200 8E1"), "{after_clear}");
    assert!(
        text(&final_status).starts_with("CPU-EC20: RUN"),
        "{}",
        text(&final_status)
    );
}
