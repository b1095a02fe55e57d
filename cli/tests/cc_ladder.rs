//! `gutta-cc ladder` through the real binary (docs/ladder.md): every example drawn as
//! SVG and as a self-contained HTML page, the same bytes twice; the page opened in
//! headless Chromium (Debian's package), its DOM holding as many networks, contacts,
//! coils and boxes as the model, and a screenshot kept in the target folder; an image
//! directory drawn through the disassembler (addresses, no symbols); a project; a bad
//! output name.

mod common;

use std::path::Path;

use common::{cc, cc_in, examples, have, root, stderr, text};
use gutta_compiler::source::SourceFile;
use gutta_compiler::{check_program, ProgramSources};
use gutta_ladder::model::{Body, BranchEnd, Ladder, Node};

/// The model of a source file, through the library.
fn model(path: &Path) -> Ladder {
    let text = std::fs::read_to_string(path).expect("reads");
    let checked = check_program(
        ProgramSources::single(SourceFile::new(path.display().to_string(), text)),
        None,
    );
    assert!(!checked.has_errors(), "{}", path.display());
    gutta_ladder::build(&checked)
}

/// Networks, contacts, coils and boxes of a model (what the page must hold).
#[derive(Debug, Default, PartialEq, Eq)]
struct Counts {
    networks: usize,
    stl: usize,
    contacts: usize,
    coils: usize,
    boxes: usize,
}

fn count_node(node: &Node, c: &mut Counts) {
    match node {
        Node::Contact(_) => c.contacts += 1,
        Node::Box(b) => {
            c.boxes += 1;
            for (_, n) in &b.power_inputs {
                count_node(n, c);
            }
        }
        Node::Series(nodes) | Node::Parallel(nodes) => nodes.iter().for_each(|n| count_node(n, c)),
    }
}

fn count_branch(branch: &gutta_ladder::model::Branch, c: &mut Counts) {
    branch.path.iter().for_each(|n| count_node(n, c));
    match &branch.end {
        BranchEnd::Coil(_) => c.coils += 1,
        BranchEnd::Box(b) => {
            c.boxes += 1;
            for (_, n) in &b.power_inputs {
                count_node(n, c);
            }
        }
        BranchEnd::Split(branches) => branches.iter().for_each(|b| count_branch(b, c)),
    }
}

fn counts(ladder: &Ladder) -> Counts {
    let mut c = Counts::default();
    for net in ladder.blocks.iter().flat_map(|b| &b.networks) {
        c.networks += 1;
        match &net.body {
            Body::Stl { .. } => c.stl += 1,
            Body::Rung(rung) => {
                if let Some(input) = &rung.input {
                    count_node(input, &mut c);
                }
                rung.outputs.iter().for_each(|b| count_branch(b, &mut c));
            }
        }
    }
    c
}

/// Elements of a class in markup: `class="NAME"` or `class="NAME ..."`.
fn class_count(markup: &str, class: &str) -> usize {
    markup.matches(&format!("class=\"{class}\"")).count()
        + markup.matches(&format!("class=\"{class} ")).count()
}

fn markup_counts(markup: &str) -> Counts {
    Counts {
        networks: class_count(markup, "network"),
        stl: markup.matches("class=\"network stl\"").count(),
        contacts: class_count(markup, "contact"),
        coils: class_count(markup, "coil"),
        boxes: class_count(markup, "box"),
    }
}

#[test]
fn every_example_is_drawn_as_svg_and_html_the_same_bytes_twice() {
    let dir = common::scratch("ladder-examples");
    for path in examples() {
        let stem = path
            .file_stem()
            .expect("stem")
            .to_string_lossy()
            .into_owned();
        let want = counts(&model(&path));
        for ext in ["svg", "html"] {
            let out = dir.join(format!("{stem}.{ext}"));
            let args = [
                "ladder",
                path.to_str().expect("path"),
                "-o",
                out.to_str().expect("path"),
            ];
            let o = cc(&args);
            assert_eq!(o.status.code(), Some(0), "{}", text(&o));
            let first = std::fs::read_to_string(&out).expect("written");
            assert_eq!(markup_counts(&first), want, "{stem}.{ext}");
            let o = cc(&args);
            assert_eq!(o.status.code(), Some(0), "{}", text(&o));
            assert_eq!(
                std::fs::read_to_string(&out).expect("written"),
                first,
                "{stem}.{ext} twice"
            );
            if ext == "html" {
                for external in ["src=\"http", "href=\"http", "url(http", "@import"] {
                    assert!(!first.contains(external), "{stem}.html loads {external}");
                }
            }
        }
    }
}

#[test]
fn the_page_opens_in_headless_chromium() {
    if !have("chromium") {
        return;
    }
    let dir = common::scratch("ladder-chromium");
    let page = dir.join("tank.html");
    let example = root().join("examples/tank.lad");
    let o = cc(&[
        "ladder",
        example.to_str().expect("path"),
        "-o",
        page.to_str().expect("path"),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let url = format!("file://{}", page.display());
    let chromium = |extra: &[&str]| {
        let mut args = vec![
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--hide-scrollbars",
        ];
        args.extend_from_slice(extra);
        args.push(&url);
        std::process::Command::new("chromium")
            .args(&args)
            .output()
            .expect("chromium runs")
    };
    let dom = chromium(&["--dump-dom"]);
    assert!(
        dom.status.success(),
        "{}",
        String::from_utf8_lossy(&dom.stderr)
    );
    let dom = String::from_utf8_lossy(&dom.stdout).into_owned();
    assert_eq!(
        markup_counts(&dom),
        counts(&model(&example)),
        "the DOM Chromium built"
    );
    // A screenshot for people to look at, kept with the build's test artifacts.
    let shot = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ladder-tank.png");
    let _ = std::fs::remove_file(&shot);
    let taken = chromium(&[
        &format!("--screenshot={}", shot.display()),
        "--window-size=1400,1800",
    ]);
    assert!(
        taken.status.success(),
        "{}",
        String::from_utf8_lossy(&taken.stderr)
    );
    let png = std::fs::read(&shot).expect("the screenshot");
    assert!(
        png.starts_with(b"\x89PNG") && png.len() > 10_000,
        "{} bytes",
        png.len()
    );
}

#[test]
fn an_image_directory_is_drawn_through_the_disassembler() {
    let dir = common::scratch("ladder-image");
    let image = dir.join("image");
    let example = root().join("examples/tank.lad");
    let o = cc(&[
        example.to_str().expect("path"),
        "-o",
        image.to_str().expect("path"),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let out = dir.join("image.svg");
    let o = cc(&[
        "ladder",
        image.to_str().expect("path"),
        "-o",
        out.to_str().expect("path"),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let svg = std::fs::read_to_string(&out).expect("written");
    assert!(svg.contains("data-operand=\"I0.0\""), "{svg}");
    assert!(!svg.contains(">Enable<"), "an image has no symbols");
    assert_eq!(
        markup_counts(&svg).networks,
        counts(&model(&example)).networks,
        "the same networks as the source"
    );
}

#[test]
fn a_project_is_drawn_with_its_symbols() {
    let dir = common::scratch("ladder-project");
    let o = cc_in(&dir, &["new", "demo"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let o = cc_in(&dir, &["ladder", "demo", "-o", "demo.html"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let page = std::fs::read_to_string(dir.join("demo.html")).expect("written");
    assert!(
        page.contains(">Start<") && page.contains("data-operand=\"I0.0\""),
        "{page}"
    );
    assert!(
        stderr(&o).contains("networks drawn as ladder"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn the_output_must_be_svg_or_html() {
    let dir = common::scratch("ladder-usage");
    let o = cc_in(
        &dir,
        &[
            "ladder",
            root().join("examples/tank.lad").to_str().expect("path"),
            "-o",
            "x.png",
        ],
    );
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(stderr(&o).contains("ends in .svg"), "{}", stderr(&o));
    assert!(!dir.join("x.png").exists());
}
