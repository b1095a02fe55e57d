//! The drawing's texts (docs/ladder.md, "Comments", "Symbol information", "System
//! names", "Fonts"): network comments and titles wrapped at the drawing's width (words,
//! long words, CJK by characters), symbol comments in the tooltips, the symbol table
//! under a rung, system bits by their names, and the CJK font stack.

mod common;

use common::checked;
use gutta_ladder::layout::{layout_network, network_header, text_width, wrap, MIN_TEXT_W};
use gutta_ladder::model::{Body, Network, Node};
use gutta_ladder::svg::{network_svg_with, DrawOptions, FONT_STACK, STYLE};
use gutta_ladder::symbol_info;

const LONG_EN: &str = "This network latches the pump when the start button is pressed and the \
tank is not full; the stop button or the high level switch drops it again, and the alarm \
lamp blinks while the pump has been asked to run but the flow switch stays open for longer \
than the delay; supercalifragilisticexpialidociousandevenlongerwordwithoutanyblanksatallinit \
ends it.";

const LONG_ZH: &str = "本网络在按下启动按钮且水箱未满时锁存水泵；停止按钮或高液位开关使其复位。\
当水泵被要求运行而流量开关在延时之后仍然断开时，报警灯闪烁，提醒操作员检查管路和阀门的状态，\
并在必要时手动切断电源以保护设备。";

fn program() -> String {
    format!(
        "SYMBOLS\n\
         \x20 Start : I0.0 // start button\n\
         \x20 Stop  : I0.1 // stop button, normally closed\n\
         \x20 Pump  : Q0.0 // pump contactor\n\
         \x20 Level : MW20 : INT // tank level in mm\n\
         \x20 Quiet : M1.0\n\
         \x20 Ready : SM0.1 // our own name for the first scan\n\
         END_SYMBOLS\n\
         ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n\
         NETWORK 1 // Pump latch\n\
         // {LONG_EN}\n\
         // {LONG_ZH}\n\
         LD Start\nO Pump\nAN Stop\nA Quiet\nLDW>= Level, 100\nOLD\n= Pump\n\
         NETWORK 2 // {LONG_EN}\n\
         LD SM0.0\nA Ready\n= Q0.1\n\
         NETWORK 3\n\
         LD I0.5\n= Q0.5\n\
         END_ORGANIZATION_BLOCK\n"
    )
}

fn networks() -> Vec<Network> {
    let checked = checked(&program());
    assert!(!checked.has_errors(), "the test program checks");
    let mut ladder = gutta_ladder::build(&checked);
    std::mem::take(&mut ladder.blocks[0].networks)
}

fn svg(net: &Network, symbol_info: bool) -> String {
    let options = DrawOptions {
        symbol_info,
        ..DrawOptions::default()
    };
    let block = gutta_ladder::model::Block {
        name: "MAIN".into(),
        numbered: "OB1".into(),
        title: None,
        networks: Vec::new(),
    };
    network_svg_with(&block, net, &options)
}

/// The drawn width of a network (as `draw_network_with` returns it).
fn drawn_size(net: &Network, symbol_info: bool) -> (i32, i32) {
    let options = DrawOptions {
        symbol_info,
        ..DrawOptions::default()
    };
    let block = gutta_ladder::model::Block {
        name: "MAIN".into(),
        numbered: "OB1".into(),
        title: None,
        networks: Vec::new(),
    };
    let mut out = String::new();
    gutta_ladder::svg::draw_network_with(&mut out, &block, net, 0, &options)
}

/// The contents of every `<text class="CLASS" ...>` of `svg`, unescaped enough for the
/// test texts (`&apos;` and `&amp;`).
fn texts(svg: &str, class: &str) -> Vec<String> {
    let open = format!("<text class=\"{class}\"");
    svg.match_indices(&open)
        .map(|(at, _)| {
            let rest = &svg[at..];
            let start = rest.find('>').expect("text opens") + 1;
            let end = rest.find("</text>").expect("text closes");
            rest[start..end]
                .replace("&apos;", "'")
                .replace("&amp;", "&")
        })
        .collect()
}

// ---- wrapping --------------------------------------------------------------------------

#[test]
fn wrap_breaks_at_blanks_and_keeps_every_word() {
    let lines = wrap("the quick brown fox jumps over the lazy dog", 10 * 7);
    assert_eq!(
        lines,
        ["the quick", "brown fox", "jumps over", "the lazy", "dog"]
    );
    assert!(lines.iter().all(|l| text_width(l) <= 70));
    assert_eq!(wrap("fits", 70), ["fits"]);
    assert_eq!(wrap("", 70), [""]);
}

#[test]
fn a_word_longer_than_the_width_is_broken() {
    let lines = wrap("a abcdefghijklmnopqrstuvwxyz b", 10 * 7);
    assert_eq!(lines, ["a", "abcdefghij", "klmnopqrst", "uvwxyz b"]);
}

#[test]
fn cjk_text_wraps_by_characters_counted_double() {
    // Ten wide characters are 140 px: five fit in 70 px.
    let lines = wrap("一二三四五六七八九十", 70);
    assert_eq!(lines, ["一二三四五", "六七八九十"]);
    // Mixed: a Latin word stays whole, wide characters break anywhere.
    let lines = wrap("启动 Start按钮按钮", 8 * 7);
    assert_eq!(lines, ["启动", "Start按", "钮按钮"]);
    assert!(lines.iter().all(|l| text_width(l) <= 56), "{lines:?}");
}

// ---- comments and titles ----------------------------------------------------------------

#[test]
fn long_comments_wrap_inside_the_drawings_width_and_the_header_grows() {
    let nets = networks();
    let net = &nets[0];
    let head = network_header(net);
    assert_eq!(head.title, ["Network 1: Pump latch"]);
    assert!(head.comment.len() >= 4, "{:?}", head.comment);
    let (width, _) = drawn_size(net, false);
    let layout = layout_network(net).expect("a rung");
    assert_eq!(
        width,
        layout.width.max(MIN_TEXT_W + 24),
        "the drawing is the wider of the rung and the minimum"
    );
    let drawn = texts(&svg(net, false), "comment");
    assert_eq!(drawn, head.comment);
    for line in &drawn {
        assert!(
            text_width(line) <= width - 24,
            "{line} is wider than {width}"
        );
    }
    // Every word of the English comment is drawn whole, save the one too long for a
    // line; the Chinese text is drawn in full, broken between characters.
    let joined = drawn.join(" ");
    for word in LONG_EN.split_whitespace() {
        if text_width(word) <= MIN_TEXT_W {
            assert!(joined.contains(word), "{word} is lost");
        }
    }
    let cjk: String = drawn.iter().filter(|l| !l.is_ascii()).cloned().collect();
    assert_eq!(cjk, LONG_ZH);
    // The rung starts under the header.
    assert_eq!(layout.header_h, head.height());
    assert_eq!(head.height(), 8 + 16 * (1 + head.comment.len() as i32));
}

#[test]
fn long_titles_wrap_too() {
    let nets = networks();
    let head = network_header(&nets[1]);
    assert!(head.title.len() >= 2, "{:?}", head.title);
    assert!(head.title[0].starts_with("Network 2: This network"));
    let (width, _) = drawn_size(&nets[1], false);
    // Titles are 13 px against the 11 px `text_width` counts.
    for line in &head.title {
        assert!(text_width(line) * 13 / 11 <= width - 24, "{line}");
    }
    assert_eq!(texts(&svg(&nets[1], false), "network-title"), head.title);
}

#[test]
fn a_wide_rung_widens_the_wrap() {
    // A 40-contact series is wider than the minimum: its comment wraps at the rung.
    let contacts: String = (0..40)
        .map(|i| format!("A M{}.{}\n", i / 8, i % 8))
        .collect();
    let words: String = "word ".repeat(300);
    let text = format!(
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\n// {words}\nLD I0.0\n{contacts}= Q0.0\n\
         END_ORGANIZATION_BLOCK\n"
    );
    let ladder = gutta_ladder::build(&checked(&text));
    let net = &ladder.blocks[0].networks[0];
    let layout = layout_network(net).expect("a rung");
    assert!(layout.width > MIN_TEXT_W + 24);
    let head = &layout.header;
    let widest = head.comment.iter().map(|l| text_width(l)).max().unwrap();
    assert!(widest <= layout.width - 24);
    assert!(
        widest > MIN_TEXT_W,
        "the comment uses the rung's width, not the minimum"
    );
}

// ---- symbols in tooltips and the symbol information --------------------------------------

#[test]
fn tooltips_hold_the_symbols_comments() {
    let nets = networks();
    let drawn = svg(&nets[0], false);
    assert!(
        drawn.contains("<title>LD Start (line 14)\nStart (I0.0): start button</title>"),
        "{drawn}"
    );
    assert!(drawn.contains("Level (MW20): tank level in mm</title>"));
    // A symbol without a comment still gives its address.
    assert!(drawn.contains("<title>A Quiet (line 17)\nQuiet (M1.0)</title>"));
}

#[test]
fn the_symbol_information_lists_the_networks_symbols_in_order_of_first_use() {
    let nets = networks();
    let rows = symbol_info::rows(&nets[0]);
    let names: Vec<&str> = rows.iter().map(|r| r.symbol).collect();
    assert_eq!(names, ["Start", "Pump", "Stop", "Quiet", "Level"]);
    assert_eq!(rows[4].data_type, "INT");
    assert_eq!(rows[0].data_type, "BOOL");
    assert_eq!(rows[0].address, "I0.0");
    assert_eq!(rows[2].comment, "stop button, normally closed");

    let drawn = svg(&nets[0], true);
    assert_eq!(drawn.matches("class=\"symbol-info\"").count(), 1);
    let row_at: Vec<usize> = names
        .iter()
        .map(|n| {
            drawn
                .find(&format!(
                    "<g class=\"symbol-info-row\" data-symbol=\"{n}\">"
                ))
                .unwrap_or_else(|| panic!("no row for {n}"))
        })
        .collect();
    assert!(row_at.windows(2).all(|w| w[0] < w[1]), "rows in order");
    assert!(texts(&drawn, "si-comment").contains(&"tank level in mm".to_string()));

    // The table counts in the network's height, not in its absence.
    let (w0, h0) = drawn_size(&nets[0], false);
    let (w1, h1) = drawn_size(&nets[0], true);
    assert_eq!(h1, h0 + 16 * (1 + 5) + 12);
    assert!(w1 >= w0);
    assert!(!svg(&nets[0], false).contains("symbol-info"));
}

#[test]
fn a_network_using_no_symbol_has_no_table() {
    let nets = networks();
    assert!(symbol_info::rows(&nets[2]).is_empty());
    let drawn = svg(&nets[2], true);
    assert!(!drawn.contains("symbol-info"), "{drawn}");
    assert_eq!(drawn_size(&nets[2], true), drawn_size(&nets[2], false));
}

// ---- system names -----------------------------------------------------------------------

#[test]
fn system_bits_show_their_names_and_a_user_symbol_wins() {
    let nets = networks();
    let Body::Rung(rung) = &nets[1].body else {
        panic!("network 2 is a rung")
    };
    let Some(Node::Series(series)) = &rung.input else {
        panic!("a series")
    };
    let [Node::Contact(always), Node::Contact(ready)] = series.as_slice() else {
        panic!("two contacts")
    };
    let op = &always.operands[0];
    assert_eq!(op.symbol.as_deref(), Some("Always_On"));
    assert_eq!(op.address.as_deref(), Some("SM0.0"));
    assert_eq!(op.comment.as_deref(), Some("Always on"));
    // `A Ready` (SM0.1 by the program's symbol) and SM0.1 written directly would both
    // be drawn as `Ready`.
    assert_eq!(ready.operands[0].symbol.as_deref(), Some("Ready"));
    let direct = gutta_ladder::build(&checked(&program().replace("A Ready", "A SM0.1")));
    let Body::Rung(rung) = &direct.blocks[0].networks[1].body else {
        panic!("a rung")
    };
    let Some(Node::Series(series)) = &rung.input else {
        panic!("a series")
    };
    let Node::Contact(sm01) = &series[1] else {
        panic!("a contact")
    };
    assert_eq!(sm01.operands[0].symbol.as_deref(), Some("Ready"));

    let drawn = svg(&nets[1], true);
    assert!(texts(&drawn, "symbol").contains(&"Always_On".to_string()));
    assert!(drawn.contains("Always_On (SM0.0): Always on</title>"));
    assert!(drawn.contains("data-symbol=\"Always_On\""));
}

#[test]
fn a_microwin_export_names_system_bits_as_micro_win_does() {
    let text = "// dialect: microwin\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\n\
                LD Always_On\nA SM0.5\n= Q0.0\nEND_ORGANIZATION_BLOCK\n";
    let checked =
        gutta_compiler::check_source(gutta_compiler::source::SourceFile::new("t.lad", text), None);
    assert!(!checked.has_errors());
    let ladder = gutta_ladder::build(&checked);
    let rows = symbol_info::rows(&ladder.blocks[0].networks[0]);
    let names: Vec<(&str, &str)> = rows.iter().map(|r| (r.symbol, r.address)).collect();
    assert_eq!(names, [("Always_On", "SM0.0"), ("Clock_1s", "SM0.5")]);
}

// ---- fonts --------------------------------------------------------------------------------

#[test]
fn the_font_stack_keeps_latin_monospace_first_and_lists_cjk_fonts() {
    assert!(STYLE.contains(&format!("text{{font-family:{FONT_STACK};")));
    let fonts: Vec<&str> = FONT_STACK.split(',').collect();
    assert_eq!(fonts[0], "\"DejaVu Sans Mono\"");
    assert_eq!(fonts.last(), Some(&"monospace"));
    for cjk in [
        "\"Noto Sans Mono CJK SC\"",
        "\"WenQuanYi Zen Hei Mono\"",
        "\"Microsoft YaHei\"",
    ] {
        assert!(fonts.contains(&cjk), "{cjk}");
    }
    let page = gutta_ladder::html::ladder_html(
        &gutta_ladder::model::Ladder {
            plc: "CPU-EC20".into(),
            blocks: Vec::new(),
        },
        &gutta_ladder::html::HtmlOptions::default(),
    );
    assert!(page.contains("body{font-family:system-ui,\"Noto Sans CJK SC\""));
}

#[test]
fn snapshot_of_a_network_with_its_symbol_information() {
    let nets = networks();
    insta::assert_snapshot!("network_with_symbol_information", svg(&nets[0], true));
}

#[test]
fn a_long_symbol_comment_wraps_in_the_table() {
    let long = "the level switch at the top of the tank, wired normally closed so that a broken \
                wire reads as a full tank and stops the pump, checked every shift by the operator";
    let text = format!(
        "SYMBOLS\n  High : I0.3 // {long}\nEND_SYMBOLS\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n\
         NETWORK 1\nLD High\n= Q0.0\nEND_ORGANIZATION_BLOCK\n"
    );
    let ladder = gutta_ladder::build(&checked(&text));
    let net = &ladder.blocks[0].networks[0];
    let drawn = svg(net, true);
    let lines = texts(&drawn, "si-comment");
    assert!(lines.len() >= 2, "{lines:?}");
    assert_eq!(
        lines.join(" "),
        long.split_whitespace().collect::<Vec<_>>().join(" ")
    );
    let (width, height) = drawn_size(net, true);
    let (_, bare) = drawn_size(net, false);
    assert_eq!(height, bare + 16 * (1 + lines.len() as i32) + 12);
    // The comment column starts after `Symbol`, `Address`, `Type` and their gaps.
    let x = drawn
        .split("<text class=\"si-comment\" x=\"")
        .nth(1)
        .and_then(|r| r.split('"').next())
        .and_then(|x| x.parse::<i32>().ok())
        .expect("a comment's x");
    for line in &lines {
        assert!(x + text_width(line) <= width - 12, "{line}");
    }
}

#[test]
fn a_network_shown_as_stl_wraps_its_header_too() {
    let words = "a long comment of a network that is not one rung ".repeat(6);
    let text = format!(
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\n// {words}\nLD I0.0\n= Q0.0\n\
         LD I0.1\n= Q0.1\nEND_ORGANIZATION_BLOCK\n"
    );
    let ladder = gutta_ladder::build(&checked(&text));
    let net = &ladder.blocks[0].networks[0];
    assert!(matches!(net.body, Body::Stl { .. }));
    let head = network_header(net);
    assert!(head.comment.len() >= 2, "{:?}", head.comment);
    let (width, _) = drawn_size(net, false);
    let drawn = texts(&svg(net, false), "comment");
    assert_eq!(drawn, head.comment);
    assert!(drawn.iter().all(|l| text_width(l) <= width - 24));
}

#[test]
fn blanks_inside_a_line_are_kept_and_dropped_at_a_break() {
    assert_eq!(
        wrap("a    b", 70),
        ["a    b"],
        "a line that fits is unchanged"
    );
    assert_eq!(wrap("  indented", 140), ["  indented"]);
    assert_eq!(
        wrap("one  two   three four", 10 * 7),
        ["one  two", "three four"]
    );
    assert_eq!(
        wrap("abcdefgh   ijklmnop", 10 * 7),
        ["abcdefgh", "ijklmnop"]
    );
}

#[test]
fn the_symbol_information_lists_a_timers_own_symbol_first() {
    let checked = checked(
        "SYMBOLS\n  Go : I0.0 // go\n  Delay : T4 // the start delay\n  Lamp : Q0.0\nEND_SYMBOLS\n\
         ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD Go\nTON Delay, 100\n= Lamp\n\
         END_ORGANIZATION_BLOCK\n",
    );
    assert!(!checked.has_errors(), "the test program checks");
    let ladder = gutta_ladder::build(&checked);
    let rows = symbol_info::rows(&ladder.blocks[0].networks[0]);
    let names: Vec<(&str, &str, &str)> = rows
        .iter()
        .map(|r| (r.symbol, r.address, r.comment))
        .collect();
    assert_eq!(
        names,
        [
            ("Go", "I0.0", "go"),
            ("Delay", "T4", "the start delay"),
            ("Lamp", "Q0.0", "")
        ]
    );
}
