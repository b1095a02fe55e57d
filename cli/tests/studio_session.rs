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
    let program =
        gutta_cli::sources::read_program_in(root, &[PathBuf::from(FILE)], &[], &mut Vec::new())
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

// ---- STL editing, programs of several files, symbols -------------------------------

/// A project made as `gutta-cc new` makes it: src/main.lad with a SYMBOLS block,
/// symbols.csv, tests/main.gtest.
fn template_project(tag: &str) -> (PathBuf, PathBuf) {
    let dir = scratch(tag);
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
    (dir, root)
}

/// The model a session opened fresh on `text` (as FILE of the machine project) has.
fn fresh_model(tag: &str, text: &str) -> gutta_ladder::json::Model {
    let (dir, root) = project(tag);
    std::fs::write(root.join(FILE), text).expect("writes");
    let session = Session::open(std::slice::from_ref(&root)).expect("opens");
    let model = session.model(FILE).expect("open").clone();
    let _ = std::fs::remove_dir_all(dir);
    model
}

#[test]
fn ladder_and_stl_edits_mixed_undo_and_redo_to_the_exact_text_and_its_model() {
    let (dir, root) = project("mixed");
    let mut session = Session::open(std::slice::from_ref(&root)).expect("opens");
    let mut texts = vec![session.text(FILE).expect("open").to_string()];
    let ladder = |session: &mut Session, edit: &str| {
        session
            .apply(FILE, edit)
            .unwrap_or_else(|e| panic!("{edit}: {e}"));
    };
    ladder(
        &mut session,
        r#"{"op": "set_operands", "at": "blocks[0].networks[0].rung.series[0].parallel[0]", "operands": ["I0.4"]}"#,
    );
    texts.push(session.text(FILE).expect("open").to_string());
    // One network's lines as STL, one more output added by hand.
    let net = session.network_stl(FILE, 0, 1).expect("network 1");
    assert!(
        net.text.to_ascii_uppercase().starts_with("NETWORK"),
        "{}",
        net.text
    );
    assert_eq!(&texts[1][net.offset..net.offset + net.text.len()], net.text);
    let edited = format!("{}=      M5.0   // added as STL\n", net.text);
    let update = session
        .set_network_stl(FILE, 0, 1, &edited)
        .expect("STL applies");
    assert_eq!(errors(&update), Vec::<String>::new());
    let drawn: Vec<usize> = update.networks.iter().map(|d| d.network).collect();
    assert_eq!(
        drawn,
        (0..networks(&session)).collect::<Vec<_>>(),
        "every network of the block is drawn again"
    );
    assert!(update.networks[1].svg.contains("data-operand=\"M5.0\""));
    assert!(update.can_undo && !update.can_redo && update.dirty);
    texts.push(session.text(FILE).expect("open").to_string());
    // The buffer changed only there.
    assert_eq!(texts[2].replacen(&edited, &net.text, 1), texts[1]);
    // A ladder edit on the model rebuilt from the STL.
    let m50 = serde_json::to_string(&session.model(FILE).expect("open").blocks[0].networks[1])
        .expect("JSON");
    assert!(m50.contains("M5.0"), "{m50}");
    ladder(
        &mut session,
        r#"{"op": "set_network_title", "at": "blocks[0].networks[1]", "title": "edited twice"}"#,
    );
    texts.push(session.text(FILE).expect("open").to_string());
    // The whole block as STL, one operand changed.
    let block = session.stl_text(FILE, 0).expect("MAIN");
    assert_eq!(block.text, session.stl(FILE, 0).expect("MAIN"));
    let replaced = block.text.replacen("M5.0", "M5.1", 1);
    session.set_stl(FILE, 0, &replaced).expect("applies");
    texts.push(session.text(FILE).expect("open").to_string());
    assert!(texts[4].contains("M5.1") && !texts[4].contains("M5.0"));
    ladder(
        &mut session,
        r#"{"op": "set_network_title", "at": "blocks[0].networks[0]", "title": "last"}"#,
    );
    texts.push(session.text(FILE).expect("open").to_string());

    for i in (0..texts.len() - 1).rev() {
        session.undo(FILE).expect("undoes");
        assert_eq!(session.text(FILE).expect("open"), texts[i], "undo to {i}");
        assert_eq!(
            session.model(FILE).expect("open"),
            &fresh_model(&format!("mixed-u{i}"), &texts[i]),
            "undo to {i}: the model is the text's"
        );
    }
    assert!(!session.is_dirty(FILE).expect("open"));
    for (i, text) in texts.iter().enumerate().skip(1) {
        session.redo(FILE).expect("redoes");
        assert_eq!(session.text(FILE).expect("open"), text, "redo to {i}");
        assert_eq!(
            session.model(FILE).expect("open"),
            &fresh_model(&format!("mixed-r{i}"), text),
            "redo to {i}: the model is the text's"
        );
    }
    assert!(session.redo(FILE).is_err());
    // Back two, then a new ladder edit: nothing left to redo, and undo goes back by it.
    session.undo(FILE).expect("undoes");
    session.undo(FILE).expect("undoes");
    ladder(
        &mut session,
        r#"{"op": "set_network_title", "at": "blocks[0].networks[2]", "title": "branch"}"#,
    );
    assert!(session.redo(FILE).is_err());
    session.undo(FILE).expect("undoes");
    assert_eq!(session.text(FILE).expect("open"), texts[3]);
    session.undo(FILE).expect("undoes");
    assert_eq!(session.text(FILE).expect("open"), texts[2]);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_network_edited_as_stl_shows_its_diagnostics_and_stays_editable_when_not_a_rung() {
    let (dir, root) = project("stl");
    let mut session = Session::open(std::slice::from_ref(&root)).expect("opens");
    let original = session.text(FILE).expect("open").to_string();
    let net = session.network_stl(FILE, 0, 0).expect("network 0");
    // Two rungs in one network: not one rung, shown as STL.
    let two = format!("{}LD     I0.6\n=      Q0.6\n", net.text);
    let update = session.set_network_stl(FILE, 0, 0, &two).expect("applies");
    assert_eq!(errors(&update), Vec::<String>::new());
    let model = serde_json::to_value(&session.model(FILE).expect("open").blocks[0].networks[0])
        .expect("JSON");
    assert!(model.get("stl").is_some(), "shown as STL: {model}");
    // Still editable as STL: a bad operand is a diagnostic at its line.
    let net = session.network_stl(FILE, 0, 0).expect("network 0");
    assert_eq!(net.text, two);
    let bad = two.replace("Q0.6", "Q99.6");
    let update = session.set_network_stl(FILE, 0, 0, &bad).expect("applies");
    assert!(!errors(&update).is_empty(), "{:?}", update.diagnostics);
    let block = session.stl_text(FILE, 0).expect("MAIN");
    let found = session.stl_diagnostics(FILE, 0).expect("MAIN");
    let d = found
        .iter()
        .find(|d| d.severity == "error")
        .unwrap_or_else(|| panic!("an error: {found:?}"));
    let line = block.text.lines().nth(d.line - 1).expect("its line");
    assert!(line.contains("Q99.6"), "{d:?} on {line}");
    assert_eq!(&block.text[d.start..d.end], "Q99.6", "{d:?}");
    assert!(d.code.starts_with('E'), "{d:?}");
    // And back to the network as it was: the text is the original, the model a rung.
    session
        .set_network_stl(
            FILE,
            0,
            0,
            &net.text[..net.text.len() - "LD     I0.6\n=      Q0.6\n".len()],
        )
        .expect("applies");
    assert_eq!(session.text(FILE).expect("open"), original);
    assert!(session.stl_diagnostics(FILE, 0).expect("MAIN").is_empty());
    let model = serde_json::to_value(&session.model(FILE).expect("open").blocks[0].networks[0])
        .expect("JSON");
    assert!(model.get("rung").is_some(), "a rung again: {model}");
    // A network that is not there is refused, nothing changed.
    let refused = session
        .set_network_stl(FILE, 0, 99, "NETWORK\n")
        .expect_err("none");
    assert!(
        matches!(&refused, StudioError::Edit(e) if e.code.as_str() == "L0014"),
        "{refused}"
    );
    assert_eq!(session.text(FILE).expect("open"), original);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn hover_and_completion_on_the_stl_come_from_the_editor_analysis() {
    let (dir, root) = template_project("hover");
    let session = Session::open(std::slice::from_ref(&root)).expect("opens");
    let file = "src/main.lad";
    let text = session.text(file).expect("open").to_string();
    let at = text.find("LD     Start").expect("the latch") + "LD     ".len();
    let hover = session
        .stl_hover(file, at + 1)
        .expect("hovers")
        .expect("something");
    assert_eq!(&text[hover.start..hover.end], "Start");
    assert!(hover.markdown.contains("I0.0"), "{}", hover.markdown);
    let complete = session.stl_complete(file, at + 2).expect("completes");
    assert_eq!(&text[complete.start..complete.end], "St");
    assert!(
        complete
            .items
            .iter()
            .any(|i| i.label == "Start" && i.kind == "symbol"),
        "{:?}",
        complete.items
    );
    assert!(session.stl_hover(file, text.len() + 5).is_err());
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_program_of_two_files_is_checked_as_one() {
    let dir = scratch("two-files");
    let root = dir.join("project");
    std::fs::create_dir_all(root.join("src")).expect("src");
    std::fs::write(
        root.join("gutta.toml"),
        "[program]\nname = \"two\"\nplc = \"CPU-EC20\"\nsources = [\"src/main.lad\", \"src/sub.lad\"]\n",
    )
    .expect("gutta.toml");
    std::fs::write(
        root.join("src/main.lad"),
        "PLC_TYPE CPU-EC20\n\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\nLD     I0.0\nCALL   Blink\nNetwork 2\nLD     M0.0\n=      Q0.0\nEND_ORGANIZATION_BLOCK\n",
    )
    .expect("main.lad");
    std::fs::write(
        root.join("src/sub.lad"),
        "SUBROUTINE_BLOCK Blink:SBR0\nBEGIN\nNetwork 1\nLD     SM0.5\n=      M0.0\nEND_SUBROUTINE_BLOCK\n",
    )
    .expect("sub.lad");
    let mut session = Session::open(std::slice::from_ref(&root)).expect("opens");
    assert_eq!(session.files(), vec!["src/main.lad", "src/sub.lad"]);
    assert_eq!(session.diagnostics("src/main.lad").expect("open"), &[]);
    assert_eq!(session.diagnostics("src/sub.lad").expect("open"), &[]);
    assert!(session
        .stl_diagnostics("src/main.lad", 0)
        .expect("MAIN")
        .is_empty());
    // The subroutine renamed in its own file: the CALL in the other file is an error
    // there, at its element; the subroutine's file stays clean.
    let sub = session.stl_text("src/sub.lad", 0).expect("Blink");
    session
        .set_stl("src/sub.lad", 0, &sub.text.replace("Blink", "Blank"))
        .expect("applies");
    let main = session.diagnostics("src/main.lad").expect("open");
    let call = main
        .iter()
        .find(|d| d.is_error())
        .unwrap_or_else(|| panic!("an error in main.lad: {main:?}"));
    assert!(call.path.starts_with("blocks[0].networks[0]"), "{call}");
    assert!(call.message.contains("Blink"), "{call}");
    assert!(session
        .diagnostics("src/sub.lad")
        .expect("open")
        .iter()
        .all(|d| !d.is_error()));
    let stl = session.stl_diagnostics("src/main.lad", 0).expect("MAIN");
    assert!(stl.iter().any(|d| d.line == 5), "{stl:?}");
    // Undone: clean again.
    session.undo("src/sub.lad").expect("undoes");
    assert_eq!(session.diagnostics("src/main.lad").expect("open"), &[]);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn symbols_are_listed_added_changed_and_renamed_everywhere() {
    let (dir, root) = template_project("symbols");
    let file = "src/main.lad";
    let mut session = Session::open(std::slice::from_ref(&root)).expect("opens");
    let rows = session.symbol_table();
    let row = |rows: &[gutta_cli::studio::SymbolRow], name: &str| {
        rows.iter()
            .find(|r| r.name == name)
            .unwrap_or_else(|| panic!("{name} in {rows:?}"))
            .clone()
    };
    let start = row(&rows, "Start");
    assert_eq!(
        (
            start.address.as_str(),
            start.declared.as_str(),
            start.file.as_str()
        ),
        ("I0.0", "table", "symbols.csv")
    );
    assert_eq!(
        start.comment.as_deref(),
        Some("Start button (normally open)")
    );
    let running = row(&rows, "Running");
    assert_eq!(
        (
            running.address.as_str(),
            running.declared.as_str(),
            running.file.as_str()
        ),
        ("M0.0", "symbols", file)
    );
    let change = |session: &mut Session, json: &str| {
        let change: gutta_cli::studio::SymbolChange = serde_json::from_str(json).expect("reads");
        session.change_symbols(&change)
    };
    // Added to the table: in memory and dirty until saved.
    let csv = std::fs::read_to_string(root.join("symbols.csv")).expect("reads");
    let updates = change(
        &mut session,
        r#"{"op": "add", "name": "Horn", "address": "q0.1", "comment": "sounds, loudly"}"#,
    )
    .expect("adds");
    assert_eq!(updates.len(), 1);
    assert!(session.project().tables[0].dirty);
    assert!(!session.is_dirty(file).expect("open"));
    assert_eq!(
        std::fs::read_to_string(root.join("symbols.csv")).expect("reads"),
        csv
    );
    let horn = row(&session.symbol_table(), "Horn");
    assert_eq!(
        (horn.address.as_str(), horn.comment.as_deref()),
        ("Q0.1", Some("sounds, loudly"))
    );
    // Refused: a taken name, a bad address, an unknown symbol; nothing changes.
    for bad in [
        r#"{"op": "add", "name": "start", "address": "I0.5"}"#,
        r#"{"op": "add", "name": "Siren", "address": "Q99"}"#,
        r#"{"op": "set", "name": "Nobody", "address": "I0.5"}"#,
        r#"{"op": "rename", "name": "Start", "to": "I0.7"}"#,
    ] {
        let before = session
            .table_text("symbols.csv")
            .expect("table")
            .to_string();
        let refused = change(&mut session, bad).expect_err(bad);
        assert!(matches!(refused, StudioError::Edit(_)), "{bad}: {refused}");
        assert_eq!(session.table_text("symbols.csv").expect("table"), before);
    }
    // An address and a comment changed where they are declared.
    change(
        &mut session,
        r#"{"op": "set", "name": "Running", "address": "M0.3", "comment": "latched"}"#,
    )
    .expect("sets");
    let text = session.text(file).expect("open").to_string();
    assert!(text.contains("Running : M0.3        // latched"), "{text}");
    assert!(session.is_dirty(file).expect("open"));
    change(
        &mut session,
        r#"{"op": "set", "name": "Stop", "comment": "Stop \"red\" button"}"#,
    )
    .expect("sets");
    let table = session.table_text("symbols.csv").expect("table");
    assert!(
        table.contains("Stop,I0.1,\"Stop \"\"red\"\" button\""),
        "{table}"
    );
    // Renamed everywhere: the table's row, every use in the program, drawn again.
    let updates = change(
        &mut session,
        r#"{"op": "rename", "name": "Start", "to": "StartButton"}"#,
    )
    .expect("renames");
    let svg: String = updates
        .iter()
        .flat_map(|u| u.networks.iter().map(|n| n.svg.clone()))
        .collect();
    assert!(svg.contains("StartButton"), "{svg}");
    let text = session.text(file).expect("open").to_string();
    assert!(
        text.contains("LD     StartButton") && !text.contains("LD     Start\n"),
        "{text}"
    );
    assert!(session
        .table_text("symbols.csv")
        .expect("table")
        .starts_with("Symbol,Address,Comment\nStartButton,I0.0,"));
    assert_eq!(session.diagnostics(file).expect("open"), &[]);
    // Saving the program writes the tables too; the project builds.
    session.save(file).expect("saves");
    assert!(!session.project().tables[0].dirty);
    let saved = std::fs::read_to_string(root.join("symbols.csv")).expect("reads");
    assert!(saved.contains("Horn,Q0.1,\"sounds, loudly\""), "{saved}");
    let program = gutta_cli::sources::read_program_in(
        &root,
        &[PathBuf::from(file)],
        &[PathBuf::from("symbols.csv")],
        &mut Vec::new(),
    )
    .expect("reads");
    let compiled = compile_program(program, None);
    assert!(
        compiled.image.is_some(),
        "{:?}",
        compiled.checked.diagnostics()
    );
    // Undoing the rename in the program's file takes back its text only.
    session.undo(file).expect("undoes");
    assert!(session.text(file).expect("open").contains("LD     Start\n"));
    // A project without tables: symbols go into the file's SYMBOLS block.
    let (dir2, root2) = project("symbols-block");
    let mut session = Session::open(std::slice::from_ref(&root2)).expect("opens");
    change(
        &mut session,
        r#"{"op": "add", "name": "Horn", "address": "Q1.1"}"#,
    )
    .expect("adds");
    let text = session.text(FILE).expect("open");
    assert!(text.contains("  Horn : Q1.1\nEND_SYMBOLS"), "{text}");
    assert_eq!(row(&session.symbol_table(), "Horn").declared, "symbols");
    let _ = std::fs::remove_dir_all(dir);
    let _ = std::fs::remove_dir_all(dir2);
}
