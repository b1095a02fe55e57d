//! The client of the FX-style programming port (seed 001; docs/devices.md) as a state
//! machine without I/O: one request at a time, sent again on NAK, silence or a broken
//! answer, at most 1 + retries times, with what every attempt missed kept for the
//! error. Like `master.rs` it never reads a clock: the caller passes the time in
//! milliseconds (any epoch, never decreasing), writes the bytes it returns and reports
//! what the line did (bytes, a read that timed out, a line that failed).
//! gutta-link's `transport::fx` is its I/O.

use std::fmt;

use gutta_catalog::plural::count;

use crate::fx::{FxError, FxReply, FxRequest, FxSplitter, FxToken};

/// How long to wait and how often to try.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FxClientConfig {
    /// Time to wait for an answer after sending, per attempt.
    pub timeout_ms: u64,
    /// Attempts after the first when the answer is NAK, missing or broken.
    pub retries: u32,
}

/// Why one attempt failed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FxMiss {
    /// The device answered NAK.
    Nak,
    /// No answer within the timeout.
    Silence,
    /// An answer that is no reply, or the line failed: what happened.
    Garbled(String),
}

/// Every attempt missed: the request and what each attempt got.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FxFailure {
    pub request: FxRequest,
    pub misses: Vec<FxMiss>,
    pub timeout_ms: u64,
}

impl FxFailure {
    /// Every attempt was refused with NAK.
    pub fn all_nak(&self) -> bool {
        self.misses.iter().all(|m| *m == FxMiss::Nak)
    }

    /// No attempt got an answer.
    pub fn all_silent(&self) -> bool {
        self.misses.iter().all(|m| *m == FxMiss::Silence)
    }
}

impl fmt::Display for FxFailure {
    /// `read (30) 2 bytes at 0E02 failed after 3 attempts: NAK, no answer in 1000 ms, ...`
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let what: Vec<String> = self
            .misses
            .iter()
            .map(|miss| match miss {
                FxMiss::Nak => "NAK".to_string(),
                FxMiss::Silence => format!("no answer in {} ms", self.timeout_ms),
                FxMiss::Garbled(e) => format!("a broken answer ({e})"),
            })
            .collect();
        write!(
            f,
            "{} failed after {}: {}",
            self.request.describe(),
            count(self.misses.len(), "attempt"),
            what.join(", ")
        )
    }
}

/// What happened on `on_bytes`, `on_timeout`, `on_tick` or `on_line_error`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FxEvent {
    /// Still waiting for the answer.
    Pending,
    /// No request outstanding; bytes were discarded.
    Idle,
    /// ACK or data: the answer. The client is idle again.
    Reply(FxReply),
    /// The attempt missed: write these bytes (the same request) again.
    Retry(Vec<u8>),
    /// Every attempt missed. The client is idle again.
    Failed(FxFailure),
}

#[derive(Debug, Clone)]
struct Outstanding {
    request: FxRequest,
    wire: Vec<u8>,
    deadline: u64,
    misses: Vec<FxMiss>,
}

/// The client state machine: Idle -> (send) -> Waiting -> Reply | Retry -> ... |
/// Failed -> Idle.
#[derive(Debug)]
pub struct FxClient {
    config: FxClientConfig,
    splitter: FxSplitter,
    outstanding: Option<Outstanding>,
}

impl FxClient {
    pub fn new(config: FxClientConfig) -> FxClient {
        FxClient {
            config,
            splitter: FxSplitter::new(),
            outstanding: None,
        }
    }

    /// Start `request` at `now`: the bytes to write. A request still outstanding is
    /// abandoned.
    pub fn send(&mut self, request: &FxRequest, now: u64) -> Result<Vec<u8>, FxError> {
        let wire = request.encode()?;
        self.splitter = FxSplitter::new();
        self.outstanding = Some(Outstanding {
            request: request.clone(),
            wire: wire.clone(),
            deadline: now.saturating_add(self.config.timeout_ms),
            misses: Vec::new(),
        });
        Ok(wire)
    }

    /// When the current attempt times out, if a request is outstanding.
    pub fn deadline(&self) -> Option<u64> {
        self.outstanding.as_ref().map(|o| o.deadline)
    }

    /// Bytes from the line: the first token they complete answers the attempt.
    pub fn on_bytes(&mut self, bytes: &[u8], now: u64) -> FxEvent {
        if self.outstanding.is_none() {
            return FxEvent::Idle;
        }
        let Some(token) = self.splitter.push(bytes).into_iter().next() else {
            return FxEvent::Pending;
        };
        match token {
            FxToken::Nak => self.miss(FxMiss::Nak, now),
            other => match FxReply::from_token(other) {
                Ok(reply) => {
                    self.outstanding = None;
                    FxEvent::Reply(reply)
                }
                Err(e) => self.miss(FxMiss::Garbled(e.to_string()), now),
            },
        }
    }

    /// The clock: a miss when the attempt's deadline has passed.
    pub fn on_tick(&mut self, now: u64) -> FxEvent {
        match self.deadline() {
            None => FxEvent::Idle,
            Some(deadline) if now >= deadline => self.miss(FxMiss::Silence, now),
            Some(_) => FxEvent::Pending,
        }
    }

    /// The line's wait for an answer ran out: the attempt got no answer.
    pub fn on_timeout(&mut self, now: u64) -> FxEvent {
        if self.outstanding.is_none() {
            return FxEvent::Idle;
        }
        self.miss(FxMiss::Silence, now)
    }

    /// The line failed while waiting (`what`: it closed, a read error).
    pub fn on_line_error(&mut self, what: String, now: u64) -> FxEvent {
        if self.outstanding.is_none() {
            return FxEvent::Idle;
        }
        self.miss(FxMiss::Garbled(what), now)
    }

    fn miss(&mut self, miss: FxMiss, now: u64) -> FxEvent {
        let Some(mut outstanding) = self.outstanding.take() else {
            return FxEvent::Idle;
        };
        outstanding.misses.push(miss);
        if outstanding.misses.len() as u64 > u64::from(self.config.retries) {
            return FxEvent::Failed(FxFailure {
                request: outstanding.request,
                misses: outstanding.misses,
                timeout_ms: self.config.timeout_ms,
            });
        }
        self.splitter = FxSplitter::new();
        outstanding.deadline = now.saturating_add(self.config.timeout_ms);
        let wire = outstanding.wire.clone();
        self.outstanding = Some(outstanding);
        FxEvent::Retry(wire)
    }
}

impl FxRequest {
    /// The request as messages name it: `read (30) 2 bytes at 0E02`.
    pub fn describe(&self) -> String {
        match self {
            FxRequest::Enquiry => "ENQ".into(),
            FxRequest::Read { address, len } => {
                format!("read (30) {} at {address:04X}", count(*len, "byte"))
            }
            FxRequest::Write { address, data } => {
                format!("write (31) {} at {address:04X}", count(data.len(), "byte"))
            }
            FxRequest::ForceOn { bit } => format!("force on (37) bit {bit:04X}"),
            FxRequest::ForceOff { bit } => format!("force off (38) bit {bit:04X}"),
            FxRequest::Baud(rate) => format!("baud (41) {rate}"),
            FxRequest::ReadConfig { address, len } => format!(
                "read configuration (E00) {} at {address:04X}",
                count(*len, "byte")
            ),
            FxRequest::ReadProgram { address, len } => format!(
                "read program (E01) {} at {address:04X}",
                count(*len, "byte")
            ),
            FxRequest::WriteProgram { address, data } => format!(
                "write program (E11) {} at {address:04X}",
                count(data.len(), "byte")
            ),
            FxRequest::EndProgramWrite => "end of program write (E87)".into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fx::{ACK, NAK};

    fn client(retries: u32) -> FxClient {
        FxClient::new(FxClientConfig {
            timeout_ms: 100,
            retries,
        })
    }

    const READ: FxRequest = FxRequest::Read {
        address: 0x0E02,
        len: 2,
    };

    #[test]
    fn data_answers_the_request_and_the_client_is_idle_again() {
        let mut c = client(2);
        let wire = c.send(&READ, 0).expect("encodes");
        assert_eq!(wire, READ.encode().expect("encodes"));
        let answer = FxReply::Data(vec![0x11, 0x22]).encode();
        let (head, tail) = answer.split_at(3);
        assert_eq!(c.on_bytes(head, 10), FxEvent::Pending);
        assert_eq!(
            c.on_bytes(tail, 20),
            FxEvent::Reply(FxReply::Data(vec![0x11, 0x22]))
        );
        assert_eq!(c.deadline(), None);
        assert_eq!(c.on_bytes(&[ACK], 30), FxEvent::Idle);
    }

    #[test]
    fn nak_silence_and_garbage_are_retried_then_reported_in_order() {
        let mut c = client(2);
        let wire = c.send(&READ, 0).expect("encodes");
        assert_eq!(c.on_bytes(&[NAK], 5), FxEvent::Retry(wire.clone()));
        assert_eq!(c.deadline(), Some(105));
        assert_eq!(c.on_tick(104), FxEvent::Pending);
        assert_eq!(c.on_tick(105), FxEvent::Retry(wire));
        let FxEvent::Failed(failure) = c.on_line_error("the connection closed".into(), 300) else {
            panic!("the third miss ends it");
        };
        assert_eq!(
            failure.to_string(),
            "read (30) 2 bytes at 0E02 failed after 3 attempts: NAK, no answer in 100 ms, \
             a broken answer (the connection closed)"
        );
        assert!(!failure.all_nak() && !failure.all_silent());
        assert_eq!(c.on_timeout(400), FxEvent::Idle);
    }

    #[test]
    fn without_retries_one_miss_fails() {
        let mut c = client(0);
        c.send(&FxRequest::ForceOn { bit: 0x0500 }, 0)
            .expect("encodes");
        let FxEvent::Failed(failure) = c.on_bytes(&[NAK], 1) else {
            panic!("no retry");
        };
        assert!(failure.all_nak());
        assert_eq!(
            failure.to_string(),
            "force on (37) bit 0500 failed after 1 attempt: NAK"
        );
    }
}
