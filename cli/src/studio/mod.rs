//! The studio's session core (docs/studio.md, "The session (Rust)"; issue 27): the
//! logic the studio's page relies on, tested without a browser. `session.rs` (`Session`:
//! the open files, their buffers, checked programs, ladder models and editors; edits,
//! undo/redo, save, a block's STL), `update.rs` (what an edit sends back to the page:
//! redrawn networks and diagnostics), `summary.rs` (the project as the page lists it),
//! `confine.rs` (the one folder the studio reads and writes in), `error.rs` (its typed
//! refusals). No HTTP, no page and no terminal here: the only I/O is reading the
//! project's files when a session opens and the atomic save.

mod complete;
mod confine;
mod error;
mod run;
mod session;
pub mod sim;
mod stl_edit;
mod summary;
mod symbols_edit;
mod tests;
mod update;

pub use complete::{Completion, CompletionRequest, Wanted};
pub use confine::Root;
pub use error::StudioError;
pub use run::{ProgramError, RunProgram};
pub use session::Session;
pub use sim::Simulator;
pub use stl_edit::{StlCompletion, StlCompletions, StlDiagnostic, StlHover, StlText};
pub use summary::{BlockSummary, FileSummary, ProjectSummary, TableSummary};
pub use symbols_edit::{SymbolChange, SymbolRow};
pub use tests::{ProgramRefused, TestFileRun, TestRun, TestsNow};
pub use update::{BlockShape, NetworkDrawing, Update};
