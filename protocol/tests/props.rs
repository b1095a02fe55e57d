//! Property tests: encode/decode round trips of every layer, decoders that accept only
//! what they can re-encode byte for byte, and the splitters on arbitrary chunkings of a
//! stream of valid frames.

use gutta_format::PackedOperand;
use gutta_protocol::modbus::{ModbusRequest, ModbusResponse};
use gutta_protocol::transfer::{read_slice, split_page};
use gutta_protocol::{
    decode_rtu, decode_tcp, encode_rtu, encode_tcp, Breakpoint, Command, DebugStep, Function,
    GuttaFrame, PackSize, PageArea, PageRef, Reassembler, Reply, Request, Response, RtuSplitter,
    Side, TcpSplitter,
};
use proptest::prelude::*;

fn page_ref() -> impl Strategy<Value = PageRef> {
    prop_oneof![
        (0..16u8).prop_map(PageRef::Data),
        (0..16u8).prop_map(PageRef::System),
        Just(PageRef::Const),
        any::<u8>().prop_map(PageRef::Argument),
        any::<u8>().prop_map(PageRef::Instruction),
    ]
}

fn area() -> impl Strategy<Value = PageArea> {
    prop_oneof![
        Just(PageArea::Data),
        Just(PageArea::System),
        Just(PageArea::Program)
    ]
}

fn bytes(max: usize) -> impl Strategy<Value = Vec<u8>> {
    proptest::collection::vec(any::<u8>(), 0..max)
}

fn command() -> impl Strategy<Value = Command> {
    let addresses = proptest::collection::vec(any::<u32>().prop_map(PackedOperand), 0..8);
    let pairs =
        proptest::collection::vec((any::<u32>().prop_map(PackedOperand), any::<u32>()), 0..8);
    prop_oneof![
        Just(Command::PlcClear),
        any::<[u8; 16]>().prop_map(|password| Command::PlcAttach { password }),
        Just(Command::GetPlcName),
        area().prop_map(Command::PageList),
        page_ref().prop_map(Command::PageAsk),
        page_ref().prop_map(Command::PageRead),
        (page_ref(), bytes(200)).prop_map(|(p, d)| Command::PageWrite(p, d)),
        any::<u8>().prop_map(|run| Command::StatusWrite { run }),
        any::<u8>().prop_map(|count| Command::StatusScan { count }),
        addresses.clone().prop_map(Command::VarRead),
        pairs.clone().prop_map(Command::VarWrite),
        addresses.prop_map(Command::ForceRead),
        pairs.prop_map(Command::ForceWrite),
        prop_oneof![
            Just(DebugStep::In),
            Just(DebugStep::Over),
            Just(DebugStep::Out)
        ]
        .prop_map(Command::DebugScan),
        (any::<u8>(), any::<u16>(), any::<u16>()).prop_map(|(index, network, step)| {
            Command::DebugInforWrite(Breakpoint {
                index,
                network,
                step,
            })
        }),
        Just(Command::DebugInforRead),
    ]
}

fn request() -> impl Strategy<Value = Request> {
    (command(), any::<u16>()).prop_map(|(command, packet)| {
        if command.function().is_paged() {
            Request { packet, command }
        } else {
            Request::single(command)
        }
    })
}

fn reply() -> impl Strategy<Value = Reply> {
    prop_oneof![
        (0..0x8000u16).prop_map(|code| Reply::Failure { code }),
        Just(Reply::Ack(Function::PlcClear)),
        page_ref().prop_map(|p| Reply::Ack(Function::PageWrite(p))),
        any::<[u8; 16]>().prop_map(Reply::PlcName),
        (area(), bytes(20)).prop_map(|(a, p)| Reply::PageList(a, p)),
        (page_ref(), any::<u16>()).prop_map(|(p, l)| Reply::PageLength(p, l)),
        (page_ref(), bytes(200)).prop_map(|(p, d)| Reply::PageData(p, d)),
        any::<u8>().prop_map(Reply::Status),
        proptest::collection::vec(any::<u32>(), 0..8).prop_map(Reply::VarValues),
        proptest::collection::vec(any::<u32>(), 0..8).prop_map(Reply::ForceValues),
        any::<u8>().prop_map(Reply::DebugState),
    ]
}

fn modbus_request() -> impl Strategy<Value = ModbusRequest> {
    prop_oneof![
        (0..=1000u16, 1..=2000u16)
            .prop_map(|(address, quantity)| ModbusRequest::ReadCoils { address, quantity }),
        (0..=1000u16, 1..=125u16).prop_map(|(address, quantity)| {
            ModbusRequest::ReadHoldingRegisters { address, quantity }
        }),
        (0..=1000u16, 1..=125u16).prop_map(|(address, quantity)| {
            ModbusRequest::ReadInputRegisters { address, quantity }
        }),
        (any::<u16>(), any::<bool>())
            .prop_map(|(address, value)| ModbusRequest::WriteSingleCoil { address, value }),
        (any::<u16>(), any::<u16>())
            .prop_map(|(address, value)| ModbusRequest::WriteSingleRegister { address, value }),
        (
            0..=1000u16,
            proptest::collection::vec(any::<bool>(), 1..=300)
        )
            .prop_map(|(address, values)| ModbusRequest::WriteMultipleCoils { address, values }),
        (
            0..=1000u16,
            proptest::collection::vec(any::<u16>(), 1..=123)
        )
            .prop_map(|(address, values)| ModbusRequest::WriteMultipleRegisters {
                address,
                values
            }),
    ]
}

fn modbus_response() -> impl Strategy<Value = ModbusResponse> {
    prop_oneof![
        proptest::collection::vec(any::<u8>(), 1..=250).prop_map(ModbusResponse::ReadCoils),
        proptest::collection::vec(any::<u16>(), 1..=125)
            .prop_map(ModbusResponse::ReadHoldingRegisters),
        (any::<u16>(), any::<bool>())
            .prop_map(|(address, value)| ModbusResponse::WriteSingleCoil { address, value }),
        (any::<u16>(), any::<u16>()).prop_map(|(address, quantity)| {
            ModbusResponse::WriteMultipleRegisters { address, quantity }
        }),
        (prop_oneof![1..=6u8, 15..=16u8], any::<u8>())
            .prop_map(|(function, code)| ModbusResponse::Exception { function, code }),
    ]
}

/// A stream of valid request frames (Modbus and GUTTA) for the slave side.
fn request_frames() -> impl Strategy<Value = Vec<Vec<u8>>> {
    let frame = prop_oneof![
        (any::<u8>(), modbus_request())
            .prop_map(|(s, r)| encode_rtu(s, &r.encode().expect("valid"))),
        (any::<u8>(), request())
            .prop_map(|(s, r)| encode_rtu(s, &r.encode().expect("valid").to_pdu().expect("fits"))),
    ];
    proptest::collection::vec(frame, 1..12)
}

/// A stream of valid response frames for the master side.
fn response_frames() -> impl Strategy<Value = Vec<Vec<u8>>> {
    let frame = prop_oneof![
        (any::<u8>(), modbus_response())
            .prop_map(|(s, r)| encode_rtu(s, &r.encode().expect("valid"))),
        (any::<u8>(), reply(), any::<u16>()).prop_map(|(s, reply, packet)| {
            let response = Response { packet, reply };
            encode_rtu(
                s,
                &response.encode().expect("valid").to_pdu().expect("fits"),
            )
        }),
    ];
    proptest::collection::vec(frame, 1..12)
}

/// Cuts `stream` at the given (sorted, deduplicated) positions.
fn chunks(stream: &[u8], cuts: &[usize]) -> Vec<Vec<u8>> {
    let mut cuts: Vec<usize> = cuts.iter().map(|c| c % (stream.len() + 1)).collect();
    cuts.sort_unstable();
    cuts.dedup();
    let mut out = vec![];
    let mut start = 0;
    for cut in cuts.into_iter().chain([stream.len()]) {
        out.push(stream[start..cut].to_vec());
        start = cut;
    }
    out
}

fn split_all(side: Side, pieces: &[Vec<u8>]) -> Vec<Vec<u8>> {
    let mut splitter = RtuSplitter::new(side);
    let mut frames = vec![];
    for piece in pieces {
        splitter.push(piece);
        while let Some(frame) = splitter.next_frame() {
            frames.push(frame.expect("only valid frames in the stream"));
        }
    }
    assert_eq!(splitter.buffered(), 0);
    frames
}

proptest! {
    #[test]
    fn rtu_round_trip(station in any::<u8>(), pdu in proptest::collection::vec(any::<u8>(), 1..300)) {
        let wire = encode_rtu(station, &pdu);
        let frame = decode_rtu(&wire).expect("own CRC checks");
        prop_assert_eq!(frame.station, station);
        prop_assert_eq!(&frame.pdu, &pdu);
        prop_assert_eq!(frame.encode(), wire);
    }

    #[test]
    fn tcp_round_trip(t in any::<u16>(), unit in any::<u8>(), pdu in proptest::collection::vec(any::<u8>(), 1..300)) {
        let wire = encode_tcp(t, unit, &pdu).expect("fits");
        let frame = decode_tcp(&wire).expect("decodes");
        prop_assert_eq!(frame.encode(), Some(wire));
    }

    #[test]
    fn gutta_frame_round_trip(function in any::<u16>(), packet in any::<u16>(), payload in bytes(300)) {
        let frame = GuttaFrame::new(function, packet, payload);
        let pdu = frame.to_pdu().expect("fits");
        prop_assert_eq!(GuttaFrame::from_pdu(&pdu), Ok(frame));
    }

    #[test]
    fn request_round_trip(request in request()) {
        let frame = request.encode().expect("valid by construction");
        prop_assert_eq!(Request::decode(&frame), Ok(request));
    }

    #[test]
    fn response_round_trip(reply in reply(), packet in any::<u16>()) {
        let response = Response { packet, reply };
        let frame = response.encode().expect("valid by construction");
        prop_assert_eq!(Response::decode(&frame), Ok(response));
    }

    #[test]
    fn gutta_decoders_accept_only_what_they_reencode(code in 0x0100..0x0A40u16, packet in any::<u16>(), payload in bytes(40), fail in any::<bool>()) {
        let function = if fail { code | 0x8000 } else { code };
        let frame = GuttaFrame::new(function, packet, payload);
        if let Ok(request) = Request::decode(&frame) {
            prop_assert_eq!(request.encode(), Ok(frame.clone()));
        }
        if let Ok(response) = Response::decode(&frame) {
            prop_assert_eq!(response.encode(), Ok(frame));
        }
    }

    #[test]
    fn modbus_round_trip(request in modbus_request(), response in modbus_response()) {
        let pdu = request.encode().expect("valid");
        prop_assert_eq!(ModbusRequest::decode(&pdu), Ok(request));
        let pdu = response.encode().expect("valid");
        prop_assert_eq!(ModbusResponse::decode(&pdu), Ok(response));
    }

    #[test]
    fn modbus_decoders_accept_only_what_they_reencode(pdu in proptest::collection::vec(any::<u8>(), 0..20)) {
        if let Ok(request) = ModbusRequest::decode(&pdu) {
            prop_assert_eq!(request.encode(), Ok(pdu.clone()));
        }
        if let Ok(response) = ModbusResponse::decode(&pdu) {
            prop_assert_eq!(response.encode(), Ok(pdu));
        }
    }

    #[test]
    fn slave_splitter_any_chunking(frames in request_frames(), cuts in proptest::collection::vec(any::<usize>(), 0..30)) {
        let stream = frames.concat();
        prop_assert_eq!(split_all(Side::Slave, &chunks(&stream, &cuts)), frames);
    }

    #[test]
    fn master_splitter_any_chunking(frames in response_frames(), cuts in proptest::collection::vec(any::<usize>(), 0..30)) {
        let stream = frames.concat();
        prop_assert_eq!(split_all(Side::Master, &chunks(&stream, &cuts)), frames);
    }

    #[test]
    fn tcp_splitter_any_chunking(pdus in proptest::collection::vec(proptest::collection::vec(any::<u8>(), 1..300), 1..8), cuts in proptest::collection::vec(any::<usize>(), 0..30)) {
        let frames: Vec<Vec<u8>> = pdus.iter().enumerate().map(|(i, p)| encode_tcp(i as u16, 1, p).expect("fits")).collect();
        let stream = frames.concat();
        let mut splitter = TcpSplitter::new(1024);
        let mut out = vec![];
        for piece in chunks(&stream, &cuts) {
            splitter.push(&piece);
            while let Some(frame) = splitter.next_frame() {
                out.push(frame.expect("valid"));
            }
        }
        prop_assert_eq!(out, frames);
    }

    #[test]
    fn split_and_reassemble(page in bytes(3000), size in 64..=1023u16) {
        let pack = PackSize::new(size).expect("in range");
        let mut reassembler = Reassembler::new(pack, 65535);
        for (number, data) in split_page(&page, pack).expect("fits") {
            prop_assert_eq!(read_slice(&page, number, pack), Ok(data));
            reassembler.push(number, data).expect("in order");
        }
        prop_assert_eq!(reassembler.finish(), Ok(page));
    }
}
