//! The one folder a studio session reads and writes in: the project's (gutta.toml's
//! folder) or the given files'. Every path is judged on its canonical form, so `..`
//! and symlinks cannot lead out; a name the page sends is relative and plain. It
//! decides and names paths; it reads and writes nothing.

use std::path::{Component, Path, PathBuf};

use super::StudioError;

/// The studio's folder, canonical.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Root {
    dir: PathBuf,
}

impl Root {
    /// `dir` as the studio's folder (it must exist).
    pub fn new(dir: &Path) -> Result<Root, StudioError> {
        let dir = dir.canonicalize().map_err(|e| StudioError::Io {
            path: dir.display().to_string(),
            message: e.to_string(),
        })?;
        Ok(Root { dir })
    }

    /// The folder itself.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// `path` (an existing file) as its canonical path, when that is inside the folder;
    /// else `StudioError::Escape` (a `..` or a symlink that leads out).
    pub fn confine(&self, path: &Path) -> Result<PathBuf, StudioError> {
        let canonical = path.canonicalize().map_err(|e| StudioError::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        if canonical.starts_with(&self.dir) && canonical != self.dir {
            Ok(canonical)
        } else {
            Err(self.escape(path))
        }
    }

    /// A name the page sends (`src/main.lad`, `./src/main.lad`) in the form
    /// [`Root::name_of`] gives, when it is relative with no `..`, root or drive; else
    /// `StudioError::Escape`. Judged on the text alone: the disk is not asked.
    pub fn plain_name(&self, name: &str) -> Result<String, StudioError> {
        let path = Path::new(name);
        let plain = path
            .components()
            .all(|c| matches!(c, Component::Normal(_) | Component::CurDir));
        let parts: Vec<_> = path
            .components()
            .filter_map(|c| match c {
                Component::Normal(part) => Some(part.to_string_lossy()),
                _ => None,
            })
            .collect();
        if !plain || parts.is_empty() {
            return Err(self.escape(path));
        }
        Ok(parts.join("/"))
    }

    /// A canonical path inside the folder as the page names it: relative, `/` between
    /// folders.
    pub fn name_of(&self, canonical: &Path) -> String {
        let relative = canonical.strip_prefix(&self.dir).unwrap_or(canonical);
        relative
            .components()
            .map(|c| c.as_os_str().to_string_lossy())
            .collect::<Vec<_>>()
            .join("/")
    }

    fn escape(&self, path: &Path) -> StudioError {
        StudioError::Escape {
            path: path.display().to_string(),
            root: self.dir.display().to_string(),
        }
    }
}
