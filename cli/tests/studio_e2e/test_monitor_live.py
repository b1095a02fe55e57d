"""`gutta-cc monitor` in Chromium against a real gutta-sim (docs/ladder.md, "Live view"):
the status bar says RUN and the PLC; a contact off the power path shows its bit
(`data-value="1"` without `on`); a network shown as STL shows per-line logic results
(`data-rlo`); RUN -> STOP shows `STOP` and no power flow within 1 s; downloading another
program shows the mismatch message; downloading the right one brings the values back
within 5 s without restarting the monitor. Its screenshots go to docs/images/monitor
when the driver updates the docs' screenshots."""

import re
import subprocess
import time

import pytest

from conftest import CC, SHOTS, SIM, cc, wait_until

PROGRAM = """PLC_TYPE CPU-EC20

SYMBOLS
  Start : I0.0
  Enable : I0.1
  Lamp : Q0.0
END_SYMBOLS

ORGANIZATION_BLOCK MAIN:OB1
BEGIN
NETWORK 1 // the lamp
LD     Start
A      Enable
=      Lamp
NETWORK 2 // a level
LD     SM0.0
MOVW   +1234, MW10
NETWORK 3 // two rungs in one network: shown as STL
LD     I0.2
AN     I0.3
=      Q0.2
LDW>=  MW10, 1000
=      Q0.3
END_ORGANIZATION_BLOCK
"""

OTHER = """PLC_TYPE CPU-EC20

ORGANIZATION_BLOCK MAIN:OB1
BEGIN
NETWORK 1
LD     I0.0
=      Q0.1
END_ORGANIZATION_BLOCK
"""


def shoot_monitor(page, name):
    """A screenshot `name`.png beside the studio's: docs/images/monitor when the driver
    updates the docs' screenshots (SHOTS is docs/images/studio then)."""
    folder = SHOTS.parent / "monitor" if SHOTS.name == "studio" else SHOTS / "monitor"
    folder.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(folder / f"{name}.png"), full_page=True)


@pytest.fixture
def images(tmp_path):
    """The program's source, and the image directories of it and of another program."""
    source = tmp_path / "lamp.lad"
    source.write_text(PROGRAM)
    cc(str(source), "-o", str(tmp_path / "right"))
    other = tmp_path / "other.lad"
    other.write_text(OTHER)
    cc(str(other), "-o", str(tmp_path / "other"))
    return source, tmp_path / "right", tmp_path / "other"


@pytest.fixture
def plc():
    """An empty gutta-sim (CPU-EC20) on a free port: its address."""
    sim = subprocess.Popen([SIM, "--plc", "CPU-EC20", "--tcp", "127.0.0.1:0"],
                           stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                           stderr=subprocess.DEVNULL, text=True)
    address = sim.stdout.readline().strip().rsplit(" ", 1)[-1]
    assert re.match(r"^127\.0\.0\.1:\d+$", address), address
    yield address
    sim.kill()
    sim.wait()


@pytest.fixture
def monitor(images, plc):
    """`gutta-cc monitor` on the program, the right image downloaded first: its URL.
    Ended with Ctrl-C, which it must obey with a page still open."""
    source, right, _ = images
    cc("download", str(right), "--tcp", plc)
    process = subprocess.Popen([CC, "monitor", source.name, "--tcp", plc,
                                "--http", "127.0.0.1:0"], cwd=source.parent,
                               stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                               stderr=subprocess.PIPE, text=True)
    line = process.stderr.readline()
    match = re.search(r"(http://[0-9.:]+)/", line)
    assert match, line
    yield match.group(1)
    process.send_signal(subprocess.signal.SIGINT)
    try:
        assert process.wait(timeout=10) == 0
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait()
        raise AssertionError("gutta-cc monitor did not end on SIGINT")


@pytest.fixture
def live(browser, monitor):
    """A browser page on the monitor, its status bar drawn; console errors fail."""
    context = browser.new_context(viewport={"width": 1100, "height": 800})
    pg = context.new_page()
    errors = []
    pg.on("pageerror", lambda e: errors.append(str(e)))
    pg.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    pg.goto(monitor)
    pg.wait_for_selector(".status")
    yield pg
    context.close()
    assert not errors, f"the page reported errors: {errors}"


def status(page):
    return page.locator(".status").inner_text()


def test_monitor_live_view(images, plc, live):
    page = live
    _, right, other = images
    # Enable on, Start off: Enable's contact is off the power path but shows its bit.
    cc("write", "I0.1=1", "I0.2=1", "--tcp", plc)
    enable = page.locator('g.contact[data-operand="I0.1"]')
    wait_until(lambda: enable.get_attribute("data-value") == "1", what="Enable's bit")
    assert "on" not in (enable.get_attribute("class") or "").split()
    assert page.locator('g.contact[data-operand="I0.0"]').get_attribute("data-value") == "0"
    assert "RUN" in status(page) and plc in status(page), status(page)
    assert "connected" in status(page)
    # The STL network: LD I0.2 (1), AN I0.3 (1), = Q0.2, LDW>= MW10, 1000 (1), = Q0.3.
    stl = page.locator('g.network[data-network="3"] .stl-line')
    wait_until(lambda: stl.nth(0).get_attribute("data-rlo") == "1", what="the STL RLO")
    rlos = [stl.nth(i).get_attribute("data-rlo") for i in range(stl.count())]
    assert rlos == ["1", "1", "1", "1", "1"], rlos
    assert "MW10 = 1234" in stl.nth(3).text_content()
    # Start on: power flows through both contacts to the lamp.
    cc("write", "I0.0=1", "--tcp", plc)
    wait_until(lambda: page.locator('g.coil.on[data-operand="Q0.0"]').count() == 1,
               what="the lamp powered")
    shoot_monitor(page, "monitor-run")
    # Start off again: the lamp goes out, Start's contact is neither on nor 1.
    cc("write", "I0.0=0", "--tcp", plc)
    start = page.locator('g.contact[data-operand="I0.0"]')
    wait_until(lambda: page.locator('g.coil.on[data-operand="Q0.0"]').count() == 0
               and start.get_attribute("data-value") == "0", what="the lamp out")
    assert "on" not in (start.get_attribute("class") or "").split()
    cc("write", "I0.0=1", "--tcp", plc)

    # RUN -> STOP: STOP and no power flow within 1 s (the values stay).
    cc("stop", "--tcp", plc)
    stopped = time.monotonic()
    wait_until(lambda: "STOP" in status(page) and page.locator(".on").count() == 0,
               timeout=1.0, what="STOP without power flow within 1 s")
    assert time.monotonic() - stopped < 1.0
    assert enable.get_attribute("data-value") == "1"
    wait_until(lambda: page.locator(".stl-line[data-rlo]").count() == 0,
               what="no RLO shown in STOP")
    shoot_monitor(page, "monitor-stop")

    # Another program: the mismatch, and nothing on.
    cc("download", str(other), "--tcp", plc)
    wait_until(lambda: "another program" in page.locator("#status").inner_text(),
               timeout=10.0, what="the mismatch message")
    wait_until(lambda: page.locator(".on").count() == 0
               and page.locator("g.network.stale").count() > 0,
               what="nothing on and the networks stale")
    # The download leaves the PLC running the other program: the bar still says so.
    wait_until(lambda: page.locator(".status .state").inner_text() == "RUN",
               what="RUN while the program differs")
    shoot_monitor(page, "monitor-mismatch")

    # The right program again: values within 5 s, the monitor not restarted.
    cc("download", str(right), "--tcp", plc)
    back = time.monotonic()
    cc("write", "I0.1=1", "--tcp", plc)
    wait_until(lambda: enable.get_attribute("data-value") == "1"
               and "RUN" in status(page) and "stale" not in status(page),
               timeout=5.0, what="values again")
    assert time.monotonic() - back < 5.0
    assert page.locator("#status").inner_text() == ""


# ---- the studio's live view: the same bits and STL status (SIMULATE) ----------------

STL_NETWORK = """Network 4 // two rungs in one network: shown as STL
LD     Stop
=      Q0.2
LDN    Running
=      Q0.3
END_ORGANIZATION_BLOCK
"""


@pytest.fixture
def project(tmp_path):
    """The demo project with a fourth network the studio shows as STL."""
    cc("new", "demo", cwd=tmp_path)
    root = tmp_path / "demo"
    main = root / "src" / "main.lad"
    text = main.read_text()
    assert text.count("END_ORGANIZATION_BLOCK") == 1
    main.write_text(text.replace("END_ORGANIZATION_BLOCK\n", STL_NETWORK))
    return root


def test_studio_simulate_shows_bits_and_stl_status(page):
    page.click('[data-command="simulate"]')
    wait_until(lambda: page.locator(".status .run").inner_text().strip() == "RUN",
               what="RUN in the status bar")
    stop = page.locator('.contact[data-operand="I0.1"]').first
    wait_until(lambda: stop.get_attribute("data-value") == "0", what="Stop's bit")
    lines = page.locator('g.network[data-network="4"] .stl-line')
    wait_until(lambda: lines.count() == 4 and lines.nth(0).get_attribute("data-rlo") == "0",
               what="the STL lines' RLO")
    # LD Stop (0), = Q0.2, LDN Running (1: not running), = Q0.3.
    assert [lines.nth(i).get_attribute("data-rlo") for i in range(4)] == ["0", "0", "1", "1"]
    # Stop pressed (a click forces it): its contact shows 1 but passes no power (AN).
    stop.click()
    wait_until(lambda: stop.get_attribute("data-value") == "1", what="Stop's bit 1")
    assert "on" not in (stop.get_attribute("class") or "").split()
    wait_until(lambda: lines.nth(0).get_attribute("data-rlo") == "1", what="LD Stop's RLO 1")
    # STOP: STOP in the status, nothing on, no RLO; the bits stay.
    page.click('[data-command="stop"]')
    wait_until(lambda: "STOP" in page.locator(".status").inner_text(), what="STOP")
    wait_until(lambda: page.locator(".network .on").count() == 0
               and page.locator(".stl-line[data-rlo]").count() == 0,
               what="no power flow and no RLO in STOP")
    assert stop.get_attribute("data-value") == "1"
