//! The files the studio serves (docs/studio.md, "The server"): the program (a project's
//! sources and symbol tables, or the files given), the one folder the studio may read
//! and write (the project's, or the given files'), and every path a request names held
//! inside it: no `..`, no absolute path, no symlink out; only `.lad` files are written.
//! It compiles what is on disk; it knows nothing of HTTP but the refusals.

use std::path::{Component, Path, PathBuf};

use gutta_cli::fatal::Fatal;
use gutta_compiler::{check_program, CheckedFile, ExplicitTarget};

use super::refusal::Refusal;
use crate::args::Cli;

/// What a path is resolved for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Access {
    Read,
    /// Writing a `.lad` source (which may not exist yet: its folder must).
    WriteLad,
}

/// The program and the folder it lives in.
pub(crate) struct ProgramFiles {
    /// The project's name, or the first file's.
    pub name: String,
    /// The folder the studio may read and write, canonical.
    pub root: PathBuf,
    /// The sources of the one program, canonical, in order.
    pub sources: Vec<PathBuf>,
    /// Symbol tables, canonical.
    pub tables: Vec<PathBuf>,
    scale_timer_presets: bool,
    target: Option<ExplicitTarget>,
}

impl ProgramFiles {
    /// A project folder, source files, or (nothing given) the project around the current
    /// directory.
    pub(crate) fn from_command_line(cli: &Cli, paths: &[PathBuf]) -> Result<ProgramFiles, Fatal> {
        match paths {
            [] => {
                let project = crate::project::required(cli.project.as_ref(), "studio")?;
                Self::of_project(cli, &project)
            }
            [dir] if dir.is_dir() => {
                let project = gutta_io::Project::find(dir)
                    .map_err(Fatal::usage)?
                    .ok_or_else(|| {
                        Fatal::usage(format!(
                            "{} is not inside a project ({}): create one with `gutta-cc new NAME`, or give the .lad files",
                            dir.display(),
                            gutta_io::MANIFEST
                        ))
                    })?;
                Self::of_project(cli, &project)
            }
            files => Self::of_files(cli, files),
        }
    }

    fn of_project(cli: &Cli, project: &gutta_io::Project) -> Result<ProgramFiles, Fatal> {
        let root = canonical(&project.root)?;
        let sources = project
            .sources
            .iter()
            .map(|p| canonical(p))
            .collect::<Result<Vec<_>, _>>()?;
        let target = gutta_cli::target::TargetArgs {
            project: project.plc.spec(),
            ..cli.target.clone()
        };
        Ok(ProgramFiles {
            name: project.name.clone(),
            root,
            sources,
            tables: project
                .symbols
                .iter()
                .map(|p| canonical(p))
                .collect::<Result<Vec<_>, _>>()?,
            scale_timer_presets: project.scale_timer_presets || cli.scale_timer_presets,
            target: target.explicit()?,
        })
    }

    fn of_files(cli: &Cli, files: &[PathBuf]) -> Result<ProgramFiles, Fatal> {
        let sources = files
            .iter()
            .map(|p| canonical(p))
            .collect::<Result<Vec<_>, _>>()?;
        let root = sources[0]
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_default();
        if let Some((given, _)) = files
            .iter()
            .zip(&sources)
            .find(|(_, s)| !s.starts_with(&root))
        {
            return Err(Fatal::usage(format!(
                "{}: the studio works in one folder, {}'s; give files of that folder (or a project)",
                given.display(),
                files[0].display()
            )));
        }
        let tables = cli
            .symbols
            .iter()
            .filter(|p| !p.extension().is_some_and(|x| x.eq_ignore_ascii_case("lad")))
            .map(|p| canonical(p))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(ProgramFiles {
            name: files[0].display().to_string(),
            root,
            sources,
            tables,
            scale_timer_presets: cli.scale_timer_presets,
            target: cli.target.explicit()?,
        })
    }

    /// `path` as the studio names it: relative to the folder, `/`-separated (a symbol
    /// table outside the folder keeps its whole path; the studio does not serve it).
    pub(crate) fn relative(&self, path: &Path) -> String {
        let Ok(inside) = path.strip_prefix(&self.root) else {
            return path.display().to_string();
        };
        inside
            .components()
            .map(|c| c.as_os_str().to_string_lossy())
            .collect::<Vec<_>>()
            .join("/")
    }

    /// The program as it is on disk now, checked.
    pub(crate) fn check(&self) -> Result<CheckedFile, Fatal> {
        let named = |paths: &[PathBuf]| -> Vec<PathBuf> {
            paths
                .iter()
                .map(|p| p.strip_prefix(&self.root).unwrap_or(p).to_path_buf())
                .collect()
        };
        let mut program = gutta_cli::sources::read_program_in(
            &self.root,
            &named(&self.sources),
            &named(&self.tables),
        )?;
        program.options.scale_timer_presets = self.scale_timer_presets;
        Ok(check_program(program, self.target.as_ref()))
    }

    /// The file a request names by `relative`, held inside the folder: refused when it
    /// leaves it by `..`, an absolute path or a symlink, and (to write) when it is not a
    /// `.lad` file or its folder does not exist. A symlink inside is followed: the
    /// answer is the file it names.
    pub(crate) fn resolve(&self, relative: &str, access: Access) -> Result<PathBuf, Refusal> {
        let path = Path::new(relative);
        if relative.trim().is_empty() || relative.contains('\0') {
            return Err(Refusal::PathInvalid(relative.to_string()));
        }
        let escapes = path.is_absolute()
            || relative.starts_with(['/', '\\'])
            || path.components().any(|c| {
                matches!(
                    c,
                    Component::ParentDir | Component::RootDir | Component::Prefix(_)
                )
            });
        if escapes {
            return Err(Refusal::PathEscape(relative.to_string()));
        }
        if access == Access::WriteLad && !is_lad(path) {
            return Err(Refusal::NotLad(relative.to_string()));
        }
        let joined = self.root.join(path);
        let resolved = match joined.canonicalize() {
            Ok(real) => real,
            // A symlink whose target is missing, or a file not there yet.
            Err(_) if joined.symlink_metadata().is_ok() => {
                return Err(Refusal::PathEscape(relative.to_string()))
            }
            Err(_) if access == Access::Read => {
                return Err(Refusal::NotFound(relative.to_string()))
            }
            Err(_) => {
                let folder = joined
                    .parent()
                    .and_then(|p| p.canonicalize().ok())
                    .ok_or_else(|| Refusal::NotFound(relative.to_string()))?;
                let name = joined
                    .file_name()
                    .ok_or_else(|| Refusal::PathInvalid(relative.to_string()))?;
                folder.join(name)
            }
        };
        if !resolved.starts_with(&self.root) {
            return Err(Refusal::PathEscape(relative.to_string()));
        }
        if resolved.is_dir() {
            return Err(Refusal::PathInvalid(relative.to_string()));
        }
        if access == Access::WriteLad && !is_lad(&resolved) {
            return Err(Refusal::NotLad(relative.to_string()));
        }
        Ok(resolved)
    }
}

fn is_lad(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("lad"))
}

fn canonical(path: &Path) -> Result<PathBuf, Fatal> {
    path.canonicalize()
        .map_err(|e| Fatal::io(format!("cannot read {}: {e}", path.display())))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn files(tag: &str) -> (ProgramFiles, PathBuf) {
        let base =
            std::env::temp_dir().join(format!("gutta-studio-files-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&base);
        let root = base.join("project");
        std::fs::create_dir_all(root.join("src")).unwrap();
        std::fs::write(root.join("src/main.lad"), "").unwrap();
        std::fs::write(base.join("outside.lad"), "").unwrap();
        let root = root.canonicalize().unwrap();
        let files = ProgramFiles {
            name: "project".into(),
            sources: vec![root.join("src/main.lad")],
            root,
            tables: Vec::new(),
            scale_timer_presets: false,
            target: None,
        };
        (files, base)
    }

    #[test]
    fn paths_stay_inside_the_folder() {
        let (f, base) = files("inside");
        let main = f.root.join("src/main.lad");
        assert_eq!(f.resolve("src/main.lad", Access::Read), Ok(main.clone()));
        assert_eq!(f.resolve("./src/main.lad", Access::WriteLad), Ok(main));
        assert_eq!(
            f.resolve("src/new.lad", Access::WriteLad),
            Ok(f.root.join("src/new.lad"))
        );
        let outside = base.join("outside.lad").display().to_string();
        for escape in [
            "../outside.lad",
            "src/../../outside.lad",
            outside.as_str(),
            "/etc/passwd",
        ] {
            let refused = f.resolve(escape, Access::WriteLad).unwrap_err();
            assert_eq!(refused.code(), "path-escape", "{escape}");
        }
        assert_eq!(
            f.resolve("gutta.toml", Access::WriteLad)
                .unwrap_err()
                .code(),
            "path-not-lad"
        );
        assert_eq!(
            f.resolve("missing.txt", Access::Read).unwrap_err().code(),
            "not-found"
        );
        assert_eq!(
            f.resolve("none/x.lad", Access::WriteLad)
                .unwrap_err()
                .code(),
            "not-found"
        );
        assert_eq!(
            f.resolve("", Access::Read).unwrap_err().code(),
            "path-invalid"
        );
        assert_eq!(
            f.resolve("src", Access::Read).unwrap_err().code(),
            "path-invalid"
        );
        assert_eq!(f.relative(&f.root.join("src/main.lad")), "src/main.lad");
        let table = base.join("symbols.csv");
        assert_eq!(f.relative(&table), table.display().to_string());
    }

    #[cfg(unix)]
    #[test]
    fn a_symlink_out_of_the_folder_is_refused() {
        let (f, base) = files("symlink");
        std::os::unix::fs::symlink(base.join("outside.lad"), f.root.join("link.lad")).unwrap();
        std::os::unix::fs::symlink(&base, f.root.join("up")).unwrap();
        std::os::unix::fs::symlink(base.join("gone.lad"), f.root.join("dangling.lad")).unwrap();
        for escape in ["link.lad", "up/outside.lad", "up/new.lad", "dangling.lad"] {
            let refused = f.resolve(escape, Access::WriteLad).unwrap_err();
            assert_eq!(refused.code(), "path-escape", "{escape}");
        }
        std::os::unix::fs::symlink(f.root.join("src/main.lad"), f.root.join("alias.lad")).unwrap();
        assert_eq!(
            f.resolve("alias.lad", Access::WriteLad),
            Ok(f.root.join("src/main.lad"))
        );
    }
}
