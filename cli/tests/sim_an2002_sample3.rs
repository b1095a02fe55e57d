//! AN2002 sample 3 end to end with two `gutta-sim` processes: the slave serves RTU over
//! TCP; the master's PORT0 leads there (`--port0 tcp-connect:`), and its EXCH polls the
//! slave every 200 ms through gutta-protocol's master. Inputs are set and outputs read
//! over Modbus TCP with gutta-link, as `gutta-cc write/read` do.

mod common;

use std::io::{BufRead, BufReader};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use gutta_catalog::stdlib;
use gutta_format::{Operand, PackedOperand};
use gutta_link::transport::TcpTransport;
use gutta_link::{Client, FACTORY_PASSWORD};

struct Sim(Child, Vec<String>);

impl Drop for Sim {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn image_dir(example: &str) -> PathBuf {
    common::image_dir(example, &common::example(example))
}

fn start(args: &[String], listeners: usize) -> Sim {
    let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("starts gutta-sim");
    let mut lines = BufReader::new(child.stdout.take().expect("stdout")).lines();
    let addresses = (0..listeners)
        .map(|_| {
            let line = lines.next().expect("listener").expect("text");
            line.rsplit(' ').next().expect("address").to_string()
        })
        .collect();
    Sim(child, addresses)
}

fn client(address: &str) -> Client {
    let mut c = Client::new(
        Box::new(TcpTransport::connect(address, 1000, 2).expect("connects")),
        1,
    );
    c.attach(&FACTORY_PASSWORD).expect("login");
    c
}

fn packed(var: &str) -> u32 {
    let target = stdlib::shared("CPU-EC20").expect("target");
    let a = target.memory.parse_address(var).expect("address");
    PackedOperand::encode(Operand::Value(a)).0
}

#[test]
fn the_master_polls_the_slave_over_exch() {
    let slave_dir = image_dir("an2002_sample3_slave.lad");
    let master_dir = image_dir("an2002_sample3_master.lad");
    let slave = start(
        &[
            slave_dir.display().to_string(),
            "--tcp".into(),
            "127.0.0.1:0".into(),
            "--rtu-tcp".into(),
            "127.0.0.1:0".into(),
        ],
        2,
    );
    let master = start(
        &[
            master_dir.display().to_string(),
            "--tcp".into(),
            "127.0.0.1:0".into(),
            "--port0".into(),
            format!("tcp-connect:{}", slave.1[1]),
        ],
        1,
    );
    let mut s = client(&slave.1[0]);
    let mut m = client(&master.1[0]);
    // The slave's I0.4 and I0.6 on, AIW0 = 3115 (it publishes AIW0 in MW0).
    s.write_vars(
        &[
            (packed("I0.4"), 1),
            (packed("I0.6"), 1),
            (packed("AIW0"), 3115),
        ],
        false,
    )
    .expect("slave inputs");
    // Polling on (I0.1 of the master, AN2002's test procedure).
    m.write_vars(&[(packed("I0.1"), 1)], false)
        .expect("master input");
    let deadline = Instant::now() + Duration::from_secs(5);
    let read = |m: &mut Client| {
        let v = m
            .read_vars(&[packed("QB0"), packed("MW110"), packed("MB20")])
            .expect("read");
        (
            v[0][0] & 0x0F,
            u16::from_le_bytes([v[1][0], v[1][1]]),
            v[2][0],
        )
    };
    let mut last = read(&mut m);
    while last != (0b0101, 3115, 0b010) && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(50));
        last = read(&mut m);
    }
    assert_eq!(
        last,
        (0b0101, 3115, 0b010),
        "Q0.0..Q0.3 = the slave's I0.4..I0.7, MW110 = the slave's MW0, table 1 done without error"
    );
    // The slave changes; the master follows within a few polls.
    s.write_vars(&[(packed("I0.7"), 1), (packed("AIW0"), 42)], false)
        .expect("slave inputs");
    let deadline = Instant::now() + Duration::from_secs(5);
    while read(&mut m).0 != 0b1101 && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(50));
    }
    let now = read(&mut m);
    assert_eq!((now.0, now.1), (0b1101, 42));
}
