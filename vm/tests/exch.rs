//! EXCH, the PLC as Modbus RTU master (AN2002): sample 3 end to end with an in-process
//! slave VM served by the simulator's Modbus data service (the toolchain's one Modbus
//! slave), and the table's error numbers, the queue limit and power flow.

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

mod common;

use common::{read, set};
use gutta_protocol::rtu::{decode_rtu, encode_rtu};
use gutta_sim::modbus_data;
use gutta_vm::exch::{PortError, SerialPort};
use gutta_vm::{Vm, VmConfig};

/// A slave VM on the RTU line: the simulator's Modbus data service answers from its
/// memory. A request with a bad CRC or for another station gets no answer; a
/// broadcast (station 0) is carried out without an answer.
#[derive(Debug, Clone)]
struct VmSlave {
    vm: Arc<Mutex<Vm>>,
    station: u8,
}

impl VmSlave {
    fn new(vm: Arc<Mutex<Vm>>, station: u8) -> VmSlave {
        VmSlave { vm, station }
    }

    /// The answer (station and PDU, no CRC) to a request without CRC.
    fn answer(&self, request: &[u8]) -> Option<Vec<u8>> {
        let (&station, pdu) = request.split_first()?;
        if station != 0 && station != self.station {
            return None;
        }
        let answer = modbus_data::serve(&mut self.vm.lock().expect("slave VM"), pdu);
        (station != 0).then(|| [&[station][..], &answer].concat())
    }
}

impl SerialPort for VmSlave {
    fn transact(&mut self, request: &[u8], _timeout_ms: u32) -> Result<Vec<u8>, PortError> {
        let frame = decode_rtu(request).map_err(|_| PortError::Timeout)?;
        let request = [&[frame.station][..], &frame.pdu].concat();
        let answer = self.answer(&request).ok_or(PortError::Timeout)?;
        Ok(encode_rtu(answer[0], &answer[1..]))
    }
}

fn vm_for(text: &str) -> Vm {
    common::load(text, VmConfig::default())
}

fn example(name: &str) -> Vm {
    let path = format!("{}/../examples/{name}", env!("CARGO_MANIFEST_DIR"));
    vm_for(&std::fs::read_to_string(path).expect("example"))
}

fn main_block(code: &str) -> String {
    format!("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n{code}\nEND_ORGANIZATION_BLOCK\n")
}

/// Table at MB`t`: send `req` from MB`send`, receive up to `recv_len` bytes at MB`recv`.
fn table(vm: &mut Vm, t: u32, send: u32, req: &[u8], recv: u32, recv_len: u32) {
    set(vm, &format!("MW{}", t + 2), req.len() as u32);
    set(vm, &format!("MW{}", t + 4), send);
    set(vm, &format!("MW{}", t + 6), recv_len);
    set(vm, &format!("MW{}", t + 8), recv);
    for (i, b) in req.iter().enumerate() {
        set(vm, &format!("MB{}", send + i as u32), u32::from(*b));
    }
}

/// (A, D, E, error number) of the table at MB`t`.
fn status(vm: &Vm, t: u32) -> (u32, u32, u32, u32) {
    (
        read(vm, &format!("M{t}.0")),
        read(vm, &format!("M{t}.1")),
        read(vm, &format!("M{t}.2")),
        read(vm, &format!("MB{}", t + 1)),
    )
}

fn slave_vm() -> Arc<Mutex<Vm>> {
    Arc::new(Mutex::new(example("an2002_sample3_slave.lad")))
}

#[test]
fn an2002_sample3_end_to_end() {
    let slave = slave_vm();
    let mut master = example("an2002_sample3_master.lad");
    master.attach_port(0, Box::new(VmSlave::new(Arc::clone(&slave), 1)));
    {
        let mut s = slave.lock().unwrap();
        set(&mut s, "I0.4", 1);
        set(&mut s, "I0.5", 0);
        set(&mut s, "I0.6", 1);
        set(&mut s, "I0.7", 1);
        set(&mut s, "AIW0", 3115);
    }
    set(&mut master, "I0.1", 1);
    let mut requests_seen = 0;
    for _ in 0..30 {
        slave.lock().unwrap().scan().expect("slave scan");
        master.scan().expect("master scan");
        if read(&master, "M20.1") == 1 {
            requests_seen += 1;
        }
    }
    assert!(requests_seen > 0, "the 200 ms pulse queued the exchanges");
    assert_eq!(status(&master, 20), (0, 1, 0, 0));
    assert_eq!(status(&master, 50), (0, 1, 0, 0));
    // The answers as stored (without CRC).
    assert_eq!(read(&master, "MB40"), 1);
    assert_eq!(read(&master, "MB41"), 2);
    assert_eq!(read(&master, "MB42"), 1);
    assert_eq!(read(&master, "MB43"), 0b1101);
    assert_eq!(read(&master, "MB72"), 8);
    assert_eq!(read(&master, "MB73"), 0x0C);
    assert_eq!(read(&master, "MB74"), 0x2B);
    // Q0.0..Q0.3 mirror the slave's I0.4..I0.7.
    let q: Vec<u32> = (0..4).map(|b| read(&master, &format!("Q0.{b}"))).collect();
    assert_eq!(q, [1, 0, 1, 1]);
    // LED gets the slave's MW0 (= AIW0), after SWAP; it lands in MW112.
    assert_eq!(read(&slave.lock().unwrap(), "MW0"), 3115);
    assert_eq!(read(&master, "MW110"), 3115);
    assert_eq!(read(&master, "MW112"), 3115);

    // The slave's inputs change; the next polls follow.
    {
        let mut s = slave.lock().unwrap();
        set(&mut s, "I0.4", 0);
        set(&mut s, "I0.5", 1);
        set(&mut s, "AIW0", 0x1234);
    }
    for _ in 0..30 {
        slave.lock().unwrap().scan().expect("slave scan");
        master.scan().expect("master scan");
    }
    let q: Vec<u32> = (0..4).map(|b| read(&master, &format!("Q0.{b}"))).collect();
    assert_eq!(q, [0, 1, 1, 1]);
    assert_eq!(read(&master, "MW112"), 0x1234);
}

#[test]
fn the_documents_capture() {
    // GUTTA.md section 5: 01 03 00 08 00 04 C5 CB and its answer.
    let slave = slave_vm();
    set(&mut slave.lock().unwrap(), "AIW0", 0x0C2B);
    slave.lock().unwrap().scan().unwrap();
    let mut port = VmSlave::new(slave, 1);
    let answer = port
        .transact(&[1, 3, 0, 8, 0, 4, 0xC5, 0xCB], 1000)
        .expect("answer");
    assert_eq!(answer, [1, 3, 8, 0x0C, 0x2B, 0, 0, 0, 0, 0, 0, 0x0E, 0x80]);
    let answer = port
        .transact(&[1, 2, 0, 4, 0, 4, 0x38, 0x08], 1000)
        .unwrap();
    assert_eq!(answer, [1, 2, 1, 0, 0xA1, 0x88]);
    // Another station, or a bad CRC: no answer.
    assert_eq!(
        port.transact(&[2, 3, 0, 8, 0, 4, 0xC5, 0xCB], 1000),
        Err(PortError::Timeout)
    );
    assert_eq!(
        port.transact(&[1, 3, 0, 8, 0, 4, 0xC5, 0xCC], 1000),
        Err(PortError::Timeout)
    );
}

const HELD: &str = "NETWORK 1\nLD I0.0\nEXCH MB20, 0";
const READ_MW0: [u8; 6] = [1, 3, 0, 8, 0, 4];

#[test]
fn timeout_without_a_device() {
    let mut vm = vm_for(&main_block(HELD));
    table(&mut vm, 20, 30, &READ_MW0, 40, 40);
    set(&mut vm, "I0.0", 1);
    vm.scan().unwrap();
    assert_eq!(status(&vm, 20), (0, 1, 1, 2));
}

#[derive(Debug)]
struct FlipByte(VmSlave);

impl SerialPort for FlipByte {
    fn transact(&mut self, request: &[u8], timeout_ms: u32) -> Result<Vec<u8>, PortError> {
        let mut a = self.0.transact(request, timeout_ms)?;
        a[3] ^= 0x40;
        Ok(a)
    }
}

#[test]
fn crc_error_in_the_answer() {
    let mut vm = vm_for(&main_block(HELD));
    vm.attach_port(0, Box::new(FlipByte(VmSlave::new(slave_vm(), 1))));
    table(&mut vm, 20, 30, &READ_MW0, 40, 40);
    set(&mut vm, "I0.0", 1);
    vm.scan().unwrap();
    assert_eq!(status(&vm, 20), (0, 1, 1, 3));
    assert_eq!(read(&vm, "MB40"), 0, "nothing stored");
}

#[test]
fn receive_buffer_too_short() {
    let mut vm = vm_for(&main_block(HELD));
    vm.attach_port(0, Box::new(VmSlave::new(slave_vm(), 1)));
    // The answer without CRC is 11 bytes.
    table(&mut vm, 20, 30, &READ_MW0, 40, 10);
    set(&mut vm, "I0.0", 1);
    vm.scan().unwrap();
    assert_eq!(status(&vm, 20), (0, 1, 1, 4));
    set(&mut vm, "MW26", 11);
    vm.scan().unwrap();
    assert_eq!(status(&vm, 20), (0, 1, 0, 0));
    assert_eq!(read(&vm, "MB42"), 8);
}

#[test]
fn bad_table() {
    let mut vm = vm_for(&main_block(HELD));
    vm.attach_port(0, Box::new(VmSlave::new(slave_vm(), 1)));
    set(&mut vm, "I0.0", 1);
    table(&mut vm, 20, 30, &[], 40, 10); // send length 0
    vm.scan().unwrap();
    assert_eq!(status(&vm, 20), (0, 1, 1, 1));
    table(&mut vm, 20, 30, &READ_MW0, 60000, 10); // receive buffer outside M
    vm.scan().unwrap();
    assert_eq!(status(&vm, 20), (0, 1, 1, 1));
}

#[test]
fn an_exception_is_a_normal_answer() {
    let mut vm = vm_for(&main_block(HELD));
    vm.attach_port(0, Box::new(VmSlave::new(slave_vm(), 1)));
    table(&mut vm, 20, 30, &[1, 3, 0xFF, 0xF0, 0, 4], 40, 10);
    set(&mut vm, "I0.0", 1);
    vm.scan().unwrap();
    assert_eq!(status(&vm, 20), (0, 1, 0, 0));
    assert_eq!(
        [read(&vm, "MB40"), read(&vm, "MB41"), read(&vm, "MB42")],
        [1, 0x83, 2]
    );
}

/// Counts requests and answers a fixed frame.
#[derive(Debug, Clone)]
struct Counter(Arc<AtomicUsize>);

impl SerialPort for Counter {
    fn transact(&mut self, request: &[u8], _timeout_ms: u32) -> Result<Vec<u8>, PortError> {
        self.0.fetch_add(1, Ordering::SeqCst);
        if request[0] == 0 {
            return Err(PortError::Timeout);
        }
        let mut a = vec![request[0], request[1], 1, 0x5A];
        let crc = gutta_format::crc16(&a);
        a.extend(crc.to_le_bytes());
        Ok(a)
    }
}

#[test]
fn queue_limit_of_eight() {
    let tables: Vec<u32> = (0..9).map(|k| 10 * k).collect();
    let code: String = tables.iter().map(|t| format!("EXCH MB{t}, 0\n")).collect();
    let mut vm = vm_for(&main_block(&format!("NETWORK 1\nLD I0.0\n{code}")));
    let n = Arc::new(AtomicUsize::new(0));
    vm.attach_port(0, Box::new(Counter(Arc::clone(&n))));
    for t in &tables {
        table(&mut vm, *t, 90, &READ_MW0, 100, 10);
    }
    set(&mut vm, "I0.0", 1);
    vm.scan().unwrap();
    assert_eq!(n.load(Ordering::SeqCst), 8);
    for t in &tables[..8] {
        assert_eq!(status(&vm, *t), (0, 1, 0, 0), "table MB{t}");
    }
    assert_eq!(status(&vm, 80), (0, 0, 0, 0), "the ninth does nothing");
    assert_eq!(read(&vm, "MB103"), 0x5A);
}

#[test]
fn pulse_held_enable_broadcast_and_no_power_flow() {
    let mut vm = vm_for(&main_block(
        "NETWORK 1\nLD I0.0\nEU\nEXCH MB20, 0\nNETWORK 2\nLD I0.1\nEXCH MB50, 0",
    ));
    let n = Arc::new(AtomicUsize::new(0));
    vm.attach_port(0, Box::new(Counter(Arc::clone(&n))));
    table(&mut vm, 20, 30, &READ_MW0, 40, 10);
    table(&mut vm, 50, 60, &[0, 6, 0, 8, 0, 1], 70, 10);
    // No power flow: nothing happens.
    vm.scan().unwrap();
    assert_eq!(n.load(Ordering::SeqCst), 0);
    assert_eq!(status(&vm, 20), (0, 0, 0, 0));
    // A pulse: one exchange, although I0.0 stays on.
    set(&mut vm, "I0.0", 1);
    for _ in 0..5 {
        vm.scan().unwrap();
    }
    assert_eq!(n.load(Ordering::SeqCst), 1);
    assert_eq!(status(&vm, 20), (0, 1, 0, 0));
    // A held enable: one exchange per scan; a broadcast is done without an answer.
    set(&mut vm, "I0.1", 1);
    for _ in 0..5 {
        vm.scan().unwrap();
    }
    assert_eq!(n.load(Ordering::SeqCst), 6);
    assert_eq!(status(&vm, 50), (0, 1, 0, 0));
    assert_eq!(read(&vm, "MB70"), 0, "a broadcast stores no answer");
}

#[test]
fn slave_writes_and_exceptions() {
    let slave = slave_vm();
    let mut port = VmSlave::new(Arc::clone(&slave), 1);
    let ask = |port: &mut VmSlave, pdu: &[u8]| port.answer(pdu).expect("answer");
    // 06 write MW2 (wire 9), 03 read it back.
    assert_eq!(
        ask(&mut port, &[1, 6, 0, 9, 0x12, 0x34]),
        [1, 6, 0, 9, 0x12, 0x34]
    );
    assert_eq!(read(&slave.lock().unwrap(), "MW2"), 0x1234);
    // 16 write MW4, MW6.
    assert_eq!(
        ask(&mut port, &[1, 16, 0, 10, 0, 2, 4, 0, 1, 0, 2]),
        [1, 16, 0, 10, 0, 2]
    );
    assert_eq!(read(&slave.lock().unwrap(), "MW6"), 2);
    // 05 and 15 on coils (Q).
    assert_eq!(
        ask(&mut port, &[1, 5, 0, 1, 0xFF, 0]),
        [1, 5, 0, 1, 0xFF, 0]
    );
    assert_eq!(read(&slave.lock().unwrap(), "Q0.1"), 1);
    assert_eq!(
        ask(&mut port, &[1, 15, 0, 8, 0, 3, 1, 0b101]),
        [1, 15, 0, 8, 0, 3]
    );
    assert_eq!(read(&slave.lock().unwrap(), "QB1"), 0b101);
    assert_eq!(ask(&mut port, &[1, 1, 0, 8, 0, 3]), [1, 1, 1, 0b101]);
    // Exceptions: unknown function, past an area, bad coil value.
    assert_eq!(ask(&mut port, &[1, 0x2B, 0, 0, 0, 1]), [1, 0xAB, 1]);
    assert_eq!(ask(&mut port, &[1, 3, 0xFF, 0xF0, 0, 4]), [1, 0x83, 2]);
    assert_eq!(ask(&mut port, &[1, 5, 0, 1, 0x12, 0]), [1, 0x85, 3]);
    // A broadcast is carried out without an answer.
    assert_eq!(port.answer(&[0, 6, 0, 9, 0, 7]), None);
    assert_eq!(read(&slave.lock().unwrap(), "MW2"), 7);
}
