//! The one sans-I/O Modbus RTU master (request, timeout, retry), shared by the download
//! client and the VM's EXCH. It never reads a clock: the caller passes the time in
//! milliseconds (any epoch, never decreasing) to `send`, `on_bytes` and `on_tick`, and
//! writes the bytes it returns. One request at a time.

use std::fmt;

use gutta_catalog::plural;

use crate::gutta::{GuttaFrame, FAILURE_BIT, MODBUS_FUNCTION_GUTTA};
use crate::modbus::{exception_of, EXCEPTION_BIT};
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
                write!(f, "no answer after {}", plural::count(*attempts, "attempt"))
            }
            MasterError::Crc { attempts } => {
                write!(
                    f,
                    "answer with a CRC error after {}",
                    plural::count(*attempts, "attempt")
                )
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
    /// The matching normal answer: the request's function code (never its exception).
    /// For function 13 it carries the request's GUTTA function or its failure (bit 15)
    /// and its packet: the caller decodes the GUTTA data. The master is idle again.
    Response(RtuFrame),
    /// The matching Modbus exception answer, `[station][function | 0x80][code]`:
    /// `function` is the request's function code (without the exception bit), `code`
    /// the exception code as received (any byte; `modbus::ExceptionCode` names the ones
    /// a GUTTA PLC sends). The master is idle again.
    Exception { station: u8, function: u8, code: u8 },
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
/// (station 0), except a function whose `modbus_registry` row says so (GUTTA function
/// 13, which a PLC answers from its own station; AN2002).
pub fn expects_answer(station: u8, function: u8) -> bool {
    station != 0 || crate::modbus_registry::lookup(function).is_some_and(|f| f.answers_broadcast)
}

/// The master state machine: Idle -> (send) -> Waiting -> Response | Exception |
/// Retry -> ... | Failed -> Idle.
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

    /// Valid frames (CRC checked) received while a request was outstanding that did not
    /// answer it.
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
    /// station it has, so an answer from any station but 0 is accepted.
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

    /// Feeds received bytes. A matching answer completes the request: `Response`, or
    /// `Exception` for a well-formed Modbus exception. A frame with a bad CRC counts as
    /// a lost answer: the request is retried when its timeout passes (unless a good
    /// answer arrives first), and fails with `Crc` instead of `Timeout` if it was the
    /// last attempt. Valid frames that do not answer (another station, station 0,
    /// another function, GUTTA packet, or an exception of the wrong shape) are counted
    /// in `ignored_frames` and ignored; framing noise is dropped.
    pub fn on_bytes(&mut self, bytes: &[u8], _now: u64) -> MasterEvent {
        let Some(outstanding) = self.outstanding.as_mut() else {
            return MasterEvent::Idle;
        };
        self.splitter.push(bytes);
        while let Some(result) = self.splitter.next_frame() {
            match result {
                Ok(wire) => match decode_rtu(&wire).ok().and_then(|f| answer(outstanding, f)) {
                    Some(event) => {
                        self.outstanding = None;
                        self.splitter.clear();
                        return event;
                    }
                    None => self.ignored_frames += 1,
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

/// The event `frame` completes the outstanding request with, or `None` if it does not
/// answer it (docs/protocol.md, "What the master does with each frame"):
/// - station 0 never answers: it is the broadcast address, no slave's, so a frame from
///   it is a request on the line (another master's, or our own echoed), not an answer;
/// - otherwise the request's station, or any station for a function 13 broadcast;
/// - `[function | 0x80, code]`, exactly two PDU bytes, is the exception answer (for
///   function 13 too: UM4001 adds nothing to the Modbus exception, which carries no
///   GUTTA function or packet); the exception bit with any other PDU length is not an
///   answer but garbage on the line;
/// - the request's function is the normal answer; for function 13 only GUTTA data of
///   the request's GUTTA function (or its failure, bit 15) and packet.
fn answer(outstanding: &Outstanding, frame: RtuFrame) -> Option<MasterEvent> {
    if frame.station == 0 || (outstanding.station != 0 && frame.station != outstanding.station) {
        return None;
    }
    let function = frame.function()?;
    let exception = outstanding.function | EXCEPTION_BIT;
    if function == exception && function != outstanding.function {
        return exception_of(&frame.pdu).map(|(function, code)| MasterEvent::Exception {
            station: frame.station,
            function,
            code,
        });
    }
    if function != outstanding.function {
        return None;
    }
    let answers = match outstanding.gutta {
        None => true,
        Some((code, packet)) => GuttaFrame::from_pdu(&frame.pdu).is_ok_and(|answer| {
            (answer.function == code || answer.function == code | FAILURE_BIT)
                && answer.packet == packet
        }),
    };
    answers.then_some(MasterEvent::Response(frame))
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
            MasterEvent::Exception {
                station: 1,
                function: 0x02,
                code: 0x02
            }
        );
        assert!(!m.is_busy());
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

    /// GUTTA PLC_CLEAR (0100), single packet: its success answer is the same GUTTA data.
    const CLEAR: [u8; 7] = [0x0D, 0x00, 0x04, 0x01, 0x00, 0x80, 0x00];
    /// The request of the `frames` fuzz target: PROGRAM_INSTRUCTION_READ (0800), packet 1.
    const READ_PAGE_0: [u8; 7] = [0x0D, 0x00, 0x04, 0x08, 0x00, 0x00, 0x01];

    /// What `answer` makes of `pdu` from `station` for the request `send` just started.
    fn judge(m: &Master, station: u8, pdu: &[u8]) -> Option<MasterEvent> {
        let outstanding = m.outstanding.as_ref().expect("a request is outstanding");
        answer(
            outstanding,
            RtuFrame {
                station,
                pdu: pdu.to_vec(),
            },
        )
    }

    #[test]
    fn an_exception_answer_is_exactly_two_pdu_bytes() {
        for (station, request) in [(1, &READ_PAGE_0[..]), (0, &READ_PAGE_0[..])] {
            let mut m = master(0);
            m.send(station, request, 0).expect("idle");
            // Short: the function with the exception bit and no code.
            assert_eq!(judge(&m, 1, &[0x8D]), None);
            // Long: a code and two more bytes.
            assert_eq!(judge(&m, 1, &[0x8D, 0x02, 0x00, 0x00]), None);
            // Well-formed: function | 0x80 and one code byte.
            assert_eq!(
                judge(&m, 1, &[0x8D, 0x06]),
                Some(MasterEvent::Exception {
                    station: 1,
                    function: 0x0D,
                    code: 0x06
                })
            );
            // Another function's exception is not this request's answer.
            assert_eq!(judge(&m, 1, &[0x83, 0x02]), None);
        }
        let mut m = master(0);
        m.send(1, &READ_INPUTS, 0).expect("idle");
        assert_eq!(judge(&m, 1, &[0x82]), None);
        assert_eq!(judge(&m, 1, &[0x82, 0x02, 0x01]), None);
        assert_eq!(
            judge(&m, 1, &[0x82, 0x02]),
            Some(MasterEvent::Exception {
                station: 1,
                function: 0x02,
                code: 0x02
            })
        );
    }

    #[test]
    fn a_short_exception_on_the_line_is_no_answer_and_the_request_is_retried() {
        let mut m = master(1);
        let wire = m.send(1, &READ_PAGE_0, 0).expect("idle");
        // `01 8D CRC CRC`: the splitter waits for the fifth byte of an exception frame.
        assert_eq!(
            m.on_bytes(&encode_rtu(1, &[0x8D]), 10),
            MasterEvent::Pending
        );
        assert_eq!(m.on_tick(100), Some(MasterEvent::Retry(wire)));
        assert_eq!(
            m.on_tick(200),
            Some(MasterEvent::Failed(MasterError::Timeout { attempts: 2 }))
        );
        assert_eq!(m.ignored_frames(), 0);
    }

    #[test]
    fn a_long_exception_on_the_line_is_no_answer_and_the_request_is_retried() {
        let mut m = master(1);
        let wire = m.send(1, &READ_PAGE_0, 0).expect("idle");
        // Framed as a five-byte exception its CRC does not check; the rest is noise.
        let long = encode_rtu(1, &[0x8D, 0x02, 0x00, 0x00]);
        assert_eq!(m.on_bytes(&long, 10), MasterEvent::Pending);
        assert_eq!(m.on_tick(100), Some(MasterEvent::Retry(wire)));
        assert_eq!(m.on_bytes(&long, 110), MasterEvent::Pending);
        assert_eq!(
            m.on_tick(200),
            Some(MasterEvent::Failed(MasterError::Crc { attempts: 2 }))
        );
    }

    #[test]
    fn a_well_formed_exception_on_the_line_answers_function_13() {
        let mut m = master(1);
        m.send(1, &READ_PAGE_0, 0).expect("idle");
        assert_eq!(
            m.on_bytes(&encode_rtu(1, &[0x8D, 0x06]), 10),
            MasterEvent::Exception {
                station: 1,
                function: 0x0D,
                code: 0x06
            }
        );
        assert!(!m.is_busy());
        assert_eq!(m.ignored_frames(), 0);
    }

    /// Issue 32, as filed: a frame from station 0 whose PDU is function 13's exception
    /// with four bytes, while a function 13 broadcast waits. With its own CRC it is not
    /// the answer by shape, nor by station; on the line the splitter sees bad CRCs, so
    /// the timeout and the retry take over.
    #[test]
    fn issue_32_a_long_exception_from_station_0_is_not_the_answer() {
        let mut m = master(1);
        let wire = m.send(0, &READ_PAGE_0, 0).expect("idle");
        let pdu = [0x8D, 0x2F, 0x8D, 0x60];
        assert_eq!(judge(&m, 0, &pdu), None);
        assert_eq!(judge(&m, 0x2F, &pdu), None);
        assert_eq!(m.on_bytes(&encode_rtu(0, &pdu), 10), MasterEvent::Pending);
        assert_eq!(m.on_tick(100), Some(MasterEvent::Retry(wire)));
        assert_eq!(
            m.on_tick(200),
            Some(MasterEvent::Failed(MasterError::Timeout { attempts: 2 }))
        );
        assert!(!m.is_busy());
    }

    /// Issue 32, the fuzzer's input replayed as the `frames` target does (first byte:
    /// chunk size, the rest the received stream). The frame the master took is
    /// `2F 8D 60 25 71`, the only CRC-valid window: a well-formed exception (code 0x60)
    /// from station 0x2F to the function 13 broadcast, preceded by noise. It is the
    /// answer, now as the typed `Exception`, never as a `Response`.
    #[test]
    fn issue_32_the_fuzz_input_ends_in_a_well_formed_exception() {
        let input = [141u8, 0, 0, 141, 47, 141, 96, 37, 113];
        let mut m = Master::new(MasterConfig {
            timeout_ms: 10,
            retries: 1,
            ..MasterConfig::default()
        });
        m.send(0, &READ_PAGE_0, 0).expect("idle");
        assert_eq!(
            m.on_bytes(&input[1..], 3),
            MasterEvent::Exception {
                station: 0x2F,
                function: 0x0D,
                code: 0x60
            }
        );
        assert_eq!(m.ignored_frames(), 0);
    }

    /// Station 0 is no slave's address: a frame from it is a request on the line, such
    /// as the echo of our own broadcast, which for PLC_CLEAR is byte for byte what its
    /// success answer would be. It is counted and ignored; the PLC's answer follows.
    #[test]
    fn a_frame_from_station_0_is_never_the_answer() {
        let mut m = master(0);
        let wire = m.send(0, &CLEAR, 0).expect("idle");
        assert_eq!(m.on_bytes(&wire, 1), MasterEvent::Pending);
        assert_eq!(
            m.on_bytes(&encode_rtu(0, &[0x8D, 0x06]), 2),
            MasterEvent::Pending
        );
        assert_eq!(m.ignored_frames(), 2);
        assert_eq!(
            m.on_bytes(&encode_rtu(7, &CLEAR), 3),
            MasterEvent::Response(RtuFrame {
                station: 7,
                pdu: CLEAR.to_vec()
            })
        );
    }

    /// Modbus RTU has no transaction id: an answer to the first attempt that arrives
    /// after the retry answers the retry (the same request); the second answer then
    /// finds the master idle and is discarded, uncounted.
    #[test]
    fn a_late_answer_after_a_retry_is_the_answer_and_the_next_finds_it_idle() {
        let mut m = master(1);
        let wire = m.send(1, &READ_INPUTS, 0).expect("idle");
        assert_eq!(m.on_tick(100), Some(MasterEvent::Retry(wire)));
        assert!(matches!(m.on_bytes(&ANSWER, 120), MasterEvent::Response(_)));
        assert_eq!(m.on_bytes(&ANSWER, 130), MasterEvent::Idle);
        assert_eq!(m.ignored_frames(), 0);
    }
}
