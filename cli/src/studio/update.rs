//! What the page gets back after an edit, an undo or a redo: the networks to redraw
//! with their SVG as `gutta-cc ladder` draws them (`gutta_ladder::svg::network_svg`, the
//! classes and `data-*` attributes of issue 27's fixed decisions), the shape of the
//! file's blocks, and every diagnostic of the file at the JSON path of its cause.
//! Which networks an edit touched is `gutta_ladder::edit::Change`'s; this file only
//! turns it into drawings.

use std::collections::BTreeMap;

use gutta_ladder::edit::Change;
use gutta_ladder::json::ModelDiagnostic;
use gutta_ladder::model::Ladder;
use gutta_ladder::svg::network_svg;
use serde::Serialize;

/// The answer to an applied edit, undo or redo.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Update {
    /// The file, as the session names it (`src/main.lad`).
    pub file: String,
    /// The networks to draw again, in order: the one an element or heading edit
    /// changed; from an inserted, deleted or moved network's place to the end of its
    /// block (their numbers moved).
    pub networks: Vec<NetworkDrawing>,
    /// Every block of the file with its title and number of networks now (the page
    /// drops what lies beyond).
    pub blocks: Vec<BlockShape>,
    /// Every diagnostic of the file, each at the JSON path of the part of the model
    /// that caused it (`blocks[0].networks[2].rung.series[1]`; `""`: the whole file).
    pub diagnostics: Vec<ModelDiagnostic>,
    /// Whether the buffer differs from the file on disk.
    pub dirty: bool,
    pub can_undo: bool,
    pub can_redo: bool,
}

/// One network drawn: `<g class="network" data-block=... data-network=...>`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct NetworkDrawing {
    /// Its block's place in the file.
    pub block: usize,
    /// Its place in the block (the JSON path's index, from 0).
    pub network: usize,
    pub svg: String,
}

/// A block's title and how many networks it has.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct BlockShape {
    pub name: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub title: Option<String>,
    pub networks: usize,
}

/// For each block, the first network `changes` moved or changed and whether the rest of
/// the block follows (inserted, deleted, moved: the later networks' places changed).
fn touched(changes: &[Change]) -> BTreeMap<usize, Vec<(usize, bool)>> {
    let mut touched: BTreeMap<usize, Vec<(usize, bool)>> = BTreeMap::new();
    for change in changes {
        let (block, network, rest) = match *change {
            Change::Lines(at) | Change::Heading(at) => (at.block, at.network, false),
            Change::Inserted(at) | Change::Deleted(at) => (at.block, at.network, true),
            Change::Moved { block, from, to } => (block, from.min(to), true),
            Change::Block(_) => continue,
        };
        touched.entry(block).or_default().push((network, rest));
    }
    touched
}

/// The networks of `ladder` (the file as it is now) that `changes` touched, drawn.
pub(super) fn drawings(ladder: &Ladder, changes: &[Change]) -> Vec<NetworkDrawing> {
    let mut out = Vec::new();
    for (b, marks) in touched(changes) {
        let Some(block) = ladder.blocks.get(b) else {
            continue;
        };
        let from_rest = marks
            .iter()
            .filter(|(_, rest)| *rest)
            .map(|(n, _)| *n)
            .min();
        let mut wanted: Vec<usize> = marks
            .iter()
            .filter(|(_, rest)| !*rest)
            .map(|(n, _)| *n)
            .collect();
        if let Some(from) = from_rest {
            wanted.extend(from..block.networks.len());
        }
        wanted.sort_unstable();
        wanted.dedup();
        for n in wanted {
            if let Some(net) = block.networks.get(n) {
                out.push(NetworkDrawing {
                    block: b,
                    network: n,
                    svg: network_svg(block, net),
                });
            }
        }
    }
    out
}

/// Every block's shape.
pub(super) fn shapes(ladder: &Ladder) -> Vec<BlockShape> {
    ladder
        .blocks
        .iter()
        .map(|b| BlockShape {
            name: b.name.clone(),
            title: b.title.clone(),
            networks: b.networks.len(),
        })
        .collect()
}
