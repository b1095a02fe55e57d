//! `gutta-sim --flash DIR` with the real binaries (docs/simulator.md, "Flash and
//! power-on"): a download survives kill -9 (the upload equals the image byte for byte,
//! the PLC runs, its password still applies); STOP survives; a flipped byte and a
//! truncated flash file are reported at start and leave an empty PLC that answers;
//! two simulators cannot share DIR; an image seeds an empty DIR only.

#![cfg(unix)]

mod common;

use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};

use common::{stdout, text};

const PASSWORD: &str = "s3cret";

/// A program that counts scans in MW30, with a password in its system block.
fn program() -> gutta_format::Image {
    common::image(
        "flash.lad",
        &format!(
            "ORGANIZATION_BLOCK MAIN\nBEGIN\nNETWORK 1\nLD SM0.0\nINCW MW30\n\
             END_ORGANIZATION_BLOCK\n\nSYSTEM_BLOCK\n  PASSWORD = \"{PASSWORD}\"\n\
             END_SYSTEM_BLOCK\n"
        ),
    )
}

/// A `gutta-sim --flash DIR` process, killed (SIGKILL) when dropped.
struct FlashSim {
    child: Child,
    address: String,
    /// The stdout lines before the listener line (the flash's).
    start: Vec<String>,
}

impl Drop for FlashSim {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl FlashSim {
    fn start(dir: &Path, extra: &[&str]) -> FlashSim {
        let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
            .args(extra)
            .arg("--flash")
            .arg(dir)
            .args(["--tcp", "127.0.0.1:0"])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("starts gutta-sim");
        let mut lines = BufReader::new(child.stdout.take().expect("stdout")).lines();
        let mut start = Vec::new();
        loop {
            let Some(Ok(line)) = lines.next() else {
                let mut err = String::new();
                if let Some(mut e) = child.stderr.take() {
                    let _ = e.read_to_string(&mut err);
                }
                let _ = child.kill();
                let _ = child.wait();
                panic!("gutta-sim ended before listening: {start:?} {err}");
            };
            if line.contains("modbus-tcp on") {
                let address = line.rsplit(' ').next().expect("address").to_string();
                return FlashSim {
                    child,
                    address,
                    start,
                };
            }
            start.push(line);
        }
    }

    /// SIGKILL, then what it said on stderr.
    fn kill(mut self) -> String {
        let _ = self.child.kill();
        let _ = self.child.wait();
        let mut err = String::new();
        if let Some(mut e) = self.child.stderr.take() {
            let _ = e.read_to_string(&mut err);
        }
        err
    }

    fn cc(&self, args: &[&str], password: Option<&str>) -> Output {
        let mut command = Command::new(env!("CARGO_BIN_EXE_gutta-cc"));
        command
            .args(args)
            .args(["--tcp", &self.address])
            .env_remove("GUTTA_PASSWORD");
        if let Some(p) = password {
            command.env("GUTTA_PASSWORD", p);
        }
        command.output().expect("gutta-cc runs")
    }

    fn status_json(&self, password: Option<&str>) -> serde_json::Value {
        let o = self.cc(&["status", "--message-format", "json"], password);
        assert!(o.status.success(), "{}", text(&o));
        serde_json::from_str(stdout(&o).trim()).expect("JSON")
    }

    fn mw30(&self, password: Option<&str>) -> u32 {
        let o = self.cc(&["read", "MW30:uint"], password);
        assert!(o.status.success(), "{}", text(&o));
        let shown = stdout(&o);
        shown
            .trim()
            .rsplit(' ')
            .next()
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("{shown}"))
    }
}

fn scratch(tag: &str) -> PathBuf {
    common::scratch(&format!("flash-{tag}"))
}

#[test]
fn a_download_survives_kill_9() {
    let base = scratch("survives");
    let flash = base.join("flash");
    let image = common::image_dir("flash-survives", &program());
    let sim = FlashSim::start(&flash, &[]);
    assert_eq!(
        sim.start,
        [format!("gutta-sim: flash {}: empty", flash.display())]
    );
    let o = sim.cc(&["download", &image.display().to_string()], None);
    assert!(o.status.success(), "{}", text(&o));
    let err = sim.kill();
    assert_eq!(err, "");

    let sim = FlashSim::start(&flash, &[]);
    assert_eq!(
        sim.start,
        [format!(
            "gutta-sim: flash {}: CPU-EC20 program, 4 pages, RUN",
            flash.display()
        )]
    );
    // The password still applies: the factory password is refused.
    let o = sim.cc(&["status"], None);
    assert!(!o.status.success(), "{}", text(&o));
    let status = sim.status_json(Some(PASSWORD));
    assert_eq!(status["state"], "running", "{status}");
    // It runs: MW30 counts scans.
    let first = sim.mw30(Some(PASSWORD));
    std::thread::sleep(std::time::Duration::from_millis(100));
    assert!(sim.mw30(Some(PASSWORD)) > first);
    let up = base.join("up");
    let o = sim.cc(&["upload", "-o", &up.display().to_string()], Some(PASSWORD));
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(
        common::tree_files(&up),
        common::tree_files(&image),
        "the upload differs from the image"
    );
}

#[test]
fn stop_survives_and_so_does_run_again() {
    let flash = scratch("stop").join("flash");
    let image = common::image_dir("flash-stop", &program());
    let sim = FlashSim::start(&flash, &[image.to_str().expect("utf-8")]);
    assert_eq!(
        sim.start,
        [format!(
            "gutta-sim: flash {}: CPU-EC20 program, 4 pages, RUN (seeded from {})",
            flash.display(),
            image.display()
        )]
    );
    let o = sim.cc(&["stop"], Some(PASSWORD));
    assert!(o.status.success(), "{}", text(&o));
    sim.kill();
    let sim = FlashSim::start(&flash, &[image.to_str().expect("utf-8")]);
    assert_eq!(
        sim.start,
        [
            format!(
                "gutta-sim: flash {}: CPU-EC20 program, 4 pages, STOP",
                flash.display()
            ),
            format!(
                "gutta-sim: flash {}: holds a flash already; the image in {} was not loaded",
                flash.display(),
                image.display()
            )
        ]
    );
    let o = sim.cc(&["status"], Some(PASSWORD));
    assert_eq!(
        stdout(&o),
        "CPU-EC20: STOP (status byte 0x04: ATTACH)\n",
        "{}",
        text(&o)
    );
    assert!(sim.cc(&["run"], Some(PASSWORD)).status.success());
    sim.kill();
    let sim = FlashSim::start(&flash, &[]);
    assert_eq!(sim.status_json(Some(PASSWORD))["state"], "running");
}

/// A flash file damaged as `damage` says: reported on stderr at start, the PLC empty,
/// answering, refusing RUN, and its status saying why.
fn damaged_flash_is_reported(tag: &str, damage: fn(&mut Vec<u8>), why: &str) {
    let flash = scratch(tag).join("flash");
    let image = common::image_dir(&format!("flash-{tag}"), &program());
    let sim = FlashSim::start(&flash, &[image.to_str().expect("utf-8")]);
    sim.kill();
    let file = flash.join("flash.bin");
    let mut bytes = std::fs::read(&file).expect("flash.bin");
    damage(&mut bytes);
    std::fs::write(&file, &bytes).expect("writes");

    let sim = FlashSim::start(&flash, &[]);
    assert_eq!(sim.start, Vec::<String>::new(), "the report goes to stderr");
    let status = sim.status_json(None);
    assert_eq!(status["state"], "flash-check-failed", "{status}");
    assert_eq!(status["error_code"], 0x11);
    let o = sim.cc(&["status"], None);
    assert_eq!(
        stdout(&o),
        "CPU-EC20: STOP, no program: the flash failed its check at power-on \
         (status byte 0x0C: ATTACH ERROR, error code 0x11)\n"
    );
    let o = sim.cc(&["run"], None);
    assert!(!o.status.success(), "RUN was accepted: {}", text(&o));
    let err = sim.kill();
    assert!(
        err.starts_with(&format!(
            "gutta-sim: flash {}: the flash file failed its check ({why}",
            flash.display()
        )),
        "{err}"
    );
    assert!(err.contains("): no program\n"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn a_flipped_byte_is_reported_and_the_plc_is_empty() {
    damaged_flash_is_reported("flip", |b| b[40] ^= 0x01, "CRC mismatch");
}

#[test]
fn a_truncated_file_is_reported_and_the_plc_is_empty() {
    damaged_flash_is_reported("cut", |b| b.truncate(b.len() * 2 / 3), "truncated");
}

#[test]
fn two_simulators_cannot_share_a_flash() {
    let flash = scratch("lock").join("flash");
    let _first = FlashSim::start(&flash, &[]);
    let o = Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
        .arg("--flash")
        .arg(&flash)
        .args(["--tcp", "127.0.0.1:0"])
        .output()
        .expect("runs");
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert_eq!(
        common::stderr(&o),
        format!(
            "gutta-sim: error: --flash {}: another gutta-sim uses this flash ({} is locked)\n",
            flash.display(),
            flash.join("lock").display()
        )
    );
}
