//! Fuzz target of the protocol core (`gutta-protocol`): arbitrary bytes go through both
//! RTU splitters (in chunks chosen by the input), the TCP splitter, every decoder (RTU,
//! MBAP, GUTTA frame, GUTTA request and response, Modbus request and response), the
//! page reassembler and the master. Whatever decodes must re-encode to the same bytes;
//! a mismatch or a panic is the bug it looks for.
#![no_main]

use gutta_protocol::modbus::{ModbusRequest, ModbusResponse};
use gutta_protocol::transfer::split_page;
use gutta_protocol::{
    decode_rtu, decode_tcp, GuttaFrame, Master, MasterConfig, MasterEvent, PackSize, Progress,
    Reassembler, Request, Response, RtuSplitter, Side, TcpSplitter,
};
use libfuzzer_sys::fuzz_target;

/// Every PDU-level decoder on `pdu`; anything decoded re-encodes to the same bytes.
fn pdu_decoders(pdu: &[u8]) {
    if let Ok(request) = ModbusRequest::decode(pdu) {
        assert_eq!(request.encode().as_deref(), Ok(pdu), "{request:?}");
    }
    if let Ok(response) = ModbusResponse::decode(pdu) {
        assert_eq!(response.encode().as_deref(), Ok(pdu), "{response:?}");
    }
    if let Ok(frame) = GuttaFrame::from_pdu(pdu) {
        assert_eq!(frame.to_pdu().as_deref(), Ok(pdu));
        gutta_decoders(&frame);
    }
}

fn gutta_decoders(frame: &GuttaFrame) {
    if let Ok(request) = Request::decode(frame) {
        assert_eq!(request.encode().as_ref(), Ok(frame), "{request:?}");
    }
    if let Ok(response) = Response::decode(frame) {
        assert_eq!(response.encode().as_ref(), Ok(frame), "{response:?}");
    }
}

fn rtu_splitter(side: Side, data: &[u8], chunk: usize) {
    let mut splitter = RtuSplitter::new(side);
    for piece in data.chunks(chunk) {
        splitter.push(piece);
        while let Some(result) = splitter.next_frame() {
            if let Ok(wire) = result {
                let frame = decode_rtu(&wire).expect("the splitter checked the CRC");
                assert_eq!(frame.encode(), wire);
                pdu_decoders(&frame.pdu);
            }
        }
    }
    assert!(splitter.buffered() <= data.len());
}

fn tcp(data: &[u8], chunk: usize) {
    if let Ok(frame) = decode_tcp(data) {
        assert_eq!(frame.encode().as_deref(), Some(data));
    }
    let mut splitter = TcpSplitter::new(1100);
    for piece in data.chunks(chunk) {
        splitter.push(piece);
        while let Some(result) = splitter.next_frame() {
            if let Ok(wire) = result {
                let frame = decode_tcp(&wire).expect("the splitter sized it");
                assert_eq!(frame.encode(), Some(wire));
                pdu_decoders(&frame.pdu);
            }
        }
    }
}

/// The input as packets `number(2) len(1) bytes`, pushed into a reassembler (ExchPackSize
/// 64); every completed page must split back into exactly the packets accepted.
fn reassembler(data: &[u8]) {
    let Ok(pack) = PackSize::new(64) else { return };
    let mut r = Reassembler::new(pack, 300);
    let mut accepted: Vec<(u16, Vec<u8>)> = vec![];
    let mut rest = data;
    while let [hi, lo, len, tail @ ..] = rest {
        let number = u16::from_be_bytes([*hi, *lo]);
        let len = usize::from(*len).min(tail.len());
        let (bytes, after) = tail.split_at(len);
        rest = after;
        match r.push(number, bytes) {
            Ok(Progress::Repeat) | Err(_) => {}
            Ok(progress) => {
                if number & 0x7FFF == 0 {
                    accepted.clear();
                }
                accepted.push((number, bytes.to_vec()));
                if progress == Progress::Complete {
                    // The page is the accepted packets in order; splitting it again
                    // gives packets of the same bytes (a sender may also end with an
                    // empty last packet after full ones, which split_page never does).
                    let page = r.clone().finish().expect("complete");
                    let joined: Vec<u8> = accepted.iter().flat_map(|(_, b)| b.clone()).collect();
                    assert_eq!(page, joined);
                    let split: Vec<u8> = split_page(&page, pack)
                        .expect("within the limit")
                        .into_iter()
                        .flat_map(|(_, b)| b.to_vec())
                        .collect();
                    assert_eq!(split, page);
                }
            }
        }
    }
}

/// A master waiting for a GUTTA answer gets the input as its receive stream.
fn master(data: &[u8], chunk: usize) {
    let mut m = Master::new(MasterConfig {
        timeout_ms: 10,
        retries: 1,
        ..MasterConfig::default()
    });
    let request = [0x0D, 0x00, 0x04, 0x08, 0x00, 0x00, 0x01];
    if m.send(0, &request, 0).is_err() {
        return;
    }
    let mut now = 0;
    for piece in data.chunks(chunk) {
        now += 3;
        match m.on_bytes(piece, now) {
            MasterEvent::Response(frame) => {
                assert_eq!(frame.pdu.first(), Some(&0x0D));
                return;
            }
            MasterEvent::Idle => return,
            _ => {}
        }
        if let Some(MasterEvent::Failed(_)) = m.on_tick(now) {
            return;
        }
    }
}

fuzz_target!(|data: &[u8]| {
    let Some((&first, rest)) = data.split_first() else {
        return;
    };
    let chunk = usize::from(first % 16) + 1;
    rtu_splitter(Side::Slave, rest, chunk);
    rtu_splitter(Side::Master, rest, chunk);
    tcp(rest, chunk);
    if let Ok(frame) = decode_rtu(rest) {
        assert_eq!(frame.encode(), rest);
        pdu_decoders(&frame.pdu);
    }
    pdu_decoders(rest);
    if let Ok(frame) = GuttaFrame::decode(rest) {
        assert_eq!(frame.encode().as_deref(), Ok(rest));
        gutta_decoders(&frame);
    }
    reassembler(rest);
    master(rest, chunk);
});
