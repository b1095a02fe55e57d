"""Boxes as Micro/WIN draws them (docs/ladder.md, "Elements", "Names"), in Chromium:
`gutta-cc ladder tests/data/ladder/every_box.lad -o x.html` opened in the browser, each
point checked through the DOM and the rendered text boxes (getBoundingClientRect):
timer and counter boxes say their kind, number, resolution and preset duration; ADD_I
shows IN1, IN2 and OUT with the in/out operand on both sides; no two pin texts overlap;
JMP is a coil; `--names stl` keeps the STL mnemonics."""

from pathlib import Path

import pytest

from conftest import cc, shoot

ROOT = Path(__file__).resolve().parents[3]
PROGRAM = ROOT / "tests" / "data" / "ladder" / "every_box.lad"


@pytest.fixture
def drawing(browser, tmp_path):
    """A page opener: the program drawn with `gutta-cc ladder ... ARGS -o x.html`."""
    contexts = []

    def open_drawing(*args):
        out = tmp_path / f"drawing{len(contexts)}.html"
        # From the repository's root: the page's heading names the program relatively.
        cc("ladder", str(PROGRAM.relative_to(ROOT)), *args, "-o", str(out), cwd=ROOT)
        context = browser.new_context(viewport={"width": 1100, "height": 900})
        contexts.append(context)
        pg = context.new_page()
        errors = []
        pg.on("pageerror", lambda e: errors.append(str(e)))
        pg.goto(out.as_uri())
        pg.wait_for_selector("g.network")
        assert not errors, errors
        return pg

    yield open_drawing
    for c in contexts:
        c.close()


def boxes(page, mnemonic):
    """Every box of `mnemonic`: its label, data-counted, counted texts and pins."""
    return page.evaluate(
        """m => Array.from(document.querySelectorAll(`.box[data-mnemonic="${m}"]`)).map(b => ({
             label: (b.querySelector(':scope > text.title') || {}).textContent,
             counted: b.getAttribute('data-counted'),
             above: Array.from(b.querySelectorAll('.operand.counted text')).map(t => t.textContent),
             resolution: (b.querySelector('text.resolution') || {}).textContent,
             duration: (b.querySelector('text.duration') || {}).textContent,
             rect: !!b.querySelector('rect'),
             path: !!b.querySelector('path'),
             classes: b.getAttribute('class'),
             pins: Array.from(b.querySelectorAll('g.pin')).map(p => [
               p.getAttribute('data-pin'), p.getAttribute('data-operand'),
               Array.from(p.querySelectorAll('.operand text, text.duration'))
                 .map(t => t.textContent).join(' ')]),
           }))""",
        mnemonic)


def test_timer_and_counter_boxes_say_what_they_are(drawing):
    page = drawing()
    (ton,) = boxes(page, "TON")
    assert ton["label"] == "TON"
    assert ton["counted"] == "T4"
    assert ton["above"] == ["RunTimer", "T4"], "symbol over address, as contacts show it"
    assert ton["resolution"] == "100 ms"
    assert ton["duration"] == "= 10.0 s"
    assert ["PT", "", "100 = 10.0 s"] in ton["pins"]
    assert ["IN", "", ""] in ton["pins"]
    expected = {"TOF": ("T2", "10 ms"), "TONR": ("T0", "1 ms"),
                "CTU": ("C1", None), "CTD": ("C2", None), "CTUD": ("C3", None)}
    for mnemonic, (counted, resolution) in expected.items():
        (box,) = boxes(page, mnemonic)
        assert box["label"] == mnemonic, box
        assert box["counted"] == counted, box
        assert box["resolution"] == resolution, box
    (ctud,) = boxes(page, "CTUD")
    assert [p[0] for p in ctud["pins"]] == ["CU", "PV", "CD", "R", "Q"]
    shoot(page, "drawing_boxes_timers")


def test_math_boxes_show_every_pin_with_in_out_on_both_sides(drawing):
    page = drawing()
    add = boxes(page, "+I")[0]
    assert add["label"] == "ADD_I"
    assert add["pins"] == [
        ["EN", "", ""], ["IN1", "MW0", "Total MW0"], ["IN2", "", "1"],
        ["ENO", "", ""], ["OUT", "MW0", "Total MW0"]]
    inc = boxes(page, "INCW")[0]
    assert inc["label"] == "INC_W"
    assert [p[:2] for p in inc["pins"] if p[1]] == [["IN", "MW42"], ["OUT", "MW42"]]
    (loop,) = boxes(page, "FOR")
    assert [p[0] for p in loop["pins"]] == ["EN", "INDX", "INIT", "FINAL"]
    labels = {m: boxes(page, m)[0]["label"] for m in
              ["-D", "*R", "MUL", "MOVB", "MOVW", "MOVD", "MOVR", "BMW", "DECD"]}
    assert labels == {"-D": "SUB_DI", "*R": "MUL_R", "MUL": "MUL", "MOVB": "MOV_B",
                      "MOVW": "MOV_W", "MOVD": "MOV_DW", "MOVR": "MOV_R",
                      "BMW": "BLKMOV_W", "DECD": "DEC_DW"}
    compares = page.evaluate(
        "() => Array.from(document.querySelectorAll('.contact[data-kind=compare] text.inside'))"
        ".map(t => t.textContent)")
    assert compares == ["==B", ">=I", "<>D", "<R"]
    page.evaluate("document.querySelector('[data-network=\"7\"]').scrollIntoView()")
    shoot(page, "drawing_boxes_math")


def test_no_two_pin_texts_overlap_and_each_sits_on_its_pin_line(drawing):
    page = drawing()
    faults = page.evaluate(
        """() => {
          const faults = [];
          const texts = [];
          document.querySelectorAll('g.pin').forEach(pin => {
            const line = pin.querySelector('line.pin-line');
            const y = line ? line.getBoundingClientRect().top : null;
            pin.querySelectorAll('text').forEach(t => {
              const r = t.getBoundingClientRect();
              texts.push({t: t.textContent, r});
              if (y !== null && (r.top > y + 1 || r.bottom < y - 1 - 14)) {
                faults.push(`${t.textContent} is not on its pin line (${r.top}-${r.bottom}, ${y})`);
              }
            });
          });
          for (let i = 0; i < texts.length; i++) {
            for (let j = i + 1; j < texts.length; j++) {
              const a = texts[i].r, b = texts[j].r;
              const e = 0.5;
              if (a.left + e < b.right && b.left + e < a.right
                  && a.top + e < b.bottom && b.top + e < a.bottom) {
                faults.push(`${texts[i].t} overlaps ${texts[j].t}`);
              }
            }
          }
          return [texts.length, faults];
        }""")
    count, problems = faults
    assert count > 100, f"only {count} pin texts"
    assert problems == []


def test_jmp_is_a_coil_and_lbl_a_label_box(drawing):
    page = drawing()
    (jmp,) = boxes(page, "JMP")
    assert "jump" in jmp["classes"].split()
    assert jmp["path"] and not jmp["rect"], "a coil, not a box"
    assert jmp["label"] == "JMP"
    assert jmp["pins"] == [["N", "", "1"]]
    (lbl,) = boxes(page, "LBL")
    assert "label" in lbl["classes"].split() and lbl["rect"]
    assert lbl["pins"] == [["N", "", "1"]]


def test_names_stl_keeps_the_mnemonics(drawing):
    page = drawing("--names", "stl")
    assert boxes(page, "+I")[0]["label"] == "+I"
    assert boxes(page, "MOVW")[0]["label"] == "MOVW"
    assert boxes(page, "TON")[0]["label"] == "TON"
    compares = page.evaluate(
        "() => Array.from(document.querySelectorAll('.contact[data-kind=compare] text.inside'))"
        ".map(t => t.textContent)")
    assert compares == ["=B", ">=W", "<>D", "<R"]
