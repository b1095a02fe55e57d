//! The files the studio serves (docs/studio.md, "The server"): the program the command
//! line names (a project's sources and symbol tables, or the files given), opened as
//! the session, and every path a request names held inside the session's one folder
//! (`gutta_cli::studio::Root`): no `..`, no absolute path, no symlink out; only `.lad`
//! files are written. It knows nothing of HTTP but the refusals.

use std::path::{Path, PathBuf};

use gutta_cli::fatal::Fatal;
use gutta_cli::studio::{Root, Session, StudioError};
use gutta_compiler::ExplicitTarget;

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
    /// A project (its gutta.toml decides), not files given by name.
    project: bool,
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
            project: true,
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
            project: false,
        })
    }

    /// The session on these files: the project's, or the files given with the
    /// command line's symbol tables, target and scaling.
    pub(crate) fn open_session(&self) -> Result<Session, Fatal> {
        let fail = |e: StudioError| Fatal::usage(e.to_string());
        if self.project {
            return Session::open(std::slice::from_ref(&self.root)).map_err(fail);
        }
        let mut session = Session::open(&self.sources).map_err(fail)?;
        if !self.tables.is_empty() || self.target.is_some() || self.scale_timer_presets {
            session
                .configure(&self.tables, self.target.clone(), self.scale_timer_presets)
                .map_err(fail)?;
        }
        Ok(session)
    }
}

/// The file a request names by `relative`, held inside the session's folder (`root`,
/// the session's one folder rule): refused when it leaves it by `..`, an absolute path
/// or a symlink, and (to write) when it is not a `.lad` file or its folder does not
/// exist. A symlink inside is followed: the answer is the file it names.
pub(crate) fn resolve(root: &Root, relative: &str, access: Access) -> Result<PathBuf, Refusal> {
    if relative.trim().is_empty() || relative.contains('\0') {
        return Err(Refusal::PathInvalid(relative.to_string()));
    }
    let escape = || Refusal::PathEscape(relative.to_string());
    let plain = root.plain_name(relative).map_err(|_| escape())?;
    if access == Access::WriteLad && !is_lad(Path::new(&plain)) {
        return Err(Refusal::NotLad(relative.to_string()));
    }
    let joined = root.dir().join(&plain);
    let resolved = if joined.exists() {
        root.confine(&joined).map_err(|_| escape())?
    } else if joined.symlink_metadata().is_ok() {
        // A symlink whose target is missing.
        return Err(escape());
    } else if access == Access::Read {
        return Err(Refusal::NotFound(relative.to_string()));
    } else {
        let folder = joined
            .parent()
            .filter(|p| p.is_dir())
            .ok_or_else(|| Refusal::NotFound(relative.to_string()))?;
        let name = joined
            .file_name()
            .ok_or_else(|| Refusal::PathInvalid(relative.to_string()))?;
        let inside = if folder == root.dir() {
            root.dir().to_path_buf()
        } else {
            root.confine(folder).map_err(|_| escape())?
        };
        inside.join(name)
    };
    if resolved.is_dir() {
        return Err(Refusal::PathInvalid(relative.to_string()));
    }
    if access == Access::WriteLad && !is_lad(&resolved) {
        return Err(Refusal::NotLad(relative.to_string()));
    }
    Ok(resolved)
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

    fn root(tag: &str) -> (Root, PathBuf) {
        let base =
            std::env::temp_dir().join(format!("gutta-studio-files-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&base);
        let dir = base.join("project");
        std::fs::create_dir_all(dir.join("src")).unwrap();
        std::fs::write(dir.join("src/main.lad"), "").unwrap();
        std::fs::write(base.join("outside.lad"), "").unwrap();
        (Root::new(&dir).unwrap(), base)
    }

    #[test]
    fn paths_stay_inside_the_folder() {
        let (r, base) = root("inside");
        let main = r.dir().join("src/main.lad");
        assert_eq!(resolve(&r, "src/main.lad", Access::Read), Ok(main.clone()));
        assert_eq!(resolve(&r, "./src/main.lad", Access::WriteLad), Ok(main));
        assert_eq!(
            resolve(&r, "src/new.lad", Access::WriteLad),
            Ok(r.dir().join("src/new.lad"))
        );
        assert_eq!(
            resolve(&r, "top.lad", Access::WriteLad),
            Ok(r.dir().join("top.lad"))
        );
        let outside = base.join("outside.lad").display().to_string();
        for escape in [
            "../outside.lad",
            "src/../../outside.lad",
            outside.as_str(),
            "/etc/passwd",
        ] {
            let refused = resolve(&r, escape, Access::WriteLad).unwrap_err();
            assert_eq!(refused.code(), "path-escape", "{escape}");
        }
        let code = |p: &str, a| resolve(&r, p, a).unwrap_err().code().to_string();
        assert_eq!(code("gutta.toml", Access::WriteLad), "path-not-lad");
        assert_eq!(code("missing.txt", Access::Read), "not-found");
        assert_eq!(code("none/x.lad", Access::WriteLad), "not-found");
        assert_eq!(code("", Access::Read), "path-invalid");
        assert_eq!(code("src", Access::Read), "path-invalid");
    }

    #[cfg(unix)]
    #[test]
    fn a_symlink_out_of_the_folder_is_refused() {
        let (r, base) = root("symlink");
        let dir = r.dir();
        std::os::unix::fs::symlink(base.join("outside.lad"), dir.join("link.lad")).unwrap();
        std::os::unix::fs::symlink(&base, dir.join("up")).unwrap();
        std::os::unix::fs::symlink(base.join("gone.lad"), dir.join("dangling.lad")).unwrap();
        for escape in ["link.lad", "up/outside.lad", "up/new.lad", "dangling.lad"] {
            let refused = resolve(&r, escape, Access::WriteLad).unwrap_err();
            assert_eq!(refused.code(), "path-escape", "{escape}");
        }
        std::os::unix::fs::symlink(dir.join("src/main.lad"), dir.join("alias.lad")).unwrap();
        assert_eq!(
            resolve(&r, "alias.lad", Access::WriteLad),
            Ok(dir.join("src/main.lad"))
        );
    }
}
