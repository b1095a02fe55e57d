//! The simulator core takes its serial ports from the factory it is given: it asks for
//! each port of the target with the line in force, again at every reset, and EXCH talks
//! through what the factory made (the `gutta-sim` binary's factory opens real ports).

mod common;

use std::sync::{Arc, Mutex};

use gutta_catalog::stdlib;
use gutta_format::LineSettings;
use gutta_sim::plc::Plc;
use gutta_sim::ports::PortFactory;
use gutta_vm::exch::{PortError, SerialPort};
use gutta_vm::VmConfig;

const MASTER: &str = include_str!("../../examples/an2002_sample3_master.lad");

/// What the factory was asked for, and the requests its ports carried.
#[derive(Debug, Default)]
struct Log {
    asked: Vec<(u8, LineSettings)>,
    requests: Vec<(u8, Vec<u8>)>,
}

/// Leads port 0 to a silent device that logs each request; other ports stay unconnected.
#[derive(Debug)]
struct Factory(Arc<Mutex<Log>>);

#[derive(Debug)]
struct SilentPort(u8, Arc<Mutex<Log>>);

impl SerialPort for SilentPort {
    fn transact(&mut self, request: &[u8], _timeout_ms: u32) -> Result<Vec<u8>, PortError> {
        self.1
            .lock()
            .expect("log")
            .requests
            .push((self.0, request.to_vec()));
        Err(PortError::Timeout)
    }
}

impl PortFactory for Factory {
    fn port(&mut self, port: u8, line: LineSettings) -> Option<Box<dyn SerialPort>> {
        self.0.lock().expect("log").asked.push((port, line));
        (port == 0).then(|| Box::new(SilentPort(port, Arc::clone(&self.0))) as Box<dyn SerialPort>)
    }
}

#[test]
fn the_plc_asks_the_factory_for_each_port_at_every_reset_and_exch_uses_it() {
    let target = stdlib::shared("CPU-EC20").expect("target");
    let ports = target.memory.serial_ports;
    let image = common::image("m.lad", MASTER);
    let mut plc = Plc::new(target, image.pages, VmConfig::default()).expect("plc");
    let log = Arc::new(Mutex::new(Log::default()));
    plc.set_port_factory(Box::new(Factory(Arc::clone(&log))));
    let every_port: Vec<(u8, LineSettings)> =
        (0..ports).map(|n| (n, plc.line(usize::from(n)))).collect();
    assert_eq!(log.lock().expect("log").asked, every_port);

    plc.reset();
    let twice: Vec<_> = every_port.iter().chain(&every_port).copied().collect();
    assert_eq!(log.lock().expect("log").asked, twice);

    // AN2002's master polls on I0.1: its EXCH goes out on port 0, which never answers.
    let at = |plc: &Plc, v: &str| plc.target().memory.parse_address(v).expect("address");
    let (i01, mb20, mb21) = (at(&plc, "I0.1"), at(&plc, "MB20"), at(&plc, "MB21"));
    plc.vm_mut().write(i01, 1).expect("polling on");
    let mut error = None;
    for _ in 0..100 {
        plc.scan().expect("scan");
        if plc.vm().read(mb20).expect("read") & 0b110 != 0 {
            error = Some(plc.vm().read(mb21).expect("read"));
            break;
        }
    }
    assert_eq!(
        error,
        Some(2),
        "a silent port ends EXCH with error 2 (timeout)"
    );
    let log = log.lock().expect("log");
    assert!(
        !log.requests.is_empty(),
        "EXCH never used the factory's port"
    );
    assert!(log.requests.iter().all(|(port, _)| *port == 0));
}
