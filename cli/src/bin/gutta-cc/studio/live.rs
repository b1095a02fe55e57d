//! Live values on the page (docs/studio.md, "Live state"): the one interface the
//! simulator (SIMULATE) and a connected PLC (ONLINE) both offer the server, so the page
//! paints power flow, runs and stops, writes and forces the same way in either mode.

#![allow(dead_code)]

use serde::Serialize;

/// A refusal or failure of a live source: a stable code (`not-running`, `no-operand`,
/// `plc-error`, ...) and a message that says what to do.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub(crate) struct LiveError {
    pub code: &'static str,
    pub message: String,
}

/// One row of the watch table: an operand (symbol or address, as the user typed it) and
/// the format to show it in (`bit`, `signed`, `unsigned`, `hex`, `binary`, `ascii`,
/// `float`; None: the operand's own).
#[derive(Debug, Clone, PartialEq, Eq, serde::Deserialize)]
pub(crate) struct WatchRequest {
    pub operand: String,
    pub format: Option<String>,
}

/// A watch table row's answer: the canonical address, the value shown in its format,
/// whether it is forced, or why it cannot be read.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub(crate) struct WatchValue {
    pub operand: String,
    pub address: Option<String>,
    pub value: Option<String>,
    pub forced: bool,
    pub error: Option<LiveError>,
}

/// The simulator or a PLC, as the server drives it.
pub(crate) trait LiveSource: Send {
    /// `"SIMULATE"` or `"ONLINE"`.
    fn mode(&self) -> &'static str;
    /// One update for the page: the `/api/live` object (docs/studio.md, "Live state").
    fn state(&mut self) -> serde_json::Value;
    /// The program runs (RUN).
    fn run(&mut self) -> Result<(), LiveError>;
    /// The program stops (STOP): outputs as the PLC leaves them, no power flow shown.
    fn stop(&mut self) -> Result<(), LiveError>;
    /// `value` (as `gutta-cc write` takes it: `1`, `-5`, `16#FF`, `2.5`) written into
    /// `operand` (a symbol or an address).
    fn write(&mut self, operand: &str, value: &str) -> Result<(), LiveError>;
    /// `operand` forced to `value`, or released (None).
    fn force(&mut self, operand: &str, value: Option<&str>) -> Result<(), LiveError>;
    /// The watch table's rows read now.
    fn read(&mut self, rows: &[WatchRequest]) -> Vec<WatchValue>;
}
