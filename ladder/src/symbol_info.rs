//! A network's symbol information (docs/ladder.md, "Symbol information"): the table of
//! the symbols its rung uses, in order of first use, drawn under the rung as
//! Micro/WIN's "symbol information" does (`DrawOptions::symbol_info`). Reads only the
//! model (the builder filled each operand's symbol, comment and type); text only.

use std::fmt::Write;

use crate::layout::{text_width, wrap, LINE_H, MARGIN, MIN_TEXT_W, RAIL_X};
use crate::model::{Body, Branch, BranchEnd, Network, Node, Operand};
use crate::svg::{escape_into, text};

/// One row: a symbol the network uses.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SymbolRow<'a> {
    pub symbol: &'a str,
    /// The canonical address (empty when the symbol has none, as a block name).
    pub address: &'a str,
    /// The declared type, else the address's width (`BOOL`, `WORD`); empty if unknown.
    pub data_type: &'a str,
    /// The symbol's comment (empty without one).
    pub comment: &'a str,
}

/// The symbols of a network's rung, once each (names compared case-insensitively), in
/// order of first use: by source line, then operand order. A network shown as STL has
/// none (the model keeps no operands of it).
pub fn rows(net: &Network) -> Vec<SymbolRow<'_>> {
    let Body::Rung(rung) = &net.body else {
        return Vec::new();
    };
    let mut used: Vec<(u32, &Operand)> = Vec::new();
    if let Some(input) = &rung.input {
        node(input, &mut used);
    }
    for branch in &rung.outputs {
        branch_operands(branch, &mut used);
    }
    // Stable: operands of one instruction keep their order.
    used.sort_by_key(|(line, _)| *line);
    let mut rows: Vec<SymbolRow<'_>> = Vec::new();
    for (_, op) in used {
        let Some(symbol) = op.symbol.as_deref() else {
            continue;
        };
        if rows.iter().any(|r| r.symbol.eq_ignore_ascii_case(symbol)) {
            continue;
        }
        rows.push(SymbolRow {
            symbol,
            address: op.address.as_deref().unwrap_or(""),
            data_type: op.data_type.as_deref().unwrap_or(""),
            comment: op.comment.as_deref().unwrap_or(""),
        });
    }
    rows
}

fn node<'a>(n: &'a Node, used: &mut Vec<(u32, &'a Operand)>) {
    match n {
        Node::Contact(c) => used.extend(c.operands.iter().map(|o| (c.line, o))),
        Node::Box(b) => node_box(b, used),
        Node::Series(nodes) | Node::Parallel(nodes) => {
            for n in nodes {
                node(n, used);
            }
        }
    }
}

fn branch_operands<'a>(branch: &'a Branch, used: &mut Vec<(u32, &'a Operand)>) {
    for n in &branch.path {
        node(n, used);
    }
    match &branch.end {
        BranchEnd::Coil(c) => {
            used.push((c.line, &c.operand));
            used.extend(c.count.iter().map(|o| (c.line, o)));
        }
        BranchEnd::Box(b) => node_box(b, used),
        BranchEnd::Split(branches) => {
            for b in branches {
                branch_operands(b, used);
            }
        }
    }
}

fn node_box<'a>(b: &'a crate::model::BoxElement, used: &mut Vec<(u32, &'a Operand)>) {
    // The timer or counter drawn above the box comes first, as it is first in its STL.
    used.extend(b.counted.iter().map(|o| (b.line, &**o)));
    used.extend(b.pins.iter().map(|p| (b.line, &p.operand)));
    for (_, path) in &b.power_inputs {
        node(path, used);
    }
}

const HEAD: [&str; 4] = ["Symbol", "Address", "Type", "Comment"];
/// Space between two columns.
const COLUMN_GAP: i32 = 16;
/// The narrowest a comment column wraps at: 24 columns.
const MIN_COMMENT_W: i32 = 24 * 7;

/// Draw the table of `rows` with its top at `top`, under a drawing `width` wide: a rule,
/// the column heads, then one `<g class="symbol-info-row" data-symbol>` per row, a long
/// comment wrapped at the drawing's width. Returns the table's (width, height); nothing
/// is drawn for no rows.
pub fn draw(out: &mut String, rows: &[SymbolRow<'_>], top: i32, width: i32) -> (i32, i32) {
    if rows.is_empty() {
        return (0, 0);
    }
    let column = |i: usize, cell: for<'r> fn(&'r SymbolRow<'r>) -> &'r str| {
        rows.iter()
            .map(|r| text_width(cell(r)))
            .chain([text_width(HEAD[i])])
            .max()
            .unwrap_or(0)
            + COLUMN_GAP
    };
    let x_symbol = RAIL_X;
    let x_address = x_symbol + column(0, |r| r.symbol);
    let x_type = x_address + column(1, |r| r.address);
    let x_comment = x_type + column(2, |r| r.data_type);
    let comment_w = (width.max(MIN_TEXT_W + 2 * RAIL_X) - RAIL_X - x_comment).max(MIN_COMMENT_W);
    let comments: Vec<Vec<String>> = rows
        .iter()
        .map(|r| {
            if r.comment.is_empty() {
                Vec::new()
            } else {
                wrap(r.comment, comment_w)
            }
        })
        .collect();
    let right = comments
        .iter()
        .flatten()
        .map(|l| x_comment + text_width(l))
        .chain([x_comment + text_width(HEAD[3])])
        .max()
        .unwrap_or(x_comment);
    let _ = write!(
        out,
        "<g class=\"symbol-info\"><line class=\"symbol-info-rule\" x1=\"{RAIL_X}\" y1=\"{top}\" \
         x2=\"{}\" y2=\"{top}\"/>",
        width.max(right + RAIL_X) - RAIL_X
    );
    let mut y = top + LINE_H;
    let xs = [x_symbol, x_address, x_type, x_comment];
    for (x, head) in xs.iter().zip(HEAD) {
        text(out, "si-head", *x, y, "start", head);
    }
    for (row, lines) in rows.iter().zip(&comments) {
        y += LINE_H;
        out.push_str("<g class=\"symbol-info-row\" data-symbol=\"");
        escape_into(out, row.symbol);
        out.push_str("\">");
        text(out, "si-symbol", x_symbol, y, "start", row.symbol);
        text(out, "si-address", x_address, y, "start", row.address);
        text(out, "si-type", x_type, y, "start", row.data_type);
        for (i, line) in lines.iter().enumerate() {
            if i > 0 {
                y += LINE_H;
            }
            text(out, "si-comment", x_comment, y, "start", line);
        }
        out.push_str("</g>");
    }
    out.push_str("</g>");
    (right + RAIL_X, y - top + MARGIN)
}
