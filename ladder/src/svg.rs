//! SVG of networks and whole ladders (docs/ladder.md, "Drawing"): draws the geometry of
//! `layout.rs` with the class and `data-*` names issue 15 fixed, so tools and the live
//! view find every element. Text only: no I/O, all text XML-escaped, integers only (the
//! same model always gives the same bytes).

use std::fmt::Write;

use crate::layout::{
    block_heading, box_pins, contact_label, contact_symbol_w, header_height, layout_network,
    operand_lines, text_width, ElementRef, NetworkLayout, PlacedElement, Power, Wire, LINE_H,
    MARGIN, RAIL_X,
};
use crate::model::{Block, Body, BoxElement, Coil, CoilKind, Contact, Ladder, Network, Operand};

/// Height of a block's heading in a standalone SVG.
const BLOCK_HEADING_H: i32 = 30;
/// Space between two networks in a standalone SVG.
const NETWORK_GAP: i32 = 8;

/// The styles of the drawing, shared by the standalone SVG and the HTML page.
pub const STYLE: &str = "\
text{font-family:monospace;font-size:11px;fill:#222}\
.network-title{font-size:13px;font-weight:bold}\
.comment{fill:#555;font-style:italic}\
.block-title{font-size:16px;font-weight:bold}\
.reason{fill:#a33}\
.stl{font-size:12px}\
.wire,.rail,.pin,.symbol-line{stroke:#222;stroke-width:1.5;fill:none}\
.rail{stroke-width:3}\
.box rect{fill:#fff;stroke:#222;stroke-width:1.5}\
.box .title{font-weight:bold}\
.inside{font-size:10px}\
";

/// XML-escape text for element content and attribute values.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    escape_into(&mut out, text);
    out
}

/// XML-escape `text` onto the end of `out`.
pub fn escape_into(out: &mut String, text: &str) {
    let mut rest = text;
    while let Some(at) = rest.find(['&', '<', '>', '"', '\'']) {
        out.push_str(&rest[..at]);
        out.push_str(match rest.as_bytes()[at] {
            b'&' => "&amp;",
            b'<' => "&lt;",
            b'>' => "&gt;",
            b'"' => "&quot;",
            _ => "&apos;",
        });
        rest = &rest[at + 1..];
    }
    out.push_str(rest);
}

/// How boxes and compare contacts are labelled (docs/ladder.md, "Names").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Names {
    /// Micro/WIN's LAD names: `ADD_I`, `MOV_W`, `>=I`.
    #[default]
    Lad,
    /// The STL mnemonics the source writes: `+I`, `MOVW`, `>=W`.
    Stl,
}

/// What a drawing shows besides the rungs; the same for `gutta-cc ladder`, the monitor
/// and the studio. `Default` is what `gutta-cc ladder` draws without flags.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct DrawOptions {
    /// Box and compare labels (`--names`).
    pub names: Names,
    /// A table of the network's symbols under each rung, Micro/WIN's "symbol
    /// information" (`--symbol-info`).
    pub symbol_info: bool,
}

/// One network as a `<g class="network">` (or `class="network stl"`) at the origin,
/// drawn with the default options.
pub fn network_svg(block: &Block, net: &Network) -> String {
    network_svg_with(block, net, &DrawOptions::default())
}

/// One network as a `<g class="network">` (or `class="network stl"`) at the origin.
pub fn network_svg_with(block: &Block, net: &Network, options: &DrawOptions) -> String {
    let mut out = String::new();
    draw_network_with(&mut out, block, net, 0, options);
    out
}

/// Append one network's group, translated down by `y`, to `out`, drawn with the default
/// options; returns the drawing's (width, height).
pub fn draw_network(out: &mut String, block: &Block, net: &Network, y: i32) -> (i32, i32) {
    draw_network_with(out, block, net, y, &DrawOptions::default())
}

/// Append one network's group, translated down by `y`, to `out`; returns the drawing's
/// (width, height).
pub fn draw_network_with(
    out: &mut String,
    block: &Block,
    net: &Network,
    y: i32,
    _options: &DrawOptions,
) -> (i32, i32) {
    let _ = write!(out, "<g class=\"network");
    if let Body::Stl { .. } = net.body {
        out.push_str(" stl");
    }
    out.push_str("\" data-block=\"");
    escape_into(out, &block.name);
    let _ = write!(out, "\" data-network=\"{}\"", net.number);
    if let Body::Stl { reason } = &net.body {
        out.push_str(" data-reason=\"");
        escape_into(out, reason);
        out.push('"');
    }
    if y != 0 {
        let _ = write!(out, " transform=\"translate(0,{y})\"");
    }
    out.push('>');
    header(out, net);
    // The title is 13 px bold against the 11 px the text widths count: 13/11 wider,
    // rounded up, so a long title is never clipped by the network's width.
    let title_w = (text_width(&title_line(net)) * 13 + 10) / 11 + 2 * RAIL_X;
    let size = match (&net.body, layout_network(net)) {
        (_, Some(layout)) => {
            rung(out, &layout);
            (layout.width.max(title_w), layout.height)
        }
        (Body::Stl { reason }, None) => {
            let mut ty = header_height(net) + LINE_H - 4;
            let reason_line = format!("shown as STL: {reason}");
            text(out, "reason", RAIL_X, ty, "start", &reason_line);
            let mut width = text_width(&reason_line);
            // Each line is `text.stl.stl-line[data-index]` (its index in `Network::stl`):
            // the live view sets `data-rlo` on it and adds its value (`tspan.value`).
            for (index, line) in net.stl.iter().enumerate() {
                ty += LINE_H;
                let _ = write!(
                    out,
                    "<text class=\"stl stl-line\" data-index=\"{index}\" x=\"{}\" y=\"{ty}\" text-anchor=\"start\">",
                    RAIL_X + 8
                );
                escape_into(out, line);
                out.push_str("</text>");
                width = width.max(text_width(line) + 8);
            }
            ((width + 2 * RAIL_X).max(title_w), ty + MARGIN)
        }
        (Body::Rung(_), None) => unreachable!("layout_network lays out every rung"),
    };
    out.push_str("</g>");
    size
}

/// A whole ladder as a standalone SVG document, drawn with the default options.
pub fn ladder_svg(ladder: &Ladder) -> String {
    ladder_svg_with(ladder, &DrawOptions::default())
}

/// A whole ladder as a standalone SVG document: blocks in order, each with its heading,
/// its networks stacked under it.
pub fn ladder_svg_with(ladder: &Ladder, options: &DrawOptions) -> String {
    let networks: usize = ladder.blocks.iter().map(|b| b.networks.len()).sum();
    let mut body = String::with_capacity(networks * 8192);
    let mut y = 0;
    let mut width = 200;
    for block in &ladder.blocks {
        y += BLOCK_HEADING_H;
        text(
            &mut body,
            "block-title",
            RAIL_X,
            y - 10,
            "start",
            &block_heading(block),
        );
        width = width.max(text_width(&block_heading(block)) * 3 / 2 + 2 * RAIL_X);
        for net in &block.networks {
            let (w, h) = draw_network_with(&mut body, block, net, y, options);
            body.push('\n');
            y += h + NETWORK_GAP;
            width = width.max(w);
        }
    }
    let height = y + MARGIN;
    let mut out = String::with_capacity(body.len() + STYLE.len() + 512);
    let _ = write!(
        out,
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" \
         class=\"ladder\" data-plc=\"{}\" width=\"{width}\" height=\"{height}\" \
         viewBox=\"0 0 {width} {height}\">\n<style>{STYLE}</style>\n",
        escape(&ladder.plc)
    );
    out.push_str(&body);
    out.push_str("</svg>\n");
    out
}

fn title_line(net: &Network) -> String {
    match &net.title {
        Some(title) => format!("Network {}: {}", net.number, title),
        None => format!("Network {}", net.number),
    }
}

fn header(out: &mut String, net: &Network) {
    text(
        out,
        "network-title",
        RAIL_X,
        LINE_H,
        "start",
        &title_line(net),
    );
    for (i, line) in net.comment.iter().enumerate() {
        text(
            out,
            "comment",
            RAIL_X,
            LINE_H * (i as i32 + 2),
            "start",
            line,
        );
    }
}

fn text(out: &mut String, class: &str, x: i32, y: i32, anchor: &str, content: &str) {
    let _ = write!(
        out,
        "<text class=\"{class}\" x=\"{x}\" y=\"{y}\" text-anchor=\"{anchor}\">"
    );
    escape_into(out, content);
    out.push_str("</text>");
}

fn rung(out: &mut String, layout: &NetworkLayout<'_>) {
    let (top, bottom) = layout.rail;
    let _ = write!(
        out,
        "<line class=\"rail\" x1=\"{RAIL_X}\" y1=\"{top}\" x2=\"{RAIL_X}\" y2=\"{bottom}\"/>"
    );
    if let Some((x, y1, y2)) = layout.right_rail {
        let _ = write!(
            out,
            "<line class=\"rail right\" x1=\"{x}\" y1=\"{y1}\" x2=\"{x}\" y2=\"{y2}\"/>"
        );
    }
    out.push('\n');
    for wire in &layout.wires {
        draw_wire(out, wire);
        out.push('\n');
    }
    for element in &layout.elements {
        match element.element {
            ElementRef::Contact(c) => contact(out, c, element),
            ElementRef::Coil(c) => coil(out, c, element),
            ElementRef::Box(b) => boxed(out, b, element),
        }
        out.push('\n');
    }
}

/// The `data-after` value: `rail` or element ids, space-separated.
pub fn after_value(after: &[Power]) -> String {
    let parts: Vec<String> = after
        .iter()
        .map(|p| match p {
            Power::Rail => "rail".to_string(),
            Power::Element(id) => id.to_string(),
        })
        .collect();
    parts.join(" ")
}

fn draw_wire(out: &mut String, w: &Wire) {
    let _ = write!(
        out,
        "<line class=\"wire\" x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" data-after=\"{}\"/>",
        w.x1,
        w.y1,
        w.x2,
        w.y2,
        after_value(&w.after)
    );
}

fn address_attr(op: Option<&Operand>) -> String {
    escape(op.and_then(|o| o.address.as_deref()).unwrap_or(""))
}

/// An operand's texts: the symbol (or the written form) at `top_y`, the address at
/// `bottom_y`, both in a `<g class="operand">` carrying the address.
fn operand(out: &mut String, op: &Operand, x: i32, top_y: i32, bottom_y: i32, anchor: &str) {
    let (top, bottom) = operand_lines(op);
    let _ = write!(
        out,
        "<g class=\"operand\" data-operand=\"{}\">",
        address_attr(Some(op))
    );
    if let Some(t) = top {
        let class = if op.symbol.is_some() {
            "symbol"
        } else {
            "written"
        };
        text(out, class, x, top_y, anchor, t);
    }
    if let Some(b) = bottom {
        text(out, "address", x, bottom_y, anchor, b);
    }
    out.push_str("</g>");
}

fn tooltip(out: &mut String, mnemonic: &str, operands: &[&Operand], line: u32) {
    let written: Vec<&str> = operands.iter().map(|o| o.written.as_str()).collect();
    let _ = write!(
        out,
        "<title>{} {} (line {line})</title>",
        escape(mnemonic),
        escape(&written.join(", "))
    );
}

fn contact(out: &mut String, c: &Contact, p: &PlacedElement<'_>) {
    let _ = write!(
        out,
        "<g class=\"contact\" data-kind=\"{}\" data-operand=\"{}\" data-id=\"{}\" data-line=\"{}\">",
        c.kind.data_kind(),
        address_attr(c.operands.first()),
        c.id,
        c.line
    );
    tooltip(
        out,
        &c.mnemonic,
        &c.operands.iter().collect::<Vec<_>>(),
        c.line,
    );
    let (cx, wy) = (p.x, p.wire_y);
    let half = contact_symbol_w(c) / 2;
    for x in [cx - half, cx + half] {
        let _ = write!(
            out,
            "<line class=\"symbol-line\" x1=\"{x}\" y1=\"{}\" x2=\"{x}\" y2=\"{}\"/>",
            wy - 12,
            wy + 12
        );
    }
    let label = contact_label(c);
    if !label.is_empty() {
        text(out, "inside", cx, wy + 4, "middle", &label);
    }
    match c.operands.as_slice() {
        [] => {}
        [one] => operand(out, one, cx, wy - 16, wy + 24, "middle"),
        [first, second, ..] => {
            operand(out, first, cx, wy - 28, wy - 16, "middle");
            operand(out, second, cx, wy + 24, wy + 36, "middle");
        }
    }
    out.push_str("</g>");
}

fn coil(out: &mut String, c: &Coil, p: &PlacedElement<'_>) {
    let _ = write!(
        out,
        "<g class=\"coil\" data-kind=\"{}\" data-operand=\"{}\" data-id=\"{}\" data-line=\"{}\">",
        c.kind.data_kind(),
        address_attr(Some(&c.operand)),
        c.id,
        c.line
    );
    let mut ops = vec![&c.operand];
    ops.extend(c.count.as_ref());
    tooltip(out, &c.mnemonic, &ops, c.line);
    let (cx, wy) = (p.x, p.wire_y);
    let _ = write!(
        out,
        "<path class=\"symbol-line\" d=\"M{} {} Q{} {} {} {} M{} {} Q{} {} {} {}\"/>",
        cx - 6,
        wy - 11,
        cx - 13,
        wy,
        cx - 6,
        wy + 11,
        cx + 6,
        wy - 11,
        cx + 13,
        wy,
        cx + 6,
        wy + 11
    );
    let inside = match c.kind {
        CoilKind::Out => "",
        CoilKind::Set => "S",
        CoilKind::Reset => "R",
        CoilKind::OutImmediate => "I",
        CoilKind::SetImmediate => "SI",
        CoilKind::ResetImmediate => "RI",
    };
    if !inside.is_empty() {
        text(out, "inside", cx, wy + 4, "middle", inside);
    }
    operand(out, &c.operand, cx, wy - 16, wy + 24, "middle");
    if let Some(count) = &c.count {
        let _ = write!(
            out,
            "<g class=\"count\" data-operand=\"{}\">",
            address_attr(Some(count))
        );
        text(out, "written", cx, wy + 36, "middle", &count.written);
        out.push_str("</g>");
    }
    out.push_str("</g>");
}

fn boxed(out: &mut String, b: &BoxElement, p: &PlacedElement<'_>) {
    let addresses: Vec<&str> = b
        .pins
        .iter()
        .filter_map(|pin| pin.operand.address.as_deref())
        .collect();
    let _ = write!(
        out,
        "<g class=\"box\" data-mnemonic=\"{}\" data-operand=\"{}\" data-id=\"{}\" data-line=\"{}\">",
        escape(&b.mnemonic),
        escape(&addresses.join(" ")),
        b.id,
        b.line
    );
    tooltip(
        out,
        &b.mnemonic,
        &b.pins.iter().map(|pin| &pin.operand).collect::<Vec<_>>(),
        b.line,
    );
    let frame = p.frame.unwrap_or(p.cell);
    let _ = write!(
        out,
        "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"/>",
        frame.x, frame.y, frame.w, frame.h
    );
    text(
        out,
        "title",
        frame.x + frame.w / 2,
        frame.y + 13,
        "middle",
        &b.title,
    );
    let pins = box_pins(b);
    let (left_x, right_x) = (frame.x, frame.x + frame.w);
    for (i, (name, op)) in pins.left.iter().enumerate() {
        let y = p.wire_y + i as i32 * crate::layout::PIN_H;
        text(out, "pin-name", left_x + 4, y + 4, "start", name);
        if let Some(op) = op {
            pin_operand(out, name, op, left_x - 14, left_x, y, "end");
        }
    }
    for (i, (name, op)) in pins.right.iter().enumerate() {
        let y = p.wire_y + i as i32 * crate::layout::PIN_H;
        text(out, "pin-name", right_x - 4, y + 4, "end", name);
        if let Some(op) = op {
            pin_operand(out, name, op, right_x + 14, right_x, y, "start");
        }
    }
    out.push_str("</g>");
}

/// A pin's stub from the box edge and its operand's texts beside it.
fn pin_operand(
    out: &mut String,
    name: &str,
    op: &Operand,
    stub_end: i32,
    edge: i32,
    y: i32,
    anchor: &str,
) {
    let _ = write!(
        out,
        "<line class=\"pin\" x1=\"{stub_end}\" y1=\"{y}\" x2=\"{edge}\" y2=\"{y}\"/>"
    );
    let _ = write!(
        out,
        "<g class=\"pin-operand\" data-pin=\"{}\">",
        escape(name)
    );
    let tx = if anchor == "end" {
        stub_end - 2
    } else {
        stub_end + 2
    };
    operand(out, op, tx, y - 3, y + 11, anchor);
    out.push_str("</g>");
}
