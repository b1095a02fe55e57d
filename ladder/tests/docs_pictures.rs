//! docs/ladder.md shows the examples as pictures: `docs/ladder/NAME.svg`, each the
//! standalone SVG `gutta-cc ladder examples/NAME.lad -o NAME.svg` writes (the same
//! library calls). This test keeps them true; `UPDATE_DOCS=1 cargo test -p gutta-ladder
//! --test docs_pictures` rewrites them. The page must link every one.

#![allow(
    clippy::disallowed_methods,
    reason = "tests read and write their data files"
)]

use std::path::{Path, PathBuf};

use gutta_compiler::source::SourceFile;
use gutta_compiler::{check_program, ProgramSources};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

#[test]
fn the_pictures_of_the_examples_are_the_drawings_of_today() {
    let mut examples: Vec<PathBuf> = std::fs::read_dir(root().join("examples"))
        .expect("examples/")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "lad"))
        .collect();
    examples.sort();
    let page = std::fs::read_to_string(root().join("docs/ladder.md")).expect("docs/ladder.md");
    let update = std::env::var_os("UPDATE_DOCS").is_some();
    let mut stale = Vec::new();
    for path in &examples {
        let stem = path
            .file_stem()
            .expect("stem")
            .to_string_lossy()
            .into_owned();
        let text = std::fs::read_to_string(path).expect("reads");
        let name = format!("examples/{stem}.lad");
        let checked = check_program(ProgramSources::single(SourceFile::new(name, text)), None);
        assert!(!checked.has_errors(), "{stem} checks clean");
        let svg = gutta_ladder::svg::ladder_svg(&gutta_ladder::build(&checked));
        let picture = root().join(format!("docs/ladder/{stem}.svg"));
        if update {
            std::fs::create_dir_all(picture.parent().expect("folder")).expect("creates");
            std::fs::write(&picture, &svg).expect("writes");
        } else if std::fs::read_to_string(&picture).ok().as_deref() != Some(svg.as_str()) {
            stale.push(picture.display().to_string());
        }
        assert!(
            page.contains(&format!("(ladder/{stem}.svg)")),
            "docs/ladder.md does not show ladder/{stem}.svg"
        );
    }
    assert!(
        stale.is_empty(),
        "stale pictures (UPDATE_DOCS=1 cargo test -p gutta-ladder --test docs_pictures): {stale:?}"
    );
}
