//! The conventions the three command-line tools (gutta-cc, gutta-vm, gutta-sim) share:
//! fatal errors with a kind and their JSON form, the NO_COLOR rule, shell completions
//! and man pages, the table of flags the tools spell alike (docs/cli.md), the `--plc`/`--target`
//! flags and the target they choose (`target`), reading a program's files (`sources`) and
//! printing the notes about them (`notes`: human or JSON), and counts
//! with their nouns (`plural`, whose home is gutta-catalog so the libraries' messages
//! share it: `1 page`, `2 pages`), and the variables gutta-cc and gutta-vm name on the
//! command line (`vars`: gutta-link's typed `Var` with its JSON and the symbol context),
//! and the studio's session core (`studio`: the open files, edits, checks and saves the
//! studio's page relies on, issue 27).
//! It must not know any one tool's commands or do any tool's work.

pub mod color;
pub mod fatal;
pub mod flags;
pub use gutta_catalog::plural;
pub mod notes;
pub mod shell;
pub mod sources;
pub mod studio;
pub mod target;
pub mod vars;
