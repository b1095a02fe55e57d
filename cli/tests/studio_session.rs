//! The studio's session core (`gutta_cli::studio`, docs/studio.md "The session (Rust)")
//! without a browser, on real files in a temporary folder: a project written from
//! tests/data/ladder_model/machine.json. A new network drawn by edits is saved and the
//! saved file compiles as `gutta-cc build` compiles it; undo and redo restore the exact
//! text; a bad operand is a diagnostic at its element's path with the network redrawn;
//! a path that leaves the project is refused and nothing is written.

use std::path::{Path, PathBuf};

use gutta_cli::studio::{Session, StudioError, Update};
use gutta_compiler::diagnostics::Severity;
use gutta_compiler::{compile_program, ExplicitTarget};

const MACHINE: &str = include_str!("../../tests/data/ladder_model/machine.json");
const MACHINE_TESTS: &str = include_str!("../../tests/data/ladder_model/machine.gtest");
const FILE: &str = "src/machine.lad";

/// A fresh folder for one test.
fn scratch(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gutta-studio-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

/// machine.json written as a .lad file (`json::program_of`).
fn machine_lad() -> String {
    let model = gutta_ladder::json::read_model(MACHINE.as_bytes()).expect("machine.json reads");
    let target = gutta_catalog::stdlib::load(&model.plc).expect("its PLC type loads");
    gutta_ladder::json::program_of(&model, &target.instructions).expect("it writes")
}

/// A project in `dir/project`: gutta.toml, src/machine.lad, tests/machine.gtest.
fn project(tag: &str) -> (PathBuf, PathBuf) {
    let dir = scratch(tag);
    let root = dir.join("project");
    std::fs::create_dir_all(root.join("src")).expect("src");
    std::fs::create_dir_all(root.join("tests")).expect("tests");
    std::fs::write(
        root.join("gutta.toml"),
        "[program]\nname = \"machine\"\nplc = \"CPU-EC20\"\nsources = [\"src/machine.lad\"]\n",
    )
    .expect("gutta.toml");
    std::fs::write(root.join(FILE), machine_lad()).expect("machine.lad");
    std::fs::write(root.join("tests/machine.gtest"), MACHINE_TESTS).expect("gtest");
    (dir, root)
}

fn networks(session: &Session) -> usize {
    session.model(FILE).expect("open").blocks[0].networks.len()
}

fn errors(update: &Update) -> Vec<String> {
    update
        .diagnostics
        .iter()
        .filter(|d| d.severity == Severity::Error)
        .map(ToString::to_string)
        .collect()
}

/// The saved file compiled as `gutta-cc build` compiles a project's sources.
fn compile_saved(root: &Path) -> Vec<String> {
    let program = gutta_cli::sources::read_program_in(root, &[PathBuf::from(FILE)], &[])
        .expect("the saved file reads");
    let target = ExplicitTarget {
        target: std::sync::Arc::new(gutta_catalog::stdlib::load("CPU-EC20").expect("loads")),
        origin: "[program] plc".to_string(),
    };
    let compiled = compile_program(program, Some(&target));
    let errors: Vec<String> = compiled
        .checked
        .diagnostics()
        .iter()
        .filter(|d| d.severity == Severity::Error)
        .map(|d| format!("{} {}", d.code.as_str(), d.message))
        .collect();
    assert_eq!(compiled.image.is_some(), errors.is_empty());
    errors
}

#[test]
fn a_project_opens_with_its_files_blocks_symbols_and_tests() {
    let (dir, root) = project("open");
    let session = Session::open(std::slice::from_ref(&root)).expect("the project opens");
    let summary = session.project();
    assert_eq!(summary.name, "machine");
    assert_eq!(summary.plc, "CPU-EC20");
    assert_eq!(session.files(), vec![FILE]);
    assert_eq!(summary.files[0].name, FILE);
    assert!(!summary.files[0].dirty);
    let main = &summary.files[0].blocks[0];
    assert_eq!(
        (main.kind.as_str(), main.name.as_str(), main.id.as_str()),
        ("ORGANIZATION_BLOCK", "MAIN", "OB1")
    );
    assert_eq!(main.networks, networks(&session));
    assert!(summary
        .symbols
        .iter()
        .any(|s| s.name == "Start" && s.address == "I0.0"));
    assert_eq!(summary.tests, vec!["tests/machine.gtest"]);
    let json: serde_json::Value = serde_json::from_str(&summary.to_json()).expect("JSON");
    assert_eq!(json["files"][0]["blocks"][0]["name"], "MAIN");
    assert!(session.diagnostics(FILE).expect("open").is_empty());
    // The gutta.toml names the project as well as its folder.
    let by_manifest = Session::open(&[root.join("gutta.toml")]).expect("opens");
    assert_eq!(by_manifest.files(), vec![FILE]);
    let stl = session.stl(FILE, 0).expect("MAIN");
    assert!(stl.starts_with("ORGANIZATION_BLOCK MAIN"), "{stl}");
    assert!(stl.ends_with("END_ORGANIZATION_BLOCK\n"), "{stl}");
    assert!(matches!(
        session.stl(FILE, 9),
        Err(StudioError::NoBlock { block: 9, .. })
    ));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_network_drawn_by_edits_is_saved_and_compiles() {
    let (dir, root) = project("draw");
    let mut session = Session::open(std::slice::from_ref(&root)).expect("opens");
    let original = session.text(FILE).expect("open").to_string();
    let n = networks(&session);
    let net = format!("blocks[0].networks[{n}]");
    let steps = [
        format!(
            r#"{{"op": "insert_network", "at": "{net}", "network": {{"title": "drawn in the studio", "comment": "", "rung": {{"series": [{{"contact": "LD", "operands": ["I1.0"]}}, {{"coil": "=", "operands": ["Q1.0"]}}]}}}}}}"#
        ),
        format!(
            r#"{{"op": "wrap_parallel", "at": "{net}.rung.series[0]", "branch": {{"contact": "LD", "operands": ["M1.0"]}}}}"#
        ),
        format!(
            r#"{{"op": "insert_box", "at": "{net}.rung.series[0]", "place": "after", "box": "TON", "operands": ["T5", "20"]}}"#
        ),
        format!(
            r#"{{"op": "insert_coil", "at": "{net}.rung.series[2]", "place": "parallel", "coil": "=", "operands": ["M1.1"]}}"#
        ),
    ];
    // A network comes with an output: a lone contact is refused (L0009), nothing changes.
    let lone = format!(
        r#"{{"op": "insert_network", "at": "{net}", "network": {{"title": "", "comment": "", "rung": {{"contact": "LD", "operands": ["I1.0"]}}}}}}"#
    );
    let refused = session.apply(FILE, &lone).expect_err("no output");
    assert!(
        matches!(&refused, StudioError::Edit(e) if e.code.as_str() == "L0009"),
        "{refused}"
    );
    assert_eq!(session.text(FILE).expect("open"), original);
    assert!(!session.is_dirty(FILE).expect("open"));
    let mut last = None;
    for step in &steps {
        let update = session
            .apply(FILE, step)
            .unwrap_or_else(|e| panic!("{step}: {e}"));
        assert!(update.dirty);
        assert!(update.can_undo && !update.can_redo);
        assert_eq!(errors(&update), Vec::<String>::new(), "{step}");
        let drawn: Vec<(usize, usize)> = update
            .networks
            .iter()
            .map(|d| (d.block, d.network))
            .collect();
        assert_eq!(drawn, vec![(0, n)], "{step}: only the new network is drawn");
        assert_eq!(update.blocks[0].networks, n + 1);
        last = Some(update);
    }
    let svg = &last.expect("four updates").networks[0].svg;
    for needed in [
        "class=\"network\"",
        &format!("data-network=\"{}\"", n + 1),
        "class=\"contact\"",
        "class=\"coil\"",
        "class=\"box\"",
        "data-operand=\"I1.0\"",
        "data-operand=\"M1.0\"",
        "data-mnemonic=\"TON\"",
        "data-kind=",
    ] {
        assert!(svg.contains(needed), "{needed} missing from {svg}");
    }
    let model = session.model(FILE).expect("open");
    let rung = serde_json::to_value(&model.blocks[0].networks[n]).expect("JSON");
    assert_eq!(rung["title"], "drawn in the studio");
    assert!(rung.to_string().contains("\"parallel\""), "{rung}");
    // Not written yet.
    assert_eq!(
        std::fs::read_to_string(root.join(FILE)).expect("reads"),
        original
    );
    session.save(FILE).expect("saves");
    assert!(!session.is_dirty(FILE).expect("open"));
    assert!(!session.project().files[0].dirty);
    let saved = std::fs::read_to_string(root.join(FILE)).expect("reads");
    assert_eq!(saved, session.text(FILE).expect("open"));
    // Only the new network differs: the old text is the saved text's start and end.
    let head = original
        .bytes()
        .zip(saved.bytes())
        .take_while(|(a, b)| a == b)
        .count();
    let tail = original
        .bytes()
        .rev()
        .zip(saved.bytes().rev())
        .take_while(|(a, b)| a == b)
        .count();
    assert!(
        head + tail >= original.len(),
        "the old bytes moved:\n{saved}"
    );
    assert!(saved.contains("TON"), "{saved}");
    assert_eq!(compile_saved(&root), Vec::<String>::new(), "{saved}");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn undo_and_redo_restore_the_exact_text() {
    let (dir, root) = project("undo");
    // A hand-formatted file: undo must give back its own bytes, not the writer's.
    let path = root.join(FILE);
    let spaced = machine_lad().replace("LD     Start", "LD Start   // the button");
    std::fs::write(&path, &spaced).expect("writes");
    let mut session = Session::open(std::slice::from_ref(&root)).expect("opens");
    let mut texts = vec![session.text(FILE).expect("open").to_string()];
    let edits = [
        r#"{"op": "set_operands", "at": "blocks[0].networks[0].rung.series[0].parallel[0]", "operands": ["I0.4"]}"#,
        r#"{"op": "set_network_title", "at": "blocks[0].networks[1]", "title": "a new title"}"#,
        r#"{"op": "move_network", "at": "blocks[0].networks[0]", "to": 2}"#,
        r#"{"op": "delete_network", "at": "blocks[0].networks[1]"}"#,
    ];
    for edit in edits {
        let update = session
            .apply(FILE, edit)
            .unwrap_or_else(|e| panic!("{edit}: {e}"));
        texts.push(session.text(FILE).expect("open").to_string());
        // A moved or deleted network renumbers the rest of its block: all redrawn.
        let drawn: Vec<usize> = update.networks.iter().map(|d| d.network).collect();
        let count = update.blocks[0].networks;
        if edit.contains("move_network") {
            assert_eq!(drawn, (0..count).collect::<Vec<_>>(), "{edit}");
        } else if edit.contains("delete_network") {
            assert_eq!(drawn, (1..count).collect::<Vec<_>>(), "{edit}");
        } else {
            assert_eq!(drawn.len(), 1, "{edit}");
        }
    }
    assert_ne!(texts[0], texts[1]);
    for i in (0..edits.len()).rev() {
        let update = session.undo(FILE).expect("undoes");
        assert_eq!(session.text(FILE).expect("open"), texts[i], "undo to {i}");
        assert_eq!(update.dirty, i != 0);
        assert!(update.can_redo);
    }
    assert_eq!(session.text(FILE).expect("open"), spaced);
    let nothing = session.undo(FILE).expect_err("nothing to undo");
    assert!(
        matches!(&nothing, StudioError::Edit(e) if e.code.as_str() == "L0019"),
        "{nothing}"
    );
    for (i, text) in texts.iter().enumerate().skip(1) {
        session.redo(FILE).expect("redoes");
        assert_eq!(session.text(FILE).expect("open"), text, "redo to {i}");
    }
    assert!(session.redo(FILE).is_err());
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_bad_operand_is_a_diagnostic_on_its_element_and_a_refused_edit_changes_nothing() {
    let (dir, root) = project("bad");
    let mut session = Session::open(std::slice::from_ref(&root)).expect("opens");
    let at = "blocks[0].networks[0].rung.series[1]";
    let update = session
        .apply(
            FILE,
            &format!(r#"{{"op": "set_operands", "at": "{at}", "operands": ["NoSuchSymbol"]}}"#),
        )
        .expect("the model takes any operand; the compiler judges it");
    let bad: Vec<_> = update
        .diagnostics
        .iter()
        .filter(|d| d.severity == Severity::Error)
        .collect();
    assert_eq!(bad.len(), 1, "{:?}", update.diagnostics);
    assert_eq!(bad[0].path, at, "{}", bad[0]);
    assert!(bad[0].code.starts_with('E'), "{}", bad[0]);
    assert_eq!(update.networks.len(), 1);
    let drawing = &update.networks[0];
    assert_eq!((drawing.block, drawing.network), (0, 0));
    assert!(drawing.svg.contains("class=\"network\""));
    // The operand as written; it resolves to no address, so its `data-operand` is empty.
    assert!(drawing.svg.contains(">NoSuchSymbol<"), "{}", drawing.svg);
    assert!(drawing.svg.contains("data-operand=\"\""), "{}", drawing.svg);
    assert_eq!(
        session.diagnostics(FILE).expect("open"),
        update.diagnostics.as_slice()
    );
    // A refused edit: its L code, and the buffer, model and history as they were.
    let text = session.text(FILE).expect("open").to_string();
    let model = session.model(FILE).expect("open").clone();
    let refused = session
        .apply(
            FILE,
            &format!(r#"{{"op": "set_mnemonic", "at": "{at}", "mnemonic": "NOPE"}}"#),
        )
        .expect_err("no such mnemonic");
    let StudioError::Edit(e) = &refused else {
        panic!("{refused:?}");
    };
    assert!(e.code.as_str().starts_with('L'), "{e}");
    assert_eq!(session.text(FILE).expect("open"), text);
    assert_eq!(session.model(FILE).expect("open"), &model);
    let not_an_edit = session
        .apply(FILE, r#"{"op": "paint"}"#)
        .expect_err("no such op");
    assert!(matches!(&not_an_edit, StudioError::Edit(e) if e.code.as_str() == "L0018"));
    // The one edit is still what undo takes back.
    session.undo(FILE).expect("undoes");
    assert!(session.diagnostics(FILE).expect("open").is_empty());
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_path_that_escapes_is_refused_and_nothing_is_written() {
    let (dir, root) = project("escape");
    let outside = dir.join("outside.lad");
    std::fs::write(&outside, machine_lad()).expect("outside");
    let before = std::fs::read(&outside).expect("reads");
    let mut session = Session::open(std::slice::from_ref(&root)).expect("opens");
    session
        .apply(
            FILE,
            r#"{"op": "set_network_title", "at": "blocks[0].networks[0]", "title": "changed"}"#,
        )
        .expect("applies");
    let absolute = outside.display().to_string();
    for name in [
        "../outside.lad",
        "src/../../outside.lad",
        absolute.as_str(),
        "",
    ] {
        let refused = session.save(name).expect_err(name);
        assert!(
            matches!(refused, StudioError::Escape { .. }),
            "{name}: {refused:?}"
        );
        let refused = session
            .apply(
                name,
                r#"{"op": "delete_network", "at": "blocks[0].networks[0]"}"#,
            )
            .expect_err(name);
        assert!(
            matches!(refused, StudioError::Escape { .. }),
            "{name}: {refused:?}"
        );
    }
    // A file inside the project that the session did not open.
    std::fs::write(root.join("src/other.lad"), "").expect("writes");
    assert!(matches!(
        session.save("src/other.lad"),
        Err(StudioError::NotOpen { .. })
    ));
    // The open file swapped for a symlink out of the project: refused at save.
    #[cfg(unix)]
    {
        let file = root.join(FILE);
        let kept = std::fs::read(&file).expect("reads");
        std::fs::remove_file(&file).expect("removes");
        std::os::unix::fs::symlink(&outside, &file).expect("symlink");
        let refused = session.save(FILE).expect_err("a symlink out");
        assert!(matches!(refused, StudioError::Escape { .. }), "{refused:?}");
        std::fs::remove_file(&file).expect("removes");
        std::fs::write(&file, kept).expect("writes");
        // A source named through a symlink out is refused when the project opens.
        std::os::unix::fs::symlink(&outside, root.join("src/linked.lad")).expect("symlink");
        std::fs::write(
            root.join("gutta.toml"),
            "[program]\nplc = \"CPU-EC20\"\nsources = [\"src/linked.lad\"]\n",
        )
        .expect("gutta.toml");
        let refused = Session::open(std::slice::from_ref(&root)).expect_err("links out");
        assert!(matches!(refused, StudioError::Escape { .. }), "{refused:?}");
    }
    // A source named with `..` in gutta.toml.
    std::fs::write(
        root.join("gutta.toml"),
        "[program]\nplc = \"CPU-EC20\"\nsources = [\"../outside.lad\"]\n",
    )
    .expect("gutta.toml");
    let refused = Session::open(std::slice::from_ref(&root)).expect_err("escapes");
    assert!(matches!(refused, StudioError::Escape { .. }), "{refused:?}");
    assert_eq!(
        std::fs::read(&outside).expect("reads"),
        before,
        "nothing written"
    );
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .expect("lists")
        .flatten()
        .map(|e| e.file_name())
        .collect();
    assert_eq!(leftovers.len(), 2, "{leftovers:?}");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn given_lad_files_open_in_their_folder_only() {
    let dir = scratch("files");
    let here = dir.join("here");
    std::fs::create_dir_all(&here).expect("here");
    std::fs::write(here.join("machine.lad"), machine_lad()).expect("writes");
    std::fs::write(dir.join("elsewhere.lad"), machine_lad()).expect("writes");
    let mut session = Session::open(&[here.join("machine.lad")]).expect("opens");
    assert_eq!(session.files(), vec!["machine.lad"]);
    session
        .apply(
            "machine.lad",
            r#"{"op": "set_network_title", "at": "blocks[0].networks[0]", "title": "t"}"#,
        )
        .expect("applies");
    session.save("machine.lad").expect("saves");
    assert!(std::fs::read_to_string(here.join("machine.lad"))
        .expect("reads")
        .contains("// t"));
    let refused = Session::open(&[here.join("machine.lad"), dir.join("elsewhere.lad")])
        .expect_err("not beside the first");
    assert!(matches!(refused, StudioError::Escape { .. }), "{refused:?}");
    let refused = Session::open(&[dir.join("here")]).expect_err("no gutta.toml");
    assert!(matches!(refused, StudioError::Project(_)), "{refused:?}");
    let refused = Session::open(&[here.join("nothing.txt")]).expect_err("not a .lad");
    assert!(
        matches!(refused, StudioError::NotAProgram { .. }),
        "{refused:?}"
    );
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_project_made_by_gutta_cc_new_opens_clean_with_its_symbol_table() {
    let dir = scratch("template");
    let root = dir.join("blinky");
    std::fs::create_dir_all(root.join("src")).expect("src");
    std::fs::create_dir_all(root.join("tests")).expect("tests");
    let templates = Path::new(env!("CARGO_MANIFEST_DIR")).join("templates");
    let manifest = std::fs::read_to_string(templates.join("gutta.toml"))
        .expect("template")
        .replace("{name}", "blinky")
        .replace("{plc}", "CPU-EC20");
    std::fs::write(root.join("gutta.toml"), manifest).expect("gutta.toml");
    for (from, to) in [
        ("main.lad", "src/main.lad"),
        ("symbols.csv", "symbols.csv"),
        ("main.gtest", "tests/main.gtest"),
    ] {
        std::fs::copy(templates.join(from), root.join(to)).expect("copies");
    }
    let mut session = Session::open(std::slice::from_ref(&root)).expect("opens");
    assert_eq!(session.diagnostics("src/main.lad").expect("open"), &[]);
    let symbols = session.project().symbols;
    assert!(symbols.iter().any(|s| s.name == "Lamp"), "{symbols:?}");
    // An edit naming a symbol of the table checks clean.
    let update = session
        .apply(
            "src/main.lad",
            r#"{"op": "set_operands", "at": "blocks[0].networks[1].rung.series[0]", "operands": ["Start"]}"#,
        )
        .expect("applies");
    assert_eq!(errors(&update), Vec::<String>::new());
    let _ = std::fs::remove_dir_all(dir);
}
