"""Simulate in the studio (docs/studio.md, "Simulate"): the demo project (with a TON
network added before the studio starts) runs on the VM inside gutta-cc; the status bar
shows SIMULATE, RUN and a rising scan count; a click on Start (I0.0) latches Running
(its coil gets class `on`); the TON's current value counts in real time; the page keeps
updating (the 20-a-second bar is the studio_page bench's); the watch table reads, writes and forces; STOP empties the
power flow; edit goes back to EDIT."""

import time
from pathlib import Path

import pytest

from conftest import CC, Studio, cc, shoot, wait_until

TON = """Network 4 // T4 counts while Running (100 ms steps)
LD     Running
TON    T4, 600
END_ORGANIZATION_BLOCK
"""


@pytest.fixture
def project(tmp_path):
    """The demo project, its MAIN with a fourth network: a TON that counts while
    Running."""
    cc("new", "demo", cwd=tmp_path)
    root = tmp_path / "demo"
    main = root / "src" / "main.lad"
    text = main.read_text()
    assert text.count("END_ORGANIZATION_BLOCK") == 1
    main.write_text(text.replace("END_ORGANIZATION_BLOCK\n", TON))
    cc("build", cwd=root)
    return root


def status(page, part):
    return page.locator(f".status .{part}").inner_text().strip()


def scans(page):
    where = status(page, "where")
    return int(where.split()[1]) if where.startswith("scan ") else -1


def timer_value(page):
    """The TON box's current value as the page shows it beside its number above the box
    (`T4 = 12`)."""
    shown = page.evaluate(
        """() => {
          const box = document.querySelector('.box[data-mnemonic="TON"]');
          const value = box && box.querySelector('.operand.counted tspan.value');
          return value ? value.textContent : '';
        }""")
    return int(shown.replace("=", "").strip()) if shown.strip() else -1


def energized(page):
    return page.locator(".network .on").count()


def test_simulate_toggle_start_see_running_on_and_the_timer_count(page):
    page.click('[data-command="simulate"]')
    wait_until(lambda: status(page, "mode") == "SIMULATE", what="SIMULATE in the status bar")
    wait_until(lambda: status(page, "run") == "RUN", what="RUN in the status bar")
    first = wait_until(lambda: scans(page) > 0 and scans(page), what="a scan count")
    wait_until(lambda: scans(page) > first + 20, what="the scan count rising")
    assert page.locator("body").get_attribute("data-mode") == "SIMULATE"
    running = page.locator('.coil[data-operand="M0.0"]').first
    assert "on" not in (running.get_attribute("class") or "").split()

    # A click on Start presses it: Running latches and its coil is energized.
    page.locator('.contact[data-operand="I0.0"]').first.click()
    wait_until(lambda: "on" in (running.get_attribute("class") or "").split(),
               what="the Running coil energized")
    start = page.locator('.contact[data-operand="I0.0"]').first
    assert "forced" in (start.get_attribute("class") or "").split()
    # A second click lets it go: Running holds.
    start.click()
    wait_until(lambda: "forced" not in (start.get_attribute("class") or "").split(),
               what="Start released")
    time.sleep(0.2)
    assert "on" in (running.get_attribute("class") or "").split()

    # The timer counts in real time (100 ms steps).
    wait_until(lambda: timer_value(page) >= 0, what="the TON's value beside it")
    t0, v0 = time.monotonic(), timer_value(page)
    time.sleep(1.5)
    t1, v1 = time.monotonic(), timer_value(page)
    counted_ms, wall_ms = (v1 - v0) * 100, (t1 - t0) * 1000
    assert abs(counted_ms - wall_ms) < 400, f"T4 counted {counted_ms} ms in {wall_ms:.0f} ms"
    shoot(page, "studio-simulate")

    # The page keeps updating (the rate's bar, 20 a second, is the studio_page bench's:
    # a test does not time the machine).
    u0 = int(page.locator("body").get_attribute("data-live-updates"))
    wait_until(lambda: int(page.locator("body").get_attribute("data-live-updates")) >= u0 + 5,
               what="five more live updates")

    # STOP: no power flow shown, the scan count stands.
    page.click('[data-command="stop"]')
    wait_until(lambda: status(page, "run") == "STOP", what="STOP in the status bar")
    wait_until(lambda: energized(page) == 0, what="no element energized")
    stopped = scans(page)
    time.sleep(0.3)
    assert scans(page) == stopped
    assert energized(page) == 0
    shoot(page, "studio-stop")

    # simulate in STOP: RUN again, the same program.
    page.click('[data-command="simulate"]')
    wait_until(lambda: status(page, "run") == "RUN", what="RUN again")
    wait_until(lambda: scans(page) > stopped, what="scanning again")
    wait_until(lambda: "on" in (running.get_attribute("class") or "").split(),
               what="Running still latched")

    # edit: back to EDIT, nothing painted.
    page.click('[data-command="edit"]')
    wait_until(lambda: status(page, "mode") == "EDIT", what="EDIT")
    wait_until(lambda: energized(page) == 0, what="no power flow in EDIT")


def test_the_watch_table_reads_writes_and_forces(page):
    page.click('[data-command="simulate"]')
    wait_until(lambda: status(page, "run") == "RUN", what="RUN")
    panel = page.locator(".watch")
    panel.locator(".watch-operand").fill("Blinks")
    panel.locator(".watch-format").select_option("hex")
    panel.locator(".watch-add button").click()
    row = panel.locator('div.watch-row[data-operand="Blinks"]')
    wait_until(lambda: row.locator(".watch-address").inner_text() == "MW10", what="Blinks read")
    assert row.locator(".watch-value").inner_text() == "16#0000"
    row.locator(".watch-new").fill("16#0A0B")
    row.locator('[data-watch="write"]').click()
    wait_until(lambda: row.locator(".watch-value").inner_text() == "16#0A0B", what="Blinks written")

    panel.locator(".watch-operand").fill("Lamp")
    panel.locator(".watch-format").select_option("")
    panel.locator(".watch-add button").click()
    lamp = panel.locator('div.watch-row[data-operand="Lamp"]')
    lamp.locator(".watch-new").fill("1")
    lamp.locator('[data-watch="force"]').click()
    wait_until(lambda: "forced" in (lamp.get_attribute("class") or "").split(), what="Lamp forced")
    assert lamp.locator(".watch-value").inner_text() == "1"
    coil = page.locator('.coil[data-operand="Q0.0"]').first
    wait_until(lambda: "forced" in (coil.get_attribute("class") or "").split(),
               what="the Lamp coil marked forced")
    shoot(page, "studio-watch")
    lamp.locator('[data-watch="release"]').click()
    wait_until(lambda: "forced" not in (lamp.get_attribute("class") or "").split(),
               what="Lamp released")

    # A name that is not a variable: the row says why (the read answers per row).
    panel.locator(".watch-operand").fill("Nowhere")
    panel.locator(".watch-add button").click()
    bad = panel.locator('div.watch-row[data-operand="Nowhere"]')
    wait_until(lambda: "[no-operand]" in bad.locator(".watch-value").inner_text(),
               what="the row's coded error")


def big_program(networks):
    """MAIN with `networks` networks: latches of inputs into M bits, every tenth a TON."""
    lines = ["ORGANIZATION_BLOCK MAIN:OB1", "BEGIN"]
    for n in range(1, networks + 1):
        bit = f"M{(n // 8) % 32}.{n % 8}"
        if n % 10 == 0:
            lines += [f"Network {n} // a timer", f"LD     {bit}", f"TON    T{4 + n % 12}, 50"]
        else:
            lines += [f"Network {n} // a latch", f"LD     I0.{n % 8}", f"O      {bit}",
                      f"AN     I1.{n % 8}", f"=      {bit}"]
    lines.append("END_ORGANIZATION_BLOCK")
    return "\n".join(lines) + "\n"


@pytest.fixture
def big_project(tmp_path):
    """A project of 1,000 networks on the front end's bench target (program limits a
    1,000-network program fits in)."""
    root = tmp_path / "big"
    (root / "src").mkdir(parents=True)
    target = Path(__file__).resolve().parents[3] / "compiler" / "benches" / "target"
    (root / "gutta.toml").write_text(
        f'[program]\nname = "big"\ntarget = "{target}"\nsources = ["src/main.lad"]\n')
    (root / "src" / "main.lad").write_text(big_program(1000))
    cc("build", cwd=root)
    return root


def test_a_thousand_networks_stay_live(browser, big_project):
    """A 1,000-network program simulates and its power flow keeps updating in the page;
    it prints the rate it got, with the last fetch and paint times. The bar (20 updates a
    second) is measured by the studio_page bench on a release build; a test does not time
    the machine."""
    s = Studio([str(big_project)], cwd=big_project)
    context = browser.new_context(viewport={"width": 1400, "height": 900})
    try:
        page = context.new_page()
        page.goto(s.url)
        page.wait_for_selector(".status")
        assert page.locator("g.network").count() >= 1000
        page.click('[data-command="simulate"]')
        wait_until(lambda: status(page, "run") == "RUN", what="RUN", timeout=30)
        page.locator('.contact[data-operand="I0.1"]').first.click()
        wait_until(lambda: energized(page) > 100, what="power flow on the latches", timeout=30)
        u0, s0 = int(page.locator("body").get_attribute("data-live-updates")), time.monotonic()
        time.sleep(3.0)
        u1, s1 = int(page.locator("body").get_attribute("data-live-updates")), time.monotonic()
        rate = (u1 - u0) / (s1 - s0)
        fetch_ms = page.locator("body").get_attribute("data-live-fetch-ms")
        paint_ms = page.locator("body").get_attribute("data-live-paint-ms")
        print(f"studio simulate: {rate:.1f} updates/s in Chromium on 1,000 networks "
              f"(last fetch {fetch_ms} ms, paint {paint_ms} ms; {CC})")
        assert u1 > u0, "no live update in 3 s on 1,000 networks"
    finally:
        context.close()
        assert s.stop() == 0
