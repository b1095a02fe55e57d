//! EXCH through a Modbus RTU <-> TCP gateway, end to end with two `gutta-sim`
//! processes: PLC A runs examples/exch_modbus_tcp_gateway.lad with `--port0
//! modbus-tcp:` leading to PLC B's Modbus TCP listener. A's inputs are set with
//! `gutta-cc write`; B's coils (its Q0.0..Q0.3) follow, read with `gutta-cc read` and
//! with mbpoll; what A reads back from B lands in A's M1.0..M1.3.

mod common;

use std::process::Command;
use std::time::{Duration, Instant};

use common::Sim;

fn start(args: &[&str]) -> Sim {
    common::sim_on_free_port(args)
}

fn read(address: &str, var: &str) -> u32 {
    common::read_number(address, var)
}

fn write(address: &str, assignments: &[&str]) {
    let mut args = vec!["write", "--tcp", address];
    args.extend_from_slice(assignments);
    let out = common::cc(&args);
    assert!(out.status.success(), "{}", common::text(&out));
}

/// Polls until `(B's QB0, A's MB1)` is `want` (each poll of A is 200 ms) or 5 s pass.
fn settle(a: &str, b: &str, want: (u32, u32)) -> (u32, u32) {
    let deadline = Instant::now() + Duration::from_secs(5);
    loop {
        let now = (read(b, "QB0"), read(a, "MB1"));
        if now == want || Instant::now() > deadline {
            return now;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
}

#[test]
fn exch_switches_and_reads_the_coils_of_another_plc_through_the_gateway() {
    let image = common::image_dir(
        "exch_modbus_tcp_gateway",
        &common::example("exch_modbus_tcp_gateway.lad"),
    );
    let b = start(&["--plc", "CPU-EC20"]);
    let image = image.display().to_string();
    let a = start(&[&image, "--port0", &format!("modbus-tcp:{}", b.1)]);

    write(&a.1, &["I0.0=1", "I0.2=1"]);
    assert_eq!(
        settle(&a.1, &b.1, (0b0101, 0b0101)),
        (0b0101, 0b0101),
        "B's Q0.0..Q0.3 follow A's I0.0..I0.3; A reads them back into M1.0..M1.3"
    );
    write(&a.1, &["I0.0=0", "I0.1=1", "I0.3=1"]);
    assert_eq!(settle(&a.1, &b.1, (0b1110, 0b1110)), (0b1110, 0b1110));
    // No exchange failed: the read table's error byte (MB81) stays 0.
    assert_eq!(read(&a.1, "MB81"), 0);

    // An independent client sees the same coils on B.
    if common::have("mbpoll") {
        let port = b.1.rsplit(':').next().expect("port").to_string();
        let out = Command::new("mbpoll")
            .args(["-m", "tcp", "-p", &port, "-a", "1", "-1"])
            .args(["-t", "0", "-r", "1", "-c", "4", "127.0.0.1"])
            .output()
            .expect("runs mbpoll");
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "{text}");
        for (coil, value) in [(1, 0), (2, 1), (3, 1), (4, 1)] {
            assert!(text.contains(&format!("[{coil}]: \t{value}")), "{text}");
        }
    }

    // B gone: the gateway's connection is refused, EXCH ends with error 2.
    drop(b);
    let deadline = Instant::now() + Duration::from_secs(5);
    while read(&a.1, "MB81") != 2 && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(100));
    }
    assert_eq!(read(&a.1, "MB81"), 2, "silence: timeout (error 2)");
}
