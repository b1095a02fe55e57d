//! The checks of the `frames` fuzz target (fuzz/fuzz_targets/frames.rs includes this
//! file): arbitrary bytes go through both RTU splitters (in chunks chosen by the
//! input), the TCP splitter, every decoder (RTU, MBAP, GUTTA frame, GUTTA request and
//! response, Modbus request and response), the page reassembler and the master.
//! Whatever decodes must re-encode to the same bytes; the master may only answer with
//! what the input holds, by the rule of docs/protocol.md ("What the master does with
//! each frame"). `tests/fuzz_regressions.rs` replays the fuzzer's finds
//! (`tests/data/fuzz/frames/`) through `check_bytes`. Test code only.

use gutta_protocol::modbus::{ModbusRequest, ModbusResponse, EXCEPTION_BIT};
use gutta_protocol::transfer::split_page;
use gutta_protocol::{
    decode_rtu, decode_tcp, encode_rtu, GuttaFrame, Master, MasterConfig, MasterEvent, PackSize,
    Progress, Reassembler, Request, Response, RtuSplitter, Side, TcpSplitter,
};

/// The whole target on one input: the first byte chooses the chunk size (1-16), the
/// rest is the stream.
pub fn check_bytes(data: &[u8]) {
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
    master(rest, chunk, 0, &GUTTA_READ);
    master(rest, chunk, 1, &GUTTA_READ);
    master(rest, chunk, 1, &READ_HOLDING);
}

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

/// PROGRAM_INSTRUCTION_READ of page 0, packet 1 (GUTTA 0800).
const GUTTA_READ: [u8; 7] = [0x0D, 0x00, 0x04, 0x08, 0x00, 0x00, 0x01];
/// Read holding registers 0-1.
const READ_HOLDING: [u8; 5] = [0x03, 0x00, 0x00, 0x00, 0x02];

/// Whether `needle` occurs in `haystack` as consecutive bytes.
fn holds(haystack: &[u8], needle: &[u8]) -> bool {
    haystack.windows(needle.len()).any(|w| w == needle)
}

/// A master that sent `request` to `station` gets the input as its receive stream. An
/// answer must be a frame the input holds, from a station other than 0 (the request's
/// own unless it went to 0): an `Exception` of the request's function, or a `Response`
/// with the request's function (for function 13 the GUTTA function or its failure and
/// the packet). Afterwards the master is idle; `ignored_frames` never decreases.
fn master(data: &[u8], chunk: usize, station: u8, request: &[u8]) {
    let mut m = Master::new(MasterConfig {
        timeout_ms: 10,
        retries: 1,
        ..MasterConfig::default()
    });
    m.send(station, request, 0)
        .expect("a valid request to an idle master");
    let from = |answer: u8| {
        assert_ne!(answer, 0, "station 0 never answers");
        if station != 0 {
            assert_eq!(answer, station);
        }
    };
    let mut now = 0;
    let mut ignored = 0;
    for piece in data.chunks(chunk) {
        now += 3;
        let event = m.on_bytes(piece, now);
        assert!(m.ignored_frames() >= ignored);
        ignored = m.ignored_frames();
        match event {
            MasterEvent::Response(frame) => {
                from(frame.station);
                assert!(
                    holds(data, &frame.encode()),
                    "{frame:?} is not in the input"
                );
                assert_eq!(frame.function(), Some(request[0]));
                if request[0] == 0x0D {
                    let answer = GuttaFrame::from_pdu(&frame.pdu).expect("GUTTA data");
                    assert_eq!(answer.function & 0x7FFF, 0x0800, "{answer:?}");
                    assert_eq!(answer.packet, 0x0001, "{answer:?}");
                }
                assert!(!m.is_busy());
                return;
            }
            MasterEvent::Exception {
                station: answer,
                function,
                code,
            } => {
                from(answer);
                assert_eq!(function, request[0]);
                let wire = encode_rtu(answer, &[function | EXCEPTION_BIT, code]);
                assert!(holds(data, &wire), "{wire:02X?} is not in the input");
                assert!(!m.is_busy());
                return;
            }
            MasterEvent::Pending => {}
            other => panic!("on_bytes while waiting: {other:?}"),
        }
        match m.on_tick(now) {
            Some(MasterEvent::Failed(_)) => {
                assert!(!m.is_busy());
                return;
            }
            None | Some(MasterEvent::Retry(_)) => {}
            Some(other) => panic!("on_tick: {other:?}"),
        }
    }
}
