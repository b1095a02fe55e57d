//! The studio benches' program (`studio_edit`, `studio_live`, `studio_page`): the
//! ladder model bench's program of real networks (ladder/benches/corpus_program),
//! 1,000 networks, in a project in a temporary folder whose gutta.toml names the front
//! end's bench target (compiler/benches/target: program limits a 1,000-network program
//! fits in).

use std::path::PathBuf;

#[path = "../../../ladder/benches/corpus_program/mod.rs"]
mod corpus_program;

#[path = "../../../compiler/benches/scale_program/mod.rs"]
#[allow(dead_code, reason = "only its bench target is used here")]
mod scale_program;

/// How many networks the program has.
pub const NETWORKS: usize = 1_000;
/// Its one source, as the session names it.
pub const FILE: &str = "src/main.lad";

/// The project, written fresh into `gutta-studio-TAG-PID` in the temporary folder:
/// gutta.toml naming the bench target, src/main.lad.
pub fn project(tag: &str) -> PathBuf {
    let root = std::env::temp_dir().join(format!("gutta-studio-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(root.join("src")).expect("project folder");
    let target = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../compiler/benches/target"
    ));
    let text = corpus_program::generate(NETWORKS, &scale_program::bench_target());
    std::fs::write(root.join(FILE), text).expect("main.lad");
    std::fs::write(
        root.join("gutta.toml"),
        format!(
            "[program]\ntarget = {:?}\nsources = [\"{FILE}\"]\n",
            target.display().to_string()
        ),
    )
    .expect("gutta.toml");
    root
}
