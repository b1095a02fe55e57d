//! `Session`: the files a studio has open (a project's program files, or `.lad` files
//! given by name), each with its buffer (the text, saved or not), its checked program,
//! its ladder (`gutta_ladder::build`) and an `Editor` over its JSON model with undo and
//! redo. An edit goes to the editor, its changes into the buffer in place
//! (`edit::apply_to_text`), then the buffer is checked again and the touched networks
//! redrawn. Reads the files at `open`, writes one at `save` (atomically, only inside the
//! studio's folder); nothing else touches the disk.

use std::path::{Path, PathBuf};

use gutta_compiler::source::{LineIndex, SourceFile, Span};
use gutta_compiler::{check_program, CheckedFile, CompileOptions, ExplicitTarget, ProgramSources};
use gutta_io::Project;
use gutta_ladder::edit::{apply_to_text, Change, Edit, Editor, NetworkPath};
use gutta_ladder::json::{self, Model, ModelDiagnostic};
use gutta_ladder::model::Ladder;

use super::summary::{symbols, FileSummary, ProjectSummary, TableSummary};
use super::update::{drawings, shapes};
use super::{Root, StudioError, Update};

type Studio<T> = Result<T, StudioError>;

/// The UTF-8 byte order mark: kept off the buffer, written back at save.
const BOM: &str = "\u{feff}";

/// An open studio session.
#[derive(Debug)]
pub struct Session {
    pub(super) root: Root,
    pub(super) name: String,
    /// The project's choice of target (`[program] plc`/`target`); `None`: each file's
    /// `PLC_TYPE`, else the stdlib default.
    pub(super) target: Option<ExplicitTarget>,
    /// The project's symbol tables: their buffers, named as the page names files.
    pub(super) tables: Vec<SourceFile>,
    /// Each table's canonical path inside the root and its text on disk.
    pub(super) table_paths: Vec<PathBuf>,
    pub(super) table_saved: Vec<String>,
    /// Whether each table began with a UTF-8 byte order mark (written back at save).
    pub(super) table_bom: Vec<bool>,
    pub(super) options: CompileOptions,
    pub(super) files: Vec<OpenFile>,
    pub(super) tests: Vec<String>,
}

/// One open `.lad` file.
#[derive(Debug)]
pub(super) struct OpenFile {
    /// As the page names it: relative to the root, `/` between folders.
    pub(super) name: String,
    /// Canonical, inside the root.
    pub(super) path: PathBuf,
    pub(super) bom: bool,
    /// The buffer.
    pub(super) text: String,
    /// The text on disk (as last read or saved).
    pub(super) saved: String,
    pub(super) checked: CheckedFile,
    pub(super) ladder: Ladder,
    pub(super) editor: Editor<'static>,
    pub(super) diagnostics: Vec<ModelDiagnostic>,
    /// The buffer before each applied edit (for undo) and before each undo (for redo):
    /// undo and redo restore the exact text, whatever the file's formatting was.
    pub(super) undo_texts: Vec<String>,
    pub(super) redo_texts: Vec<String>,
    /// How many steps on top of `undo_texts` (and of `redo_texts`) the editor's own
    /// history can take back (and apply again): ladder edits since the model was last
    /// rebuilt from the text. Any other step (an STL edit, a symbol rename, an undo or
    /// redo past them) rebuilds the model from the text it restores, and the editor's
    /// history starts again.
    pub(super) editor_undo: usize,
    pub(super) editor_redo: usize,
}

impl Session {
    /// A session on `paths`: one project folder or its gutta.toml (the program's
    /// sources and tables), or `.lad` files in one folder (with what is below it).
    /// Every file must lie inside that folder once symlinks are resolved.
    pub fn open(paths: &[PathBuf]) -> Studio<Session> {
        let project_manifest = match paths {
            [one] if one.is_dir() => Some(one.join(gutta_io::MANIFEST)),
            [one] if one.file_name().is_some_and(|n| n == gutta_io::MANIFEST) => Some(one.clone()),
            _ => None,
        };
        let mut session = match project_manifest {
            Some(manifest) => Session::of_project(&manifest)?,
            None => Session::of_files(paths)?,
        };
        session.tests = gtest_files(&session.root);
        Ok(session)
    }

    fn of_project(manifest: &Path) -> Studio<Session> {
        let project = Project::load(manifest).map_err(StudioError::Project)?;
        let root = Root::new(&project.root)?;
        let target = gutta_cli_target(&project)?;
        let mut tables = Vec::new();
        let mut table_paths = Vec::new();
        let mut table_bom = Vec::new();
        for table in &project.symbols {
            let path = root.confine(table)?;
            let name = root.name_of(&path);
            let bytes = read(&path)?;
            table_bom.push(bytes.starts_with(BOM.as_bytes()));
            let (file, _) =
                SourceFile::from_program_file_bytes(&name, bytes, true).map_err(|e| {
                    StudioError::NotUtf8 {
                        path: name.clone(),
                        offset: e.offset,
                    }
                })?;
            tables.push(file);
            table_paths.push(path);
        }
        let table_saved = tables.iter().map(|t| t.text.clone()).collect();
        let mut session = Session {
            root,
            name: project.name.clone(),
            target,
            tables,
            table_paths,
            table_saved,
            table_bom,
            options: CompileOptions {
                scale_timer_presets: project.scale_timer_presets,
                s_area: project.s_area.as_deref().and_then(|s| s.parse().ok()),
            },
            files: Vec::new(),
            tests: Vec::new(),
        };
        for source in &project.sources {
            session.add(source)?;
        }
        Ok(session)
    }

    fn of_files(paths: &[PathBuf]) -> Studio<Session> {
        let Some(first) = paths.first() else {
            return Err(StudioError::NotAProgram {
                path: String::new(),
            });
        };
        for path in paths {
            let lad = path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("lad"));
            if !lad || !path.is_file() {
                return Err(StudioError::NotAProgram {
                    path: path.display().to_string(),
                });
            }
        }
        let folder = first
            .canonicalize()
            .map_err(|e| StudioError::Io {
                path: first.display().to_string(),
                message: e.to_string(),
            })?
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_default();
        let root = Root::new(&folder)?;
        let name = folder
            .file_name()
            .map_or_else(|| "program".into(), |n| n.to_string_lossy().into_owned());
        let mut session = Session {
            root,
            name,
            target: None,
            tables: Vec::new(),
            table_paths: Vec::new(),
            table_saved: Vec::new(),
            table_bom: Vec::new(),
            options: CompileOptions::default(),
            files: Vec::new(),
            tests: Vec::new(),
        };
        for path in paths {
            session.add(path)?;
        }
        Ok(session)
    }

    /// A source file read, confined, checked and modelled.
    fn add(&mut self, path: &Path) -> Studio<()> {
        let path = self.root.confine(path)?;
        let name = self.root.name_of(&path);
        if self.files.iter().any(|f| f.path == path) {
            return Ok(());
        }
        let bytes = read(&path)?;
        let text = String::from_utf8(bytes).map_err(|e| StudioError::NotUtf8 {
            path: name.clone(),
            offset: e.utf8_error().valid_up_to(),
        })?;
        let (bom, text) = match text.strip_prefix(BOM) {
            Some(rest) => (true, rest.to_string()),
            None => (false, text),
        };
        let checked = self.check(&name, &text);
        let ladder = gutta_ladder::build(&checked);
        let model = json::model_of(&checked, &ladder);
        let editor = Editor::owning(model, checked.target.instructions.clone());
        let mut file = OpenFile {
            name,
            path,
            bom,
            saved: text.clone(),
            text,
            checked,
            ladder,
            editor,
            diagnostics: Vec::new(),
            undo_texts: Vec::new(),
            redo_texts: Vec::new(),
            editor_undo: 0,
            editor_redo: 0,
        };
        file.diagnostics = model_diagnostics(&file, self.target.as_ref());
        self.files.push(file);
        if self.files.len() > 1 {
            self.diagnose_program();
        }
        Ok(())
    }

    /// The buffer `text` of the file `name` checked as a program with the project's
    /// tables, on the project's target.
    fn check(&self, name: &str, text: &str) -> CheckedFile {
        check_program(
            ProgramSources {
                sources: vec![SourceFile::new(name, text)],
                symbol_tables: self.tables.clone(),
                options: self.options.clone(),
            },
            self.target.as_ref(),
        )
    }

    /// The studio's folder.
    pub fn root(&self) -> &Path {
        self.root.dir()
    }

    /// The open files' names, in order (`src/main.lad`).
    pub fn files(&self) -> Vec<&str> {
        self.files.iter().map(|f| f.name.as_str()).collect()
    }

    /// The project for the page: files, blocks, symbols, tests.
    pub fn project(&self) -> ProjectSummary {
        ProjectSummary {
            name: self.name.clone(),
            plc: self
                .files
                .first()
                .map(|f| f.editor.model().plc.clone())
                .unwrap_or_default(),
            files: self
                .files
                .iter()
                .map(|f| FileSummary::of(&f.name, f.is_dirty(), f.editor.model()))
                .collect(),
            symbols: symbols(self.files.iter().map(|f| f.editor.model())),
            tables: self
                .tables
                .iter()
                .zip(&self.table_saved)
                .map(|(t, saved)| TableSummary {
                    name: t.name.clone(),
                    dirty: t.text != *saved,
                })
                .collect(),
            tests: self.tests.clone(),
        }
    }

    /// The buffer of `file`, saved or not.
    pub fn text(&self, file: &str) -> Studio<&str> {
        Ok(&self.file(file)?.text)
    }

    /// The ladder model of `file` as it is now.
    pub fn model(&self, file: &str) -> Studio<&Model> {
        Ok(self.file(file)?.editor.model())
    }

    /// The checked program of `file`'s buffer.
    pub fn checked(&self, file: &str) -> Studio<&CheckedFile> {
        Ok(&self.file(file)?.checked)
    }

    /// Every diagnostic of `file` at the JSON path of its cause.
    pub fn diagnostics(&self, file: &str) -> Studio<&[ModelDiagnostic]> {
        Ok(&self.file(file)?.diagnostics)
    }

    /// Whether `file`'s buffer differs from the file on disk.
    pub fn is_dirty(&self, file: &str) -> Studio<bool> {
        Ok(self.file(file)?.is_dirty())
    }

    /// `edit_json` (an edit operation's JSON, docs/ladder.md "Editing the model")
    /// applied to `file`: written into its buffer in place, checked, the touched
    /// networks redrawn. A refused edit is its L code, and nothing changed.
    pub fn apply(&mut self, file: &str, edit_json: &str) -> Studio<Update> {
        let edit = Edit::from_json(edit_json)?;
        let target = self.target.clone();
        let index = self.index(file)?;
        let f = &mut self.files[index];
        let changes = f.editor.apply(edit)?;
        let text = match rewrite(f, &changes) {
            Ok(text) => text,
            Err(e) => {
                // The text did not take the change: the model goes back with it, and
                // nothing can be redone (the editor keeps the refused edit as undone;
                // `redo` goes by the texts, which have none for it).
                let _ = f.editor.undo();
                f.redo_texts.clear();
                f.editor_redo = 0;
                return Err(e);
            }
        };
        let before = std::mem::replace(&mut f.text, text);
        f.undo_texts.push(before);
        f.redo_texts.clear();
        f.editor_undo += 1;
        f.editor_redo = 0;
        Ok(self.refresh(index, target.as_ref(), &changes))
    }

    /// The last change of `file` taken back (a ladder edit, an STL edit, a rename):
    /// the buffer as it was before it, exactly, and the model with it (the editor's
    /// own step for a ladder edit it made, else the model rebuilt from the text).
    pub fn undo(&mut self, file: &str) -> Studio<Update> {
        let target = self.target.clone();
        let index = self.index(file)?;
        let f = &mut self.files[index];
        let Some(before) = f.undo_texts.pop() else {
            return Err(nothing("nothing to undo"));
        };
        if f.editor_undo == 0 {
            let after = std::mem::replace(&mut f.text, before);
            f.redo_texts.push(after);
            return Ok(self.rebuild(index));
        }
        let changes = match f.editor.undo() {
            Ok(changes) => changes,
            Err(e) => {
                f.undo_texts.push(before);
                return Err(e.into());
            }
        };
        f.editor_undo -= 1;
        f.editor_redo += 1;
        let after = std::mem::replace(&mut f.text, before);
        f.redo_texts.push(after);
        Ok(self.refresh(index, target.as_ref(), &changes))
    }

    /// The last undone change of `file` made again: the buffer as it was after it.
    pub fn redo(&mut self, file: &str) -> Studio<Update> {
        let target = self.target.clone();
        let index = self.index(file)?;
        let f = &mut self.files[index];
        // The texts decide what can be redone: an edit whose text was refused is in the
        // editor's redo list without one, and is never applied again.
        let Some(after) = f.redo_texts.pop() else {
            return Err(nothing("nothing to redo"));
        };
        if f.editor_redo == 0 {
            let before = std::mem::replace(&mut f.text, after);
            f.undo_texts.push(before);
            return Ok(self.rebuild(index));
        }
        let changes = match f.editor.redo() {
            Ok(changes) => changes,
            Err(e) => {
                f.redo_texts.push(after);
                return Err(e.into());
            }
        };
        f.editor_redo -= 1;
        f.editor_undo += 1;
        let before = std::mem::replace(&mut f.text, after);
        f.undo_texts.push(before);
        Ok(self.refresh(index, target.as_ref(), &changes))
    }

    /// `text` as the new buffer of the file at `index` (an STL edit, a rename): one
    /// step of its history; the model rebuilt from it.
    pub(super) fn replace_text(&mut self, index: usize, text: String) -> Update {
        let f = &mut self.files[index];
        let before = std::mem::replace(&mut f.text, text);
        f.undo_texts.push(before);
        f.redo_texts.clear();
        self.rebuild(index)
    }

    /// The buffer of `file` written to its file atomically (the networks edits changed
    /// differ, every other byte is as it was read); then it is not dirty. The file
    /// must still be inside the studio's folder (a symlink put in its place since it
    /// was opened is refused, and nothing is written).
    /// A symbol table's name saves that table (`save_table`); a source file's save
    /// also writes every table a symbol change left dirty, so nothing the page shows
    /// as saved is still only in memory.
    pub fn save(&mut self, file: &str) -> Studio<()> {
        if self.table_index(file).is_ok() {
            return self.save_table(file);
        }
        let index = self.index(file)?;
        for j in 0..self.tables.len() {
            if self.tables[j].text != self.table_saved[j] {
                let name = self.tables[j].name.clone();
                self.save_table(&name)?;
            }
        }
        let f = &self.files[index];
        let path = self.root.confine(&f.path)?;
        if path != f.path {
            return Err(StudioError::Escape {
                path: f.path.display().to_string(),
                root: self.root.dir().display().to_string(),
            });
        }
        let mut bytes = String::with_capacity(f.text.len() + BOM.len());
        if f.bom {
            bytes.push_str(BOM);
        }
        bytes.push_str(&f.text);
        gutta_io::write_file_atomically(&path, bytes.as_bytes()).map_err(|e| StudioError::Io {
            path: f.name.clone(),
            message: format!("cannot write: {e}"),
        })?;
        let f = &mut self.files[index];
        f.saved = f.text.clone();
        Ok(())
    }

    /// The STL text of block `block` (its place in the file) as the buffer holds it,
    /// from its header line to its END line: what `view-stl` shows.
    pub fn stl(&self, file: &str, block: usize) -> Studio<String> {
        let f = self.file(file)?;
        // The buffer is the first part of the checked text (the tables follow it), so
        // the tree's spans are the buffer's.
        let unit = f.unit(block)?;
        let start = unit.header.span.start as usize;
        let end = unit
            .end
            .map(|s| s.end as usize)
            .or_else(|| unit.networks.last().map(|n| n.span.end as usize))
            .unwrap_or(unit.header.span.end as usize);
        let text = &f.text;
        let end = end.min(text.len());
        let end = text[end..].find('\n').map_or(text.len(), |i| end + i + 1);
        Ok(text.get(start..end).unwrap_or_default().to_string())
    }

    /// The open file the page names `file` (a name, not a path: the disk is not asked).
    pub(super) fn index(&self, file: &str) -> Studio<usize> {
        let name = self.root.plain_name(file)?;
        self.files
            .iter()
            .position(|f| f.name == name)
            .ok_or_else(|| StudioError::NotOpen {
                file: file.to_string(),
            })
    }

    fn file(&self, file: &str) -> Studio<&OpenFile> {
        Ok(&self.files[self.index(file)?])
    }

    /// The file at `index` checked again after `changes`, and the page's update.
    fn refresh(
        &mut self,
        index: usize,
        target: Option<&ExplicitTarget>,
        changes: &[Change],
    ) -> Update {
        if self.files.len() == 1 {
            // The buffer's check and drawing, and the model's check (for the diagnostics
            // at paths) do not depend on each other: on two threads, an edit waits for
            // the longer of the two, not their sum (docs/studio.md, "Benchmarks (page)").
            let f = &self.files[index];
            let (checked, ladder, diagnostics) = std::thread::scope(|scope| {
                let diagnostics = scope.spawn(|| model_diagnostics(f, target));
                let checked = self.check(&f.name, &f.text);
                let ladder = gutta_ladder::build(&checked);
                let diagnostics = diagnostics
                    .join()
                    .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
                (checked, ladder, diagnostics)
            });
            let f = &mut self.files[index];
            f.ladder = ladder;
            f.checked = checked;
            f.diagnostics = diagnostics;
        } else {
            let checked = self.check(&self.files[index].name, &self.files[index].text);
            let f = &mut self.files[index];
            f.ladder = gutta_ladder::build(&checked);
            f.checked = checked;
            self.diagnose_program();
        }
        self.update(index, changes)
    }

    /// The file at `index` checked again from its buffer and its model rebuilt from
    /// it (the editor's history starts again): the networks that differ from the
    /// model before are redrawn.
    pub(super) fn rebuild(&mut self, index: usize) -> Update {
        let checked = self.check(&self.files[index].name, &self.files[index].text);
        let ladder = gutta_ladder::build(&checked);
        let model = json::model_of(&checked, &ladder);
        let f = &mut self.files[index];
        let changes = differences(f.editor.model(), &model);
        f.editor = Editor::owning(model, checked.target.instructions.clone());
        f.editor_undo = 0;
        f.editor_redo = 0;
        f.ladder = ladder;
        f.checked = checked;
        if self.files.len() == 1 {
            let target = self.target.clone();
            let f = &mut self.files[index];
            f.diagnostics = model_diagnostics(f, target.as_ref());
        } else {
            self.diagnose_program();
        }
        self.update(index, &changes)
    }

    /// The page's update of the file at `index` after `changes`.
    pub(super) fn update(&self, index: usize, changes: &[Change]) -> Update {
        let f = &self.files[index];
        Update {
            file: f.name.clone(),
            networks: drawings(&f.ladder, changes),
            blocks: shapes(&f.ladder),
            diagnostics: f.diagnostics.clone(),
            dirty: f.is_dirty(),
            can_undo: !f.undo_texts.is_empty(),
            can_redo: !f.redo_texts.is_empty(),
        }
    }

    /// The program's files read again with the symbol tables at `tables` (read now;
    /// the command line named them, so they may lie outside the folder: they are only
    /// read), `target` and timer-preset scaling: what `gutta-cc studio FILE.lad...
    /// --symbols TABLE` opens. Buffers and histories start over.
    pub fn configure(
        &mut self,
        tables: &[PathBuf],
        target: Option<ExplicitTarget>,
        scale_timer_presets: bool,
    ) -> Studio<()> {
        let mut read_tables = Vec::new();
        for table in tables {
            let name = table.display().to_string();
            let (file, _) = SourceFile::from_program_file_bytes(&name, read(table)?, true)
                .map_err(|e| StudioError::NotUtf8 {
                    path: name.clone(),
                    offset: e.offset,
                })?;
            read_tables.push(file);
        }
        self.table_saved = read_tables.iter().map(|t| t.text.clone()).collect();
        self.table_bom = vec![false; read_tables.len()];
        self.table_paths = tables.to_vec();
        self.tables = read_tables;
        self.target = target;
        self.options.scale_timer_presets = scale_timer_presets;
        let paths: Vec<PathBuf> = self.files.drain(..).map(|f| f.path).collect();
        for path in &paths {
            self.add(path)?;
        }
        Ok(())
    }

    /// The open file at `path` (canonical) read again from disk after something other
    /// than `save` wrote it: its buffer, model and history start over. False when no
    /// open file is there; on an error the file stays as it was.
    pub fn reload(&mut self, path: &Path) -> Studio<bool> {
        let Some(index) = self.files.iter().position(|f| f.path == path) else {
            return Ok(false);
        };
        let old = self.files.remove(index);
        if let Err(e) = self.add(&old.path) {
            self.files.insert(index, old);
            return Err(e);
        }
        if let Some(new) = self.files.pop() {
            self.files.insert(index, new);
        }
        Ok(true)
    }

    /// Every open file's diagnostics with the files checked as one program (a project
    /// whose `[program] sources` are several files, as `gutta-cc build` checks them):
    /// each file's model written as its program text, the texts joined in the
    /// project's order, the symbols of all of them declared once in the first, each
    /// diagnostic at the JSON path of its cause in its own file. A file whose model
    /// does not write is its structural L code, and its buffer stands in for it.
    pub(super) fn diagnose_program(&mut self) {
        let own = self.files.first().map(|f| ExplicitTarget {
            target: f.checked.target.clone(),
            origin: "the program".to_string(),
        });
        let Some(target) = self.target.clone().or(own) else {
            return;
        };
        let set = &target.target.instructions;
        let mut symbols: Vec<json::SymbolJson> = Vec::new();
        for f in &self.files {
            for s in &f.editor.model().symbols {
                if !symbols.iter().any(|o| o.name.eq_ignore_ascii_case(&s.name)) {
                    symbols.push(s.clone());
                }
            }
        }
        let mut written = Vec::with_capacity(self.files.len());
        let mut sources = Vec::with_capacity(self.files.len());
        for (i, f) in self.files.iter().enumerate() {
            let mut model = f.editor.model().clone();
            model.symbols = if i == 0 { symbols.clone() } else { Vec::new() };
            let program =
                json::validate(&model, set).and_then(|()| json::written_program(&model, set));
            match program {
                Ok(w) => {
                    sources.push(SourceFile::new(f.name.clone(), w.text.clone()));
                    written.push(Ok(w));
                }
                Err(e) => {
                    sources.push(SourceFile::new(f.name.clone(), f.text.clone()));
                    written.push(Err(e));
                }
            }
        }
        let compiled = gutta_compiler::compile_program(
            ProgramSources {
                sources,
                symbol_tables: Vec::new(),
                options: self.options.clone(),
            },
            Some(&target),
        );
        let checked = &compiled.checked;
        let parts = checked.file.parts();
        let mut found: Vec<Vec<ModelDiagnostic>> = vec![Vec::new(); self.files.len()];
        for (i, w) in written.iter().enumerate() {
            if let Err(e) = w {
                found[i].push(structural(e));
            }
        }
        let indexes: Vec<Option<LineIndex>> = written
            .iter()
            .map(|w| w.as_ref().ok().map(|w| LineIndex::new(&w.text)))
            .collect();
        let place = |span: Span| -> (usize, String) {
            let offset = span.start as usize;
            let part = checked.file.part_index(offset);
            let path = match (parts.get(part), written.get(part), indexes.get(part)) {
                (Some(p), Some(Ok(w)), Some(Some(index)))
                    if offset < p.end && !(span.is_empty() && offset == p.start) =>
                {
                    w.path_of_line(index.line_of(offset - p.start)).to_string()
                }
                _ => String::new(),
            };
            (part, path)
        };
        for d in checked.diagnostics() {
            let (part, path) = place(d.primary.span);
            let Some(into) = found.get_mut(part) else {
                continue;
            };
            if written.get(part).is_some_and(Result::is_err) {
                continue;
            }
            into.push(ModelDiagnostic {
                path,
                code: d.code.as_str().to_string(),
                severity: d.severity,
                message: d.message.clone(),
                label: d.primary.message.clone(),
                help: d.help.clone(),
                notes: d
                    .secondary
                    .iter()
                    .map(|l| json::ModelNote {
                        path: place(l.span).1,
                        message: l.message.clone().unwrap_or_default(),
                    })
                    .collect(),
            });
        }
        for (f, diagnostics) in self.files.iter_mut().zip(found) {
            f.diagnostics = diagnostics;
        }
    }
}

/// The changes that take `old` to `new` for the page: each network whose model
/// differs, and from the first place where a block's networks were inserted or
/// deleted to its end; every network of every block when the blocks changed.
fn differences(old: &Model, new: &Model) -> Vec<Change> {
    let mut changes = Vec::new();
    let same_blocks = old.blocks.len() == new.blocks.len();
    for (b, block) in new.blocks.iter().enumerate() {
        let before = old.blocks.get(b).filter(|_| same_blocks);
        let Some(before) = before else {
            changes.push(Change::Inserted(NetworkPath {
                block: b,
                network: 0,
            }));
            continue;
        };
        if before.title != block.title {
            changes.push(Change::Block(b));
        }
        let common = before.networks.len().min(block.networks.len());
        for n in 0..common {
            if before.networks[n] != block.networks[n] {
                changes.push(Change::Lines(NetworkPath {
                    block: b,
                    network: n,
                }));
            }
        }
        if before.networks.len() != block.networks.len() {
            // Where the lists start to differ for good: the rest is redrawn.
            let first = (0..common)
                .find(|&n| before.networks[n] != block.networks[n])
                .unwrap_or(common);
            changes.push(Change::Inserted(NetworkPath {
                block: b,
                network: first,
            }));
        }
    }
    changes
}

/// A structural L code as a diagnostic of the whole file's model.
fn structural(e: &json::ModelError) -> ModelDiagnostic {
    ModelDiagnostic {
        path: e.path.clone(),
        code: e.code.as_str().to_string(),
        severity: gutta_compiler::diagnostics::Severity::Error,
        message: e.message.clone(),
        label: None,
        help: None,
        notes: Vec::new(),
    }
}

impl OpenFile {
    fn is_dirty(&self) -> bool {
        self.text != self.saved
    }

    /// Block `block` (its place in the file) of the checked buffer, else `NoBlock`.
    pub(super) fn unit(&self, block: usize) -> Studio<&gutta_compiler::syntax::ast::Unit> {
        self.checked
            .ast
            .units
            .get(block)
            .ok_or_else(|| StudioError::NoBlock {
                file: self.name.clone(),
                block,
            })
    }
}

/// L0019: the history has no step to take.
fn nothing(message: &str) -> StudioError {
    StudioError::Edit(json::ModelError::new(
        json::ModelErrorCode::NothingToUndo,
        "",
        message,
    ))
}

/// The buffer with `changes` written in (the editor's model is already changed).
fn rewrite(f: &OpenFile, changes: &[Change]) -> Studio<String> {
    Ok(apply_to_text(
        &f.text,
        f.editor.model(),
        &f.checked.target.instructions,
        changes,
    )?)
}

/// Every diagnostic of the file's model at its JSON path (`json::check`: the model's
/// program through the compiler's whole pipeline), on the project's target, else the
/// one the file was checked on.
fn model_diagnostics(f: &OpenFile, target: Option<&ExplicitTarget>) -> Vec<ModelDiagnostic> {
    let own = ExplicitTarget {
        target: f.checked.target.clone(),
        origin: "the program".to_string(),
    };
    json::check(f.editor.model(), target.unwrap_or(&own)).diagnostics
}

/// The project's `[program] plc`/`target`, loaded by the one target rule.
fn gutta_cli_target(project: &Project) -> Studio<Option<ExplicitTarget>> {
    crate::target::TargetArgs {
        project: project.plc.spec(),
        ..crate::target::TargetArgs::default()
    }
    .explicit()
    .map_err(|e| StudioError::Project(e.message))
}

fn read(path: &Path) -> Studio<Vec<u8>> {
    std::fs::read(path).map_err(|e| StudioError::Io {
        path: path.display().to_string(),
        message: format!("cannot read: {e}"),
    })
}

/// The `.gtest` files under the root, by name, sorted; hidden folders, `target` and
/// symlinks are not followed.
fn gtest_files(root: &Root) -> Vec<String> {
    let mut found = Vec::new();
    let mut folders = vec![root.dir().to_path_buf()];
    while let Some(folder) = folders.pop() {
        let Ok(entries) = std::fs::read_dir(&folder) else {
            continue;
        };
        for entry in entries.flatten() {
            let Ok(kind) = entry.file_type() else {
                continue;
            };
            let path = entry.path();
            let name = entry.file_name().to_string_lossy().into_owned();
            if kind.is_dir() && !name.starts_with('.') && name != "target" {
                folders.push(path);
            } else if kind.is_file()
                && path
                    .extension()
                    .is_some_and(|e| e.eq_ignore_ascii_case("gtest"))
            {
                found.push(root.name_of(&path));
            }
        }
    }
    found.sort();
    found
}
