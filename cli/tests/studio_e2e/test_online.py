"""Online against a real gutta-sim (docs/studio.md, "Online"): the demo project's
[connection] pointed at a simulated PLC on a free port; `online` connects (status ONLINE
and the PLC's address), the PLC holds no program so the online panel offers a download;
`download` (confirmed in the panel) sends the studio's program with its progress; Start
forced on the PLC shows power flow (`.on`) from the PLC; `stop` puts it in STOP: the
status shows STOP and nothing is `on`."""

import re
import subprocess

import pytest

from conftest import SIM, cc, shoot, wait_until


@pytest.fixture
def plc(project):
    """A gutta-sim of the project's PLC type on a free port, gutta.toml pointed at it:
    its address."""
    manifest = project / "gutta.toml"
    text = manifest.read_text()
    plc_type = re.search(r'^plc = "([^"]+)"', text, re.M).group(1)
    sim = subprocess.Popen([SIM, "--plc", plc_type, "--tcp", "127.0.0.1:0"],
                           stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                           stderr=subprocess.DEVNULL, text=True)
    address = sim.stdout.readline().strip().rsplit(" ", 1)[-1]
    assert re.match(r"^127\.0\.0\.1:\d+$", address), address
    manifest.write_text(text.replace("127.0.0.1:5020", address))
    yield address
    sim.kill()
    sim.wait()


def status(page, part):
    return page.locator(f".status .{part}").inner_text()


def test_online_download_power_flow_and_stop(plc, project, page):
    panel = page.locator('.panel[data-panel="online"]')
    page.click('button[data-command="online"]')
    wait_until(lambda: status(page, "mode") == "ONLINE", what="ONLINE")
    assert page.locator("body").get_attribute("data-mode") == "ONLINE"
    wait_until(lambda: status(page, "where") == plc, what="the PLC address")
    # A fresh simulator holds no program: said, with a Download button.
    offer = panel.locator(".online-offer .offer-download")
    offer.wait_for()
    assert "holds no program" in panel.locator(".online-offer").inner_text()
    shoot(page, "studio-online-offer")

    offer.click()
    panel.locator(".confirm-download").click()
    result = panel.locator(".download-result")
    result.wait_for(timeout=30000)
    assert re.match(r"downloaded \d+ pages \(\d+ bytes\) in [0-9.]+ s: the PLC runs",
                    result.inner_text()), result.inner_text()
    assert panel.locator("progress.download-progress").get_attribute("value") is not None
    wait_until(lambda: panel.locator(".online-state").get_attribute("data-program") == "same",
               what="program same")
    wait_until(lambda: panel.locator(".online-offer").is_hidden(), what="no offer")
    wait_until(lambda: status(page, "run") == "RUN", what="RUN")
    assert status(page, "updated") != ""

    # Start pressed on the PLC (forced, as `gutta-cc force` does): Running latches and
    # the page shows the power flow the PLC reports.
    cc("force", "I0.0=1", cwd=project)
    wait_until(lambda: page.locator('.coil.on[data-operand="M0.0"]').count() > 0,
               what="the Running coil on")
    assert page.locator('.contact.on[data-operand="I0.0"]').count() > 0
    shoot(page, "studio-online")

    page.click('button[data-command="stop"]')
    wait_until(lambda: status(page, "run") == "STOP", what="STOP")
    wait_until(lambda: page.locator(".network .on").count() == 0, what="no power flow")
    assert status(page, "mode") == "ONLINE"
    wait_until(lambda: panel.locator(".online-state").get_attribute("data-run") == "STOP",
               what="the online panel's STOP")
    shoot(page, "studio-online-stop")
    # The PLC is in STOP indeed.
    assert ": STOP" in cc("status", cwd=project).stdout
