//! Ctrl-C on a `gutta-sim` process (SIGINT, sent with `kill -INT`) and SIGTERM: it stops cleanly
//! with exit status 0 and one line saying so, as its help promises, also with a client
//! connected. Unix only (SIGINT); nothing here drives the protocol.

#![cfg(unix)]

use std::io::{BufRead, BufReader, Read};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A running simulator, killed on drop if the test did not stop it.
struct Sim(Child);

impl Drop for Sim {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

#[test]
fn ctrl_c_stops_the_simulator_with_status_0() {
    stops_cleanly_on("-INT", "gutta-sim: stopped by Ctrl-C\n");
}

/// SIGTERM (what a service manager or `docker stop` sends) is a clean stop too.
#[test]
fn sigterm_stops_the_simulator_with_status_0() {
    stops_cleanly_on("-TERM", "gutta-sim: stopped by SIGTERM\n");
}

/// `kill SIGNAL` on a simulator with a client connected: exit status 0, `line` the
/// only output after the listener line, nothing on stderr.
fn stops_cleanly_on(signal: &str, line: &str) {
    let mut sim = Sim(Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
        .args(["--tcp", "127.0.0.1:0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("gutta-sim starts"));
    let mut stdout = BufReader::new(sim.0.stdout.take().expect("stdout"));
    let mut listening = String::new();
    stdout.read_line(&mut listening).expect("listener line");
    let address = listening.trim().rsplit(' ').next().expect("address");
    // A connected client does not keep it running.
    let _client = TcpStream::connect(address).expect("connects");
    let sent = Command::new("kill")
        .args([signal, &sim.0.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(sent.success(), "kill {signal} failed");

    let deadline = Instant::now() + Duration::from_secs(10);
    let status = loop {
        if let Some(status) = sim.0.try_wait().expect("wait") {
            break status;
        }
        assert!(
            Instant::now() < deadline,
            "gutta-sim still runs 10 s after kill {signal}"
        );
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut rest = String::new();
    stdout.read_to_string(&mut rest).expect("stdout");
    let mut stderr = String::new();
    if let Some(mut e) = sim.0.stderr.take() {
        e.read_to_string(&mut stderr).expect("stderr");
    }
    assert_eq!(status.code(), Some(0), "{status}; stderr: {stderr}");
    assert_eq!(rest, line, "stderr: {stderr}");
    assert_eq!(stderr, "");
}
