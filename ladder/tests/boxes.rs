//! Boxes as Micro/WIN draws them (docs/ladder.md, "Elements", "Names"), on
//! tests/data/ladder/every_box.lad (every timer and counter kind, every math family,
//! moves, FOR/NEXT, JMP/LBL, compares): insta snapshots of one network per point, in
//! LAD and STL names; the DOM the live view relies on (`g.pin[data-pin]`,
//! `data-counted`, `g.operand.counted`); and the property that on this program and on
//! every example no two texts of a rung overlap (by the layout's text widths) and every
//! pin's texts stay within its pin's row.

mod common;

use gutta_ladder::layout::{text_width, Rect, PIN_H};
use gutta_ladder::model::{Block, Ladder, Network};
use gutta_ladder::svg::{network_svg_with, DrawOptions, Names};

use common::{checked_file, files, root};

fn every_box() -> Ladder {
    let ladder = gutta_ladder::build(&checked_file(
        &root().join("tests/data/ladder/every_box.lad"),
    ));
    for net in &ladder.blocks[0].networks {
        assert!(
            matches!(net.body, gutta_ladder::model::Body::Rung(_)),
            "network {} of every_box.lad is drawn",
            net.number
        );
    }
    ladder
}

fn network(ladder: &Ladder, number: u32) -> (&Block, &Network) {
    let block = &ladder.blocks[0];
    let net = block
        .networks
        .iter()
        .find(|n| n.number == number)
        .expect("network");
    (block, net)
}

fn svg(ladder: &Ladder, number: u32, names: Names) -> String {
    let (block, net) = network(ladder, number);
    let options = DrawOptions {
        names,
        ..DrawOptions::default()
    };
    network_svg_with(block, net, &options)
}

// ---- a small SVG reader: elements with their attributes, text and parent chain ------

type El = common::xml::Element;

fn parse(svg: &str) -> Vec<El> {
    common::xml::parse(&format!("<svg>{svg}</svg>")).0
}

/// A text's box by the layout's width estimate (11 px monospace; 8 px above the
/// baseline, 3 px under it).
fn text_box(t: &El) -> Rect {
    let w = text_width(&t.text);
    let (x, y) = (t.num("x"), t.num("y"));
    let left = match t.attr("text-anchor") {
        Some("middle") => x - w / 2,
        Some("end") => x - w,
        _ => x,
    };
    Rect {
        x: left,
        y: y - 8,
        w,
        h: 11,
    }
}

/// Texts of a rung (not the network's title and comment lines), with their boxes.
fn rung_texts(els: &[El]) -> Vec<(usize, Rect)> {
    els.iter()
        .enumerate()
        .filter(|(_, e)| e.name == "text")
        .filter(|(_, e)| !e.has_class("network-title") && !e.has_class("comment"))
        .map(|(i, e)| (i, text_box(e)))
        .collect()
}

/// Every overlap of two texts, and every pin text outside its pin's row, in `svg`.
fn layout_faults(svg: &str) -> Vec<String> {
    let els = parse(svg);
    let texts = rung_texts(&els);
    let mut faults = Vec::new();
    for (a, (i, ra)) in texts.iter().enumerate() {
        for (j, rb) in &texts[a + 1..] {
            if ra.overlaps(rb) {
                faults.push(format!(
                    "`{}` {ra:?} overlaps `{}` {rb:?}",
                    els[*i].text, els[*j].text
                ));
            }
        }
    }
    for (p, pin) in els.iter().enumerate() {
        if !pin.has_class("pin") || pin.name != "g" {
            continue;
        }
        let Some(line) = els
            .iter()
            .find(|e| e.has_class("pin-line") && e.parents.last() == Some(&p))
        else {
            continue;
        };
        let y = line.num("y1");
        for (i, r) in &texts {
            if els[*i].parents.contains(&p) && (r.y < y - PIN_H / 2 || r.y + r.h > y + PIN_H / 2) {
                faults.push(format!(
                    "pin {}: `{}` {r:?} outside its row at y {y}",
                    pin.attr("data-pin").unwrap_or("?"),
                    els[*i].text
                ));
            }
        }
    }
    faults
}

// ---- snapshots of each point -------------------------------------------------------------

#[test]
fn snapshots_of_every_kind_of_box() {
    let ladder = every_box();
    let cases = [
        ("timer_with_symbol", 1, Names::Lad),
        ("timer_10ms", 2, Names::Lad),
        ("counter_up", 4, Names::Lad),
        ("counter_up_down", 6, Names::Lad),
        ("integer_math_chain", 7, Names::Lad),
        ("integer_math_chain_stl", 7, Names::Stl),
        ("increments", 11, Names::Lad),
        ("moves", 12, Names::Lad),
        ("block_move", 13, Names::Lad),
        ("compares", 14, Names::Lad),
        ("compares_stl", 14, Names::Stl),
        ("for_loop", 15, Names::Lad),
        ("jump", 18, Names::Lad),
        ("label", 20, Names::Lad),
    ];
    for (name, number, names) in cases {
        insta::assert_snapshot!(name, svg(&ladder, number, names));
    }
}

// ---- the points, through the DOM ----------------------------------------------------------

#[test]
fn a_timer_box_says_its_kind_number_resolution_and_duration() {
    let ladder = every_box();
    let els = parse(&svg(&ladder, 1, Names::Lad));
    let bi = els.iter().position(|e| e.has_class("box")).expect("a box");
    let b = &els[bi];
    assert_eq!(b.attr("data-mnemonic"), Some("TON"));
    assert_eq!(b.attr("data-counted"), Some("T4"));
    let title = els.iter().find(|e| e.has_class("title")).expect("title");
    assert_eq!(title.text, "TON");
    let counted = els
        .iter()
        .find(|e| e.has_class("counted"))
        .expect("the timer above the box");
    assert_eq!(counted.attr("data-operand"), Some("T4"));
    assert_eq!(counted.text, "RunTimerT4", "symbol over address");
    let text = |class: &str| {
        els.iter()
            .find(|e| e.has_class(class))
            .map(|e| e.text.clone())
    };
    assert_eq!(text("resolution").as_deref(), Some("100 ms"));
    assert_eq!(text("duration").as_deref(), Some("= 10.0 s"));
    let pt = els
        .iter()
        .find(|e| e.has_class("pin") && e.attr("data-pin") == Some("PT"))
        .expect("PT pin");
    assert_eq!(pt.text, "PT100= 10.0 s");
    let tooltip = els
        .iter()
        .find(|e| e.name == "title" && e.parents.last() == Some(&bi))
        .expect("tooltip");
    assert_eq!(
        tooltip.text,
        "TON RunTimer, 100 (line 20)\nRunTimer (T4): a 100 ms timer"
    );
    // Other resolutions: 10 ms and 1 ms timers.
    let t2 = parse(&svg(&ladder, 2, Names::Lad));
    assert!(t2
        .iter()
        .any(|e| e.has_class("duration") && e.text == "= 2.50 s"));
    let t0 = parse(&svg(&ladder, 3, Names::Lad));
    assert!(t0
        .iter()
        .any(|e| e.has_class("resolution") && e.text == "1 ms"));
}

#[test]
fn math_boxes_show_every_pin_with_the_in_out_operand_on_both_sides() {
    let ladder = every_box();
    let els = parse(&svg(&ladder, 7, Names::Lad));
    let add = els
        .iter()
        .position(|e| e.attr("data-mnemonic") == Some("+I"))
        .expect("+I");
    let pins: Vec<(String, String)> = els
        .iter()
        .filter(|e| e.has_class("pin") && e.parents.contains(&add))
        .filter(|e| e.attr("data-operand") != Some("") || e.text.len() > 3)
        .map(|e| (e.attr("data-pin").unwrap_or("").to_string(), e.text.clone()))
        .collect();
    assert_eq!(
        pins,
        vec![
            ("IN1".to_string(), "IN1TotalMW0".to_string()),
            ("IN2".to_string(), "IN21".to_string()),
            ("OUT".to_string(), "OUTTotalMW0".to_string()),
        ]
    );
    let labels: Vec<&str> = els
        .iter()
        .filter(|e| e.has_class("title"))
        .map(|e| e.text.as_str())
        .collect();
    assert_eq!(labels, ["ADD_I", "SUB_I", "MUL_I", "DIV_I"]);
    let stl = parse(&svg(&ladder, 7, Names::Stl));
    let labels: Vec<&str> = stl
        .iter()
        .filter(|e| e.has_class("title"))
        .map(|e| e.text.as_str())
        .collect();
    assert_eq!(labels, ["+I", "-I", "*I", "/I"]);
    // INC_W has its IN (= its OUT); FOR has INDX, INIT, FINAL on the input side.
    let inc = parse(&svg(&ladder, 16, Names::Lad));
    let inc_pins: Vec<&str> = inc
        .iter()
        .filter(|e| e.has_class("pin") && e.attr("data-operand") == Some("MW92"))
        .filter_map(|e| e.attr("data-pin"))
        .collect();
    assert_eq!(inc_pins, ["IN", "OUT"]);
    let for_svg = svg(&ladder, 15, Names::Lad);
    let for_els = parse(&for_svg);
    let names: Vec<&str> = for_els
        .iter()
        .filter(|e| e.has_class("pin-name"))
        .map(|e| e.text.as_str())
        .collect();
    assert_eq!(names, ["EN", "INDX", "INIT", "FINAL"]);
}

#[test]
fn jumps_are_coils_labels_are_boxes_and_compares_read_like_micro_win() {
    let ladder = every_box();
    let jump = parse(&svg(&ladder, 18, Names::Lad));
    let j = jump
        .iter()
        .position(|e| e.has_class("jump"))
        .expect("a jump");
    assert!(!jump.iter().any(|e| e.name == "rect"), "a jump is no box");
    assert!(jump
        .iter()
        .any(|e| e.name == "path" && e.parents.contains(&j)));
    assert!(jump
        .iter()
        .any(|e| e.has_class("pin") && e.attr("data-pin") == Some("N") && e.text == "1"));
    let label = parse(&svg(&ladder, 20, Names::Lad));
    assert!(label.iter().any(|e| e.has_class("label")));
    assert!(label
        .iter()
        .any(|e| e.has_class("title") && e.text == "LBL"));
    assert!(!label.iter().any(|e| e.has_class("pin-name")), "no EN");
    let inside = |names| -> Vec<String> {
        parse(&svg(&ladder, 14, names))
            .iter()
            .filter(|e| e.has_class("inside"))
            .map(|e| e.text.clone())
            .collect()
    };
    assert_eq!(inside(Names::Lad), ["==B", ">=I", "<>D", "<R"]);
    assert_eq!(inside(Names::Stl), ["=B", ">=W", "<>D", "<R"]);
}

#[test]
fn no_two_texts_overlap_and_pin_texts_stay_in_their_rows() {
    let mut faults = Vec::new();
    let mut programs = vec![root().join("tests/data/ladder/every_box.lad")];
    programs.extend(files("examples", &["lad"]));
    let mut drawn = 0;
    for path in programs {
        let ladder = gutta_ladder::build(&checked_file(&path));
        for block in &ladder.blocks {
            for net in &block.networks {
                for names in [Names::Lad, Names::Stl] {
                    let options = DrawOptions {
                        names,
                        ..DrawOptions::default()
                    };
                    let svg = network_svg_with(block, net, &options);
                    drawn += 1;
                    for fault in layout_faults(&svg) {
                        faults.push(format!(
                            "{} {} network {} ({names:?}): {fault}",
                            path.file_name().unwrap_or_default().to_string_lossy(),
                            block.name,
                            net.number
                        ));
                    }
                }
            }
        }
    }
    assert!(drawn > 40, "{drawn} networks drawn");
    assert!(faults.is_empty(), "{}", faults.join("\n"));
}

#[test]
fn the_fault_finder_finds_overlaps() {
    // Two texts at the same place, and a pin text far from its pin's line.
    let svg = "<g class=\"network\"><text x=\"10\" y=\"20\">MW10</text>\
               <text x=\"12\" y=\"22\">MW12</text>\
               <g class=\"pin\" data-pin=\"IN\"><line class=\"pin-line\" x1=\"0\" y1=\"100\" x2=\"5\" y2=\"100\"/>\
               <text x=\"0\" y=\"140\">far</text></g></g>";
    let faults = layout_faults(svg);
    assert_eq!(faults.len(), 2, "{faults:?}");
}
