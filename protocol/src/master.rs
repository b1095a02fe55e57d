//! The one sans-I/O Modbus RTU master (request, timeout, retry), shared by the download
//! client and the VM's EXCH. It never reads a clock: the caller passes the time in
//! milliseconds (any epoch, never decreasing) to `send`, `on_bytes` and `on_tick`, and
//! writes the bytes it returns. One request at a time.

use std::fmt;

use crate::gutta::{GuttaFrame, FAILURE_BIT, MODBUS_FUNCTION_GUTTA};
use crate::modbus::EXCEPTION_BIT;
use crate::rtu::{decode_rtu, encode_rtu, FrameError, RtuFrame};
use crate::stream::{RtuSplitter, Side, DEFAULT_MAX_RTU_FRAME};

/// Timing and size limits of a master.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MasterConfig {
    /// Time to wait for an answer after sending, per attempt.
    pub timeout_ms: u64,
    /// Extra attempts after the first (0 = send once).
    pub retries: u32,
    /// Largest answer frame accepted (see `RtuSplitter::with_max_frame`).
    pub max_frame: usize,
}

impl Default for MasterConfig {
    /// AN2002's default response timeout (10 x 100 ms) and 2 retries.
    fn default() -> Self {
        MasterConfig {
            timeout_ms: 1000,
            retries: 2,
            max_frame: DEFAULT_MAX_RTU_FRAME,
        }
    }
}

/// Why a request failed, or why `send` refused it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum MasterError {
    /// `send` while a request is outstanding.
    Busy,
    /// `send` with an empty PDU, or a function 13 PDU that is not valid GUTTA data.
    BadRequest { detail: String },
    /// No matching answer within the timeout, on every attempt (EXCH error 2).
    Timeout { attempts: u32 },
    /// The last attempt's answer arrived with a bad CRC and no good one followed
    /// (EXCH error 3).
    Crc { attempts: u32 },
}

impl fmt::Display for MasterError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MasterError::Busy => write!(f, "a request is already outstanding"),
            MasterError::BadRequest { detail } => write!(f, "bad request: {detail}"),
            MasterError::Timeout { attempts } => {
                write!(f, "no answer after {attempts} attempt(s)")
            }
            MasterError::Crc { attempts } => {
                write!(f, "answer with a CRC error after {attempts} attempt(s)")
            }
        }
    }
}

impl std::error::Error for MasterError {}

/// What happened on `on_bytes` / `on_tick`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum MasterEvent {
    /// Still waiting for the answer.
    Pending,
    /// No request outstanding; bytes were discarded.
    Idle,
    /// The matching answer (may be a Modbus exception or a GUTTA failure: the caller
    /// interprets the PDU). The master is idle again.
    Response(RtuFrame),
    /// The timeout passed: write these bytes (the same request) again.
    Retry(Vec<u8>),
    /// Gave up. The master is idle again.
    Failed(MasterError),
}

#[derive(Debug, Clone)]
struct Outstanding {
    wire: Vec<u8>,
    station: u8,
    function: u8,
    /// GUTTA function and packet of a function 13 request.
    gutta: Option<(u16, u16)>,
    deadline: u64,
    attempts: u32,
    crc_error_seen: bool,
}

/// Whether a request to `station` with `function` is answered: not a broadcast
/// (station 0), except GUTTA function 13, which a PLC answers from its own station
/// (AN2002).
pub fn expects_answer(station: u8, function: u8) -> bool {
    station != 0 || function == MODBUS_FUNCTION_GUTTA
}

/// The master state machine: Idle -> (send) -> Waiting -> Response | Retry -> ... |
/// Failed -> Idle.
#[derive(Debug, Clone)]
pub struct Master {
    config: MasterConfig,
    splitter: RtuSplitter,
    outstanding: Option<Outstanding>,
    ignored_frames: u64,
}

impl Master {
    pub fn new(config: MasterConfig) -> Self {
        Master {
            config,
            splitter: RtuSplitter::with_max_frame(Side::Master, config.max_frame),
            outstanding: None,
            ignored_frames: 0,
        }
    }

    pub fn config(&self) -> MasterConfig {
        self.config
    }

    /// Whether a request is outstanding.
    pub fn is_busy(&self) -> bool {
        self.outstanding.is_some()
    }

    /// Valid frames received that did not answer the outstanding request.
    pub fn ignored_frames(&self) -> u64 {
        self.ignored_frames
    }

    /// Attempts made so far for the outstanding request (1 after `send`).
    pub fn attempts(&self) -> u32 {
        self.outstanding.as_ref().map_or(0, |o| o.attempts)
    }

    /// Starts a request; returns the RTU frame to write. A broadcast (station 0) of any
    /// function but 13 expects no answer: the bytes are returned and the master stays
    /// idle. Station 0 with function 13 is answered by the PLC (AN2002), from whatever
    /// station it has, so any station's answer is accepted.
    pub fn send(&mut self, station: u8, pdu: &[u8], now: u64) -> Result<Vec<u8>, MasterError> {
        if self.outstanding.is_some() {
            return Err(MasterError::Busy);
        }
        let Some(&function) = pdu.first() else {
            return Err(MasterError::BadRequest {
                detail: "empty PDU".into(),
            });
        };
        let gutta = if function == MODBUS_FUNCTION_GUTTA {
            let frame = GuttaFrame::from_pdu(pdu).map_err(|e| MasterError::BadRequest {
                detail: e.to_string(),
            })?;
            Some((frame.function, frame.packet))
        } else {
            None
        };
        let wire = encode_rtu(station, pdu);
        if !expects_answer(station, function) {
            return Ok(wire);
        }
        self.splitter.clear();
        self.outstanding = Some(Outstanding {
            wire: wire.clone(),
            station,
            function,
            gutta,
            deadline: now.saturating_add(self.config.timeout_ms),
            attempts: 1,
            crc_error_seen: false,
        });
        Ok(wire)
    }

    /// Abandons the outstanding request, if any.
    pub fn cancel(&mut self) {
        self.outstanding = None;
        self.splitter.clear();
    }

    /// Feeds received bytes. A matching answer completes the request. A frame with a
    /// bad CRC counts as a lost answer: the request is retried when its timeout passes
    /// (unless a good answer arrives first), and fails with `Crc` instead of `Timeout`
    /// if it was the last attempt. Non-matching valid frames and framing noise are
    /// ignored.
    pub fn on_bytes(&mut self, bytes: &[u8], _now: u64) -> MasterEvent {
        let Some(outstanding) = self.outstanding.as_mut() else {
            return MasterEvent::Idle;
        };
        self.splitter.push(bytes);
        while let Some(result) = self.splitter.next_frame() {
            match result {
                Ok(wire) => match decode_rtu(&wire) {
                    Ok(frame) if answers(outstanding, &frame) => {
                        self.outstanding = None;
                        self.splitter.clear();
                        return MasterEvent::Response(frame);
                    }
                    _ => self.ignored_frames += 1,
                },
                Err(FrameError::CrcMismatch { .. }) => outstanding.crc_error_seen = true,
                Err(_) => {}
            }
        }
        MasterEvent::Pending
    }

    /// Checks the timeout: `Retry` with the bytes to write again, `Failed` after the
    /// last attempt, `None` if nothing is due (or idle).
    pub fn on_tick(&mut self, now: u64) -> Option<MasterEvent> {
        let outstanding = self.outstanding.as_mut()?;
        if now < outstanding.deadline {
            return None;
        }
        if outstanding.attempts <= self.config.retries {
            outstanding.attempts += 1;
            outstanding.deadline = now.saturating_add(self.config.timeout_ms);
            outstanding.crc_error_seen = false;
            let wire = outstanding.wire.clone();
            self.splitter.clear();
            return Some(MasterEvent::Retry(wire));
        }
        let attempts = outstanding.attempts;
        let error = if outstanding.crc_error_seen {
            MasterError::Crc { attempts }
        } else {
            MasterError::Timeout { attempts }
        };
        self.outstanding = None;
        self.splitter.clear();
        Some(MasterEvent::Failed(error))
    }
}

/// Whether `frame` answers the outstanding request: same station (any for a function 13
/// broadcast), same function or its exception; for function 13 also the same GUTTA
/// function (or its failure) and packet.
fn answers(outstanding: &Outstanding, frame: &RtuFrame) -> bool {
    if outstanding.station != 0 && frame.station != outstanding.station {
        return false;
    }
    let Some(function) = frame.function() else {
        return false;
    };
    if function == outstanding.function | EXCEPTION_BIT {
        return true;
    }
    if function != outstanding.function {
        return false;
    }
    match outstanding.gutta {
        None => true,
        Some((code, packet)) => GuttaFrame::from_pdu(&frame.pdu).is_ok_and(|answer| {
            (answer.function == code || answer.function == code | FAILURE_BIT)
                && answer.packet == packet
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const READ_INPUTS: [u8; 5] = [0x02, 0x00, 0x04, 0x00, 0x04];
    const ANSWER: [u8; 6] = [0x01, 0x02, 0x01, 0x00, 0xA1, 0x88];

    fn master(retries: u32) -> Master {
        Master::new(MasterConfig {
            timeout_ms: 100,
            retries,
            ..MasterConfig::default()
        })
    }

    #[test]
    fn success_in_pieces() {
        let mut m = master(2);
        let wire = m.send(1, &READ_INPUTS, 0).expect("idle");
        assert_eq!(wire, [0x01, 0x02, 0x00, 0x04, 0x00, 0x04, 0x38, 0x08]);
        assert_eq!(m.send(1, &READ_INPUTS, 0), Err(MasterError::Busy));
        assert_eq!(m.on_bytes(&ANSWER[..3], 10), MasterEvent::Pending);
        assert_eq!(m.on_tick(50), None);
        let event = m.on_bytes(&ANSWER[3..], 20);
        assert_eq!(
            event,
            MasterEvent::Response(RtuFrame {
                station: 1,
                pdu: vec![2, 1, 0]
            })
        );
        assert!(!m.is_busy());
        assert_eq!(m.on_bytes(&ANSWER, 30), MasterEvent::Idle);
    }

    #[test]
    fn timeout_retry_then_success() {
        let mut m = master(2);
        let wire = m.send(1, &READ_INPUTS, 1000).expect("idle");
        assert_eq!(m.on_tick(1099), None);
        assert_eq!(m.on_tick(1100), Some(MasterEvent::Retry(wire.clone())));
        assert_eq!(m.attempts(), 2);
        assert_eq!(m.on_tick(1150), None);
        assert!(matches!(
            m.on_bytes(&ANSWER, 1160),
            MasterEvent::Response(_)
        ));
    }

    #[test]
    fn all_attempts_time_out() {
        let mut m = master(1);
        let wire = m.send(1, &READ_INPUTS, 0).expect("idle");
        assert_eq!(m.on_tick(100), Some(MasterEvent::Retry(wire)));
        assert_eq!(
            m.on_tick(200),
            Some(MasterEvent::Failed(MasterError::Timeout { attempts: 2 }))
        );
        assert!(!m.is_busy());
        assert_eq!(m.on_tick(300), None);
    }

    #[test]
    fn crc_error_is_a_lost_answer() {
        let mut m = master(1);
        let wire = m.send(1, &READ_INPUTS, 0).expect("idle");
        let mut bad = ANSWER;
        bad[5] ^= 0x55;
        assert_eq!(m.on_bytes(&bad, 10), MasterEvent::Pending);
        assert_eq!(m.on_tick(100), Some(MasterEvent::Retry(wire)));
        assert_eq!(m.on_bytes(&bad, 110), MasterEvent::Pending);
        assert_eq!(
            m.on_tick(200),
            Some(MasterEvent::Failed(MasterError::Crc { attempts: 2 }))
        );
    }

    #[test]
    fn ignores_other_stations_and_functions_and_accepts_exceptions() {
        let mut m = master(0);
        m.send(1, &READ_INPUTS, 0).expect("idle");
        assert_eq!(
            m.on_bytes(&encode_rtu(2, &[0x02, 0x01, 0x00]), 1),
            MasterEvent::Pending
        );
        assert_eq!(
            m.on_bytes(&encode_rtu(1, &[0x01, 0x01, 0x00]), 2),
            MasterEvent::Pending
        );
        assert_eq!(m.ignored_frames(), 2);
        let exception = encode_rtu(1, &[0x82, 0x02]);
        assert_eq!(
            m.on_bytes(&exception, 3),
            MasterEvent::Response(RtuFrame {
                station: 1,
                pdu: vec![0x82, 0x02]
            })
        );
    }

    #[test]
    fn gutta_matches_function_and_packet_and_broadcast() {
        let mut m = master(0);
        let read = GuttaFrame::new(0x0831, 0x0001, vec![])
            .to_pdu()
            .expect("small");
        m.send(0, &read, 0).expect("idle");
        // Wrong packet, then wrong function, then the failure answer from station 5.
        let wrong_packet = GuttaFrame::new(0x0831, 0x0000, vec![1])
            .to_pdu()
            .expect("small");
        let wrong_function = GuttaFrame::new(0x0832, 0x0001, vec![1])
            .to_pdu()
            .expect("small");
        let failure = GuttaFrame::new(0x8831, 0x0001, vec![])
            .to_pdu()
            .expect("small");
        assert_eq!(
            m.on_bytes(&encode_rtu(5, &wrong_packet), 1),
            MasterEvent::Pending
        );
        assert_eq!(
            m.on_bytes(&encode_rtu(5, &wrong_function), 2),
            MasterEvent::Pending
        );
        assert_eq!(
            m.on_bytes(&encode_rtu(5, &failure), 3),
            MasterEvent::Response(RtuFrame {
                station: 5,
                pdu: failure
            })
        );
        // Broadcast of a standard function: no answer expected.
        let wire = m.send(0, &[0x06, 0, 1, 0, 3], 4).expect("idle");
        assert_eq!(wire.len(), 8);
        assert!(!m.is_busy());
        assert!(matches!(
            m.send(1, &[], 5),
            Err(MasterError::BadRequest { .. })
        ));
        assert!(matches!(
            m.send(1, &[0x0D, 0, 5], 5),
            Err(MasterError::BadRequest { .. })
        ));
    }
}
