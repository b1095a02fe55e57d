//! Every request, failure and success example of UM4001 (tests/data/um4001.txt) decodes
//! to the named function, re-encodes to the same bytes, and survives RTU framing and
//! the stream splitter of its direction; plus the typed values of the examples.

use gutta_format::PackedOperand;
use gutta_protocol::message::{sys_state, FACTORY_PASSWORD};
use gutta_protocol::{
    encode_rtu, Breakpoint, Command, DebugInfo, DebugStep, Function, GuttaFrame, PageArea, PageRef,
    Reply, Request, Response, RtuSplitter, Side,
};

struct Example {
    line: usize,
    kind: String,
    name: String,
    bytes: Vec<u8>,
}

fn examples() -> Vec<Example> {
    let text = include_str!("data/um4001.txt");
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.starts_with('#'))
        .map(|(i, l)| {
            let mut words = l.split_whitespace();
            let kind = words.next().expect("kind").to_string();
            let name = words.next().expect("name").to_string();
            let bytes = words
                .map(|w| u8::from_str_radix(w, 16).expect("hex byte"))
                .collect();
            Example {
                line: i + 1,
                kind,
                name,
                bytes,
            }
        })
        .collect()
}

fn hex(s: &str) -> Vec<u8> {
    s.split_whitespace()
        .map(|w| u8::from_str_radix(w, 16).expect("hex byte"))
        .collect()
}

fn split_one(side: Side, station: u8, data: &[u8]) -> Vec<u8> {
    let mut pdu = vec![0x0D];
    pdu.extend_from_slice(data);
    let wire = encode_rtu(station, &pdu);
    let mut splitter = RtuSplitter::new(side);
    let mut frames = vec![];
    for chunk in wire.chunks(3) {
        splitter.push(chunk);
        while let Some(frame) = splitter.next_frame() {
            frames.push(frame.expect("valid frame"));
        }
    }
    assert_eq!(frames, std::slice::from_ref(&wire));
    wire
}

#[test]
fn every_um4001_example() {
    let examples = examples();
    assert_eq!(
        examples.len(),
        3 * gutta_protocol::FUNCTIONS.len(),
        "one request, failure and success per registry row"
    );
    let mut names = std::collections::BTreeSet::new();
    for ex in &examples {
        let at = format!("um4001.txt:{} {} {}", ex.line, ex.kind, ex.name);
        let frame = GuttaFrame::decode(&ex.bytes).unwrap_or_else(|e| panic!("{at}: {e}"));
        assert_eq!(frame.encode().as_ref(), Ok(&ex.bytes), "{at}");
        names.insert(ex.name.clone());
        match ex.kind.as_str() {
            "request" => {
                let request = Request::decode(&frame).unwrap_or_else(|e| panic!("{at}: {e}"));
                assert_eq!(request.function().name(), ex.name, "{at}");
                assert_eq!(request.encode().as_ref(), Ok(&frame), "{at}");
                split_one(Side::Slave, 1, &ex.bytes);
            }
            "failure" | "success" => {
                let response = Response::decode(&frame).unwrap_or_else(|e| panic!("{at}: {e}"));
                let code = match response.reply {
                    Reply::Failure { code } => {
                        assert_eq!(ex.kind, "failure", "{at}");
                        code
                    }
                    _ => {
                        assert_eq!(ex.kind, "success", "{at}");
                        response.code()
                    }
                };
                let function = Function::from_code(code).expect("defined");
                assert_eq!(function.name(), ex.name, "{at}");
                assert_eq!(response.encode().as_ref(), Ok(&frame), "{at}");
                split_one(Side::Master, 1, &ex.bytes);
            }
            other => panic!("{at}: unknown kind {other}"),
        }
    }
    assert_eq!(names.len(), gutta_protocol::FUNCTIONS.len());
}

/// A test per registry row: UM4001's request, failure and success examples of the
/// function are in the data file, and their payloads have the row's shapes.
#[test]
fn every_registry_row_has_its_examples() {
    let examples = examples();
    for spec in gutta_protocol::FUNCTIONS {
        for kind in ["request", "failure", "success"] {
            let example = examples
                .iter()
                .find(|ex| ex.name == spec.name && ex.kind == kind)
                .unwrap_or_else(|| panic!("{}: no {kind} example in um4001.txt", spec.name));
            let frame = GuttaFrame::decode(&example.bytes).expect("frame");
            assert!(spec.covers(frame.function & !gutta_protocol::FAILURE_BIT));
            let shape = match kind {
                "request" => spec.request,
                "success" => spec.success,
                _ => gutta_protocol::Payload::Empty,
            };
            let at = format!("{} {kind}", spec.name);
            assert!(shape.accepts(frame.payload.len()), "{at}: {shape}");
            let paged = spec.packets == gutta_protocol::Packets::Paged;
            assert_eq!(frame.packet != 0x8000, paged, "{at}: packet number");
        }
    }
}

#[test]
fn typed_values_of_the_examples() {
    let req =
        |s: &str| Request::decode(&GuttaFrame::decode(&hex(s)).expect("frame")).expect("request");
    let resp =
        |s: &str| Response::decode(&GuttaFrame::decode(&hex(s)).expect("frame")).expect("response");

    assert_eq!(req("00 04 01 00 80 00"), Request::single(Command::PlcClear));
    let attach = format!("00 14 01 10 80 00{}", " FF".repeat(16));
    assert_eq!(
        req(&attach),
        Request::single(Command::PlcAttach {
            password: FACTORY_PASSWORD
        })
    );
    assert_eq!(
        req("00 04 02 33 00 01"),
        Request {
            packet: 1,
            command: Command::PageRead(PageRef::Data(3))
        }
    );
    assert_eq!(
        req("00 08 09 2A 80 05 01 02 03 04"),
        Request {
            packet: 0x8005,
            command: Command::PageWrite(PageRef::Instruction(0x2A), vec![1, 2, 3, 4])
        }
    );
    assert_eq!(
        req("00 04 03 11 80 00").command,
        Command::PageRead(PageRef::Const)
    );
    assert_eq!(
        req("00 04 02 60 80 00").command,
        Command::PageList(PageArea::System)
    );
    assert_eq!(
        req("00 05 0A 02 80 00 0A").command,
        Command::StatusScan { count: 10 }
    );
    assert_eq!(
        req("00 05 0A 32 80 00 03").command,
        Command::DebugScan(DebugStep::Out)
    );
    // STATUS_VAR_READ addresses go low byte first: 10 02 04 00 = 0x0004_0210.
    let Command::VarRead(addresses) = req("00 08 0A 10 80 00 10 02 04 00").command else {
        panic!("not a var read");
    };
    assert_eq!(addresses, [PackedOperand(0x0004_0210)]);
    assert_eq!(
        (
            addresses[0].offset(),
            addresses[0].bit(),
            addresses[0].width_code()
        ),
        (4, 0, 2)
    );
    assert_eq!((addresses[0].slot(), addresses[0].use_code()), (1, 0));
    // gutta-format decodes it: the WORD at offset 4 of slot 1, by value.
    assert_eq!(
        addresses[0].decode(),
        Ok(gutta_format::Operand::Value(gutta_format::Address {
            slot: 1,
            width: gutta_format::Width::Word,
            offset: 4,
            bit: 0
        }))
    );
    assert_eq!(
        req("00 0C 0A 21 80 00 10 02 04 00 34 12 00 00").command,
        Command::ForceWrite(vec![(PackedOperand(0x0004_0210), 0x1234)])
    );
    assert_eq!(
        req("00 09 0A 35 80 00 02 00 05 00 07").command,
        Command::DebugInforWrite(Breakpoint {
            index: 2,
            network: 5,
            step: 7
        })
    );

    assert_eq!(
        resp("00 06 02 23 80 00 01 50").reply,
        Reply::PageLength(PageRef::Data(3), 0x0150)
    );
    assert_eq!(
        resp("00 06 04 2A 80 00 2A 00").reply,
        Reply::PageLength(PageRef::Argument(0x2A), 0x2A00)
    );
    assert_eq!(
        resp("00 07 03 00 80 00 00 01 02").reply,
        Reply::PageList(PageArea::Program, vec![0, 1, 2])
    );
    let Reply::Status(state) = resp("00 05 0A 00 80 00 05").reply else {
        panic!("status")
    };
    assert_eq!(state, sys_state::RUN | sys_state::ATTACH);
    assert_eq!(
        resp("00 08 0A 10 80 00 2B 0C 00 00").reply,
        Reply::VarValues(vec![0x0C2B])
    );
    assert_eq!(
        resp("00 14 0A 34 80 00 02 00 05 00 07 01 00 03 00 04 12 34 00 01 02 00").reply,
        Reply::DebugInfo(DebugInfo {
            breakpoint: Breakpoint {
                index: 2,
                network: 5,
                step: 7
            },
            state_index: 1,
            state_network: 3,
            state_step: 4,
            stack_data: 0x1234,
            stack_logic: 1,
            sp: 2,
            error: 0,
        })
    );
    assert_eq!(
        resp("00 04 8A 11 80 00").reply,
        Reply::Failure { code: 0x0A11 }
    );
    assert_eq!(
        resp("00 04 82 43 00 01"),
        Response {
            packet: 1,
            reply: Reply::Failure { code: 0x0243 }
        }
    );
    assert_eq!(
        resp("00 04 01 10 80 00").reply,
        Reply::Ack(Function::PlcAttach)
    );
}

#[test]
fn violated_success_conditions_are_typed_errors() {
    use gutta_protocol::MessageError;
    let decode = |s: &str| Request::decode(&GuttaFrame::decode(&hex(s)).expect("frame"));
    // "发送数据长度为 0" / "为 1" / "为 16" / "为 5" / "能够被 4 (8) 整除".
    assert!(matches!(
        decode("00 05 01 00 80 00 00"),
        Err(MessageError::PayloadLength { .. })
    ));
    assert!(matches!(
        decode("00 05 01 10 80 00 FF"),
        Err(MessageError::PayloadLength { .. })
    ));
    assert!(matches!(
        decode("00 04 0A 01 80 00"),
        Err(MessageError::PayloadLength { .. })
    ));
    assert!(matches!(
        decode("00 06 0A 35 80 00 01 02"),
        Err(MessageError::PayloadLength { .. })
    ));
    assert!(matches!(
        decode("00 07 0A 10 80 00 01 02 03"),
        Err(MessageError::PayloadLength { .. })
    ));
    assert!(matches!(
        decode("00 08 0A 11 80 00 01 02 03 04"),
        Err(MessageError::PayloadLength { .. })
    ));
    assert_eq!(
        decode("00 05 0A 32 80 00 04"),
        Err(MessageError::DebugStep { value: 4 })
    );
    assert_eq!(
        decode("00 04 02 50 80 00"),
        Err(MessageError::UnknownFunction { code: 0x0250 })
    );
    assert_eq!(
        decode("00 04 81 00 80 00"),
        Err(MessageError::FailureBitInRequest { code: 0x8100 })
    );
    assert!(matches!(
        decode("00 04 01 00 00 00"),
        Err(MessageError::PacketNumber { .. })
    ));
    // A failure never carries a payload.
    let failure = GuttaFrame::decode(&hex("00 05 81 00 80 00 01")).expect("frame");
    assert_eq!(
        Response::decode(&failure),
        Err(MessageError::FailureWithPayload { code: 0x0100 })
    );
    // Encoding refuses what decoding could never produce.
    let bad_page = Request::single(Command::PageAsk(PageRef::Data(16)));
    assert_eq!(
        bad_page.encode(),
        Err(MessageError::PageNumber {
            page: PageRef::Data(16)
        })
    );
    let not_ack = Response {
        packet: 0x8000,
        reply: Reply::Ack(Function::StatusRead),
    };
    assert_eq!(
        not_ack.encode(),
        Err(MessageError::NotAnAck {
            function: Function::StatusRead
        })
    );
}
