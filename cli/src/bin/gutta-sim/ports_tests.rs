//! The PLC's serial ports for EXCH, through the shared master: a device that answers
//! with a bad CRC makes EXCH end with error 3, one that never answers with error 2.
//! (The unit tests of `ports.rs`: the simulator core takes these ports from the factory.)

use std::io::{Read, Write};
use std::net::TcpListener;

use gutta_catalog::stdlib;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};
use gutta_sim::plc::Plc;
use gutta_vm::VmConfig;

use crate::ports::{PortSpec, PortWiring};

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
    let target = stdlib::shared("CPU-EC20").expect("target");
    let image = image("m.lad", MASTER);
    let mut plc = Plc::new(target, image.pages, VmConfig::default()).expect("plc");
    let mut wiring = PortWiring::default();
    wiring.lead(0, PortSpec::TcpConnect(address));
    plc.set_port_factory(Box::new(wiring));
    let at = |plc: &Plc, v: &str| plc.target().memory.parse_address(v).expect("address");
    let i01 = at(&plc, "I0.1");
    plc.vm_mut().write(i01, 1).expect("polling on");
    let (mb20, mb21) = (at(&plc, "MB20"), at(&plc, "MB21"));
    for _ in 0..100 {
        plc.scan().expect("scan");
        if plc.vm().read(mb20).expect("read") & 0b110 != 0 {
            return plc.vm().read(mb21).expect("read");
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
