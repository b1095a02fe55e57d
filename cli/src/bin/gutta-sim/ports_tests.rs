//! The PLC's serial ports for EXCH, through the shared master: a device that answers
//! with a bad CRC makes EXCH end with error 3, one that never answers with error 2.
//! Through `modbus-tcp:` the same EXCH reaches a Modbus TCP device: its answer comes
//! back as an RTU frame, and a refused connection or a device that never answers is
//! error 2. (The unit tests of `ports.rs`: the simulator core takes these ports from the
//! factory.)

use std::io::{Read, Write};
use std::net::TcpListener;

use gutta_catalog::stdlib;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};
use gutta_sim::plc::Plc;
use gutta_vm::VmConfig;

use gutta_protocol::rtu::encode_rtu;
use gutta_protocol::tcp::decode_tcp;
use gutta_vm::exch::{PortError, SerialPort};

use crate::ports::{GatewayPort, PortSpec, PortWiring};

const MASTER: &str = include_str!("../../../../examples/an2002_sample3_master.lad");

/// `text` compiled for CPU-EC20 (it must compile).
fn image(name: &str, text: &str) -> gutta_format::Image {
    let target = stdlib::shared("CPU-EC20").expect("target");
    let c = compile(
        SourceFile::new(name, text),
        Some(&ExplicitTarget {
            target,
            origin: "test".into(),
        }),
    );
    c.image
        .unwrap_or_else(|| panic!("{name} does not compile: {:?}", c.checked.diagnostics()))
}

/// A device on TCP: answers every request with `answer(request)` (None: silence).
fn device(answer: fn(&[u8]) -> Option<Vec<u8>>) -> String {
    let listener = TcpListener::bind("127.0.0.1:0").expect("binds");
    let address = listener.local_addr().expect("address").to_string();
    std::thread::spawn(move || {
        for stream in listener.incoming() {
            let Ok(mut s) = stream else { continue };
            let mut buf = [0u8; 256];
            while let Ok(n) = s.read(&mut buf) {
                if n == 0 {
                    break;
                }
                if let Some(a) = answer(&buf[..n]) {
                    let _ = s.write_all(&a);
                }
            }
        }
    });
    address
}

/// The AN2002 master with its port 0 leading to `address`, polling on; the error number
/// in table 1 (MB21) once an exchange has ended.
fn error_after_poll(address: String) -> u32 {
    error_and_data_after_poll(PortSpec::TcpConnect(address)).0
}

/// The AN2002 master with its port 0 leading to `spec`, polling on; table 1's error
/// number (MB21) and the data byte of its answer (MB43) once an exchange has ended.
fn error_and_data_after_poll(spec: PortSpec) -> (u32, u32) {
    let target = stdlib::shared("CPU-EC20").expect("target");
    let image = image("m.lad", MASTER);
    let mut plc = Plc::new(target, image.pages, VmConfig::default()).expect("plc");
    let mut wiring = PortWiring::default();
    wiring.lead(0, spec);
    plc.set_port_factory(Box::new(wiring));
    let at = |plc: &Plc, v: &str| plc.target().memory.parse_address(v).expect("address");
    let i01 = at(&plc, "I0.1");
    plc.vm_mut().write(i01, 1).expect("polling on");
    let (mb20, mb21, mb43) = (at(&plc, "MB20"), at(&plc, "MB21"), at(&plc, "MB43"));
    for _ in 0..100 {
        plc.scan().expect("scan");
        if plc.vm().read(mb20).expect("read") & 0b110 != 0 {
            let read = |a| plc.vm().read(a).expect("read");
            return (read(mb21), read(mb43));
        }
    }
    panic!("no exchange ended in 100 scans");
}

#[test]
fn a_bad_crc_is_error_3_and_silence_is_error_2() {
    let bad_crc = device(|req| {
        // 01 02 01 00 with a wrong CRC.
        let _ = req;
        Some(vec![0x01, 0x02, 0x01, 0x00, 0x00, 0x00])
    });
    assert_eq!(error_after_poll(bad_crc), 3);
    let silent = device(|_| None);
    assert_eq!(error_after_poll(silent), 2);
}

/// A Modbus TCP device: answers function 02 with the data byte 0b1010 under the request's
/// transaction and unit, after first sending an answer of another transaction; function
/// 05 is echoed. Records what it received.
fn modbus_tcp_device() -> (String, std::sync::mpsc::Receiver<Vec<u8>>) {
    let (seen, received) = std::sync::mpsc::channel();
    let listener = TcpListener::bind("127.0.0.1:0").expect("binds");
    let address = listener.local_addr().expect("address").to_string();
    std::thread::spawn(move || {
        for stream in listener.incoming() {
            let Ok(mut s) = stream else { continue };
            let mut buf = [0u8; 256];
            while let Ok(n) = s.read(&mut buf) {
                if n == 0 {
                    break;
                }
                let _ = seen.send(buf[..n].to_vec());
                let Ok(request) = decode_tcp(&buf[..n]) else {
                    continue;
                };
                let (t, u) = (request.transaction, request.unit);
                let answer = match request.pdu[0] {
                    0x02 => {
                        let stale = gutta_protocol::encode_tcp(t.wrapping_sub(1), u, &[2, 1, 0xFF]);
                        let _ = s.write_all(&stale.expect("fits"));
                        gutta_protocol::encode_tcp(t, u, &[2, 1, 0b1010])
                    }
                    _ => gutta_protocol::encode_tcp(t, u, &request.pdu),
                };
                let _ = s.write_all(&answer.expect("fits"));
            }
        }
    });
    (address, received)
}

#[test]
fn exch_through_the_gateway_reads_a_modbus_tcp_device() {
    let (address, _) = modbus_tcp_device();
    assert_eq!(
        error_and_data_after_poll(PortSpec::ModbusTcp(address)),
        (0, 0b1010),
        "no error; the device's data byte in MB43, the stale answer skipped"
    );
}

#[test]
fn the_gateway_converts_both_ways_and_counts_transactions() {
    let (address, received) = modbus_tcp_device();
    let mut port = GatewayPort::new(address);
    let request = encode_rtu(1, &[0x05, 0x02, 0x00, 0xFF, 0x00]);
    assert_eq!(port.transact(&request, 1000), Ok(request.clone()));
    assert_eq!(
        received.recv().expect("sent"),
        [0, 1, 0, 0, 0, 6, 1, 0x05, 0x02, 0x00, 0xFF, 0x00]
    );
    let request = encode_rtu(7, &[0x05, 0x02, 0x01, 0x00, 0x00]);
    assert_eq!(port.transact(&request, 1000), Ok(request));
    assert_eq!(
        received.recv().expect("sent"),
        [0, 2, 0, 0, 0, 6, 7, 0x05, 0x02, 0x01, 0x00, 0x00]
    );
}

#[test]
fn a_bad_crc_from_the_plc_is_dropped_and_silence_follows() {
    let (address, received) = modbus_tcp_device();
    let mut port = GatewayPort::new(address);
    let mut request = encode_rtu(1, &[0x05, 0x02, 0x00, 0xFF, 0x00]);
    request[7] ^= 0xFF;
    assert_eq!(port.transact(&request, 200), Err(PortError::Timeout));
    let good = encode_rtu(1, &[0x05, 0x02, 0x00, 0x00, 0x00]);
    assert_eq!(port.transact(&good, 1000), Ok(good));
    assert_eq!(
        received.recv().expect("sent")[..2],
        [0, 1],
        "the dropped frame never reached the device"
    );
}

#[test]
fn a_refused_connection_or_a_silent_device_is_error_2() {
    let free = TcpListener::bind("127.0.0.1:0").expect("binds");
    let refused = free.local_addr().expect("address").to_string();
    drop(free);
    assert_eq!(error_and_data_after_poll(PortSpec::ModbusTcp(refused)).0, 2);
    let silent = device(|_| None);
    let started = std::time::Instant::now();
    assert_eq!(error_and_data_after_poll(PortSpec::ModbusTcp(silent)).0, 2);
    assert!(
        started.elapsed() < std::time::Duration::from_secs(5),
        "the port's timeout bounds the wait"
    );
}

#[test]
fn port_specs_parse() {
    assert_eq!(
        PortSpec::parse("modbus-tcp:127.0.0.1:502"),
        Ok(PortSpec::ModbusTcp("127.0.0.1:502".into()))
    );
    assert!(PortSpec::parse("modbus:127.0.0.1:502")
        .expect_err("unknown kind")
        .contains("modbus-tcp:HOST:PORT"));
}
