//! The simulator's download safety rule through the real binaries: one `gutta-sim`, two
//! `gutta-cc download` processes over Modbus TCP at once, round after round. One wins
//! (or they serialise), the loser exits 2 with the busy message, and the image the PLC
//! holds afterwards (uploaded) is byte for byte one of the two, never a mix. A download
//! while another connection holds a window is refused the same way and changes nothing;
//! the window ends when that connection closes.
#![allow(clippy::disallowed_methods, clippy::disallowed_types)]

mod common;

use common::{cc, text, Sim};

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Output;
use std::sync::{Arc, Barrier};
use std::time::{Duration, Instant};

use gutta_link::transport::TcpTransport;
use gutta_link::{Client, FACTORY_PASSWORD};
use gutta_protocol::function::PageArea;

const BUSY: &str = "busy: another client is downloading into this PLC; \
                    try again when it has finished";

/// Rounds of two concurrent downloads.
const ROUNDS: usize = 12;

/// Two different images without a password (so either can follow the other): a long
/// MAIN (so downloads take long enough to overlap) and blink (MAIN, a subroutine, an
/// interrupt, a data block, a system block), whose pages a mix would combine.
fn two_image_dirs(tag: &str) -> [PathBuf; 2] {
    let networks: String = (0..450)
        .map(|i| {
            let (from, to) = (2 * (i % 60), 2 * ((i + 1) % 60));
            format!("NETWORK {}\nLD SM0.0\nMOVW MW{from}, MW{to}\n", i + 1)
        })
        .collect();
    let long = common::image(
        "long.lad",
        &format!("ORGANIZATION_BLOCK MAIN\nBEGIN\n{networks}END_ORGANIZATION_BLOCK\n"),
    );
    let blink_path = format!("{}/../examples/blink.lad", env!("CARGO_MANIFEST_DIR"));
    let blink_text: String = std::fs::read_to_string(blink_path)
        .expect("blink.lad")
        .lines()
        .filter(|l| !l.trim_start().starts_with("PASSWORD"))
        .map(|l| format!("{l}\n"))
        .collect();
    let blink = common::image("blink.lad", &blink_text);
    assert_ne!(
        long.pages.keys().collect::<Vec<_>>(),
        blink.pages.keys().collect::<Vec<_>>()
    );
    [
        common::image_dir(&format!("{tag}-long"), &long),
        common::image_dir(&format!("{tag}-blink"), &blink),
    ]
}

fn files_under(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    gutta_io::directory_files(dir).expect("a readable directory")
}

/// The PLC's program, uploaded into a fresh directory.
fn upload(sim: &Sim, tag: &str) -> BTreeMap<String, Vec<u8>> {
    let dir = std::env::temp_dir().join(format!(
        "gutta-sim-test-upload-{tag}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    let o = cc(&[
        "upload",
        "-o",
        dir.to_str().expect("path"),
        "--tcp",
        sim.1.as_str(),
    ]);
    assert!(o.status.success(), "upload: {}", text(&o));
    let files = files_under(&dir);
    let _ = std::fs::remove_dir_all(&dir);
    files
}

/// A loser: exit status 2, the busy message, nothing on stdout.
fn assert_busy(o: &Output) {
    assert_eq!(o.status.code(), Some(2), "{}", text(o));
    assert!(
        String::from_utf8_lossy(&o.stderr).contains(BUSY),
        "not the busy message: {}",
        text(o)
    );
    assert!(o.stdout.is_empty(), "{}", text(o));
}

#[test]
fn two_concurrent_downloads_never_leave_a_mix() {
    let sim = common::sim("CPU-EC20", None);
    let dirs = two_image_dirs("concurrent");
    let expected = [files_under(&dirs[0]), files_under(&dirs[1])];
    let mut contended = 0;
    for round in 0..ROUNDS {
        let start = Arc::new(Barrier::new(2));
        let runs: Vec<_> = dirs
            .iter()
            .map(|dir| {
                let (dir, address, start) = (dir.clone(), sim.1.clone(), Arc::clone(&start));
                std::thread::spawn(move || {
                    start.wait();
                    cc(&[
                        "download",
                        dir.to_str().expect("path"),
                        "--tcp",
                        address.as_str(),
                    ])
                })
            })
            .collect();
        let outputs: Vec<Output> = runs
            .into_iter()
            .map(|r| r.join().expect("the download thread"))
            .collect();
        let won: Vec<usize> = (0..2).filter(|&i| outputs[i].status.success()).collect();
        for (i, o) in outputs.iter().enumerate() {
            if !won.contains(&i) {
                assert_busy(o);
            }
        }
        assert!(!won.is_empty(), "round {round}: nobody won");
        let held = upload(&sim, &format!("round{round}"));
        if let [winner] = won[..] {
            contended += 1;
            assert!(
                held == expected[winner],
                "round {round}: not the winner's image"
            );
        } else {
            // They serialised: the PLC holds one of the two whole.
            assert!(
                held == expected[0] || held == expected[1],
                "round {round}: a mix of the two images"
            );
        }
    }
    eprintln!("{contended} of {ROUNDS} rounds had a loser");
}

#[test]
fn a_download_during_another_connections_window_is_busy_and_changes_nothing() {
    let sim = common::sim("CPU-EC20", None);
    let dirs = two_image_dirs("held-window");
    let dir = dirs[0].to_str().expect("path");
    // Another client has cleared the PLC and holds its window (its connection is open).
    let mut holder = Client::new(
        Box::new(TcpTransport::connect(&sim.1, 1000, 2).expect("connects")),
        1,
    );
    holder.clear().expect("PLC_CLEAR");
    holder.attach(&FACTORY_PASSWORD).expect("login");
    let constants = gutta_format::PageId::new(gutta_format::PageKind::Const, 0);
    holder
        .write_page(constants, &[7; 3], 64, &mut |_| {})
        .expect("the holder writes");

    let o = cc(&["download", dir, "--tcp", sim.1.as_str()]);
    assert_busy(&o);
    // Nothing changed: the holder's one page is all the flash holds, and looking is
    // still allowed for everyone.
    let status = cc(&["status", "--tcp", sim.1.as_str()]);
    assert!(status.status.success(), "{}", text(&status));
    assert_eq!(holder.read_page(constants, 64).expect("reads"), [7; 3]);
    assert!(holder
        .page_list(PageArea::Program)
        .expect("lists")
        .is_empty());

    // The holder's connection closes: its window ends and the next download goes in.
    drop(holder);
    let deadline = Instant::now() + Duration::from_secs(5);
    let o = loop {
        let o = cc(&["download", dir, "--tcp", sim.1.as_str()]);
        if o.status.success() || Instant::now() > deadline {
            break o;
        }
        // The simulator may not have seen the close yet: then this is busy again.
        assert_busy(&o);
        std::thread::sleep(Duration::from_millis(50));
    };
    assert!(o.status.success(), "{}", text(&o));
    assert!(upload(&sim, "after-close") == files_under(&dirs[0]));
}
