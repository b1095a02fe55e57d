//! The download safety rule on `Plc` with two connections (docs/simulator.md): A's
//! PLC_CLEAR opens a window in which only A writes pages; B may look but every change
//! is refused as busy (Modbus exception 06 on the wire); the window ends at A's
//! STATUS_RESET, when A disconnects, or after 30 s without a request from A, and a
//! reset only ever runs the pages of one window.

mod common;

use std::collections::BTreeMap;

use gutta_catalog::stdlib;
use gutta_format::{Image, Operand, PackedOperand, PageId, PageKind};
use gutta_protocol::function::{PageArea, PageRef};
use gutta_protocol::gutta::GuttaFrame;
use gutta_protocol::message::{Breakpoint, Command, DebugStep, Request};
use gutta_protocol::transfer::{split_page, PackSize};
use gutta_sim::plc::{
    ConnectionId, Plc, Refusal, FACTORY_PASSWORD, LAST_PACKET, WINDOW_TIMEOUT_MS,
};
use gutta_sim::session::{Framing, Session};
use gutta_vm::VmConfig;

const A: ConnectionId = ConnectionId(1);
const B: ConnectionId = ConnectionId(2);

const POINTERS: &str = include_str!("../../examples/in1001_pointers.lad");
const OTHER: &str = "ORGANIZATION_BLOCK MAIN\nBEGIN\nNETWORK 1\nLD SM0.0\nMOVW 16#0BEE, MW24\nEND_ORGANIZATION_BLOCK\n";

fn image(text: &str) -> Image {
    common::image("t.lad", text)
}

/// A PLC running the POINTERS image.
fn running_plc() -> Plc {
    let plc = Plc::new(
        stdlib::shared("CPU-EC20").expect("target"),
        image(POINTERS).pages,
        VmConfig::default(),
    )
    .expect("plc");
    assert!(plc.vm().is_running());
    plc
}

fn send(plc: &mut Plc, from: ConnectionId, packet: u16, command: Command, now: u64) -> GuttaFrame {
    let request = Request { packet, command }.encode().expect("encodes");
    plc.answer(from, &request, now)
}

fn ok(plc: &mut Plc, from: ConnectionId, command: Command, now: u64) {
    let answer = send(plc, from, LAST_PACKET, command, now);
    assert!(!answer.is_failure(), "refused: {:?}", plc.last_refusal());
}

fn busy(plc: &mut Plc, from: ConnectionId, command: Command, now: u64) {
    let what = format!("{command:?}");
    let answer = send(plc, from, LAST_PACKET, command, now);
    assert!(answer.is_failure(), "{what} was allowed");
    assert!(
        matches!(plc.last_refusal(), Some(Refusal::Busy { owner: A, .. })),
        "{what}: {:?}",
        plc.last_refusal()
    );
}

fn write_page(plc: &mut Plc, from: ConnectionId, id: PageId, bytes: &[u8], now: u64) -> bool {
    let pack = u16::try_from(plc.target().plc.exch_pack_size)
        .ok()
        .and_then(|p| PackSize::new(p).ok())
        .expect("pack size");
    let page = PageRef::of(id).expect("page");
    split_page(bytes, pack)
        .expect("splits")
        .into_iter()
        .all(|(packet, chunk)| {
            let command = Command::PageWrite(page, chunk.to_vec());
            !send(plc, from, packet, command, now).is_failure()
        })
}

/// A's download up to (not including) the reset: CLEAR, login, every page.
fn download_without_reset(plc: &mut Plc, from: ConnectionId, image: &Image, now: u64) {
    ok(plc, from, Command::PlcClear, now);
    ok(
        plc,
        from,
        Command::PlcAttach {
            password: FACTORY_PASSWORD,
        },
        now,
    );
    for (id, bytes) in &image.pages {
        assert!(
            write_page(plc, from, *id, bytes, now),
            "{id:?}: {:?}",
            plc.last_refusal()
        );
    }
}

fn mw24() -> PackedOperand {
    let target = stdlib::shared("CPU-EC20").expect("target");
    let address = target.memory.parse_address("MW24").expect("MW24");
    PackedOperand::encode(Operand::Value(address))
}

fn q0() -> PackedOperand {
    let target = stdlib::shared("CPU-EC20").expect("target");
    let address = target.memory.parse_address("Q0.0").expect("Q0.0");
    PackedOperand::encode(Operand::Value(address))
}

#[test]
fn while_a_downloads_b_may_look_but_every_change_is_busy() {
    let mut plc = running_plc();
    ok(
        &mut plc,
        A,
        Command::PlcAttach {
            password: FACTORY_PASSWORD,
        },
        0,
    );
    ok(&mut plc, A, Command::PlcClear, 10);
    assert_eq!(
        plc.download_window().map(|w| (w.owner, w.opened_ms)),
        Some((A, 10))
    );
    ok(
        &mut plc,
        A,
        Command::PlcAttach {
            password: FACTORY_PASSWORD,
        },
        20,
    );
    let constants = PageId::new(PageKind::Const, 0);
    assert!(write_page(&mut plc, A, constants, &[1, 2, 3], 30));

    let changes = [
        Command::PlcClear,
        Command::PlcDetach,
        Command::PageWrite(PageRef::Const, vec![9]),
        Command::PageWrite(PageRef::Instruction(0), vec![9]),
        Command::PageWrite(PageRef::Argument(0), vec![9]),
        Command::PageWrite(PageRef::Data(0), vec![9]),
        Command::PageWrite(PageRef::System(0), vec![9]),
        Command::StatusWrite { run: 1 },
        Command::StatusWrite { run: 0 },
        Command::StatusScan { count: 1 },
        Command::StatusReset,
        Command::VarWrite(vec![(mw24(), 7)]),
        Command::ForceWrite(vec![(q0(), 1)]),
        Command::DebugWrite { run: 1 },
        Command::DebugScan(DebugStep::In),
        Command::DebugReset,
        Command::DebugInforWrite(Breakpoint {
            index: 0,
            network: 1,
            step: 1,
        }),
        // A wrong password during a download is busy, not a failed login.
        Command::PlcAttach { password: [0; 16] },
    ];
    for command in changes {
        busy(&mut plc, B, command, 40);
    }
    // Refused logins did not count: A's login is not locked out.
    ok(
        &mut plc,
        A,
        Command::PlcAttach {
            password: FACTORY_PASSWORD,
        },
        50,
    );
    assert_eq!(plc.pages().len(), 1, "only A's page");
    assert_eq!(plc.pages()[&constants], [1, 2, 3]);

    let looks = [
        Command::PlcAttach {
            password: FACTORY_PASSWORD,
        },
        Command::GetPlcName,
        Command::GetPlcInfor,
        Command::PageList(PageArea::Program),
        Command::PageAsk(PageRef::Const),
        Command::PageRead(PageRef::Const),
        Command::StatusRead,
        Command::VarRead(vec![mw24()]),
        Command::ForceRead(vec![q0()]),
        Command::DebugRead,
        Command::DebugInforRead,
    ];
    for command in looks {
        ok(&mut plc, B, command, 60);
    }
    assert_eq!(
        plc.download_window().map(|w| w.owner),
        Some(A),
        "the window stays A's"
    );

    // A finishes; its reset runs exactly its image and ends the window.
    let other = image(OTHER);
    for (id, bytes) in &other.pages {
        assert!(write_page(&mut plc, A, *id, bytes, 70));
    }
    ok(&mut plc, A, Command::StatusReset, 80);
    assert_eq!(plc.download_window(), None);
    assert_eq!(plc.pages(), &other.pages);
    assert!(plc.vm().is_running());
    // Now B may clear: the window is B's.
    ok(&mut plc, B, Command::PlcClear, 90);
    assert_eq!(plc.download_window().map(|w| w.owner), Some(B));
}

#[test]
fn a_window_ends_when_its_owner_disconnects() {
    let mut plc = running_plc();
    download_without_reset(&mut plc, A, &image(OTHER), 0);
    plc.disconnect(B);
    assert_eq!(
        plc.download_window().map(|w| w.owner),
        Some(A),
        "B's close is not A's"
    );
    plc.disconnect(A);
    assert_eq!(plc.download_window(), None);
    assert!(plc.pages().is_empty(), "the unfinished download is erased");
    // A reset (by anyone) now finds an empty PLC: stopped, no ERROR, no half image.
    ok(&mut plc, B, Command::StatusReset, 10);
    assert!(!plc.vm().is_running());
    assert_eq!(plc.status_byte() & 0b1001, 0);
    ok(&mut plc, B, Command::PlcClear, 20);
    assert_eq!(plc.download_window().map(|w| w.owner), Some(B));
}

#[test]
fn a_window_ends_after_its_owner_is_silent_for_the_timeout() {
    let mut plc = running_plc();
    download_without_reset(&mut plc, A, &image(OTHER), 0);
    // Every request of A's keeps the window open.
    ok(&mut plc, A, Command::StatusRead, 20_000);
    busy(
        &mut plc,
        B,
        Command::PlcClear,
        20_000 + WINDOW_TIMEOUT_MS - 1,
    );
    ok(
        &mut plc,
        B,
        Command::PlcAttach {
            password: FACTORY_PASSWORD,
        },
        20_000 + WINDOW_TIMEOUT_MS,
    );
    assert_eq!(plc.download_window(), None, "A was silent for the timeout");
    assert!(plc.pages().is_empty(), "A's unfinished pages are erased");
    ok(&mut plc, B, Command::PlcClear, 60_000);
    // A comes back: its writes and its reset are B's window's now, so busy.
    let page = PageId::new(PageKind::Const, 0);
    assert!(!write_page(&mut plc, A, page, &[1], 60_001));
    assert!(matches!(
        plc.last_refusal(),
        Some(Refusal::Busy { owner: B, .. })
    ));
    let reset = send(&mut plc, A, LAST_PACKET, Command::StatusReset, 60_002);
    assert!(reset.is_failure());
    assert!(plc.pages().is_empty());
}

#[test]
fn a_page_write_outside_a_window_of_ones_own_fails() {
    let mut plc = Plc::new(
        stdlib::shared("CPU-EC20").expect("target"),
        BTreeMap::new(),
        VmConfig::default(),
    )
    .expect("plc");
    ok(
        &mut plc,
        A,
        Command::PlcAttach {
            password: FACTORY_PASSWORD,
        },
        0,
    );
    let page = PageId::new(PageKind::Const, 0);
    assert!(!write_page(&mut plc, A, page, &[1], 0));
    assert_eq!(plc.last_refusal(), Some(&Refusal::FlashLocked));
}

#[test]
fn busy_is_modbus_exception_06_on_the_wire() {
    let mut plc = running_plc();
    ok(&mut plc, A, Command::PlcClear, 0);
    let mut session = Session::new(Framing::Tcp, B);
    // PLC_CLEAR in an MBAP frame: transaction 7, unit 1, function 13.
    let clear = Request::single(Command::PlcClear)
        .encode()
        .expect("encodes");
    let pdu = clear.to_pdu().expect("pdu");
    let mut frame = vec![0, 7, 0, 0, 0, (pdu.len() + 1) as u8, 1];
    frame.extend(&pdu);
    let answer = session.on_bytes(&mut plc, &frame, 5).expect("frames");
    assert_eq!(answer, [0, 7, 0, 0, 0, 3, 1, 0x8D, 0x06]);
    assert_eq!(session.busy, 1);
    // Any other refusal keeps UM4001's failure form.
    let mut owner = Session::new(Framing::Tcp, A);
    let run = Request::single(Command::StatusWrite { run: 1 })
        .encode()
        .expect("encodes");
    let pdu = run.to_pdu().expect("pdu");
    let mut frame = vec![0, 8, 0, 0, 0, (pdu.len() + 1) as u8, 1];
    frame.extend(&pdu);
    let answer = owner.on_bytes(&mut plc, &frame, 6).expect("frames");
    assert_eq!(answer[7], 0x0D, "a GUTTA answer, not an exception");
    assert_eq!(owner.busy, 0);
}
