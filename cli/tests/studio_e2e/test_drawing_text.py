"""The drawing's texts in Chromium (docs/ladder.md, "Comments", "Symbol information",
"System names", "Fonts"): `gutta-cc ladder --symbol-info -o x.html` on a program with a
long English and a long Chinese network comment, symbols with comments and SM0.0. The
wrapped comment lines lie inside their network's width as the browser measures them,
tooltips hold the symbols' comments, the symbol table lists the network's symbols,
SM0.0 shows as Always_On, and CJK text is drawn by a CJK font (CI installs one)
(told by glyph widths, not by the CSS)."""

import json
import urllib.error
import urllib.request

import pytest

from conftest import cc, shoot, wait_until

LONG_EN = ("This network latches the pump when the start button is pressed and the tank is "
           "not full; the stop button or the high level switch drops it again, and the alarm "
           "lamp blinks while the pump has been asked to run but the flow switch stays open "
           "for longer than the delay set in the symbol table.")
LONG_ZH = ("本网络在按下启动按钮且水箱未满时锁存水泵；停止按钮或高液位开关使其复位。"
           "当水泵被要求运行而流量开关在延时之后仍然断开时，报警灯闪烁，提醒操作员检查管路和阀门的状态，"
           "并在必要时手动切断电源以保护设备。")

PROGRAM = f"""SYMBOLS
  Start : I0.0  // start button
  Stop  : I0.1  // stop button, normally closed
  Pump  : Q0.0  // pump contactor
  Level : MW20 : INT // tank level in mm
  启动  : I0.2  // 现场启动按钮
END_SYMBOLS
ORGANIZATION_BLOCK MAIN:OB1
BEGIN
NETWORK 1 // Pump latch
// {LONG_EN}
// {LONG_ZH}
LD Start
O Pump
AN Stop
A 启动
LDW>= Level, 100
OLD
= Pump
NETWORK 2 // Always
LD SM0.0
= Q0.1
NETWORK 3 // No symbols here
LD I0.5
= Q0.5
END_ORGANIZATION_BLOCK
"""


@pytest.fixture
def drawing(tmp_path, browser):
    """The page `gutta-cc ladder --symbol-info` writes for PROGRAM, open in Chromium."""
    source = tmp_path / "pump.lad"
    source.write_text(PROGRAM, encoding="utf-8")
    out = tmp_path / "pump.html"
    cc("ladder", "pump.lad", "--symbol-info", "-o", "pump.html", cwd=tmp_path)
    context = browser.new_context(viewport={"width": 1100, "height": 900})
    page = context.new_page()
    errors = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.goto(out.as_uri())
    page.wait_for_selector("g.network")
    yield page
    context.close()
    assert not errors, f"the page reported errors: {errors}"


def network(page, n):
    return page.locator(f'g.network[data-network="{n}"]')


def test_comment_lines_lie_inside_the_network_width(drawing):
    boxes = drawing.evaluate("""() => {
        const g = document.querySelector('g.network[data-network="1"]');
        const svg = g.ownerSVGElement;
        const lines = [...g.querySelectorAll('text.comment, text.network-title')];
        return {width: svg.width.baseVal.value,
                lines: lines.map(t => { const b = t.getBBox();
                                        return {x: b.x, right: b.x + b.width, text: t.textContent}; })};
    }""")
    comments = [l for l in boxes["lines"] if l["text"] != "Network 1: Pump latch"]
    assert len(comments) >= 4, boxes
    for line in boxes["lines"]:
        assert line["x"] >= 0 and line["right"] <= boxes["width"], (line, boxes["width"])
    drawn = " ".join(l["text"] for l in comments)
    for word in LONG_EN.split():
        assert word in drawn, word
    assert "".join(l["text"] for l in comments if not l["text"].isascii()) == LONG_ZH


def test_tooltips_hold_the_symbol_comments(drawing):
    title = network(drawing, 1).locator('g.contact[data-operand="I0.0"] > title').text_content()
    assert title.splitlines() == ["LD Start (line 13)", "Start (I0.0): start button"]
    title = network(drawing, 1).locator('g.contact[data-operand="I0.2"] > title').text_content()
    assert "启动 (I0.2): 现场启动按钮" in title.splitlines()


def test_the_symbol_table_lists_the_networks_symbols(drawing):
    rows = network(drawing, 1).locator(".symbol-info .symbol-info-row")
    assert [rows.nth(i).get_attribute("data-symbol") for i in range(rows.count())] == \
        ["Start", "Pump", "Stop", "启动", "Level"]
    level = network(drawing, 1).locator('.symbol-info-row[data-symbol="Level"] text')
    assert level.all_text_contents() == ["Level", "MW20", "INT", "tank level in mm"]
    # The table lies inside the network's drawing, under the rung.
    inside = drawing.evaluate("""() => {
        const g = document.querySelector('g.network[data-network="1"]');
        const table = g.querySelector('.symbol-info').getBBox();
        const rail = g.querySelector('line.rail').getBBox();
        const svg = g.ownerSVGElement;
        return table.y >= rail.y + rail.height && table.y + table.height <= svg.height.baseVal.value
            && table.x + table.width <= svg.width.baseVal.value;
    }""")
    assert inside
    assert network(drawing, 3).locator(".symbol-info").count() == 0


def test_sm0_0_shows_its_system_name(drawing):
    contact = network(drawing, 2).locator('g.contact[data-operand="SM0.0"]')
    assert contact.locator("text.symbol").text_content() == "Always_On"
    assert contact.locator("text.address").text_content() == "SM0.0"
    assert "Always_On (SM0.0): Always on" in contact.locator("title").text_content()
    assert network(drawing, 2).locator('.symbol-info-row[data-symbol="Always_On"]').count() == 1


def test_cjk_text_is_drawn_by_a_cjk_font(drawing):
    # Which fonts of the stack the browser has: a Latin probe measures the same in
    # `"FONT", monospace` and `"FONT", serif` only when FONT exists.
    measured = drawing.evaluate("""() => {
        const family = getComputedStyle(document.querySelector('text.comment')).fontFamily;
        const fonts = family.split(',').map(f => f.trim().replace(/^"|"$/g, ''))
            .filter(f => f !== 'monospace');
        const c = document.createElement('canvas').getContext('2d');
        const width = (font, text) => { c.font = font; return c.measureText(text).width; };
        const probe = 'mmmmmmmmmmlli0O@';
        const present = fonts.filter(f =>
            width(`72px "${f}", monospace`, probe) === width(`72px "${f}", serif`, probe));
        const cjk = ['Noto Sans Mono CJK SC', 'Sarasa Mono SC', 'WenQuanYi Zen Hei Mono',
                     'Microsoft YaHei', 'Noto Sans CJK SC', 'WenQuanYi Zen Hei'];
        // Widths as the drawing's comment text draws them (11 px, its own stack).
        const svgText = (s) => {
            const t = document.createElementNS('http://www.w3.org/2000/svg', 'text');
            t.setAttribute('class', 'comment');
            t.textContent = s;
            document.querySelector('g.network').appendChild(t);
            const w = t.getComputedTextLength();
            t.remove();
            return w;
        };
        return {present, cjkFonts: present.filter(f => cjk.includes(f)),
                latin: svgText('MMMMMMMMMM') / 10, han: svgText('水泵启动按钮报警灯闪烁') / 11,
                hanInFirstCjk: present.some(f => cjk.includes(f))
                    ? width(`11px "${present.find(f => cjk.includes(f))}"`, '水泵启动按钮报警灯闪烁') / 11
                    : null};
    }""")
    # Latin text keeps monospace metrics: the layout counts 7 px a character at 11 px.
    assert 5.5 <= measured["latin"] <= 7.0, measured
    # A CJK font must be there (CI installs fonts-wqy-zenhei): Han characters are drawn
    # by it, a full em wide (what a CJK font's glyphs measure on their own), about twice
    # a Latin character, and never more than the two columns the layout counts.
    assert measured["cjkFonts"], (
        "no font of the drawing's CJK stack on this machine: "
        "install one (apt-get install fonts-wqy-zenhei)", measured)
    assert measured["han"] == pytest.approx(measured["hanInFirstCjk"], abs=0.05), measured
    assert 10.0 <= measured["han"] <= 14.0, measured
    page = drawing
    shoot(page, "drawing_text")


def test_the_studio_turns_the_symbol_information_on_and_off(page):
    """The studio's `symbol-info` command: every network redrawn with its symbol table,
    kept for the networks drawn after (a reload of the page), and off again."""
    assert page.locator(".symbol-info").count() == 0
    page.locator('button[data-command="symbol-info"]').click()
    wait_until(lambda: page.locator(".symbol-info").count() > 0, what="the symbol tables")
    assert page.locator("body").get_attribute("data-symbol-info") == "on"
    rows = page.locator(".symbol-info-row")
    symbols = {rows.nth(i).get_attribute("data-symbol") for i in range(rows.count())}
    assert "Start" in symbols, symbols
    page.reload()
    page.wait_for_selector(".status")
    wait_until(lambda: page.locator(".symbol-info").count() > 0,
               what="the symbol tables after the reload")
    assert page.locator("body").get_attribute("data-symbol-info") == "on"
    page.keyboard.press("Alt+i")
    wait_until(lambda: page.locator(".symbol-info").count() == 0, what="the tables gone")
    assert page.locator("body").get_attribute("data-symbol-info") == "off"


def test_a_view_request_without_symbol_info_is_refused(studio):
    """`POST /api/view` needs `symbol_info` true or false: anything else is a coded 400,
    and the drawing options stay as they were."""
    def post(body):
        req = urllib.request.Request(studio.base + "/api/view", data=json.dumps(body).encode(),
                                     method="POST", headers={"X-Gutta-Token": studio.token})
        try:
            with urllib.request.urlopen(req, timeout=10) as answer:
                return answer.status, json.loads(answer.read())
        except urllib.error.HTTPError as refused:
            return refused.code, json.loads(refused.read())

    for bad in [{}, {"symbol_info": "yes"}, {"symbol_info": 1}]:
        status, answer = post(bad)
        assert status == 400, (bad, status, answer)
        assert answer["code"] == "bad-request" and "symbol_info" in answer["message"], answer
    status, answer = post({"symbol_info": False})
    assert status == 200 and answer["symbol_info"] is False
    assert all("symbol-info" not in n["html"] for b in answer["blocks"] for n in b["networks"])
    status, answer = post({"symbol_info": True})
    assert status == 200 and answer["symbol_info"] is True
    assert any("symbol-info-row" in n["html"] for b in answer["blocks"] for n in b["networks"])
