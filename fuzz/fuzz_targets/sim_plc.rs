//! Fuzz target of the simulated PLC (`gutta-sim`'s `Plc` and `Session`): a PLC holding
//! the format tests' full program (every operand kind) gets an arbitrary sequence of
//! GUTTA requests from two connections (so download windows open, refuse and end),
//! Modbus data requests, raw bytes on a Modbus TCP and an RTU session, and scans. Panics are the bugs it looks for, and three rules must hold throughout:
//! - every GUTTA answer echoes the request's packet number and its function code, or the
//!   code with bit 15 and no payload (the failure form);
//! - every Modbus data answer is the request's function or its exception (2 bytes);
//! - afterwards the PLC still serves: a fresh TCP session reads a holding register.
#![no_main]

use std::collections::BTreeMap;
use std::sync::Arc;

use gutta_format::SystemPage;
use gutta_format::{PageId, PageKind};
use gutta_protocol::GuttaFrame;
use gutta_sim::plc::{ConnectionId, Plc};
use gutta_sim::session::{Framing, Session};
use gutta_vm::VmConfig;
use libfuzzer_sys::fuzz_target;

#[allow(dead_code)]
mod shared;

use shared::{base_image, default_target};

/// The connections: two that send GUTTA requests straight to the PLC, the two sessions,
/// and the fresh one of the final check.
const TCP: ConnectionId = ConnectionId(3);
const RTU: ConnectionId = ConnectionId(4);

/// Reads records off the input: each takes its bytes or stops the run.
struct Input<'a>(&'a [u8]);

impl<'a> Input<'a> {
    fn byte(&mut self) -> Option<u8> {
        let (&b, rest) = self.0.split_first()?;
        self.0 = rest;
        Some(b)
    }
    fn word(&mut self) -> Option<u16> {
        Some(u16::from_be_bytes([self.byte()?, self.byte()?]))
    }
    fn bytes(&mut self, n: usize) -> &'a [u8] {
        let n = n.min(self.0.len());
        let (head, rest) = self.0.split_at(n);
        self.0 = rest;
        head
    }
}

/// Login-free GUTTA functions a sequence may start from, and a few that need login, so
/// short inputs reach deep states: CLEAR, RESET, ATTACH, STATUS_READ, page writes.
const FUNCTIONS: [u16; 16] = [
    0x0100, 0x0110, 0x0111, 0x0120, 0x0210, 0x0220, 0x0230, 0x0240, 0x0312, 0x0600, 0x0900, 0x0A00,
    0x0A01, 0x0A03, 0x0A10, 0x0A35,
];

fn check_gutta(request: &GuttaFrame, answer: &GuttaFrame) {
    assert_eq!(answer.packet, request.packet, "packet echoed: {request:?}");
    if answer.function == request.function | 0x8000 && request.function & 0x8000 == 0 {
        assert!(answer.payload.is_empty(), "failure without payload");
    } else {
        assert_eq!(answer.function, request.function, "function echoed");
    }
}

fn check_modbus(pdu: &[u8], answer: &[u8]) {
    let function = pdu.first().copied().unwrap_or(0);
    match answer {
        [f, _code] if *f == function | 0x80 => {}
        [f, ..] => assert_eq!(*f, function, "answer to {pdu:02X?}: {answer:02X?}"),
        [] => panic!("no answer to {pdu:02X?}"),
    }
}

fuzz_target!(|data: &[u8]| {
    let target = default_target();
    let image = base_image();
    let config = VmConfig {
        watchdog: 20_000,
        ..VmConfig::default()
    };
    let pages: BTreeMap<PageId, Vec<u8>> = image.pages.clone();
    let Ok(mut plc) = Plc::new(Arc::clone(target), pages, config) else {
        return;
    };
    let password = image
        .pages
        .get(&PageId::new(PageKind::System, 0))
        .and_then(|b| SystemPage::decode(b).ok())
        .map_or([0xFF; 16], |s| s.password);
    let mut tcp = Session::new(Framing::Tcp, TCP);
    let mut rtu = Session::new(Framing::Rtu, RTU);
    let mut input = Input(data);
    let mut now = 0u64;
    while let Some(kind) = input.byte() {
        now += 7;
        match kind % 6 {
            // A GUTTA request: a listed function (or any code), packet, payload.
            0 | 1 => {
                let Some(selector) = input.word() else { break };
                let function = if kind % 6 == 0 {
                    FUNCTIONS[usize::from(selector) % FUNCTIONS.len()]
                } else {
                    selector
                };
                let Some(packet) = input.word() else { break };
                let Some(len) = input.byte() else { break };
                let payload = if function == 0x0110 && len == 0xFF {
                    password.to_vec()
                } else {
                    input.bytes(usize::from(len)).to_vec()
                };
                let request = GuttaFrame::new(function, packet, payload);
                // Bit 7 of the record's kind picks one of two connections.
                let from = ConnectionId(u64::from(kind >> 7) + 1);
                let answer = plc.answer(from, &request, now);
                check_gutta(&request, &answer);
            }
            // A Modbus data request straight to the PLC.
            2 => {
                let Some(len) = input.byte() else { break };
                let pdu = input.bytes(usize::from(len % 16) + 1);
                let answer = plc.modbus(pdu);
                check_modbus(pdu, &answer);
            }
            // Raw bytes on either session.
            3 | 4 => {
                let Some(len) = input.byte() else { break };
                let bytes = input.bytes(usize::from(len));
                if kind % 6 == 3 {
                    if tcp.on_bytes(&mut plc, bytes, now).is_err() {
                        // A TCP stream that cannot be framed is closed by the server.
                        plc.disconnect(TCP);
                        tcp = Session::new(Framing::Tcp, TCP);
                    }
                } else {
                    // RTU drops what does not frame and resynchronises: never an error.
                    rtu.on_bytes(&mut plc, bytes, now)
                        .expect("an RTU session never fails");
                }
            }
            // Scans.
            _ => {
                for _ in 0..(kind / 6) % 4 + 1 {
                    let _ = plc.scan();
                }
            }
        }
    }
    // Still serving: read holding register 0 on a fresh connection.
    let mut fresh = Session::new(Framing::Tcp, ConnectionId(5));
    let answer = fresh
        .on_bytes(
            &mut plc,
            &[0x12, 0x34, 0, 0, 0, 6, 1, 0x03, 0x00, 0x00, 0x00, 0x01],
            now + 1,
        )
        .expect("a well-formed request frames");
    assert_eq!(
        answer,
        [&[0x12, 0x34, 0, 0, 0, 5, 1, 0x03, 2][..], &answer[9..]].concat()
    );
    assert_eq!(answer.len(), 11, "{answer:02X?}");
});
