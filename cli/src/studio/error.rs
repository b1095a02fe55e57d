//! The studio session's refusals, typed so a server can answer each one (a path that
//! escapes the project is a 403, an edit the model refuses its L code). Messages only;
//! nothing here decides whether something is refused.

use gutta_ladder::json::ModelError;

/// Why a session did not open, or refused a request. Nothing was written when a request
/// is refused.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum StudioError {
    /// A path outside the studio's folder (`..`, an absolute path, a symlink out).
    Escape { path: String, root: String },
    /// A file the session has not opened.
    NotOpen { file: String },
    /// A block the file does not have.
    NoBlock { file: String, block: usize },
    /// Something other than a project folder, a gutta.toml or `.lad` files.
    NotAProgram { path: String },
    /// A `.lad` file that is not UTF-8 text: the studio edits text in place and would
    /// rewrite every byte of another encoding.
    NotUtf8 { path: String, offset: usize },
    /// gutta.toml is missing or wrong, or its PLC type does not load.
    Project(String),
    /// Reading or writing a file failed.
    Io { path: String, message: String },
    /// The edit was refused (its L code and path): nothing changed.
    Edit(ModelError),
}

impl std::fmt::Display for StudioError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            StudioError::Escape { path, root } => write!(
                f,
                "{path} is outside {root}: the studio reads and writes only files inside it"
            ),
            StudioError::NotOpen { file } => write!(f, "{file} is not a file of this session"),
            StudioError::NoBlock { file, block } => write!(f, "{file} has no block {block}"),
            StudioError::NotAProgram { path } => write!(
                f,
                "{path}: the studio opens a project folder, its gutta.toml, or .lad files"
            ),
            StudioError::NotUtf8 { path, offset } => write!(
                f,
                "{path} is not UTF-8 text (invalid byte at offset {offset}): the studio edits UTF-8 files only"
            ),
            StudioError::Project(message) => f.write_str(message),
            StudioError::Io { path, message } => write!(f, "{path}: {message}"),
            StudioError::Edit(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for StudioError {}

impl From<ModelError> for StudioError {
    fn from(e: ModelError) -> StudioError {
        StudioError::Edit(e)
    }
}
