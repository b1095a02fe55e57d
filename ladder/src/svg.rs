//! SVG of networks and whole ladders (docs/ladder.md, "Drawing"): draws the geometry of
//! `layout.rs` with the class and `data-*` names issue 15 fixed, so tools and the live
//! view find every element. Text only: no I/O, all text XML-escaped, integers only (the
//! same model always gives the same bytes).

use std::fmt::Write;

use crate::layout::{
    above_operand, block_heading, box_label, box_pins, box_top, contact_label, contact_symbol_w,
    header_height, layout_network_with, network_header_with, operand_lines, pin_text_ys,
    preset_duration, resolution_text, text_width, ElementRef, Header, NetworkLayout, PlacedElement,
    Power, Wire, LINE_H, MARGIN, PIN_H, RAIL_X,
};
use crate::model::{
    Block, Body, BoxElement, BoxShape, Coil, CoilKind, Contact, Ladder, Network, Operand,
};

/// Height of a block's heading in a standalone SVG.
const BLOCK_HEADING_H: i32 = 30;
/// Space between two networks in a standalone SVG.
const NETWORK_GAP: i32 = 8;

/// The drawing's fonts as a literal, for `concat!` (`FONT_STACK`).
macro_rules! font_stack {
    () => {
        "\"DejaVu Sans Mono\",\"Liberation Mono\",Consolas,Menlo,\"Noto Sans Mono CJK SC\",\
         \"Sarasa Mono SC\",\"WenQuanYi Zen Hei Mono\",\"Microsoft YaHei\",\"Noto Sans CJK SC\",\
         \"WenQuanYi Zen Hei\",monospace"
    };
}

/// The drawing's fonts: Latin monospace fonts first (the layout's widths assume
/// monospace metrics), then fonts that show CJK text where the system has them, which
/// the browser takes per character for what the first ones lack, and `monospace` last
/// (docs/ladder.md, "Fonts").
pub const FONT_STACK: &str = font_stack!();

/// The styles of the drawing, shared by the standalone SVG and the HTML page.
pub const STYLE: &str = concat!(
    "text{font-family:",
    font_stack!(),
    ";font-size:11px;fill:#222}\
.network-title{font-size:13px;font-weight:bold}\
.comment{fill:#555;font-style:italic}\
.block-title{font-size:16px;font-weight:bold}\
.reason{fill:#a33}\
.stl{font-size:12px}\
.wire,.rail,.pin-line,.symbol-line{stroke:#222;stroke-width:1.5;fill:none}\
.rail{stroke-width:3}\
.box rect{fill:#fff;stroke:#222;stroke-width:1.5}\
.box .title{font-weight:bold}\
.inside{font-size:10px}\
.resolution,.duration{fill:#555}\
.symbol-info .si-head{font-weight:bold;fill:#444}\
.symbol-info .si-comment{fill:#555;font-style:italic}\
.symbol-info-rule{stroke:#bbb;stroke-width:1}\
"
);

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
    options: &DrawOptions,
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
    let layout = layout_network_with(net, options.names);
    let stl_header;
    let head = match &layout {
        Some(layout) => &layout.header,
        None => {
            stl_header = network_header_with(net, options.names);
            &stl_header
        }
    };
    header(out, head);
    // The header is wrapped at the drawing's width; its widest line still counts, so no
    // header text is ever clipped by the network's width.
    let title_w = head.width() + 2 * RAIL_X;
    let size = match (&net.body, layout) {
        (_, Some(layout)) => {
            rung(out, &layout, options);
            let (mut width, mut height) = (layout.width.max(title_w), layout.height);
            if options.symbol_info {
                let rows = crate::symbol_info::rows(net);
                let (w, h) = crate::symbol_info::draw(out, &rows, height, width);
                width = width.max(w);
                height += h;
            }
            (width, height)
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

/// The network's title and comment lines, as `layout::network_header` wrapped them.
fn header(out: &mut String, head: &Header) {
    let mut y = 0;
    for line in &head.title {
        y += LINE_H;
        text(out, "network-title", RAIL_X, y, "start", line);
    }
    for line in &head.comment {
        y += LINE_H;
        text(out, "comment", RAIL_X, y, "start", line);
    }
}

pub(crate) fn text(out: &mut String, class: &str, x: i32, y: i32, anchor: &str, content: &str) {
    let _ = write!(
        out,
        "<text class=\"{class}\" x=\"{x}\" y=\"{y}\" text-anchor=\"{anchor}\">"
    );
    escape_into(out, content);
    out.push_str("</text>");
}

fn rung(out: &mut String, layout: &NetworkLayout<'_>, options: &DrawOptions) {
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
            ElementRef::Contact(c) => contact(out, c, element, options.names),
            ElementRef::Coil(c) => coil(out, c, element),
            ElementRef::Box(b) => boxed(out, b, element, options.names),
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
    operand_class(out, "operand", op, x, top_y, bottom_y, anchor);
}

/// [`operand`] in a group of `class` (`operand counted` above a timer's box).
fn operand_class(
    out: &mut String,
    class: &str,
    op: &Operand,
    x: i32,
    top_y: i32,
    bottom_y: i32,
    anchor: &str,
) {
    let (top, bottom) = operand_lines(op);
    let _ = write!(
        out,
        "<g class=\"{class}\" data-operand=\"{}\">",
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

/// An element's `<title>`: the mnemonic, its operands as written and the source line,
/// then one line per symbol it uses (once each): `Start (I0.0): start button`.
fn tooltip(out: &mut String, mnemonic: &str, operands: &[&Operand], line: u32) {
    let written: Vec<&str> = operands.iter().map(|o| o.written.as_str()).collect();
    let _ = write!(
        out,
        "<title>{} {} (line {line})",
        escape(mnemonic),
        escape(&written.join(", "))
    );
    let mut seen: Vec<&str> = Vec::new();
    for op in operands {
        let Some(symbol) = op.symbol.as_deref() else {
            continue;
        };
        if seen.iter().any(|s| s.eq_ignore_ascii_case(symbol)) {
            continue;
        }
        seen.push(symbol);
        out.push('\n');
        out.push_str(&escape(&symbol_line(op, symbol)));
    }
    out.push_str("</title>");
}

/// `Start (I0.0): start button`, `Start (I0.0)` without a comment, `Start` without an
/// address.
fn symbol_line(op: &Operand, symbol: &str) -> String {
    let mut line = symbol.to_string();
    if let Some(address) = &op.address {
        let _ = write!(line, " ({address})");
    }
    if let Some(comment) = &op.comment {
        let _ = write!(line, ": {comment}");
    }
    line
}

fn contact(out: &mut String, c: &Contact, p: &PlacedElement<'_>, names: Names) {
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
    let half = contact_symbol_w(c, names) / 2;
    for x in [cx - half, cx + half] {
        let _ = write!(
            out,
            "<line class=\"symbol-line\" x1=\"{x}\" y1=\"{}\" x2=\"{x}\" y2=\"{}\"/>",
            wy - 12,
            wy + 12
        );
    }
    let label = contact_label(c, names);
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

fn boxed(out: &mut String, b: &BoxElement, p: &PlacedElement<'_>, names: Names) {
    let addresses: Vec<&str> = b
        .pins
        .iter()
        .filter_map(|pin| pin.operand.address.as_deref())
        .collect();
    let _ = write!(
        out,
        "<g class=\"box{}\" data-mnemonic=\"{}\" data-operand=\"{}\" data-id=\"{}\" data-line=\"{}\"",
        match b.shape {
            BoxShape::Box => "",
            BoxShape::Jump => " jump",
            BoxShape::Label => " label",
        },
        escape(&b.mnemonic),
        escape(&addresses.join(" ")),
        b.id,
        b.line
    );
    if let Some(counted) = &b.counted {
        let _ = write!(out, " data-counted=\"{}\"", address_attr(Some(&**counted)));
    }
    out.push('>');
    let mut operands: Vec<&Operand> = b.counted.iter().map(|c| &**c).collect();
    operands.extend(b.pins.iter().map(|pin| &pin.operand));
    tooltip(out, &b.mnemonic, &operands, b.line);
    let frame = p.frame.unwrap_or(p.cell);
    let label = box_label(b, names);
    let centre = frame.x + frame.w / 2;
    let wy = p.wire_y;
    if b.shape == BoxShape::Jump {
        // A coil with the label inside, as Micro/WIN draws JMP.
        let (l, r) = (frame.x, frame.x + frame.w);
        let _ = write!(
            out,
            "<path class=\"symbol-line\" d=\"M{} {} Q{} {} {} {} M{} {} Q{} {} {} {}\"/>",
            l + 7,
            wy - 11,
            l,
            wy,
            l + 7,
            wy + 11,
            r - 7,
            wy - 11,
            r,
            wy,
            r - 7,
            wy + 11
        );
        text(out, "title", centre, wy + 4, "middle", label);
    } else {
        let _ = write!(
            out,
            "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"/>",
            frame.x, frame.y, frame.w, frame.h
        );
        // A timer's or counter's kind and a label's LBL share the first row.
        let title_y = if box_top(b) == 26 {
            frame.y + 13
        } else {
            wy + 4
        };
        text(out, "title", centre, title_y, "middle", label);
    }
    match above_operand(b) {
        Some((None, counted)) => {
            operand_class(
                out,
                "operand counted",
                counted,
                centre,
                wy - 28,
                wy - 16,
                "middle",
            );
        }
        Some((Some(pin), op)) => {
            let _ = write!(
                out,
                "<g class=\"pin\" data-pin=\"{}\" data-operand=\"{}\">",
                escape(pin),
                address_attr(Some(op))
            );
            operand(out, op, centre, wy - 28, wy - 16, "middle");
            out.push_str("</g>");
        }
        None => {}
    }
    let pins = box_pins(b);
    let (left_x, right_x) = (frame.x, frame.x + frame.w);
    for (i, (name, op)) in pins.left.iter().enumerate() {
        let y = wy + i as i32 * PIN_H;
        pin(
            out,
            b,
            name,
            *op,
            (left_x, left_x + 4, left_x - 14),
            y,
            "start",
            "end",
        );
        if i == 1 {
            if let Some(res) = resolution_text(b) {
                text(out, "resolution", right_x - 4, y + 4, "end", &res);
            }
        }
    }
    for (i, (name, op)) in pins.right.iter().enumerate() {
        let y = wy + i as i32 * PIN_H;
        pin(
            out,
            b,
            name,
            *op,
            (right_x, right_x - 4, right_x + 14),
            y,
            "end",
            "start",
        );
    }
    out.push_str("</g>");
}

/// One pin of a box: a `<g class="pin" data-pin data-operand>` with its name inside the
/// box and, for an operand, the stub from the box edge (`xs`: edge, name x, stub end)
/// and the operand's texts beside it on the pin's line (a preset's duration under it).
#[allow(clippy::too_many_arguments)]
fn pin(
    out: &mut String,
    b: &BoxElement,
    name: &str,
    op: Option<&Operand>,
    xs: (i32, i32, i32),
    y: i32,
    name_anchor: &str,
    anchor: &str,
) {
    let (edge, name_x, stub_end) = xs;
    let _ = write!(
        out,
        "<g class=\"pin\" data-pin=\"{}\" data-operand=\"{}\">",
        escape(name),
        address_attr(op)
    );
    text(out, "pin-name", name_x, y + 4, name_anchor, name);
    if let Some(op) = op {
        let _ = write!(
            out,
            "<line class=\"pin-line\" x1=\"{stub_end}\" y1=\"{y}\" x2=\"{edge}\" y2=\"{y}\"/>"
        );
        let tx = if anchor == "end" {
            stub_end - 2
        } else {
            stub_end + 2
        };
        let duration = preset_duration(b, name, op);
        let (top, bottom) = operand_lines(op);
        let (top_y, bottom_y) =
            pin_text_ys(y, duration.is_some() || (top.is_some() && bottom.is_some()));
        operand(out, op, tx, top_y, bottom_y, anchor);
        if let Some(d) = duration {
            text(out, "duration", tx, bottom_y, anchor, &d);
        }
    }
    out.push_str("</g>");
}
