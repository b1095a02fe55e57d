//! The simulated PLC's GUTTA protocol, without transports: a whole download as the
//! client does it, the login and its lockout, and the rules of UM4001.

mod common;

use std::collections::BTreeMap;
use std::sync::Arc;

use gutta_catalog::stdlib;
use gutta_format::{Image, LineSettings, PageId, PageKind};
use gutta_protocol::gutta::GuttaFrame;
use gutta_sim::plc::{ConnectionId, Plc, Refusal, FACTORY_PASSWORD, LAST_PACKET};
use gutta_vm::VmConfig;

const POINTERS: &str = include_str!("../../examples/in1001_pointers.lad");

/// The one connection of the single-client tests.
const A: ConnectionId = ConnectionId(1);

fn image(text: &str) -> Image {
    common::image("t.lad", text)
}

fn blank_plc() -> Plc {
    Plc::new(
        stdlib::shared("CPU-EC20").expect("target"),
        BTreeMap::new(),
        VmConfig::default(),
    )
    .expect("plc")
}

fn ok(r: GuttaFrame) -> Vec<u8> {
    assert!(!r.is_failure(), "failed: {r:?}");
    r.payload
}

/// The function codes of a page: (ask, read, write).
fn codes(id: PageId) -> (u16, u16, u16) {
    let n = u16::from(id.number);
    match id.kind {
        PageKind::Data => (0x0220 | n, 0x0230 | n, 0x0240 | n),
        PageKind::System => (0x0270 | n, 0x0280 | n, 0x0290 | n),
        PageKind::Const => (0x0310, 0x0311, 0x0312),
        PageKind::Argument => (0x0400 | n, 0x0500 | n, 0x0600 | n),
        PageKind::Instruction => (0x0700 | n, 0x0800 | n, 0x0900 | n),
    }
}

fn write_page(plc: &mut Plc, id: PageId, bytes: &[u8]) {
    let size = plc.target().plc.exch_pack_size as usize;
    let chunks: Vec<&[u8]> = if bytes.is_empty() {
        vec![&[]]
    } else {
        bytes.chunks(size).collect()
    };
    for (i, chunk) in chunks.iter().enumerate() {
        let last = if i + 1 == chunks.len() {
            LAST_PACKET
        } else {
            0
        };
        ok(plc.gutta(A, codes(id).2, i as u16 | last, chunk, 0));
    }
}

fn read_page(plc: &mut Plc, id: PageId) -> Vec<u8> {
    let (ask, read, _) = codes(id);
    let len = ok(plc.gutta(A, ask, LAST_PACKET, &[], 0));
    let len = usize::from(u16::from_be_bytes([len[0], len[1]]));
    let size = plc.target().plc.exch_pack_size as usize;
    let packets = len.div_ceil(size).max(1);
    let mut out = Vec::new();
    for i in 0..packets {
        let last = if i + 1 == packets { LAST_PACKET } else { 0 };
        out.extend(ok(plc.gutta(A, read, i as u16 | last, &[], 0)));
    }
    out
}

#[test]
fn a_download_runs_the_image() {
    let image = image(POINTERS);
    let mut plc = blank_plc();
    // CLEAR needs no login; the factory password then logs in.
    ok(plc.gutta(A, 0x0100, LAST_PACKET, &[], 0));
    ok(plc.gutta(A, 0x0110, LAST_PACKET, &FACTORY_PASSWORD, 0));
    let name = ok(plc.gutta(A, 0x0120, LAST_PACKET, &[], 0));
    assert_eq!(&name[..8], b"CPU-EC20");
    assert_eq!(name.len(), 16);
    assert!(name[8..].iter().all(|&b| b == 0));
    for (id, bytes) in &image.pages {
        write_page(&mut plc, *id, bytes);
    }
    for (id, bytes) in &image.pages {
        assert_eq!(&read_page(&mut plc, *id), bytes, "{id:?} reads back");
    }
    assert_eq!(ok(plc.gutta(A, 0x0300, LAST_PACKET, &[], 0)), [0]);
    ok(plc.gutta(A, 0x0A03, LAST_PACKET, &[], 0));
    assert!(!plc.is_attached(), "a reset ends the login");
    plc.scan().expect("scan");
    ok(plc.gutta(A, 0x0110, LAST_PACKET, &FACTORY_PASSWORD, 0));
    // RUN and ATTACH.
    assert_eq!(ok(plc.gutta(A, 0x0A00, LAST_PACKET, &[], 0)), [0b0101]);
    // STATUS_VAR_READ MW24 (slot 4, offset 24): 4 bytes from MB24, low byte first.
    let mb24 = (24u32 << 16) | (1 << 8) | (4 << 4);
    assert_eq!(
        ok(plc.gutta(A, 0x0A10, LAST_PACKET, &mb24.to_le_bytes(), 0)),
        [0x01, 0x0E, 0x02, 0x0E]
    );
}

#[test]
fn login_rules() {
    let mut plc = blank_plc();
    // Without ATTACH: refused, except CLEAR, RESET and DEBUG_RESET.
    for f in [0x0120, 0x0A00, 0x0210] {
        assert!(plc.gutta(A, f, LAST_PACKET, &[], 0).is_failure());
        assert_eq!(plc.last_refusal(), Some(&Refusal::NotAttached));
    }
    assert!(!plc.gutta(A, 0x0A03, LAST_PACKET, &[], 0).is_failure());
    // The failure form echoes the function with bit 15 and no payload.
    assert_eq!(
        plc.gutta(A, 0x0A00, LAST_PACKET, &[], 0),
        GuttaFrame::new(0x8A00, LAST_PACKET, vec![])
    );
    // Two wrong passwords are free; the third locks ATTACH for 1 s, then 2 s ...
    let wrong = [0u8; 16];
    for _ in 0..3 {
        assert!(plc.gutta(A, 0x0110, LAST_PACKET, &wrong, 100).is_failure());
    }
    assert!(plc
        .gutta(A, 0x0110, LAST_PACKET, &FACTORY_PASSWORD, 500)
        .is_failure());
    assert_eq!(
        plc.last_refusal(),
        Some(&Refusal::LockedOut { until_ms: 1100 })
    );
    ok(plc.gutta(A, 0x0110, LAST_PACKET, &FACTORY_PASSWORD, 1100));
    assert!(plc
        .gutta(A, 0x0110, LAST_PACKET, &[0xFF; 15], 1100)
        .is_failure());
    assert_eq!(plc.last_refusal(), Some(&Refusal::BadLength));
}

#[test]
fn a_locked_out_attach_is_modbus_exception_04_on_the_wire() {
    let mut plc = blank_plc();
    // PLC_ATTACH as a PDU: function 13, byte count, code 0110, packet 8000, password.
    let attach = |password: [u8; 16]| {
        let mut pdu = vec![0x0D, 0x00, 0x14, 0x01, 0x10, 0x80, 0x00];
        pdu.extend(password);
        pdu
    };
    // A wrong password keeps UM4001's failure form, even the one that starts the lockout.
    for _ in 0..3 {
        assert_eq!(
            gutta_sim::session::answer(&mut plc, A, &attach([0; 16]), 100),
            [0x0D, 0x00, 0x04, 0x81, 0x10, 0x80, 0x00]
        );
    }
    // Locked: exception 04 (Server Device Failure), even to the right password, so a
    // client can tell the lockout from a wrong password.
    assert_eq!(
        gutta_sim::session::answer(&mut plc, A, &attach(FACTORY_PASSWORD), 500),
        [0x8D, 0x04]
    );
    // After it, the right password logs in.
    assert_eq!(
        gutta_sim::session::answer(&mut plc, A, &attach(FACTORY_PASSWORD), 1100),
        [0x0D, 0x00, 0x04, 0x01, 0x10, 0x80, 0x00]
    );
}

#[test]
fn page_writes_need_clear_and_stop() {
    let image = image(POINTERS);
    let mut plc = Plc::new(
        stdlib::shared("CPU-EC20").expect("target"),
        image.pages.clone(),
        VmConfig::default(),
    )
    .expect("plc");
    ok(plc.gutta(A, 0x0110, LAST_PACKET, &FACTORY_PASSWORD, 0));
    assert!(plc.vm().is_running());
    let id = PageId::new(PageKind::Const, 0);
    assert!(plc.gutta(A, 0x0312, LAST_PACKET, &[1, 2], 0).is_failure());
    assert_eq!(plc.last_refusal(), Some(&Refusal::Running));
    ok(plc.gutta(A, 0x0A01, LAST_PACKET, &[0], 0));
    assert!(plc.gutta(A, 0x0312, LAST_PACKET, &[1, 2], 0).is_failure());
    assert_eq!(plc.last_refusal(), Some(&Refusal::FlashLocked));
    // After CLEAR: the pages are gone and writes go in, packet by packet in order.
    ok(plc.gutta(A, 0x0100, LAST_PACKET, &[], 0));
    assert!(plc.pages().is_empty());
    let size = plc.target().plc.exch_pack_size as usize;
    assert!(
        plc.gutta(A, 0x0312, 1, &vec![0; size], 0).is_failure(),
        "packet 1 first"
    );
    assert_eq!(plc.last_refusal(), Some(&Refusal::BadPacket));
    assert!(
        plc.gutta(A, 0x0312, 0, &[1, 2], 0).is_failure(),
        "a short non-last packet"
    );
    ok(plc.gutta(A, 0x0312, LAST_PACKET, &[1, 2], 0));
    assert_eq!(plc.pages()[&id], [1, 2]);
    // A reset with an image that does not verify: stopped, ERROR set.
    ok(plc.gutta(A, 0x0A03, LAST_PACKET, &[], 0));
    ok(plc.gutta(A, 0x0110, LAST_PACKET, &FACTORY_PASSWORD, 0));
    let status = ok(plc.gutta(A, 0x0A00, LAST_PACKET, &[], 0))[0];
    assert_eq!(status & 0b1001, 0b1000, "ERROR, not RUN");
    assert!(
        plc.gutta(A, 0x0A01, LAST_PACKET, &[1], 0).is_failure(),
        "cannot run it"
    );
}

#[test]
fn exch_support_limits_the_functions() {
    let mut target = (*stdlib::shared("CPU-EC20").expect("target")).clone();
    // Only the control functions (01xx) and STATUS_RESET.
    target.plc.exch_support =
        gutta_catalog::ExchSupport::parse("FF00|0100|FFFF|0A03").expect("rules");
    let mut plc = Plc::new(Arc::new(target), BTreeMap::new(), VmConfig::default()).expect("plc");
    ok(plc.gutta(A, 0x0110, LAST_PACKET, &FACTORY_PASSWORD, 0));
    assert!(plc.gutta(A, 0x0A00, LAST_PACKET, &[], 0).is_failure());
    assert_eq!(plc.last_refusal(), Some(&Refusal::Unsupported));
    ok(plc.gutta(A, 0x0A03, LAST_PACKET, &[], 0));
}

#[test]
fn malformed_requests_fail_with_the_failure_form() {
    let mut plc = blank_plc();
    ok(plc.gutta(A, 0x0110, LAST_PACKET, &FACTORY_PASSWORD, 0));
    // A single-packet function must carry packet 0x8000.
    let r = plc.gutta(A, 0x0A00, 0, &[], 0);
    assert_eq!(r, GuttaFrame::new(0x8A00, 0, vec![]));
    assert!(matches!(plc.last_refusal(), Some(Refusal::Malformed(_))));
    // STATUS_DEBUG_SCAN knows steps 1, 2 and 3 only.
    assert!(plc.gutta(A, 0x0A32, LAST_PACKET, &[4], 0).is_failure());
    assert!(matches!(plc.last_refusal(), Some(Refusal::Malformed(_))));
    // Payload lengths: STATUS_VAR_READ takes whole addresses, ATTACH 16 bytes.
    assert!(plc.gutta(A, 0x0A10, LAST_PACKET, &[0; 5], 0).is_failure());
    assert_eq!(plc.last_refusal(), Some(&Refusal::BadLength));
    assert!(plc
        .gutta(A, 0x0110, LAST_PACKET, &[0xFF; 15], 0)
        .is_failure());
    assert_eq!(plc.last_refusal(), Some(&Refusal::BadLength));
    // Codes UM4001 does not define, and requests with the failure bit.
    for code in [0x0B00, 0x8A00] {
        assert!(plc.gutta(A, code, LAST_PACKET, &[], 0).is_failure());
        assert_eq!(plc.last_refusal(), Some(&Refusal::UnknownFunction));
    }
    // After all that the PLC still answers.
    assert_eq!(ok(plc.gutta(A, 0x0A00, LAST_PACKET, &[], 0)).len(), 1);
}

#[test]
fn the_system_page_sets_station_and_lines_at_reset_and_clear_reverts_them() {
    let blink = image(include_str!("../../examples/blink.lad"));
    let mut plc = blank_plc();
    assert_eq!((plc.station(), plc.line(0)), (1, LineSettings::DEFAULT));
    ok(plc.gutta(A, 0x0100, LAST_PACKET, &[], 0));
    ok(plc.gutta(A, 0x0110, LAST_PACKET, &FACTORY_PASSWORD, 0));
    for (id, bytes) in &blink.pages {
        write_page(&mut plc, *id, bytes);
    }
    // Written but not yet reset: the PLC still answers as before.
    assert_eq!((plc.station(), plc.line(0)), (1, LineSettings::DEFAULT));
    ok(plc.gutta(A, 0x0A03, LAST_PACKET, &[], 0));
    let port0 = LineSettings {
        baud: 38400,
        data_bits: 8,
        parity: 1,
        stop_bits: 1,
    };
    assert_eq!((plc.station(), plc.line(0)), (20, port0));
    assert_eq!(plc.line(1), LineSettings::DEFAULT, "blink sets port 0 only");
    // PLC_CLEAR erases the system page: station 1, 19200 8E1 (UM4001).
    ok(plc.gutta(A, 0x0100, LAST_PACKET, &[], 0));
    assert_eq!((plc.station(), plc.line(0)), (1, LineSettings::DEFAULT));
}
