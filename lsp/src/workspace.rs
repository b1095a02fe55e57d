//! Which program a document belongs to, and that program's analysis. A document in a
//! project (the nearest gutta.toml above it lists it as a source or symbol table) is
//! part of the project's one program: its sources and tables, open documents' text
//! winning over the disk; the PLC type is `[program] plc`/`target`, else the sources'
//! PLC_TYPE, else the stdlib default. Any other document is a program alone. Each
//! program is analysed once per change and kept until its last open document closes.
//! It converts LSP positions through documents.rs only and knows no LSP feature.

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

use gutta_catalog::{choose_target, TargetInputs};
use gutta_compiler::source::{FilePart, SourceFile};
use gutta_compiler::{check_program, CheckedFile, ExplicitTarget, ProgramSources};
use gutta_io::Project;
use lsp_types::{Position, Uri};

use crate::documents::{path_to_uri, uri_to_path, Documents, Lines};

/// A program's identity: its project's manifest, or the one document it is.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum ProgramKey {
    Project(PathBuf),
    Alone(Uri),
}

/// One analysed program.
#[derive(Debug)]
pub struct Program {
    pub key: ProgramKey,
    pub project: Option<Project>,
    /// The URI of each file of the program, parallel to `checked.file.parts()`.
    pub files: Vec<Uri>,
    pub parts: Vec<FilePart>,
    pub checked: CheckedFile,
    /// Line starts of the joined text (`checked.file.text`).
    pub lines: Lines,
    explicit: Option<ExplicitTarget>,
}

impl Program {
    /// The joined text every span points into.
    pub fn text(&self) -> &str {
        &self.checked.file.text
    }

    /// Index of `uri`'s file in the program.
    pub fn part_of(&self, uri: &Uri) -> Option<usize> {
        self.files.iter().position(|f| f == uri)
    }

    /// The byte offset in the joined text of `position` in `uri` (clamped to its file).
    pub fn offset(&self, uri: &Uri, position: Position) -> Option<usize> {
        let part = &self.parts[self.part_of(uri)?];
        let first = self.lines.line_of(part.start) as u32;
        let last = self.lines.line_of(part.end) as u32;
        let line = first.saturating_add(position.line);
        if line > last {
            return Some(part.end);
        }
        let at = self
            .lines
            .offset(self.text(), Position::new(line, position.character));
        Some(at.clamp(part.start, part.end))
    }

    /// The file (index into `files`) and position there of a joined-text offset.
    pub fn position(&self, offset: usize) -> (usize, Position) {
        let index = self.checked.file.part_index(offset);
        let first = self
            .parts
            .get(index)
            .map(|p| self.lines.line_of(p.start))
            .unwrap_or(0) as u32;
        let at = self.lines.position(self.text(), offset);
        (index, Position::new(at.line - first, at.character))
    }
}

/// What an update did, for the diagnostics publisher.
#[derive(Debug, Default)]
pub struct Update {
    /// The program analysed anew (publish all its files).
    pub analysed: Option<ProgramKey>,
    /// Files no program covers any more (publish empty lists).
    pub cleared: Vec<Uri>,
    /// Problems with a project that did not stop the analysis (for showMessage).
    pub warnings: Vec<String>,
}

/// Every program with an open document.
#[derive(Debug, Default)]
pub struct Workspace {
    programs: HashMap<ProgramKey, Program>,
    /// The program of each open document.
    members: HashMap<Uri, ProgramKey>,
}

impl Workspace {
    pub fn program(&self, key: &ProgramKey) -> Option<&Program> {
        self.programs.get(key)
    }

    /// The program an open document belongs to.
    pub fn program_of(&self, uri: &Uri) -> Option<&Program> {
        self.programs.get(self.members.get(uri)?)
    }

    /// The program of the open document `uri` and the joined-text offset of `position`.
    pub fn at(&self, uri: &Uri, position: Position) -> Option<(&Program, usize)> {
        let program = self.program_of(uri)?;
        Some((program, program.offset(uri, position)?))
    }

    pub fn programs(&self) -> impl Iterator<Item = &Program> {
        self.programs.values()
    }

    /// `uri` was opened (or saved): find its project again and analyse its program.
    pub fn opened(&mut self, documents: &Documents, uri: &Uri) -> Update {
        let mut update = Update::default();
        let Some(found) = resolve(uri, &mut update.warnings) else {
            // A symbol table outside a project is not a program.
            let mut closed = self.closed(documents, uri);
            closed.warnings.append(&mut update.warnings);
            return closed;
        };
        self.join(uri, &found.key, &mut update);
        self.analyse(
            documents,
            found.key,
            found.project,
            found.explicit,
            &mut update,
        );
        update
    }

    /// Files on disk changed (`changed`: their URIs): every open document finds its
    /// project again when a gutta.toml changed; each program that holds a changed file
    /// or whose membership changed is analysed once.
    pub fn files_changed(&mut self, documents: &Documents, changed: &[Uri]) -> Vec<Update> {
        let manifest_changed = changed.iter().any(|u| {
            uri_to_path(u)
                .and_then(|p| p.file_name().map(|n| n == gutta_io::MANIFEST))
                .unwrap_or(false)
        });
        let mut updates = Vec::new();
        let mut to_analyse: Vec<(ProgramKey, Option<Project>, Option<ExplicitTarget>)> = Vec::new();
        if manifest_changed {
            let mut update = Update::default();
            let members: Vec<Uri> = self.members.keys().cloned().collect();
            for uri in members {
                match resolve(&uri, &mut update.warnings) {
                    Some(found) => {
                        self.join(&uri, &found.key, &mut update);
                        if !to_analyse.iter().any(|(k, _, _)| *k == found.key) {
                            to_analyse.push((found.key, found.project, found.explicit));
                        }
                    }
                    None => updates.push(self.closed(documents, &uri)),
                }
            }
            updates.push(update);
        } else {
            let changed: HashSet<&str> = changed.iter().map(|u| u.as_str()).collect();
            for program in self.programs.values() {
                let touched = program
                    .files
                    .iter()
                    .any(|f| changed.contains(f.as_str()) && !documents.is_open(f));
                if touched {
                    to_analyse.push((
                        program.key.clone(),
                        program.project.clone(),
                        program.explicit.clone(),
                    ));
                }
            }
        }
        for (key, project, explicit) in to_analyse {
            let mut update = Update::default();
            self.analyse(documents, key, project, explicit, &mut update);
            updates.push(update);
        }
        updates
    }

    /// Make `uri` a member of `key`, dropping the program it leaves if that one has no
    /// open document left.
    fn join(&mut self, uri: &Uri, key: &ProgramKey, update: &mut Update) {
        if let Some(old) = self.members.insert(uri.clone(), key.clone()) {
            if old != *key && !self.members.values().any(|k| *k == old) {
                if let Some(p) = self.programs.remove(&old) {
                    update.cleared.extend(p.files);
                }
            }
        }
    }

    /// `uri` changed: analyse its program again.
    pub fn changed(&mut self, documents: &Documents, uri: &Uri) -> Update {
        match self.members.get(uri).cloned() {
            Some(key) => self.changed_key(documents, key),
            None => Update::default(),
        }
    }

    /// `uri` was closed (already gone from `documents`): its program is dropped when no
    /// open document is left in it, else analysed again with the file from disk.
    pub fn closed(&mut self, documents: &Documents, uri: &Uri) -> Update {
        let mut update = Update::default();
        let Some(key) = self.members.remove(uri) else {
            return update;
        };
        if self.members.values().any(|k| *k == key) {
            return self.changed_key(documents, key);
        }
        if let Some(p) = self.programs.remove(&key) {
            update.cleared.extend(p.files);
        }
        update
    }

    /// Analyse the program `key` again with the project it was found with.
    fn changed_key(&mut self, documents: &Documents, key: ProgramKey) -> Update {
        let mut update = Update::default();
        let (project, explicit) = match self.programs.get(&key) {
            Some(p) => (p.project.clone(), p.explicit.clone()),
            None => (None, None),
        };
        self.analyse(documents, key, project, explicit, &mut update);
        update
    }

    fn analyse(
        &mut self,
        documents: &Documents,
        key: ProgramKey,
        project: Option<Project>,
        explicit: Option<ExplicitTarget>,
        update: &mut Update,
    ) {
        // Open documents by path, also canonical (a symlinked folder is the same file).
        let mut open_paths: HashMap<PathBuf, Uri> = HashMap::new();
        if project.is_some() {
            for u in documents.uris() {
                let Some(path) = uri_to_path(u) else { continue };
                if let Ok(canonical) = std::fs::canonicalize(&path) {
                    open_paths.insert(canonical, u.clone());
                }
                open_paths.insert(path, u.clone());
            }
        }
        let mut files = Vec::new();
        let mut sources = ProgramSources::default();
        match (&key, &project) {
            (ProgramKey::Project(_), Some(p)) => {
                sources.options.scale_timer_presets = p.scale_timer_presets;
                sources.options.s_area = p.s_area.as_deref().and_then(|s| s.parse().ok());
                for (paths, tables) in [(&p.sources, false), (&p.symbols, true)] {
                    for path in paths {
                        let (uri, file) = load(
                            documents,
                            &open_paths,
                            &p.root,
                            (path, tables),
                            &mut update.warnings,
                        );
                        files.push(uri);
                        if tables {
                            sources.symbol_tables.push(file);
                        } else {
                            sources.sources.push(file);
                        }
                    }
                }
            }
            _ => {
                let uri = match &key {
                    ProgramKey::Alone(uri) => uri.clone(),
                    ProgramKey::Project(_) => return,
                };
                let text = documents
                    .get(&uri)
                    .map(|d| d.text.clone())
                    .unwrap_or_default();
                let name = uri_to_path(&uri)
                    .and_then(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
                    .unwrap_or_else(|| uri.as_str().to_string());
                sources.sources.push(SourceFile::new(name, text));
                files.push(uri);
            }
        }
        let checked = check_program(sources, explicit.as_ref());
        let lines = Lines::new(&checked.file.text);
        let parts = checked.file.parts();
        let program = Program {
            key: key.clone(),
            project,
            files,
            parts,
            checked,
            lines,
            explicit,
        };
        if let Some(old) = self.programs.insert(key.clone(), program) {
            let now: HashSet<&str> = self.programs[&key]
                .files
                .iter()
                .map(|u| u.as_str())
                .collect();
            update
                .cleared
                .extend(old.files.into_iter().filter(|f| !now.contains(f.as_str())));
        }
        update.analysed = Some(key);
    }
}

/// Where a document belongs.
struct Resolution {
    key: ProgramKey,
    project: Option<Project>,
    explicit: Option<ExplicitTarget>,
}

/// The program `uri` belongs to: its project's when the nearest gutta.toml lists it,
/// else itself alone; `None` for a symbol table outside a project.
fn resolve(uri: &Uri, warnings: &mut Vec<String>) -> Option<Resolution> {
    let path = uri_to_path(uri);
    let project = match path.as_deref().and_then(Path::parent) {
        Some(folder) => match Project::find(folder) {
            Ok(found) => found.filter(|p| lists(p, path.as_deref())),
            Err(e) => {
                warnings.push(e);
                None
            }
        },
        None => None,
    };
    if let Some(p) = project {
        return Some(Resolution {
            key: ProgramKey::Project(p.manifest.clone()),
            explicit: project_target(&p, warnings),
            project: Some(p),
        });
    }
    let is_table = path
        .as_deref()
        .and_then(Path::extension)
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("csv") || e.eq_ignore_ascii_case("tsv"));
    (!is_table).then(|| Resolution {
        key: ProgramKey::Alone(uri.clone()),
        project: None,
        explicit: None,
    })
}

/// Whether project `p` lists `path` as a source or a symbol table.
fn lists(p: &Project, path: Option<&Path>) -> bool {
    let Some(path) = path else { return false };
    let canonical = std::fs::canonicalize(path).ok();
    p.sources
        .iter()
        .chain(&p.symbols)
        .any(|f| f == path || (canonical.is_some() && std::fs::canonicalize(f).ok() == canonical))
}

/// A project file (`table`: one of its symbol tables): the open document's text if it is
/// open, else the disk's, decoded as gutta-cc decodes it (empty, and a warning, if
/// unreadable). Named by its path relative to the project's folder.
fn load(
    documents: &Documents,
    open: &HashMap<PathBuf, Uri>,
    root: &Path,
    (path, table): (&Path, bool),
    warnings: &mut Vec<String>,
) -> (Uri, SourceFile) {
    let name = path
        .strip_prefix(root)
        .unwrap_or(path)
        .to_string_lossy()
        .replace('\\', "/");
    let open_uri = open.get(path).cloned().or_else(|| {
        let canonical = std::fs::canonicalize(path).ok()?;
        open.get(&canonical).cloned()
    });
    if let Some(uri) = open_uri {
        if let Some(doc) = documents.get(&uri) {
            return (uri, SourceFile::new(name, doc.text.clone()));
        }
    }
    let uri = path_to_uri(path).unwrap_or_else(|| fallback_uri(&name));
    let file = match std::fs::read(path) {
        // Micro/WIN exports and symbol tables in their code page, as gutta-cc reads them.
        Ok(bytes) => match SourceFile::from_program_file_bytes(name.clone(), bytes, table) {
            Ok((file, _)) => file,
            Err(e) => {
                warnings.push(format!("{name}: not UTF-8 at byte {}", e.offset));
                SourceFile::new(name, "")
            }
        },
        Err(e) => {
            warnings.push(format!("cannot read {}: {e}", path.display()));
            SourceFile::new(name, "")
        }
    };
    (uri, file)
}

/// A URI for a file whose path would not encode (never in practice).
fn fallback_uri(name: &str) -> Uri {
    format!(
        "untitled:{}",
        name.replace(|c: char| !c.is_ascii_alphanumeric(), "_")
    )
    .parse()
    .unwrap_or_else(|_| panic!("an alphanumeric untitled: URI always parses"))
}

/// `[program] plc`/`target` as the compiler's explicit target; a target that does not
/// load is a warning, and the sources' PLC_TYPE decides instead.
fn project_target(p: &Project, warnings: &mut Vec<String>) -> Option<ExplicitTarget> {
    let project = p.plc.spec();
    let chosen = choose_target(&TargetInputs {
        project: project.as_ref(),
        ..TargetInputs::default()
    })
    .named()?;
    match gutta_io::load_target(&chosen.spec) {
        Ok(target) => Some(ExplicitTarget {
            target,
            origin: chosen.origin.to_string(),
        }),
        Err(e) => {
            let key = chosen.origin.project_key().unwrap_or_default();
            warnings.push(format!("{}: {key}: {e}", p.manifest.display()));
            None
        }
    }
}
