"""Sequence control relays of a Micro/WIN export drawn as Micro/WIN draws them
(docs/ladder.md, "Sequence control relays"), in Chromium: `gutta-cc ladder
tests/data/microwin/scr_sequence_utf8_crlf.awl -o x.html` opened in the browser. Each
`LSCR` is an `SCR` box on the rail with its S bit above, each `SCRT` a `(SCRT)` coil with
its S bit, `SCRE` and `CSCRE` `(SCRE)` coils; every S operand shows its S name drawn
above the GUTTA address it went to (M96.x, the default S area), and no text of a network
overlaps another."""

from pathlib import Path

from conftest import cc, shoot

ROOT = Path(__file__).resolve().parents[3]
PROGRAM = ROOT / "tests" / "data" / "microwin" / "scr_sequence_utf8_crlf.awl"


def open_drawing(browser, tmp_path):
    out = tmp_path / "scr.html"
    cc("ladder", str(PROGRAM.relative_to(ROOT)), "-o", str(out), cwd=ROOT)
    context = browser.new_context(viewport={"width": 900, "height": 1000})
    page = context.new_page()
    errors = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.goto(out.as_uri())
    page.wait_for_selector("g.network")
    assert not errors, errors
    return context, page


def scr_elements(page):
    """Every SCR element: mnemonic, the text inside, its operand and the rendered
    S name and address above it (text, top edge), and the shape's top edge."""
    return page.evaluate(
        """() => Array.from(document.querySelectorAll(
              '.box[data-mnemonic="LSCR"], .box[data-mnemonic="SCRT"],'
              + ' .box[data-mnemonic="SCRE"], .box[data-mnemonic="CSCRE"]')).map(b => {
             const texts = Array.from(b.querySelectorAll('.operand text')).map(t => {
               const r = t.getBoundingClientRect();
               return [t.textContent, r.top, r.bottom];
             });
             const shape = b.querySelector('rect, path');
             return {
               mnemonic: b.getAttribute('data-mnemonic'),
               classes: b.getAttribute('class'),
               operand: b.getAttribute('data-operand'),
               title: (b.querySelector(':scope > text.title') || {}).textContent,
               texts,
               shapeTop: shape ? shape.getBoundingClientRect().top : null,
             };
           })""")


def test_scr_lines_are_drawn_as_micro_win_draws_them(browser, tmp_path):
    context, page = open_drawing(browser, tmp_path)
    try:
        elements = scr_elements(page)
        by = {}
        for e in elements:
            by.setdefault(e["mnemonic"], []).append(e)
        assert len(by["LSCR"]) == 4 and len(by["SCRT"]) == 4, elements
        assert len(by["SCRE"]) == 4 and len(by["CSCRE"]) == 1, elements
        for e in by["LSCR"]:
            assert "label" in e["classes"] and e["title"] == "SCR", e
        for e in by["SCRT"]:
            assert "jump" in e["classes"] and e["title"] == "SCRT", e
        for e in by["SCRE"] + by["CSCRE"]:
            assert e["title"] == "SCRE" and e["operand"] == "", e
        # The S name above its GUTTA address, both above the shape.
        for e in by["LSCR"] + by["SCRT"]:
            assert e["operand"].startswith("M96."), e
            bit = e["operand"].split(".")[1]
            (name, name_top, name_bottom), (address, address_top, _) = e["texts"][:2]
            assert (name, address) == (f"S0.{bit}", e["operand"]), e
            assert name_bottom <= address_top + 1, e
            assert e["shapeTop"] is not None and address_top < e["shapeTop"], e
        # No two texts of a network overlap (headers, operands, titles).
        overlaps = page.evaluate(
            """() => {
                 const bad = [];
                 for (const n of document.querySelectorAll('g.network')) {
                   const rs = Array.from(n.querySelectorAll('text'))
                     .filter(t => t.textContent.trim() && !t.closest('title'))
                     .map(t => [t.textContent, t.getBoundingClientRect()]);
                   for (let i = 0; i < rs.length; i++) for (let j = i + 1; j < rs.length; j++) {
                     const [a, r] = rs[i], [b, s] = rs[j];
                     if (r.left < s.right - 1 && s.left < r.right - 1
                         && r.top < s.bottom - 1 && s.top < r.bottom - 1) bad.push([a, b]);
                   }
                 }
                 return bad;
               }""")
        assert overlaps == [], overlaps
        shoot(page, "drawing_scr")
    finally:
        context.close()
