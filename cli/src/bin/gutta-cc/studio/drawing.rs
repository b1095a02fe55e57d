//! The networks as the studio page draws them (docs/studio.md, "The page"): each one an
//! inline `<svg>` of `gutta_ladder::svg::draw_network_with` (the classes and `data-*` of
//! `gutta-cc ladder`), every contact, coil and box also carrying `data-path`, the JSON
//! path of the ladder model the edit operations and diagnostics use
//! (`blocks[0].networks[2].rung.series[1]`). The paths follow the model's own shape
//! (`gutta_ladder::json`'s `rung_element`: a rung is its input path in series with its
//! outputs, nested series spliced, a series of one its element). Text only.

use std::fmt::Write as _;

use gutta_ladder::model::{Block, Body, Branch, BranchEnd, Network, Node};
use gutta_ladder::svg::{draw_network_with, escape, DrawOptions};

/// The model's shape with element ids at the leaves.
enum Shape {
    Leaf(u32),
    Series(Vec<Shape>),
    Parallel(Vec<Shape>),
    Box(u32, Vec<Shape>),
}

fn series(parts: Vec<Shape>) -> Shape {
    let mut flat = Vec::with_capacity(parts.len());
    for p in parts {
        match p {
            Shape::Series(inner) => flat.extend(inner),
            other => flat.push(other),
        }
    }
    if flat.len() == 1 {
        flat.remove(0)
    } else {
        Shape::Series(flat)
    }
}

fn node(n: &Node) -> Shape {
    match n {
        Node::Contact(c) => Shape::Leaf(c.id),
        Node::Box(b) => Shape::Box(b.id, b.power_inputs.iter().map(|(_, n)| node(n)).collect()),
        Node::Series(nodes) => series(nodes.iter().map(node).collect()),
        Node::Parallel(nodes) => Shape::Parallel(nodes.iter().map(node).collect()),
    }
}

fn outputs(branches: &[Branch]) -> Shape {
    match branches {
        [one] => branch(one),
        _ => Shape::Parallel(branches.iter().map(branch).collect()),
    }
}

fn branch(b: &Branch) -> Shape {
    let mut parts: Vec<Shape> = b.path.iter().map(node).collect();
    parts.push(match &b.end {
        BranchEnd::Coil(c) => Shape::Leaf(c.id),
        BranchEnd::Box(b) => {
            Shape::Box(b.id, b.power_inputs.iter().map(|(_, n)| node(n)).collect())
        }
        BranchEnd::Split(branches) => outputs(branches),
    });
    series(parts)
}

fn walk(shape: &Shape, path: &str, out: &mut Vec<(u32, String)>) {
    match shape {
        Shape::Leaf(id) => out.push((*id, path.to_string())),
        Shape::Series(parts) => {
            for (i, p) in parts.iter().enumerate() {
                walk(p, &format!("{path}.series[{i}]"), out);
            }
        }
        Shape::Parallel(parts) => {
            for (i, p) in parts.iter().enumerate() {
                walk(p, &format!("{path}.parallel[{i}]"), out);
            }
        }
        Shape::Box(id, inputs) => {
            out.push((*id, path.to_string()));
            for (i, p) in inputs.iter().enumerate() {
                walk(p, &format!("{path}.inputs[{i}]"), out);
            }
        }
    }
}

/// Each element id of network `n` of block `b` with its JSON path.
pub(crate) fn element_paths(b: usize, n: usize, net: &Network) -> Vec<(u32, String)> {
    let mut out = Vec::new();
    if let Body::Rung(rung) = &net.body {
        let mut parts = Vec::new();
        if let Some(input) = &rung.input {
            parts.push(node(input));
        }
        parts.push(outputs(&rung.outputs));
        walk(
            &series(parts),
            &format!("blocks[{b}].networks[{n}].rung"),
            &mut out,
        );
    }
    out
}

/// Network `n` of block `b` as the page's `<svg>` drawn with `draw`, its elements with
/// `data-path`.
pub(crate) fn network_html(
    b: usize,
    n: usize,
    block: &Block,
    net: &Network,
    draw: &DrawOptions,
) -> String {
    let mut drawn = String::new();
    let (w, h) = draw_network_with(&mut drawn, block, net, 0, draw);
    for (id, path) in element_paths(b, n, net) {
        let from = format!(" data-id=\"{id}\" ");
        let to = format!(" data-id=\"{id}\" data-path=\"{}\" ", escape(&path));
        drawn = drawn.replacen(&from, &to, 1);
    }
    let mut out = String::with_capacity(drawn.len() + 128);
    let _ = write!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" \
         viewBox=\"0 0 {w} {h}\">{drawn}</svg>"
    );
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_element_gets_the_path_of_its_model_json() {
        let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD I0.0\nO Q0.0\nAN I0.1\n\
                    LPS\nA I0.2\n= Q0.0\nLPP\nTON T37, 100\nEND_ORGANIZATION_BLOCK\n";
        let checked = gutta_compiler::check_program(
            gutta_compiler::ProgramSources {
                sources: vec![gutta_compiler::source::SourceFile::new("t.lad", text)],
                symbol_tables: Vec::new(),
                options: Default::default(),
            },
            None,
        );
        let ladder = gutta_ladder::build(&checked);
        let block = &ladder.blocks[0];
        let html = network_html(0, 0, block, &block.networks[0], &DrawOptions::default());
        let paths: Vec<&str> = html
            .split("data-path=\"")
            .skip(1)
            .map(|s| &s[..s.find('"').unwrap()])
            .collect();
        let rung = "blocks[0].networks[0].rung";
        let want: Vec<String> = [
            ".series[0].parallel[0]",
            ".series[0].parallel[1]",
            ".series[1]",
            ".series[2].parallel[0].series[0]",
            ".series[2].parallel[0].series[1]",
            ".series[2].parallel[1]",
        ]
        .iter()
        .map(|p| format!("{rung}{p}"))
        .collect();
        let mut got: Vec<String> = paths.iter().map(|s| s.to_string()).collect();
        got.sort();
        assert_eq!(got, want, "{html}");
    }
}
