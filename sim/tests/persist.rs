//! The flash file's format and the PLC's commits, without I/O (a memory store): bytes
//! round-trip; every flipped byte and every truncation is a typed error, never a panic;
//! PLC_CLEAR, STATUS_RESET and STATUS_WRITE are committed before they are answered and
//! a failed commit refuses the request and changes nothing; power-on from each state
//! (docs/simulator.md, "Flash and power-on").

mod common;

use std::collections::BTreeMap;
use std::sync::Arc;

use gutta_catalog::stdlib;
use gutta_format::{Image, PageId, PageKind};
use gutta_protocol::function::PageRef;
use gutta_protocol::message::{Command, Request};
use gutta_protocol::transfer::{split_page, PackSize};
use gutta_sim::persist::{DecodeError, FlashImage, FlashState, MemoryStore};
use gutta_sim::plc::{
    ConnectionId, FlashFault, Plc, PowerOn, Refusal, ERROR_DOWNLOAD_INTERRUPTED, ERROR_FLASH_CHECK,
    FACTORY_PASSWORD, LAST_PACKET,
};
use gutta_vm::VmConfig;

const A: ConnectionId = ConnectionId(1);
const PROGRAM: &str = "ORGANIZATION_BLOCK MAIN\nBEGIN\nNETWORK 1\nLD SM0.0\nMOVW 16#0BEE, MW24\nEND_ORGANIZATION_BLOCK\n";

fn image() -> Image {
    common::image("t.lad", PROGRAM)
}

fn target() -> Arc<gutta_catalog::Target> {
    stdlib::shared("CPU-EC20").expect("target")
}

fn sample() -> FlashImage {
    FlashImage {
        plc_type: "CPU-EC20".into(),
        state: FlashState::Committed,
        running: true,
        pages: image().pages,
    }
}

fn ok(plc: &mut Plc, packet: u16, command: Command) {
    let request = Request { packet, command }.encode().expect("encodes");
    let answer = plc.answer(A, &request, 0);
    assert!(!answer.is_failure(), "refused: {:?}", plc.last_refusal());
}

fn refused(plc: &mut Plc, command: Command) -> Option<Refusal> {
    let request = Request {
        packet: LAST_PACKET,
        command,
    }
    .encode()
    .expect("encodes");
    assert!(plc.answer(A, &request, 0).is_failure());
    plc.last_refusal().cloned()
}

/// Log in, PLC_CLEAR, log in, every page of `image` (no STATUS_RESET).
fn clear_and_write(plc: &mut Plc, image: &Image) {
    ok(
        plc,
        LAST_PACKET,
        Command::PlcAttach {
            password: FACTORY_PASSWORD,
        },
    );
    ok(plc, LAST_PACKET, Command::PlcClear);
    ok(
        plc,
        LAST_PACKET,
        Command::PlcAttach {
            password: FACTORY_PASSWORD,
        },
    );
    let pack = PackSize::new(u16::try_from(plc.target().plc.exch_pack_size).expect("u16"))
        .expect("pack size");
    for (id, bytes) in &image.pages {
        let page = PageRef::of(*id).expect("page");
        for (packet, chunk) in split_page(bytes, pack).expect("splits") {
            ok(plc, packet, Command::PageWrite(page, chunk.to_vec()));
        }
    }
}

fn with_store(plc: &mut Plc) -> MemoryStore {
    let store = MemoryStore::default();
    plc.set_flash_store(Box::new(store.clone()));
    store
}

fn debug_error(plc: &mut Plc) -> u8 {
    let request = Request {
        packet: LAST_PACKET,
        command: Command::DebugInforRead,
    }
    .encode()
    .expect("encodes");
    let answer = plc.answer(A, &request, 0);
    assert!(!answer.is_failure(), "{:?}", plc.last_refusal());
    answer.payload[15]
}

#[test]
fn encode_decode_round_trips() {
    let flash = sample();
    let bytes = flash.encode().expect("encodes");
    assert_eq!(FlashImage::decode(&bytes), Ok(flash));
    let cleared = FlashImage {
        plc_type: "CPU-EC20".into(),
        state: FlashState::Cleared,
        running: false,
        pages: BTreeMap::new(),
    };
    assert_eq!(FlashImage::decode(&cleared.encode().unwrap()), Ok(cleared));
}

#[test]
fn every_flipped_byte_and_every_truncation_is_an_error() {
    let bytes = sample().encode().expect("encodes");
    for i in 0..bytes.len() {
        let mut bad = bytes.clone();
        bad[i] ^= 0x40;
        assert!(
            FlashImage::decode(&bad).is_err(),
            "byte {i} flipped decodes"
        );
    }
    for n in 0..bytes.len() {
        let e = FlashImage::decode(&bytes[..n]).expect_err("truncated decodes");
        assert!(
            matches!(e, DecodeError::Truncated { .. }),
            "cut at {n}: {e}"
        );
    }
    let mut version = bytes.clone();
    version[8] = 9;
    assert_eq!(
        FlashImage::decode(&version),
        Err(DecodeError::UnknownVersion(9))
    );
    assert_eq!(
        FlashImage::decode(b"PK\x03\x04 a zip"),
        Err(DecodeError::BadMagic)
    );
    let mut crc = bytes.clone();
    let body = crc.len() - 10;
    crc[body] ^= 1;
    assert!(matches!(
        FlashImage::decode(&crc),
        Err(DecodeError::BadCrc { .. })
    ));
}

#[test]
fn a_download_commits_clear_then_reset_and_run() {
    let mut plc = Plc::new(target(), BTreeMap::new(), VmConfig::default()).unwrap();
    let store = with_store(&mut plc);
    let image = image();
    clear_and_write(&mut plc, &image);
    // The page writes are not committed: the flash still says cleared.
    let commits = store.commits.lock().unwrap().clone();
    assert_eq!(commits.len(), 1);
    assert_eq!(commits[0].state, FlashState::Cleared);
    assert!(commits[0].pages.is_empty());
    ok(&mut plc, LAST_PACKET, Command::StatusReset);
    let last = store.last().unwrap();
    assert_eq!(last.state, FlashState::Committed);
    assert!(last.running);
    assert_eq!(last.pages, image.pages);
    assert!(plc.vm().is_running());
    ok(
        &mut plc,
        LAST_PACKET,
        Command::PlcAttach {
            password: FACTORY_PASSWORD,
        },
    );
    ok(&mut plc, LAST_PACKET, Command::StatusWrite { run: 0 });
    assert!(!store.last().unwrap().running);
    assert!(!plc.vm().is_running());
}

#[test]
fn a_failed_commit_refuses_and_changes_nothing() {
    let mut plc = Plc::new(target(), image().pages, VmConfig::default()).unwrap();
    let store = with_store(&mut plc);
    *store.fail.lock().unwrap() = Some("disk full".into());
    ok(
        &mut plc,
        LAST_PACKET,
        Command::PlcAttach {
            password: FACTORY_PASSWORD,
        },
    );
    let failed = Some(Refusal::FlashFailed("disk full".into()));
    assert_eq!(refused(&mut plc, Command::StatusWrite { run: 0 }), failed);
    assert!(plc.vm().is_running());
    assert_eq!(refused(&mut plc, Command::PlcClear), failed);
    assert!(plc.vm().is_running());
    assert!(plc.download_window().is_none());
    assert_eq!(plc.pages(), &image().pages);
    // A reset refused inside a window keeps the window and the pages written.
    *store.fail.lock().unwrap() = None;
    clear_and_write(&mut plc, &image());
    *store.fail.lock().unwrap() = Some("disk full".into());
    assert_eq!(refused(&mut plc, Command::StatusReset), failed);
    assert!(plc.download_window().is_some());
    assert!(!plc.vm().is_running());
    *store.fail.lock().unwrap() = None;
    ok(&mut plc, LAST_PACKET, Command::StatusReset);
    assert!(plc.vm().is_running());
}

#[test]
fn power_on_runs_what_was_committed_running() {
    let plc = Plc::power_on(target(), PowerOn::Flash(sample()), VmConfig::default()).unwrap();
    assert!(plc.vm().is_running());
    assert_eq!(plc.status_byte() & 0x09, 0x01);
    let stopped = FlashImage {
        running: false,
        ..sample()
    };
    let mut plc = Plc::power_on(target(), PowerOn::Flash(stopped), VmConfig::default()).unwrap();
    assert!(!plc.vm().is_running());
    assert_eq!(plc.status_byte() & 0x09, 0);
    ok(
        &mut plc,
        LAST_PACKET,
        Command::PlcAttach {
            password: FACTORY_PASSWORD,
        },
    );
    ok(&mut plc, LAST_PACKET, Command::StatusWrite { run: 1 });
    assert!(plc.vm().is_running());
}

#[test]
fn power_on_from_a_cleared_flash_has_no_program_and_says_why() {
    let cleared = FlashImage {
        plc_type: "CPU-EC20".into(),
        state: FlashState::Cleared,
        running: false,
        pages: BTreeMap::new(),
    };
    let mut plc = Plc::power_on(target(), PowerOn::Flash(cleared), VmConfig::default()).unwrap();
    assert_eq!(plc.flash_fault(), Some(&FlashFault::DownloadInterrupted));
    assert_eq!(plc.status_byte() & 0x09, 0x08, "ERROR, no RUN");
    ok(
        &mut plc,
        LAST_PACKET,
        Command::PlcAttach {
            password: FACTORY_PASSWORD,
        },
    );
    assert_eq!(debug_error(&mut plc), ERROR_DOWNLOAD_INTERRUPTED);
    assert_eq!(
        refused(&mut plc, Command::StatusWrite { run: 1 }),
        Some(Refusal::NoProgram)
    );
    // A download clears the fault.
    clear_and_write(&mut plc, &image());
    ok(&mut plc, LAST_PACKET, Command::StatusReset);
    assert_eq!(plc.flash_fault(), None);
    assert!(plc.vm().is_running());
}

#[test]
fn power_on_from_a_bad_or_foreign_flash_has_no_program() {
    for found in [
        PowerOn::Unreadable("CRC mismatch".into()),
        PowerOn::Flash(FlashImage {
            plc_type: "CPU-EC10".into(),
            ..sample()
        }),
    ] {
        let mut plc = Plc::power_on(target(), found.clone(), VmConfig::default()).unwrap();
        assert!(
            matches!(plc.flash_fault(), Some(FlashFault::CheckFailed(_))),
            "{found:?}"
        );
        assert!(plc.pages().is_empty());
        assert!(!plc.vm().is_running());
        ok(
            &mut plc,
            LAST_PACKET,
            Command::PlcAttach {
                password: FACTORY_PASSWORD,
            },
        );
        assert_eq!(debug_error(&mut plc), ERROR_FLASH_CHECK);
        assert_eq!(
            refused(&mut plc, Command::StatusWrite { run: 1 }),
            Some(Refusal::NoProgram)
        );
    }
}

#[test]
fn an_abandoned_window_is_a_download_interrupted() {
    let mut plc = Plc::new(target(), image().pages, VmConfig::default()).unwrap();
    clear_and_write(&mut plc, &image());
    assert_eq!(plc.status_byte() & 0x08, 0, "no ERROR while downloading");
    plc.disconnect(A);
    assert_eq!(plc.flash_fault(), Some(&FlashFault::DownloadInterrupted));
    assert_eq!(plc.status_byte() & 0x09, 0x08);
    assert!(!plc
        .pages()
        .contains_key(&PageId::new(PageKind::Instruction, 0)));
}
