//! Layout of one network (docs/ladder.md, "Drawing"): where every contact, coil, box and
//! wire of a rung goes, in whole pixels, so the SVG (`svg.rs`) and the tests read the
//! same geometry. Pure arithmetic on the model: no text output, no I/O, no hashing (the
//! same model always gives the same layout).
//!
//! Rules: the left rail at `RAIL_X`; series elements left to right, each in its own
//! cell (its lead-in wire, its symbol, its lead-out wire); parallel branches stacked top
//! to bottom, padded with wire to the widest, joined by vertical connectors; the
//! outputs split after the input path and every coil or end box aligned in one column;
//! coils wired to the right rail. A box's extra power inputs (a counter's R) get rows of
//! their own under the rung, from the left rail to their pin. A box's pin operands sit
//! on their pins' lines outside the box, with room between chained boxes; a timer's or
//! counter's number stands above its box; a jump is a coil. Labels follow `Names`, so
//! widths do too. Networks are never wrapped: a wide network is as wide as it needs
//! (the page scrolls).

use crate::model::{
    Block, BoxElement, BoxShape, Branch, BranchEnd, Coil, Contact, Network, Node, Operand, Rung,
};
use crate::svg::Names;

/// Height of one row of elements (texts above and below the wire included).
pub const ROW_H: i32 = 84;
/// The wire's offset from the top of its row.
pub const WIRE_Y: i32 = 40;
/// Narrowest cell of a contact or coil.
pub const CELL_W: i32 = 90;
/// Room for the vertical connectors of a parallel block, each side.
pub const PAR_GAP: i32 = 12;
/// Distance between two pins of a box.
pub const PIN_H: i32 = 28;
/// The left rail's x.
pub const RAIL_X: i32 = 12;
/// Margin right of the right rail and below the rung.
pub const MARGIN: i32 = 12;
/// Height of a text line of the header and of STL text.
pub const LINE_H: i32 = 16;
/// Font size of operand and pin text (monospace), for the width estimate.
const CHAR_W: i32 = 7;
/// Length of a box's pin stub outside the box.
const STUB: i32 = 14;
/// Room between a pin's texts and the edge of the box's cell.
const PIN_GAP: i32 = 12;
/// Horizontal spacing of the vertical wires into a box's extra power inputs.
const POWER_LANE: i32 = 8;

/// An axis-aligned rectangle in pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rect {
    pub x: i32,
    pub y: i32,
    pub w: i32,
    pub h: i32,
}

impl Rect {
    /// Whether the two rectangles share interior area (touching edges do not count).
    pub fn overlaps(&self, other: &Rect) -> bool {
        self.x < other.x + other.w
            && other.x < self.x + self.w
            && self.y < other.y + other.h
            && other.y < self.y + self.h
    }
}

/// What powers a wire segment (`data-after`): the left rail, or the output of an element.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Power {
    Rail,
    Element(u32),
}

/// A horizontal or vertical wire segment, energized when any of `after` passes power.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Wire {
    pub x1: i32,
    pub y1: i32,
    pub x2: i32,
    pub y2: i32,
    pub after: Vec<Power>,
}

/// A drawn element.
#[derive(Debug, Clone, Copy)]
pub enum ElementRef<'a> {
    Contact(&'a Contact),
    Coil(&'a Coil),
    Box(&'a BoxElement),
}

impl ElementRef<'_> {
    pub fn id(&self) -> u32 {
        match self {
            ElementRef::Contact(c) => c.id,
            ElementRef::Coil(c) => c.id,
            ElementRef::Box(b) => b.id,
        }
    }
}

/// An element in its cell. `cell` holds everything the element draws (its texts, its
/// lead wires, a box's pins and operands); cells of one network never overlap.
#[derive(Debug, Clone)]
pub struct PlacedElement<'a> {
    pub element: ElementRef<'a>,
    pub cell: Rect,
    /// The y of the power wire through the element (a box: its EN pin).
    pub wire_y: i32,
    /// Contacts and coils: the symbol's centre. Boxes: the box's left edge.
    pub x: i32,
    /// Boxes: the rectangle of the box itself.
    pub frame: Option<Rect>,
}

/// The layout of one network's rung.
#[derive(Debug, Clone)]
pub struct NetworkLayout<'a> {
    pub width: i32,
    pub height: i32,
    /// Height of the header (number, title, comment lines) above the rung.
    pub header_h: i32,
    /// The header's lines, wrapped at the drawing's width.
    pub header: Header,
    pub elements: Vec<PlacedElement<'a>>,
    pub wires: Vec<Wire>,
    /// The left rail's vertical extent.
    pub rail: (i32, i32),
    /// The right rail (x, top, bottom), when there is a coil.
    pub right_rail: Option<(i32, i32, i32)>,
}

/// Estimated width of `text` in monospace pixels (wide characters count double).
pub fn text_width(text: &str) -> i32 {
    text.chars()
        .map(|c| if is_wide(c) { 2 * CHAR_W } else { CHAR_W })
        .sum()
}

fn is_wide(c: char) -> bool {
    matches!(c as u32,
        0x1100..=0x115F | 0x2E80..=0xA4CF | 0xAC00..=0xD7A3 | 0xF900..=0xFAFF
        | 0xFE30..=0xFE4F | 0xFF00..=0xFF60 | 0xFFE0..=0xFFE6 | 0x20000..=0x3FFFD)
}

/// The narrowest width header texts wrap at: 100 columns of monospace text, so a
/// narrow rung keeps a comment of ordinary length on one line (docs/ladder.md,
/// "Comments").
pub const MIN_TEXT_W: i32 = 100 * CHAR_W;

/// A network's header as drawn: its title line(s) (`Network n: title`) and comment
/// lines, each wrapped at the drawing's width.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Header {
    /// The title, wrapped (at least one line).
    pub title: Vec<String>,
    /// The comment lines, each wrapped.
    pub comment: Vec<String>,
}

impl Header {
    /// The header's height above the rung (or the STL lines).
    pub fn height(&self) -> i32 {
        8 + LINE_H * (self.title.len() + self.comment.len()) as i32
    }

    /// The widest line in pixels (the title counted at its 13 px against 11 px).
    pub fn width(&self) -> i32 {
        let title = self.title.iter().map(|l| title_width(l)).max();
        let comment = self.comment.iter().map(|l| text_width(l)).max();
        title.max(comment).unwrap_or(0)
    }
}

/// The title is 13 px bold against the 11 px the text widths count: 13/11 wider,
/// rounded up.
fn title_width(text: &str) -> i32 {
    (text_width(text) * 13 + 10) / 11
}

/// The header of `net` wrapped at the wider of `body_w` (the rung's or the STL lines'
/// width, rails included) and `MIN_TEXT_W`.
pub fn header_at(net: &Network, body_w: i32) -> Header {
    let wrap_w = (body_w - 2 * RAIL_X).max(MIN_TEXT_W);
    let title = match &net.title {
        Some(title) => format!("Network {}: {}", net.number, title),
        None => format!("Network {}", net.number),
    };
    Header {
        title: wrap(&title, wrap_w * 11 / 13),
        comment: net.comment.iter().flat_map(|l| wrap(l, wrap_w)).collect(),
    }
}

/// Whether some header line of `net` may be wider than `MIN_TEXT_W`, so that its wrap
/// depends on the body's width.
fn header_may_wrap(net: &Network) -> bool {
    let title_w = net
        .title
        .as_deref()
        .map_or(0, |t| title_width(t) + title_width("Network 0000000000: "));
    title_w > MIN_TEXT_W || net.comment.iter().any(|l| text_width(l) > MIN_TEXT_W)
}

/// The header of `net` as drawn: wrapped at the rung's width (laid out once more only
/// when a header line is wider than `MIN_TEXT_W`), or for a network shown as STL at
/// the width of its reason and STL lines.
pub fn network_header(net: &Network) -> Header {
    network_header_with(net, Names::default())
}

/// `network_header` for a rung laid out with `names` (its width follows the labels).
pub fn network_header_with(net: &Network, names: Names) -> Header {
    if !header_may_wrap(net) {
        return header_at(net, 0);
    }
    let body_w = match &net.body {
        crate::model::Body::Rung(rung) => layout_rung(rung, 0, names).width,
        crate::model::Body::Stl { reason } => {
            let reason_w = text_width(&format!("shown as STL: {reason}"));
            let lines_w = net.stl.iter().map(|l| text_width(l) + 8).max();
            reason_w.max(lines_w.unwrap_or(0)) + 2 * RAIL_X
        }
    };
    header_at(net, body_w)
}

/// The header height of a network: its title line(s), then its comment lines, wrapped
/// as `network_header` wraps them.
pub fn header_height(net: &Network) -> i32 {
    network_header(net).height()
}

/// `text` broken into lines no wider than `width` pixels (`text_width`): at blanks,
/// between two wide (CJK) characters or beside one, and inside a word that is wider
/// than the whole width. Blanks inside a line are kept as written, blanks at a break
/// dropped; a text that fits is its one line, unchanged (an empty text too).
pub fn wrap(text: &str, width: i32) -> Vec<String> {
    if text_width(text) <= width {
        return vec![text.to_string()];
    }
    let width = width.max(2 * CHAR_W);
    let mut lines = Vec::new();
    let mut line = String::new();
    let mut line_w = 0;
    for (blanks, piece) in wrap_pieces(text) {
        let gap = if line.is_empty() { "" } else { blanks };
        let (gap_w, piece_w) = (text_width(gap), text_width(piece));
        if line_w + gap_w + piece_w <= width {
            line.push_str(gap);
            line.push_str(piece);
            line_w += gap_w + piece_w;
            continue;
        }
        if !line.is_empty() {
            lines.push(std::mem::take(&mut line));
            line_w = 0;
        }
        // A piece wider than a whole line is broken by characters.
        for c in piece.chars() {
            let w = text_width(c.encode_utf8(&mut [0; 4]));
            if line_w + w > width && !line.is_empty() {
                lines.push(std::mem::take(&mut line));
                line_w = 0;
            }
            line.push(c);
            line_w += w;
        }
    }
    if !line.is_empty() || lines.is_empty() {
        lines.push(line);
    }
    lines
}

/// The unbreakable pieces of `text`, each with the blanks before it: runs of narrow
/// non-blank characters, and every wide character on its own (CJK text breaks between
/// any two characters). Blanks at the end are left out.
fn wrap_pieces(text: &str) -> Vec<(&str, &str)> {
    let mut pieces = Vec::new();
    // The blank run not yet given to a piece, and the word being read with its blanks.
    let mut blanks: Option<(usize, usize)> = None;
    let mut word: Option<(usize, &str)> = None;
    for (i, c) in text.char_indices() {
        let blank = c.is_whitespace();
        let wide = !blank && is_wide(c);
        if blank || wide {
            if let Some((start, before)) = word.take() {
                pieces.push((before, &text[start..i]));
            }
        }
        if blank {
            let from = blanks.map_or(i, |(from, _)| from);
            blanks = Some((from, i + c.len_utf8()));
            continue;
        }
        let before = blanks.take().map_or("", |(from, to)| &text[from..to]);
        if wide {
            pieces.push((before, &text[i..i + c.len_utf8()]));
        } else if word.is_none() {
            word = Some((i, before));
        }
    }
    if let Some((start, before)) = word {
        pieces.push((before, &text[start..]));
    }
    pieces
}

/// The text lines of an operand as drawn: (symbol or written form above, address below).
pub fn operand_lines(op: &crate::model::Operand) -> (Option<&str>, Option<&str>) {
    let top = match (&op.symbol, &op.address) {
        (Some(s), _) => Some(s.as_str()),
        (None, Some(a)) if *a == op.written => None,
        (None, _) => Some(op.written.as_str()),
    };
    (top, op.address.as_deref())
}

fn operand_width(op: &crate::model::Operand) -> i32 {
    let (top, bottom) = operand_lines(op);
    text_width(top.unwrap_or("")).max(text_width(bottom.unwrap_or("")))
}

/// Width of a contact's symbol (between its plates), by what it holds inside.
pub fn contact_symbol_w(c: &Contact, names: Names) -> i32 {
    let inside = contact_label(c, names);
    (text_width(&inside) + 10).max(16)
}

/// The text inside a contact: `/`, `P`, `N`, `NOT`, the relation (`>=I` in LAD names,
/// `>=W` in STL names), `I` when immediate.
pub fn contact_label(c: &Contact, names: Names) -> String {
    use crate::model::ContactKind::*;
    let base = match c.kind {
        NormallyOpen => String::new(),
        NormallyClosed => "/".to_string(),
        PositiveEdge => "P".to_string(),
        NegativeEdge => "N".to_string(),
        Not => "NOT".to_string(),
        Compare => crate::names::compare_label(c.relation.as_deref().unwrap_or("?"), names),
    };
    if c.immediate {
        format!("{base}I")
    } else {
        base
    }
}

fn contact_w(c: &Contact, names: Names) -> i32 {
    let texts = c.operands.iter().map(operand_width).max().unwrap_or(0);
    CELL_W.max(texts + 16).max(contact_symbol_w(c, names) + 40)
}

fn coil_w(c: &Coil) -> i32 {
    let count = c.count.as_ref().map(operand_width).unwrap_or(0);
    CELL_W.max(operand_width(&c.operand) + 16).max(count + 16)
}

/// The pins of a box, as drawn: left (name, operand) and right.
#[derive(Debug)]
pub struct BoxPins<'a> {
    pub left: Vec<(&'a str, Option<&'a Operand>)>,
    pub right: Vec<(&'a str, Option<&'a Operand>)>,
    /// Index in `left` of the first extra power input (they come last).
    pub first_power: usize,
}

/// A box's pins: the enable pin, the input sides of in/out operands (ADD_I's `IN1`),
/// the input operands, then extra power inputs on the left; the power output, then
/// output operands on the right. A jump or a label has none: its operand is drawn
/// above it (`above_operand`).
pub fn box_pins(b: &BoxElement) -> BoxPins<'_> {
    if b.shape != BoxShape::Box {
        return BoxPins {
            left: Vec::new(),
            right: Vec::new(),
            first_power: 0,
        };
    }
    let mut left = vec![(b.enable.as_str(), None)];
    left.extend(
        b.pins
            .iter()
            .filter_map(|p| Some((p.input.as_deref()?, Some(&p.operand)))),
    );
    left.extend(
        b.pins
            .iter()
            .filter(|p| !p.output)
            .map(|p| (p.name.as_str(), Some(&p.operand))),
    );
    let first_power = left.len();
    left.extend(b.power_inputs.iter().map(|(name, _)| (name.as_str(), None)));
    let mut right = Vec::new();
    if let Some(out) = &b.output {
        right.push((out.as_str(), None));
    }
    right.extend(
        b.pins
            .iter()
            .filter(|p| p.output)
            .map(|p| (p.name.as_str(), Some(&p.operand))),
    );
    BoxPins {
        left,
        right,
        first_power,
    }
}

/// The label inside a box: a timer's or counter's kind (`TON`, `CTUD`), a CALL's
/// subroutine, else the instruction's LAD name (`ADD_I`) or STL mnemonic (`+I`).
pub fn box_label(b: &BoxElement, names: Names) -> &str {
    if b.counted.is_none() && b.title != b.mnemonic {
        return &b.title;
    }
    crate::names::box_label(&b.mnemonic, names)
}

/// The operand drawn above a box, with its pin's name: a timer's or counter's number
/// (no pin), a jump's or label's label number (`N`).
pub fn above_operand(b: &BoxElement) -> Option<(Option<&str>, &Operand)> {
    if let Some(c) = &b.counted {
        return Some((None, &**c));
    }
    match b.shape {
        BoxShape::Box => None,
        BoxShape::Jump | BoxShape::Label => {
            b.pins.first().map(|p| (Some(p.name.as_str()), &p.operand))
        }
    }
}

/// A timer preset's duration as drawn under it (`= 10.0 s`): a constant preset (`PT`)
/// of a timer whose resolution is known.
pub fn preset_duration(b: &BoxElement, pin: &str, op: &Operand) -> Option<String> {
    let resolution = b.resolution_ms?;
    if pin != "PT" || op.address.is_some() {
        return None;
    }
    let preset: i64 = op.written.parse().ok()?;
    Some(format!(
        "= {}",
        gutta_catalog::timer_duration(resolution, preset)?
    ))
}

/// A timer's resolution as drawn in its box (`100 ms`).
pub fn resolution_text(b: &BoxElement) -> Option<String> {
    // One unit of the timer, in the wording of every duration (`100 ms`, `1 s`).
    b.resolution_ms
        .and_then(|ms| gutta_catalog::timer_duration(ms, 1))
}

/// Offset of a box's top above its wire: room for its label above the first row, or
/// none for a box whose label shares the first row (a timer or counter: its number is
/// above the box) and for a label box.
pub fn box_top(b: &BoxElement) -> i32 {
    if b.counted.is_some() || b.shape != BoxShape::Box {
        12
    } else {
        26
    }
}

/// The lines of a pin's texts beside the box: (top line, bottom line). Two lines sit
/// just above and just under the pin's line, one line on it.
pub fn pin_text_ys(y: i32, two_lines: bool) -> (i32, i32) {
    if two_lines {
        (y - 3, y + 11)
    } else {
        (y + 4, y + 4)
    }
}

/// Width of a pin's texts beside the box (its operand, a preset's duration).
fn pin_text_w(b: &BoxElement, name: &str, op: Option<&Operand>) -> i32 {
    op.map(|op| {
        let duration = preset_duration(b, name, op).map_or(0, |d| text_width(&d));
        operand_width(op).max(duration)
    })
    .unwrap_or(0)
}

struct BoxGeometry {
    left_area: i32,
    box_w: i32,
    right_area: i32,
    rows: i32,
}

fn box_geometry(b: &BoxElement, names: Names) -> BoxGeometry {
    let label = text_width(box_label(b, names));
    let above = above_operand(b).map_or(0, |(_, op)| operand_width(op));
    match b.shape {
        BoxShape::Jump => {
            let w = CELL_W.max(above + 16).max(label + 40);
            return BoxGeometry {
                left_area: 0,
                box_w: w,
                right_area: 0,
                rows: 1,
            };
        }
        BoxShape::Label => {
            let box_w = (label + 16).max(above + 8).max(40);
            return BoxGeometry {
                left_area: 20,
                box_w,
                right_area: 20,
                rows: 1,
            };
        }
        BoxShape::Box => {}
    }
    let pins = box_pins(b);
    let side = |list: &[(&str, Option<&Operand>)]| {
        list.iter()
            .map(|(name, op)| pin_text_w(b, name, *op))
            .max()
            .unwrap_or(0)
    };
    let names_w = |list: &[(&str, Option<&Operand>)]| {
        list.iter().map(|(n, _)| text_width(n)).max().unwrap_or(0)
    };
    // Room for a row's pin names around a text centred in the box (8 px each side).
    let row_w = |i: usize| {
        let l = pins.left.get(i).map_or(0, |(n, _)| text_width(n));
        let r = pins.right.get(i).map_or(0, |(n, _)| text_width(n));
        2 * l.max(r)
    };
    // The extra power inputs' lanes, and room for their paths: a path drawn from the
    // left rail then ends left of its lane wherever the box stands.
    let lanes = POWER_LANE * (b.power_inputs.len() as i32 + 1);
    let paths = b
        .power_inputs
        .iter()
        .map(|(_, node)| node_size(node, names).0 + lanes)
        .max()
        .unwrap_or(0);
    // A pin's texts keep `PIN_GAP` from the cell's edge: a box after a box leaves wire
    // for both boxes' texts, never one against the other.
    let left_area = (side(&pins.left) + STUB + PIN_GAP)
        .max(lanes)
        .max(paths)
        .max(20);
    let right_area = (side(&pins.right) + STUB + PIN_GAP).max(20);
    let mut box_w = (names_w(&pins.left) + names_w(&pins.right) + 24).max(70);
    if b.counted.is_some() {
        // The kind shares the first row with its pins; the number is centred above.
        box_w = box_w.max(row_w(0) + label + 24).max(above + 8);
        if let Some(res) = resolution_text(b) {
            let pt = pins.left.get(1).map_or(0, |(n, _)| text_width(n));
            box_w = box_w.max(pt + text_width(&res) + 24);
        }
    } else {
        box_w = box_w.max(label + 16);
    }
    BoxGeometry {
        left_area,
        box_w,
        right_area,
        rows: pins.left.len().max(pins.right.len()).max(1) as i32,
    }
}

fn box_size(b: &BoxElement, names: Names) -> (i32, i32) {
    let g = box_geometry(b, names);
    let h = ROW_H.max(WIRE_Y + (g.rows - 1) * PIN_H + 28);
    (g.left_area + g.box_w + g.right_area, h)
}

/// Width and height of a piece of power path.
fn node_size(node: &Node, names: Names) -> (i32, i32) {
    match node {
        Node::Contact(c) => (contact_w(c, names), ROW_H),
        Node::Box(b) => box_size(b, names),
        Node::Series(items) => items
            .iter()
            .map(|n| node_size(n, names))
            .fold((0, 0), |(w, h), (iw, ih)| (w + iw, h.max(ih))),
        Node::Parallel(items) => {
            let (w, h) = items
                .iter()
                .map(|n| node_size(n, names))
                .fold((0, 0), |(w, h), (iw, ih)| (w.max(iw), h + ih));
            (w + 2 * PAR_GAP, h)
        }
    }
}

/// Width from a branch's start to the column of its end element.
fn branch_reach(b: &Branch, names: Names) -> i32 {
    let path: i32 = b.path.iter().map(|n| node_size(n, names).0).sum();
    match &b.end {
        BranchEnd::Split(subs) => {
            path + PAR_GAP
                + subs
                    .iter()
                    .map(|s| branch_reach(s, names))
                    .max()
                    .unwrap_or(0)
        }
        _ => path,
    }
}

/// Width of the widest end element of a branch.
fn end_width(b: &Branch, names: Names) -> i32 {
    match &b.end {
        BranchEnd::Coil(c) => coil_w(c),
        BranchEnd::Box(bx) => box_size(bx, names).0,
        BranchEnd::Split(subs) => subs.iter().map(|s| end_width(s, names)).max().unwrap_or(0),
    }
}

fn branch_height(b: &Branch, names: Names) -> i32 {
    let path = b
        .path
        .iter()
        .map(|n| node_size(n, names).1)
        .max()
        .unwrap_or(0);
    let end = match &b.end {
        BranchEnd::Coil(_) => ROW_H,
        BranchEnd::Box(bx) => box_size(bx, names).1,
        BranchEnd::Split(subs) => subs.iter().map(|s| branch_height(s, names)).sum(),
    };
    path.max(end)
}

struct Placer<'a> {
    elements: Vec<PlacedElement<'a>>,
    wires: Vec<Wire>,
    /// Boxes with extra power inputs, with their frame and wire y, for the rows under
    /// the rung.
    powered_boxes: Vec<(&'a BoxElement, Rect, i32)>,
    coil_x: i32,
    end_w: i32,
    /// The wire y of every coil, for the right rail.
    coils: Vec<i32>,
    names: Names,
}

impl<'a> Placer<'a> {
    fn wire(&mut self, x1: i32, y1: i32, x2: i32, y2: i32, after: &[Power]) {
        if (x1, y1) != (x2, y2) {
            self.wires.push(Wire {
                x1,
                y1,
                x2,
                y2,
                after: after.to_vec(),
            });
        }
    }

    /// Place `node` with its row top at `y`, from `x`; returns what powers its exit.
    fn node(&mut self, node: &'a Node, x: i32, y: i32, input: &[Power]) -> Vec<Power> {
        match node {
            Node::Contact(c) => {
                let w = contact_w(c, self.names);
                let wy = y + WIRE_Y;
                let cx = x + w / 2;
                let half = contact_symbol_w(c, self.names) / 2;
                self.wire(x, wy, cx - half, wy, input);
                self.wire(cx + half, wy, x + w, wy, &[Power::Element(c.id)]);
                self.elements.push(PlacedElement {
                    element: ElementRef::Contact(c),
                    cell: Rect { x, y, w, h: ROW_H },
                    wire_y: wy,
                    x: cx,
                    frame: None,
                });
                vec![Power::Element(c.id)]
            }
            Node::Box(b) => {
                self.boxed(b, x, y, input, true);
                vec![Power::Element(b.id)]
            }
            Node::Series(items) => {
                let mut cur = input.to_vec();
                let mut cx = x;
                for item in items {
                    cur = self.node(item, cx, y, &cur);
                    cx += node_size(item, self.names).0;
                }
                cur
            }
            Node::Parallel(items) => {
                let (w, _) = node_size(node, self.names);
                let right = x + w;
                let mut cy = y;
                let mut first_last = (y + WIRE_Y, y + WIRE_Y);
                let mut all = Vec::new();
                for (i, item) in items.iter().enumerate() {
                    let (iw, ih) = node_size(item, self.names);
                    let wy = cy + WIRE_Y;
                    if i == 0 {
                        first_last.0 = wy;
                    }
                    first_last.1 = wy;
                    self.wire(x, wy, x + PAR_GAP, wy, input);
                    let out = self.node(item, x + PAR_GAP, cy, input);
                    self.wire(x + PAR_GAP + iw, wy, right, wy, &out);
                    all.extend(out);
                    cy += ih;
                }
                all.sort();
                all.dedup();
                self.wire(x, first_last.0, x, first_last.1, input);
                self.wire(right, first_last.0, right, first_last.1, &all);
                all
            }
        }
    }

    /// Place a box in its cell; `lead_out` draws the wire from ENO to the cell's end.
    fn boxed(&mut self, b: &'a BoxElement, x: i32, y: i32, input: &[Power], lead_out: bool) {
        let g = box_geometry(b, self.names);
        let (w, h) = box_size(b, self.names);
        let wy = y + WIRE_Y;
        let bx = x + g.left_area;
        let top = box_top(b);
        let frame = if b.shape == BoxShape::Jump {
            // A coil holding its label: the frame is the coil's symbol.
            let half = text_width(box_label(b, self.names)) / 2 + 10;
            Rect {
                x: x + w / 2 - half,
                y: wy - 12,
                w: 2 * half,
                h: 24,
            }
        } else {
            Rect {
                x: bx,
                y: wy - top,
                w: g.box_w,
                h: top + (g.rows - 1) * PIN_H + 12,
            }
        };
        if !input.is_empty() {
            self.wire(x, wy, frame.x, wy, input);
        }
        if b.output.is_some() && lead_out {
            self.wire(bx + g.box_w, wy, x + w, wy, &[Power::Element(b.id)]);
        }
        if !b.power_inputs.is_empty() {
            self.powered_boxes.push((b, frame, wy));
        }
        self.elements.push(PlacedElement {
            element: ElementRef::Box(b),
            cell: Rect { x, y, w, h },
            wire_y: wy,
            x: bx,
            frame: Some(frame),
        });
    }

    fn branch(&mut self, b: &'a Branch, x: i32, y: i32, input: &[Power]) {
        let mut cur = input.to_vec();
        let mut cx = x;
        for item in &b.path {
            cur = self.node(item, cx, y, &cur);
            cx += node_size(item, self.names).0;
        }
        self.end(&b.end, cx, y, &cur);
    }

    fn end(&mut self, end: &'a BranchEnd, x: i32, y: i32, input: &[Power]) {
        let wy = y + WIRE_Y;
        match end {
            BranchEnd::Coil(c) => {
                let w = coil_w(c);
                let cx = self.coil_x + w / 2;
                self.wire(x, wy, cx - 10, wy, input);
                self.wire(
                    cx + 10,
                    wy,
                    self.coil_x + self.end_w,
                    wy,
                    &[Power::Element(c.id)],
                );
                self.coils.push(wy);
                self.elements.push(PlacedElement {
                    element: ElementRef::Coil(c),
                    cell: Rect {
                        x: self.coil_x,
                        y,
                        w,
                        h: ROW_H,
                    },
                    wire_y: wy,
                    x: cx,
                    frame: None,
                });
            }
            BranchEnd::Box(bx) => {
                if !input.is_empty() {
                    self.wire(x, wy, self.coil_x, wy, input);
                }
                self.boxed(bx, self.coil_x, y, input, false);
            }
            BranchEnd::Split(subs) => self.split(subs, x, y, input),
        }
    }

    fn split(&mut self, subs: &'a [Branch], x: i32, y: i32, input: &[Power]) {
        let mut cy = y;
        let mut last = y + WIRE_Y;
        for sub in subs {
            last = cy + WIRE_Y;
            if !input.is_empty() {
                self.wire(x, last, x + PAR_GAP, last, input);
            }
            self.branch(sub, x + PAR_GAP, cy, input);
            cy += branch_height(sub, self.names);
        }
        if !input.is_empty() {
            self.wire(x, y + WIRE_Y, x, last, input);
        }
    }
}

/// Lay out a rung with its header above, with the default names.
pub fn layout_network<'a>(net: &'a Network) -> Option<NetworkLayout<'a>> {
    layout_network_with(net, Names::default())
}

/// Lay out a rung with its header above, its boxes and compares labelled with `names`
/// (their widths follow the labels); `network_svg_with` draws it.
pub fn layout_network_with<'a>(net: &'a Network, names: Names) -> Option<NetworkLayout<'a>> {
    match &net.body {
        crate::model::Body::Rung(rung) => {
            let header = network_header_with(net, names);
            let mut layout = layout_rung(rung, header.height(), names);
            layout.header = header;
            Some(layout)
        }
        crate::model::Body::Stl { .. } => None,
    }
}

/// Whether a rung without a power path is a sequence control relay of a Micro/WIN
/// export (`LSCR`, `SCRE`), drawn wired to the left rail.
fn on_rail_wired(rung: &Rung) -> bool {
    rung.outputs.iter().all(|b| {
        b.path.is_empty()
            && matches!(&b.end, crate::model::BranchEnd::Box(x) if crate::model::is_scr(&x.mnemonic))
    })
}

fn layout_rung(rung: &Rung, top: i32, names: Names) -> NetworkLayout<'_> {
    let (in_w, in_h) = rung
        .input
        .as_ref()
        .map(|n| node_size(n, names))
        .unwrap_or((0, 0));
    let start = RAIL_X;
    let reach = rung
        .outputs
        .iter()
        .map(|b| branch_reach(b, names))
        .max()
        .unwrap_or(0);
    let coil_x = start + in_w + PAR_GAP + reach;
    let end_w = rung
        .outputs
        .iter()
        .map(|b| end_width(b, names))
        .max()
        .unwrap_or(0);
    let mut placer = Placer {
        elements: Vec::new(),
        wires: Vec::new(),
        powered_boxes: Vec::new(),
        coil_x,
        end_w,
        coils: Vec::new(),
        names,
    };
    let input = match &rung.input {
        Some(node) => placer.node(node, start, top, &[Power::Rail]),
        // Micro/WIN's SCR box and SCRE coil stand on the rail, wired to it; a label,
        // `NEXT`, `RET` stand free of it.
        None if on_rail_wired(rung) => vec![Power::Rail],
        None => Vec::new(),
    };
    let out_h: i32 = rung.outputs.iter().map(|b| branch_height(b, names)).sum();
    placer.split(&rung.outputs, start + in_w, top, &input);
    let mut bottom = top + in_h.max(out_h);

    // Extra power inputs: one row each under everything, from the left rail to the pin.
    let powered = std::mem::take(&mut placer.powered_boxes);
    for (b, frame, box_wy) in powered {
        let pins = box_pins(b);
        let n = b.power_inputs.len() as i32;
        for (i, (_, node)) in b.power_inputs.iter().enumerate() {
            let (w, h) = node_size(node, names);
            let wy = bottom + WIRE_Y;
            let out = placer.node(node, start, bottom, &[Power::Rail]);
            let lane_x = frame.x - POWER_LANE * (n - i as i32);
            let pin_y = box_wy + (pins.first_power as i32 + i as i32) * PIN_H;
            placer.wire(start + w, wy, lane_x, wy, &out);
            placer.wire(lane_x, wy, lane_x, pin_y, &out);
            placer.wire(lane_x, pin_y, frame.x, pin_y, &out);
            bottom += h;
        }
    }

    let content_right = placer
        .elements
        .iter()
        .map(|e| e.cell.x + e.cell.w)
        .chain(placer.wires.iter().map(|w| w.x1.max(w.x2)))
        .max()
        .unwrap_or(start);
    let right_rail = if placer.coils.is_empty() {
        None
    } else {
        let ys = &placer.coils;
        let top_y = top.min(*ys.iter().min().unwrap_or(&top) - WIRE_Y);
        let bottom_y = ys
            .iter()
            .max()
            .map(|y| y + ROW_H - WIRE_Y)
            .unwrap_or(bottom);
        Some((coil_x + end_w, top_y, bottom_y))
    };
    NetworkLayout {
        width: content_right + MARGIN,
        height: bottom + MARGIN,
        header_h: top,
        header: Header::default(),
        elements: placer.elements,
        wires: placer.wires,
        rail: (top, bottom),
        right_rail,
    }
}

/// A block's heading as drawn above its networks.
pub fn block_heading(block: &Block) -> String {
    match &block.title {
        Some(title) => format!("{} ({}): {}", block.name, block.numbered, title),
        None => format!("{} ({})", block.name, block.numbered),
    }
}
