//! Power cuts during a download (docs/simulator.md, "Flash and power-on"): a
//! `gutta-sim --flash DIR` holding an old program is killed (SIGKILL) at more than 20
//! points of `gutta-cc download NEW` — before each request (a proxy that counts Modbus
//! TCP frames kills it instead of forwarding the next one), in the middle of requests
//! (half a frame forwarded), and inside the flash commits of PLC_CLEAR and STATUS_RESET
//! (GUTTA_SIM_FLASH_PAUSE_MS), and right after STATUS_RESET's answer — then
//! restarted on DIR. Each time the PLC holds the old
//! program, or no program with the interrupted state (RUN refused, `gutta-cc status`
//! says so), or the new program; never a half image, never a flash that fails its
//! check, and in that order as the cut moves later.

#![cfg(unix)]

mod common;

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::sync::mpsc;
use std::time::Duration;

use common::{stdout, text};

const PASSWORD: &str = "n3w";

fn old_image() -> gutta_format::Image {
    common::image(
        "old.lad",
        "ORGANIZATION_BLOCK MAIN\nBEGIN\nNETWORK 1\nLD SM0.0\nMOVW 16#0A1D, MW24\n\
         END_ORGANIZATION_BLOCK\n",
    )
}

/// Bigger than the old one (a data block, a subroutine, a password).
fn new_image() -> gutta_format::Image {
    common::image(
        "new.lad",
        &format!(
            "ORGANIZATION_BLOCK MAIN\nBEGIN\nNETWORK 1\nLD SM0.0\nINCW MW30\nCALL SBR_0\n\
             END_ORGANIZATION_BLOCK\n\nSUBROUTINE_BLOCK SBR_0\nBEGIN\nNETWORK 1\nLD SM0.0\n\
             MOVW 16#0BEE, MW24\nEND_SUBROUTINE_BLOCK\n\nDATA_BLOCK DAT_0:DAT0\n  MW40 UINT 6\n\
             MW42 UINT 30\nEND_DATA_BLOCK\n\nSYSTEM_BLOCK\n  PASSWORD = \"{PASSWORD}\"\nEND_SYSTEM_BLOCK\n"
        ),
    )
}

/// A simulator on DIR, killed when dropped; its stderr lines arrive on `stderr`.
struct Sim {
    child: Child,
    address: String,
    stderr: mpsc::Receiver<String>,
}

impl Drop for Sim {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Sim {
    /// `pause`: (milliseconds, the commit that pauses).
    fn start(dir: &Path, image: Option<&Path>, pause: Option<(u64, usize)>) -> Sim {
        let mut command = Command::new(env!("CARGO_BIN_EXE_gutta-sim"));
        command.args(image).arg("--flash").arg(dir);
        command.args(["--tcp", "127.0.0.1:0"]);
        command.env_remove("GUTTA_SIM_FLASH_PAUSE_MS");
        command.env_remove("GUTTA_SIM_FLASH_PAUSE_COMMIT");
        if let Some((ms, k)) = pause {
            command.env("GUTTA_SIM_FLASH_PAUSE_MS", ms.to_string());
            command.env("GUTTA_SIM_FLASH_PAUSE_COMMIT", k.to_string());
        }
        let mut child = command
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("starts gutta-sim");
        let (tx, stderr) = mpsc::channel();
        let err = child.stderr.take().expect("stderr");
        std::thread::spawn(move || {
            for line in BufReader::new(err).lines().map_while(Result::ok) {
                let _ = tx.send(line);
            }
        });
        let out = BufReader::new(child.stdout.take().expect("stdout"));
        let listening = out
            .lines()
            .map_while(Result::ok)
            .find(|l| l.contains("modbus-tcp on"));
        let Some(listening) = listening else {
            let _ = child.kill();
            let _ = child.wait();
            panic!(
                "gutta-sim did not listen: {:?}",
                stderr.try_iter().collect::<Vec<_>>()
            );
        };
        let address = listening.rsplit(' ').next().expect("address").to_string();
        Sim {
            child,
            address,
            stderr,
        }
    }

    fn kill(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn cc(address: &str, args: &[&str], password: Option<&str>) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_gutta-cc"));
    command
        .args(args)
        .args(["--tcp", address])
        .env_remove("GUTTA_PASSWORD");
    if let Some(p) = password {
        command.env("GUTTA_PASSWORD", p);
    }
    command.output().expect("gutta-cc runs")
}

/// Where a cut falls.
#[derive(Debug, Clone, Copy)]
enum Cut {
    /// Killed instead of forwarding request N (0-based): requests before it answered.
    Before(usize),
    /// Half of request N forwarded, then killed.
    Inside(usize),
    /// Request N forwarded and answered, then killed.
    After(usize),
    /// Killed while the N-th flash commit (1-based) pauses.
    Commit(usize),
}

/// What the PLC holds after the restart.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Outcome {
    Old,
    Interrupted,
    New,
}

/// One Modbus TCP frame (MBAP header and PDU) from `stream`.
fn read_frame(stream: &mut TcpStream) -> Option<Vec<u8>> {
    let mut header = [0u8; 6];
    stream.read_exact(&mut header).ok()?;
    let len = usize::from(u16::from_be_bytes([header[4], header[5]]));
    let mut frame = header.to_vec();
    frame.resize(6 + len, 0);
    stream.read_exact(&mut frame[6..]).ok()?;
    Some(frame)
}

/// A proxy in front of `sim` for one client connection: forwards requests and answers,
/// and at `cut` (a `Before` or `Inside`) kills the simulator (by pid) and closes. Returns
/// its address and a handle giving the number of requests it saw.
fn proxy(
    sim_address: String,
    pid: u32,
    cut: Option<Cut>,
) -> (String, std::thread::JoinHandle<usize>) {
    let listener = TcpListener::bind("127.0.0.1:0").expect("binds");
    let address = listener.local_addr().expect("address").to_string();
    let handle = std::thread::spawn(move || {
        let kill = || {
            let _ = Command::new("kill").args(["-9", &pid.to_string()]).status();
        };
        let mut seen = 0;
        // gutta-cc may connect more than once; serve connections until one ends in a cut.
        for client in listener.incoming() {
            let Ok(mut client) = client else { break };
            let Ok(mut server) = TcpStream::connect(&sim_address) else {
                break;
            };
            while let Some(frame) = read_frame(&mut client) {
                match cut {
                    Some(Cut::Before(n)) if n == seen => {
                        kill();
                        return seen;
                    }
                    Some(Cut::Inside(n)) if n == seen => {
                        let _ = server.write_all(&frame[..frame.len() / 2]);
                        let _ = server.flush();
                        std::thread::sleep(Duration::from_millis(50));
                        kill();
                        return seen;
                    }
                    _ => {}
                }
                seen += 1;
                if server.write_all(&frame).is_err() {
                    return seen;
                }
                let Some(answer) = read_frame(&mut server) else {
                    return seen;
                };
                if client.write_all(&answer).is_err() {
                    return seen;
                }
                if matches!(cut, Some(Cut::After(n)) if n + 1 == seen) {
                    kill();
                    return seen;
                }
            }
            if cut.is_none() {
                return seen;
            }
        }
        seen
    });
    (address, handle)
}

/// A fresh DIR holding the old program, committed and running.
fn seeded(tag: &str, old: &Path) -> PathBuf {
    let dir = common::scratch(&format!("flash-kill-{tag}")).join("flash");
    let mut sim = Sim::start(&dir, Some(old), None);
    sim.kill();
    dir
}

/// Restart on `dir` and say what the PLC holds, checking each state fully.
fn outcome(dir: &Path, old: &Path, new: &Path, scratch: &Path) -> Outcome {
    let sim = Sim::start(dir, None, None);
    let status = |password| {
        let o = cc(
            &sim.address,
            &["status", "--message-format", "json"],
            password,
        );
        o.status
            .success()
            .then(|| serde_json::from_str::<serde_json::Value>(stdout(&o).trim()).expect("JSON"))
    };
    let (status, password) = match status(None) {
        Some(s) => (s, None),
        None => (
            status(Some(PASSWORD)).expect("neither password logs in"),
            Some(PASSWORD),
        ),
    };
    let state = status["state"].as_str().expect("state").to_string();
    let up = scratch.join("up");
    let _ = std::fs::remove_dir_all(&up);
    match state.as_str() {
        "running" => {
            let o = cc(
                &sim.address,
                &["upload", "-o", up.to_str().expect("utf-8")],
                password,
            );
            assert!(o.status.success(), "{}", text(&o));
            let expected = if password.is_some() { new } else { old };
            assert_eq!(
                common::tree_files(&up),
                common::tree_files(expected),
                "uploaded a program that is neither"
            );
            if password.is_some() {
                Outcome::New
            } else {
                Outcome::Old
            }
        }
        "download-interrupted" => {
            assert_eq!(password, None, "the cleared flash keeps no password");
            assert_eq!(status["error_code"], 0x10);
            let o = cc(&sim.address, &["status"], None);
            assert!(
                stdout(&o).starts_with("CPU-EC20: STOP, no program: a download was interrupted"),
                "{}",
                text(&o)
            );
            let o = cc(&sim.address, &["run"], None);
            assert!(
                !o.status.success(),
                "RUN accepted without a program: {}",
                text(&o)
            );
            Outcome::Interrupted
        }
        other => panic!("after the restart the PLC is `{other}`: {status}"),
    }
}

/// Cut a download at `cut`, restart, and say what the PLC holds.
fn cut_download(cut: Cut, n: usize, old: &Path, new: &Path) -> Outcome {
    let tag = format!("{n}");
    let dir = seeded(&tag, old);
    let scratch = dir.parent().expect("parent").to_path_buf();
    let new_arg = new.to_str().expect("utf-8").to_string();
    match cut {
        Cut::Before(_) | Cut::Inside(_) | Cut::After(_) => {
            let mut sim = Sim::start(&dir, None, None);
            let (address, seen) = proxy(sim.address.clone(), sim.child.id(), Some(cut));
            let o = cc(&address, &["download", &new_arg], None);
            let seen = seen.join().expect("proxy");
            if !matches!(cut, Cut::After(_)) {
                assert!(
                    !o.status.success(),
                    "{cut:?}: the download went through ({seen} requests)"
                );
            }
            sim.kill();
        }
        Cut::Commit(k) => {
            let mut sim = Sim::start(&dir, None, Some((20_000, k)));
            let address = sim.address.clone();
            let download = std::thread::spawn(move || cc(&address, &["download", &new_arg], None));
            let line = sim
                .stderr
                .recv_timeout(Duration::from_secs(20))
                .expect("a commit pauses");
            assert!(line.contains("paused 20000 ms in a commit"), "{line}");
            sim.kill();
            let o = download.join().expect("download");
            assert!(!o.status.success(), "{}", text(&o));
        }
    }
    outcome(&dir, old, new, &scratch)
}

#[test]
fn a_power_cut_at_any_point_of_a_download_loses_nothing_committed() {
    let old = common::image_dir("flash-kill-old", &old_image());
    let new = common::image_dir("flash-kill-new", &new_image());
    // A whole download through the proxy: how many requests it takes.
    let dir = seeded("count", &old);
    let sim = Sim::start(&dir, None, None);
    let (address, seen) = proxy(sim.address.clone(), sim.child.id(), None);
    let o = cc(&address, &["download", new.to_str().expect("utf-8")], None);
    assert!(o.status.success(), "{}", text(&o));
    let requests = seen.join().expect("proxy");
    drop(sim);
    assert!(requests >= 16, "only {requests} requests");

    let mut cuts: Vec<Cut> = (0..requests).map(Cut::Before).collect();
    cuts.extend([0, 2, requests / 2, requests - 1].map(Cut::Inside));
    cuts.extend([1, 2].map(Cut::Commit));
    // Killed right after STATUS_RESET's answer left: the new program is committed.
    cuts.push(Cut::After(requests - 1));
    assert!(cuts.len() >= 20);
    let mut seen_outcomes = Vec::new();
    for (n, cut) in cuts.iter().enumerate() {
        let outcome = cut_download(*cut, n, &old, &new);
        seen_outcomes.push((*cut, outcome));
    }
    // As the cut moves later the PLC goes old -> interrupted -> new, never back.
    let before: Vec<Outcome> = seen_outcomes
        .iter()
        .filter(|(c, _)| matches!(c, Cut::Before(_)))
        .map(|(_, o)| *o)
        .collect();
    assert!(before.windows(2).all(|w| w[0] <= w[1]), "{seen_outcomes:?}");
    for wanted in [Outcome::Old, Outcome::Interrupted] {
        assert!(
            before.contains(&wanted),
            "never {wanted:?}: {seen_outcomes:?}"
        );
    }
    assert_eq!(
        seen_outcomes.last().map(|(_, o)| *o),
        Some(Outcome::New),
        "{seen_outcomes:?}"
    );
    // A kill during the commit of PLC_CLEAR keeps the old program; during the commit
    // of STATUS_RESET, the flash stays cleared.
    let commits: Vec<Outcome> = seen_outcomes
        .iter()
        .filter(|(c, _)| matches!(c, Cut::Commit(_)))
        .map(|(_, o)| *o)
        .collect();
    assert_eq!(
        commits,
        [Outcome::Old, Outcome::Interrupted],
        "{seen_outcomes:?}"
    );
}
