//! Standard Modbus data functions on a simulated CPU-EC20 (8051), with the byte
//! examples of AN2002 and IN1001's address mapping.

mod common;

use std::sync::Arc;

use gutta_catalog::stdlib;
use gutta_protocol::rtu::RtuFrame;
use gutta_sim::modbus_data::{answer_frame, answer_rtu, serve};
use gutta_vm::{Vm, VmConfig};

/// A CPU-EC20 VM running an empty MAIN.
fn vm() -> Vm {
    let target = stdlib::shared("CPU-EC20").expect("target");
    let image = common::image(
        "t.lad",
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\nEND_ORGANIZATION_BLOCK\n",
    );
    let verified = gutta_format::verify(&image, &target).expect("verifies");
    Vm::new(verified, Arc::clone(&target), VmConfig::default()).expect("loads")
}

fn set(vm: &mut Vm, var: &str, v: u32) {
    let a = vm.target().memory.parse_address(var).expect("address");
    vm.write(a, v).expect("write");
}

fn get(vm: &Vm, var: &str) -> u32 {
    let a = vm.target().memory.parse_address(var).expect("address");
    vm.read(a).expect("read")
}

#[test]
fn an2002_capture_read_inputs_and_holding_registers() {
    let mut vm = vm();
    // 01 02 00 04 00 04: inputs 100005..100008 (I0.4..I0.7), all off: 02 01 00.
    assert_eq!(
        serve(&mut vm, &[0x02, 0x00, 0x04, 0x00, 0x04]),
        [0x02, 0x01, 0x00]
    );
    set(&mut vm, "I0.4", 1);
    set(&mut vm, "I0.7", 1);
    assert_eq!(
        serve(&mut vm, &[0x02, 0x00, 0x04, 0x00, 0x04]),
        [0x02, 0x01, 0b1001]
    );
    // 01 03 00 08 00 04: holding 400009..400012 = MW0, MW2, MW4, MW6; the capture's
    // answer 0C 2B 00 00 00 00 00 00 is MW0 = 16#0C2B.
    set(&mut vm, "MW0", 0x0C2B);
    assert_eq!(
        serve(&mut vm, &[0x03, 0x00, 0x08, 0x00, 0x04]),
        [0x03, 0x08, 0x0C, 0x2B, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00]
    );
}

#[test]
fn writes_reach_the_documented_variables() {
    let mut vm = vm();
    // Q3.0 is coil 000025 (wire 24).
    assert_eq!(
        serve(&mut vm, &[0x05, 0x00, 0x18, 0xFF, 0x00]),
        [0x05, 0x00, 0x18, 0xFF, 0x00]
    );
    assert_eq!(get(&vm, "Q3.0"), 1);
    assert_eq!(
        serve(&mut vm, &[0x01, 0x00, 0x18, 0x00, 0x01]),
        [0x01, 0x01, 0x01]
    );
    // MW20 is 400019 (wire 18); MB31 is the high byte of 400024 (wire 23).
    assert_eq!(
        serve(&mut vm, &[0x06, 0x00, 0x12, 0x12, 0x34]),
        [0x06, 0x00, 0x12, 0x12, 0x34]
    );
    assert_eq!(get(&vm, "MW20"), 0x1234);
    serve(&mut vm, &[0x06, 0x00, 0x17, 0xAB, 0xCD]);
    assert_eq!(get(&vm, "MB31"), 0xAB);
    // 15: Q0.0..Q0.9 from 2 bytes; 16: AQW0, AQW2 (400001, 400002).
    assert_eq!(
        serve(
            &mut vm,
            &[0x0F, 0x00, 0x00, 0x00, 0x0A, 0x02, 0b1010_0101, 0b10]
        ),
        [0x0F, 0x00, 0x00, 0x00, 0x0A]
    );
    assert_eq!(get(&vm, "QB0"), 0b1010_0101);
    assert_eq!(get(&vm, "Q1.1"), 1);
    assert_eq!(
        serve(
            &mut vm,
            &[0x10, 0x00, 0x00, 0x00, 0x02, 0x04, 0x00, 0x64, 0xFF, 0xFF]
        ),
        [0x10, 0x00, 0x00, 0x00, 0x02]
    );
    assert_eq!((get(&vm, "AQW0"), get(&vm, "AQW2")), (100, 0xFFFF));
    // AI through 04: AIW0 = 300001.
    set(&mut vm, "AIW0", 1234);
    assert_eq!(
        serve(&mut vm, &[0x04, 0x00, 0x00, 0x00, 0x01]),
        [0x04, 0x02, 0x04, 0xD2]
    );
}

#[test]
fn exceptions() {
    let mut vm = vm();
    // Unknown function: 01.
    assert_eq!(serve(&mut vm, &[0x07]), [0x87, 0x01]);
    assert_eq!(serve(&mut vm, &[0x2B, 0x0E, 0x01, 0x00]), [0xAB, 0x01]);
    // Past the holding registers (J ends at 400112 = wire 111): 02.
    assert_eq!(serve(&mut vm, &[0x03, 0x00, 0x6F, 0x00, 0x01]).len(), 4);
    assert_eq!(
        serve(&mut vm, &[0x03, 0x00, 0x6F, 0x00, 0x02]),
        [0x83, 0x02]
    );
    // Q has 64 coils: wire 64 is outside.
    assert_eq!(
        serve(&mut vm, &[0x05, 0x00, 0x40, 0xFF, 0x00]),
        [0x85, 0x02]
    );
    // Bad quantities and values: 03.
    assert_eq!(
        serve(&mut vm, &[0x03, 0x00, 0x00, 0x00, 0x00]),
        [0x83, 0x03]
    );
    assert_eq!(
        serve(&mut vm, &[0x03, 0x00, 0x00, 0x00, 0x7E]),
        [0x83, 0x03]
    );
    assert_eq!(
        serve(&mut vm, &[0x01, 0x00, 0x00, 0x07, 0xD1]),
        [0x81, 0x03]
    );
    assert_eq!(
        serve(&mut vm, &[0x05, 0x00, 0x00, 0x12, 0x34]),
        [0x85, 0x03]
    );
    assert_eq!(
        serve(&mut vm, &[0x10, 0x00, 0x00, 0x00, 0x02, 0x03, 0, 0, 0]),
        [0x90, 0x03]
    );
    assert_eq!(serve(&mut vm, &[0x03, 0x00]), [0x83, 0x03], "short request");
    // A failed multiple write changes nothing: the last J register (wire 111) keeps its
    // value when the range runs past it.
    set(&mut vm, "J14", 7);
    let read_last = |vm: &mut Vm| serve(vm, &[0x03, 0x00, 0x6F, 0x00, 0x01]);
    assert_eq!(read_last(&mut vm), [0x03, 0x02, 0x00, 0x07]);
    assert_eq!(
        serve(
            &mut vm,
            &[0x10, 0x00, 0x6F, 0x00, 0x02, 0x04, 0x11, 0x11, 0x22, 0x22]
        ),
        [0x90, 0x02]
    );
    assert_eq!(read_last(&mut vm), [0x03, 0x02, 0x00, 0x07]);
    // Inputs are not writable through Modbus: there is no write function for 1x/3x.
}

#[test]
fn a_slave_at_a_station_on_an_rtu_line() {
    let mut vm = vm();
    set(&mut vm, "MW0", 0x0C2B);
    // The AN2002 capture, CRC and all: 01 03 00 08 00 04 C5 CB.
    assert_eq!(
        answer_rtu(&mut vm, 1, &[1, 3, 0, 8, 0, 4, 0xC5, 0xCB]),
        Some(vec![1, 3, 8, 0x0C, 0x2B, 0, 0, 0, 0, 0, 0, 0x0E, 0x80])
    );
    // A bad CRC, or another station: silence.
    assert_eq!(
        answer_rtu(&mut vm, 1, &[1, 3, 0, 8, 0, 4, 0xC5, 0xCC]),
        None
    );
    assert_eq!(
        answer_rtu(&mut vm, 2, &[1, 3, 0, 8, 0, 4, 0xC5, 0xCB]),
        None
    );
    assert_eq!(
        answer_rtu(&mut vm, 1, &[1, 3]),
        None,
        "shorter than a frame"
    );
    // Without CRC; an exception is an answer like any other.
    let ask = |vm: &mut Vm, station: u8, pdu: &[u8]| {
        answer_frame(
            vm,
            1,
            &RtuFrame {
                station,
                pdu: pdu.to_vec(),
            },
        )
    };
    assert_eq!(
        ask(&mut vm, 1, &[0x03, 0x00, 0x6F, 0x00, 0x02]),
        Some(RtuFrame {
            station: 1,
            pdu: vec![0x83, 0x02]
        })
    );
    // A broadcast is carried out without an answer.
    assert_eq!(ask(&mut vm, 0, &[0x06, 0x00, 0x12, 0x12, 0x34]), None);
    assert_eq!(get(&vm, "MW20"), 0x1234);
}
