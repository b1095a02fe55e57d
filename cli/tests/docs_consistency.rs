//! The documentation stands on its own and agrees with the repository:
//!
//! - no Markdown file and no doc comment points at documents outside the repository
//!   (the vendor documents are described in docs/sources.md);
//! - docs/testing.md's manual install list names every tool `.ci/run` installs, and
//!   its description of `.ci/run` lists the steps in the script's order;
//! - README.md's "Documentation" list names every page of docs/.

mod common;

use common::docs::{read, relative, repo, walk};

// ---------------------------------------------------------------------------------
// The docs stand on their own

/// The lines of `text` that point outside the repository: the folder the project's
/// source documents were handed over in, or their file names. `markdown`: every line
/// counts; otherwise (Rust) only doc comments do.
fn outside_references(text: &str, markdown: bool) -> Vec<(usize, String)> {
    let shared = concat!("..", "/shared");
    let seeds = concat!("seeds", "/");
    text.lines()
        .enumerate()
        .filter(|(_, line)| {
            let t = line.trim_start();
            markdown || t.starts_with("///") || t.starts_with("//!")
        })
        .filter(|(_, line)| line.contains(shared) || line.contains(seeds))
        .map(|(n, line)| (n + 1, line.to_string()))
        .collect()
}

#[test]
fn no_doc_points_outside_the_repository() {
    // The check itself finds what it looks for.
    let sample = format!("see `{}/GUTTA.md`\n", concat!("..", "/shared"));
    assert_eq!(outside_references(&sample, true).len(), 1);
    assert_eq!(outside_references(&format!("/// {sample}"), false).len(), 1);
    assert!(outside_references(&format!("let s = \"{sample}\";"), false).is_empty());

    let mut found = Vec::new();
    let mut markdown = 0;
    walk(&repo(), &mut |p| {
        let ext = p.extension().and_then(|e| e.to_str()).unwrap_or("");
        if !matches!(ext, "md" | "rs") {
            return;
        }
        markdown += usize::from(ext == "md");
        let Ok(text) = std::fs::read_to_string(p) else {
            return;
        };
        for (n, line) in outside_references(&text, ext == "md") {
            found.push(format!("{}:{n}: {line}", relative(p)));
        }
    });
    assert!(markdown >= 20, "only {markdown} Markdown files found");
    assert!(
        found.is_empty(),
        "docs must stand on their own: cite the vendor documents through docs/sources.md:\n{}",
        found.join("\n")
    );
}

/// The words after `install` on `line`, flags left out.
fn installed(line: &str) -> Vec<String> {
    let (_, rest) = line
        .split_once("install ")
        .unwrap_or_else(|| panic!("no `install` in {line}"));
    let mut words: Vec<String> = rest
        .split_whitespace()
        .filter(|w| !w.starts_with('-') && !w.starts_with('>') && !w.starts_with('$'))
        .map(|w| w.trim_matches('"').to_string())
        .collect();
    words.sort();
    words
}

/// The text of `file` from the line starting with `from` up to the next heading.
fn section<'a>(text: &'a str, from: &str) -> &'a str {
    let start = text.find(from).unwrap_or_else(|| panic!("no `{from}`"));
    let rest = &text[start + from.len()..];
    let end = rest.find("\n#").map_or(rest.len(), |e| e + 1);
    &rest[..end]
}

#[test]
fn the_manual_install_list_is_what_ci_installs() {
    let ci = read(&repo().join(".ci/run"));
    let packages = ci
        .lines()
        .find_map(|l| l.strip_prefix("PACKAGES=\""))
        .and_then(|l| l.strip_suffix('"'))
        .expect(".ci/run sets PACKAGES=\"...\"");
    let mut apt: Vec<String> = packages.split_whitespace().map(str::to_string).collect();
    apt.sort();
    let pip = installed(
        ci.lines()
            .find(|l| l.contains("pip install"))
            .expect(".ci/run installs with pip"),
    );

    let testing = read(&repo().join("docs/testing.md"));
    let tools = section(&testing, "### External tools");
    let doc_apt = installed(
        tools
            .lines()
            .find(|l| l.starts_with("apt-get install"))
            .expect("docs/testing.md's External tools: an `apt-get install` line"),
    );
    let doc_pip = installed(
        tools
            .lines()
            .find(|l| l.contains("pip install"))
            .expect("docs/testing.md's External tools: a `pip install` line"),
    );
    assert!(apt.len() >= 5 && pip.len() >= 3, "{apt:?} {pip:?}");
    assert_eq!(
        doc_apt, apt,
        "docs/testing.md's apt-get line vs .ci/run's PACKAGES"
    );
    assert_eq!(doc_pip, pip, "docs/testing.md's pip line vs .ci/run's");
}

/// The commands `.ci/run` runs after installing, in order, as docs/testing.md names
/// them: each `cargo ...` line (but `cargo --version`) up to a pipe or redirection.
fn ci_steps(script: &str) -> Vec<String> {
    script
        .lines()
        .map(str::trim)
        .filter(|l| l.starts_with("cargo ") || l.starts_with("RUSTDOCFLAGS="))
        .filter(|l| *l != "cargo --version")
        .map(|l| {
            let end = [" 2>", " |", " >", " ||", ";"]
                .iter()
                .filter_map(|s| l.find(s))
                .min()
                .unwrap_or(l.len());
            l[..end].to_string()
        })
        .collect()
}

#[test]
fn docs_testing_md_lists_ci_steps_in_the_scripts_order() {
    let script = read(&repo().join(".ci/run"));
    let steps = ci_steps(&script);
    assert!(steps.len() >= 4, "{steps:?}");
    let install = script.find("PACKAGES=").expect("installs");
    let first = script.find(&steps[0]).expect("a step");
    assert!(install < first, ".ci/run installs before it builds");
    assert!(
        steps.last().is_some_and(|s| s.starts_with("cargo test")),
        "the tests run last: {steps:?}"
    );
    assert!(script.contains("passed, "), ".ci/run prints a summary line");

    let testing = read(&repo().join("docs/testing.md"));
    let list = section(&testing, "`bash .ci/run` (CI) runs these steps");
    let mut at = list
        .find("installs the external tools")
        .expect("step 1: installs");
    for step in &steps {
        let span = format!("`{step}`");
        let found = list[at..].find(&span).unwrap_or_else(|| {
            panic!("docs/testing.md does not list `{step}` (after the steps before it): {steps:?}")
        });
        at += found + span.len();
    }
    assert!(
        list[at..].contains("N passed, N failed"),
        "docs/testing.md: the summary line comes last"
    );
}

#[test]
fn readme_lists_every_page_of_docs() {
    let readme = read(&repo().join("README.md"));
    let list = section(&readme, "## Documentation");
    let mut pages: Vec<String> = std::fs::read_dir(repo().join("docs"))
        .expect("docs/")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .map(|p| format!("docs/{}", p.file_name().unwrap().to_string_lossy()))
        .collect();
    pages.sort();
    assert!(pages.len() >= 20, "{pages:?}");
    let missing: Vec<&String> = pages
        .iter()
        .filter(|p| !list.contains(&format!("]({p})")))
        .collect();
    assert!(
        missing.is_empty(),
        "README.md's Documentation list lacks {missing:?}: add each with one line saying what it is"
    );
    // And every link there leads to a file.
    for link in list.split("](").skip(1) {
        let target = link.split(')').next().unwrap_or("");
        assert!(
            repo().join(target).is_file(),
            "README.md links {target}, which does not exist"
        );
    }
}
