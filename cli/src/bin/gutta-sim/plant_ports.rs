//! A plant's in-process line (`port0 = "device:NAME"`): a PLC's serial port wired to
//! another device of the same process, no socket between them. The request frame goes
//! where a line would take it: into the other PLC's RTU session (a `Session` with
//! `Framing::Rtu` and a connection identity of its own, what a `--rtu-tcp` connection
//! gets), or through the Modbus RTU <-> TCP gateway conversion into a relay board's
//! session (what `modbus-tcp:` does over a socket). The answer comes back through
//! gutta-protocol's `Master`, as on a line, so CRC checks, exceptions and timeouts are
//! the same. Every wait is bounded by the port's timeout: a PLC busy scanning (its
//! scan may itself be waiting on this PLC's lock) is silence, EXCH error 2, never a
//! deadlock. No protocol logic of its own.

use std::sync::{Arc, Mutex, TryLockError};
use std::time::{Duration, Instant};

use gutta_protocol::gateway::{answer_to_rtu, Gateway};
use gutta_protocol::master::{Master, MasterConfig};
use gutta_protocol::rtu::decode_rtu;
use gutta_protocol::stream::TcpSplitter;
use gutta_protocol::tcp::MAX_STANDARD_MBAP_LENGTH;
use gutta_sim::plc::Plc;
use gutta_sim::relay::RelaySession;
use gutta_sim::session::{Framing, Session};
use gutta_vm::exch::{PortError, SerialPort};

use crate::ports::exch_result;
use crate::relay::Board;

/// How long a port waits before it tries a busy PLC's lock again.
const RETRY: Duration = Duration::from_millis(1);

/// The device at the other end of an in-process line.
#[derive(Debug, Clone)]
pub enum InProcessLine {
    /// A PLC of the plant, answering on its RTU slave; `start` is the plant's clock
    /// (the time its sessions see, as its network connections do).
    Plc {
        plc: Arc<Mutex<Plc>>,
        start: Instant,
    },
    /// A relay board of the plant, behind a Modbus RTU <-> TCP gateway.
    Board(Board),
}

impl InProcessLine {
    /// A port on this line, with a session of its own at the far end.
    pub fn port(&self) -> DevicePort {
        let far = match self {
            InProcessLine::Plc { plc, start } => FarEnd::Plc {
                plc: Arc::clone(plc),
                start: *start,
                session: Session::new(Framing::Rtu, crate::next_connection()),
            },
            InProcessLine::Board(board) => FarEnd::Board {
                board: board.clone(),
                gateway: Gateway::new(),
                session: RelaySession::new(),
                splitter: TcpSplitter::new(MAX_STANDARD_MBAP_LENGTH),
            },
        };
        DevicePort { far }
    }
}

/// A PLC's serial port on an in-process line.
#[derive(Debug)]
pub struct DevicePort {
    far: FarEnd,
}

#[derive(Debug)]
enum FarEnd {
    Plc {
        plc: Arc<Mutex<Plc>>,
        start: Instant,
        session: Session,
    },
    Board {
        board: Board,
        gateway: Gateway,
        session: RelaySession,
        splitter: TcpSplitter,
    },
}

impl FarEnd {
    /// The bytes the far end sends back for `frame` (none: silence), or `None` when
    /// `deadline` passed first.
    fn answer(&mut self, frame: &[u8], deadline: Instant) -> Option<Vec<u8>> {
        match self {
            FarEnd::Plc {
                plc,
                start,
                session,
            } => loop {
                match plc.try_lock() {
                    Ok(mut plc) => {
                        let now_ms = start.elapsed().as_millis() as u64;
                        return Some(
                            session
                                .on_bytes(&mut plc, frame, now_ms)
                                .unwrap_or_default(),
                        );
                    }
                    Err(TryLockError::WouldBlock) if Instant::now() < deadline => {
                        std::thread::sleep(RETRY);
                    }
                    Err(_) => return None,
                }
            },
            FarEnd::Board {
                board,
                gateway,
                session,
                splitter,
            } => {
                // What the gateway drops (a bad CRC, a reserved station) is silence.
                let forwarded = gateway.forward(frame).ok()?;
                let Ok(tcp) = board.on_bytes(session, &forwarded.tcp) else {
                    *session = RelaySession::new();
                    return Some(Vec::new());
                };
                if !forwarded.answered {
                    return Some(Vec::new());
                }
                splitter.clear();
                splitter.push(&tcp);
                while let Some(answer) = splitter.next_frame() {
                    if let Ok(Ok(rtu)) = answer.map(|a| answer_to_rtu(&forwarded, &a)) {
                        return Some(rtu);
                    }
                }
                Some(Vec::new())
            }
        }
    }
}

impl SerialPort for DevicePort {
    fn transact(&mut self, request: &[u8], timeout_ms: u32) -> Result<Vec<u8>, PortError> {
        let begun = Instant::now();
        let deadline = begun + Duration::from_millis(u64::from(timeout_ms.max(1)));
        let now = || begun.elapsed().as_millis() as u64;
        let silence = || {
            // A silent line: EXCH hears nothing until its timeout.
            std::thread::sleep(deadline.saturating_duration_since(Instant::now()));
            Err(PortError::Timeout)
        };
        let Ok(frame) = decode_rtu(request) else {
            return silence();
        };
        let mut master = Master::new(MasterConfig {
            timeout_ms: u64::from(timeout_ms),
            retries: 0,
            ..MasterConfig::default()
        });
        let Ok(bytes) = master.send(frame.station, &frame.pdu, now()) else {
            return silence();
        };
        let broadcast = frame.station == 0 && frame.pdu.first() != Some(&0x0D);
        let Some(answer) = self.far.answer(&bytes, deadline) else {
            return Err(PortError::Timeout);
        };
        if broadcast {
            return Ok(Vec::new());
        }
        if answer.is_empty() {
            return silence();
        }
        // Anything but an answer frame or a bad CRC is what a line's silence gives.
        match exch_result(master.on_bytes(&answer, now())) {
            Some(Err(PortError::Timeout)) | None => silence(),
            Some(result) => result,
        }
    }
}

impl Drop for DevicePort {
    /// The far PLC forgets this line's connection (a download window it opened ends),
    /// if it can be had now; a busy PLC keeps it, as it keeps a line that went quiet.
    fn drop(&mut self) {
        if let FarEnd::Plc { plc, session, .. } = &self.far {
            if let Ok(mut plc) = plc.try_lock() {
                plc.disconnect(session.connection());
            }
        }
    }
}

#[cfg(test)]
mod tests {
    //! The in-process line against what a line gives: the far PLC's answer is the one
    //! its RTU session gives any connection, an exception comes back as the frame
    //! received, a station that is not there and a PLC held by someone else are
    //! silence bounded by the timeout, and a relay board answers through the gateway
    //! conversion.

    use super::*;
    use gutta_catalog::stdlib;
    use gutta_protocol::modbus::EXCEPTION_BIT;
    use gutta_protocol::rtu::encode_rtu;
    use gutta_vm::VmConfig;

    fn plc() -> Arc<Mutex<Plc>> {
        let target = stdlib::shared("CPU-EC20").expect("target");
        let plc = Plc::new(target, Default::default(), VmConfig::default()).expect("an empty PLC");
        Arc::new(Mutex::new(plc))
    }

    fn line(plc: &Arc<Mutex<Plc>>) -> DevicePort {
        InProcessLine::Plc {
            plc: Arc::clone(plc),
            start: Instant::now(),
        }
        .port()
    }

    #[test]
    fn the_far_plc_answers_as_its_rtu_session_answers_any_connection() {
        let far = plc();
        let request = encode_rtu(1, &[0x03, 0x00, 0x08, 0x00, 0x02]);
        let answer = line(&far).transact(&request, 500).expect("an answer");
        let mut session = Session::new(Framing::Rtu, crate::next_connection());
        let direct = session
            .on_bytes(&mut far.lock().expect("plc"), &request, 0)
            .expect("answers");
        assert_eq!(answer, direct);
        assert_eq!(answer, encode_rtu(1, &[0x03, 4, 0, 0, 0, 0]));
        // An exception is the frame as received.
        let refused = line(&far)
            .transact(&encode_rtu(1, &[0x03, 0xFF, 0xF0, 0x00, 0x01]), 500)
            .expect("an exception frame");
        assert_eq!(refused, encode_rtu(1, &[0x03 | EXCEPTION_BIT, 0x02]));
    }

    #[test]
    fn silence_and_a_busy_plc_end_at_the_timeout() {
        let far = plc();
        let begun = Instant::now();
        let other_station = encode_rtu(7, &[0x03, 0x00, 0x08, 0x00, 0x01]);
        assert_eq!(
            line(&far).transact(&other_station, 100),
            Err(PortError::Timeout)
        );
        assert!(begun.elapsed() >= Duration::from_millis(100));
        let held = far.lock().expect("plc");
        let begun = Instant::now();
        let ours = encode_rtu(1, &[0x03, 0x00, 0x08, 0x00, 0x01]);
        assert_eq!(line(&far).transact(&ours, 100), Err(PortError::Timeout));
        let waited = begun.elapsed();
        assert!(
            waited >= Duration::from_millis(100) && waited < Duration::from_secs(2),
            "{waited:?}"
        );
        drop(held);
        assert!(line(&far).transact(&ours, 100).is_ok());
    }

    #[test]
    fn a_relay_board_answers_through_the_gateway_conversion() {
        let mut port = InProcessLine::Board(Board::new()).port();
        let switch_on = encode_rtu(1, &[0x05, 0x02, 0x00, 0xFF, 0x00]);
        assert_eq!(port.transact(&switch_on, 500), Ok(switch_on.clone()));
        let read = encode_rtu(1, &[0x01, 0x02, 0x00, 0x00, 0x04]);
        assert_eq!(
            port.transact(&read, 500),
            Ok(encode_rtu(1, &[0x01, 0x01, 0b0001]))
        );
    }
}
