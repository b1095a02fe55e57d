//! The self-contained HTML page of a ladder (docs/ladder.md, "Drawing"): a block index,
//! every network as its own inline SVG (from `svg.rs`), inline CSS with the `on` and
//! `forced` styles the live view sets, and an optional inline script. No external URL:
//! the page works from a file with no network access. Text only, no I/O.

use std::fmt::Write;

use crate::layout::block_heading;
use crate::model::Ladder;
use crate::svg::{draw_network_with, escape, DrawOptions, STYLE};

/// What the page carries besides the drawing.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct HtmlOptions {
    /// The page's `<title>` and top heading.
    pub title: String,
    /// JavaScript put inline at the end of the body (the live view), if any.
    pub live_script: Option<String>,
    /// How the networks are drawn.
    pub draw: DrawOptions,
}

/// Styles of the page around the drawing: its fonts (a sans-serif stack that shows CJK
/// headings where the system has such a font; the drawing has its own monospace stack,
/// `svg::FONT_STACK`), energized (`on`) and forced elements.
const PAGE_STYLE: &str = "\
body{font-family:system-ui,\"Noto Sans CJK SC\",\"Source Han Sans SC\",\"Microsoft YaHei\",\
\"PingFang SC\",\"WenQuanYi Zen Hei\",sans-serif;margin:16px;color:#222}\
nav ul{list-style:none;padding:0}nav li{display:inline-block;margin-right:12px}\
.block{margin-top:24px}\
.network-view{overflow-x:auto;border-top:1px solid #ccc;padding:4px 96px 4px 0}\
.network-view svg{display:block;overflow:visible}\
.wire.on{stroke:#1a7f37;stroke-width:3}\
.contact.on .symbol-line,.coil.on .symbol-line{stroke:#1a7f37;stroke-width:3}\
.box.on rect{stroke:#1a7f37;stroke-width:3;fill:#e9f7ec}\
.forced .address,.forced .symbol,.forced.address{fill:#b3261e;font-weight:bold}\
.forced .symbol-line{stroke-dasharray:3 2}\
.value{fill:#1558b0}\
.stale{opacity:.5}\
#status{font-weight:bold}\
";

/// The page: a heading, an index of blocks, then each block's networks, each network an
/// inline `<svg>` inside a horizontally scrolling `<div class="network-view">`.
pub fn ladder_html(ladder: &Ladder, options: &HtmlOptions) -> String {
    let networks: usize = ladder.blocks.iter().map(|b| b.networks.len()).sum();
    let mut out = String::with_capacity(networks * 8192);
    let mut drawn = String::new();
    let title = escape(&options.title);
    let _ = write!(
        out,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n<title>{title}</title>\n\
         <style>{PAGE_STYLE}{STYLE}</style>\n</head>\n<body>\n<h1>{title}</h1>\n\
         <p id=\"status\" data-plc=\"{}\"></p>\n<nav><ul>",
        escape(&ladder.plc)
    );
    for (i, block) in ladder.blocks.iter().enumerate() {
        let _ = write!(
            out,
            "<li><a href=\"#block-{i}\">{}</a></li>",
            escape(&block_heading(block))
        );
    }
    out.push_str("</ul></nav>\n");
    for (i, block) in ladder.blocks.iter().enumerate() {
        let _ = write!(
            out,
            "<section class=\"block\" id=\"block-{i}\" data-block=\"{}\">\n<h2>{}</h2>\n",
            escape(&block.name),
            escape(&block_heading(block))
        );
        for net in &block.networks {
            drawn.clear();
            let (w, h) = draw_network_with(&mut drawn, block, net, 0, &options.draw);
            let _ = writeln!(
                out,
                "<div class=\"network-view\" id=\"block-{i}-network-{}\">\
                 <svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" \
                 viewBox=\"0 0 {w} {h}\">{}</svg></div>",
                net.number, drawn,
            );
        }
        out.push_str("</section>\n");
    }
    if let Some(script) = &options.live_script {
        // Inside <script> only `</script` can end the element early.
        let safe = script.replace("</script", "<\\/script");
        let _ = write!(out, "<script>\n{safe}\n</script>\n");
    }
    out.push_str("</body>\n</html>\n");
    out
}
