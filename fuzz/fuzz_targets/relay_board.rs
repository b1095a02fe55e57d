//! Fuzz target of the simulated relay board (`gutta_sim::relay`): arbitrary connection
//! bytes, cut into pieces by the input's first byte, go through one `RelaySession` on
//! one board (Modbus TCP, the board's own frames, garbage). Panics are the bugs it looks
//! for, and these rules must hold:
//! - the answers are whole frames: each is Modbus TCP (protocol id 0, its length field
//!   right) or the 12-byte status frame;
//! - a report exists exactly when the channels changed and reporting is on;
//! - afterwards (the session closed or not) the board still serves: a fresh session's
//!   own read answers the status frame of its channels.
#![no_main]

use gutta_protocol::relay::{decode_status, status_frame};
use gutta_protocol::tcp::MbapHeader;
use gutta_sim::relay::{RelayBoard, RelaySession};
use libfuzzer_sys::fuzz_target;

/// Checks that `out` is a sequence of whole answer frames.
fn whole_frames(mut out: &[u8]) {
    while !out.is_empty() {
        let len = if out.len() >= 4 && out[2..4] == [0, 0] {
            MbapHeader::decode(out).expect("an MBAP answer").frame_len()
        } else {
            12
        };
        assert!(out.len() >= len, "a cut answer: {out:02X?}");
        if out[2..4] != [0, 0] {
            decode_status(&out[..len]).expect("a status frame");
        }
        out = &out[len..];
    }
}

fuzz_target!(|data: &[u8]| {
    let Some((&piece, bytes)) = data.split_first() else {
        return;
    };
    let piece = usize::from(piece % 16) + 1;
    let mut board = RelayBoard::default();
    let mut session = RelaySession::new();
    for chunk in bytes.chunks(piece) {
        let before = board.channels();
        let result = session.on_bytes(&mut board, chunk);
        let report = board.report(before);
        assert_eq!(
            report.is_some(),
            board.reporting() && board.channels() != before
        );
        match result {
            Ok(out) => whole_frames(&out),
            Err(_) => break,
        }
    }
    let read = [1, 1, 2, 0, 0, 5, 0, 0x20, 0, 0, 0, 0];
    let out = RelaySession::new()
        .on_bytes(&mut board, &read)
        .expect("a read");
    assert_eq!(out, status_frame(board.channels()));
});
