"""Fixtures of the studio's browser suite (run by cli/tests/studio_browser.rs).

Environment, set by the Rust driver:
  GUTTA_CC           the gutta-cc binary under test
  GUTTA_SIM          the gutta-sim binary (the online tests' PLC)
  GUTTA_SCREENSHOTS  where `shoot` writes its PNGs
Chromium is Debian's (`chromium` on PATH, or GUTTA_CHROMIUM), never Playwright's own.
"""

import os
import re
import shutil
import signal
import subprocess
import time
from pathlib import Path

import pytest
from playwright.sync_api import sync_playwright

CC = os.environ.get("GUTTA_CC", "gutta-cc")
SIM = os.environ.get("GUTTA_SIM", "gutta-sim")
SHOTS = Path(os.environ.get("GUTTA_SCREENSHOTS", "target/studio-screenshots"))
FIRST_LINE = re.compile(r"^gutta-cc studio: http://([0-9.]+):([0-9]+)/\?token=([0-9a-f]+)$")


def cc(*args, cwd=None, check=True):
    """gutta-cc ARGS, its CompletedProcess (text); fails the test on a non-zero exit."""
    done = subprocess.run([CC, *args], cwd=cwd, capture_output=True, text=True, timeout=120)
    if check and done.returncode != 0:
        raise AssertionError(f"gutta-cc {' '.join(args)}: exit {done.returncode}\n"
                             f"{done.stdout}\n{done.stderr}")
    return done


class Studio:
    """A running `gutta-cc studio --no-open`: its address, token and process."""

    def __init__(self, args, cwd):
        self.process = subprocess.Popen(
            [CC, "studio", *args, "--no-open"], cwd=cwd,
            stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
            text=True)
        line = self.process.stdout.readline().rstrip("\n")
        match = FIRST_LINE.match(line)
        if not match:
            self.process.kill()
            raise AssertionError(f"first line {line!r}; stderr: {self.process.stderr.read()}")
        self.host, self.port, self.token = match.group(1), int(match.group(2)), match.group(3)
        self.base = f"http://{self.host}:{self.port}"
        self.url = f"{self.base}/?token={self.token}"

    def stop(self):
        """Ctrl-C: the studio exits 0."""
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGINT)
            try:
                return self.process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
                raise AssertionError("gutta-cc studio did not end on SIGINT")
        return self.process.returncode


@pytest.fixture
def project(tmp_path):
    """A fresh `gutta-cc new demo` project (src/main.lad, symbols.csv, tests/main.gtest)."""
    cc("new", "demo", cwd=tmp_path)
    return tmp_path / "demo"


@pytest.fixture
def studio(project):
    """The studio on `project`, stopped with Ctrl-C (exit 0) after the test."""
    s = Studio([str(project)], cwd=project)
    yield s
    assert s.stop() == 0


@pytest.fixture(scope="session")
def browser():
    executable = os.environ.get("GUTTA_CHROMIUM") or shutil.which("chromium")
    assert executable, "Debian's chromium is not installed (apt install chromium)"
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=executable, args=["--no-sandbox"])
        yield b
        b.close()


@pytest.fixture
def page(browser, studio):
    """A fresh browser page on the studio, its status bar drawn. Console errors fail the
    test."""
    context = browser.new_context(viewport={"width": 1400, "height": 900})
    pg = context.new_page()
    errors = []
    pg.on("pageerror", lambda e: errors.append(str(e)))
    pg.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    pg.goto(studio.url)
    pg.wait_for_selector(".status")
    yield pg
    context.close()
    assert not errors, f"the page reported errors: {errors}"


def shoot(page, name):
    """A screenshot `name`.png into GUTTA_SCREENSHOTS (docs/images/studio when the driver
    updates the docs' screenshots)."""
    SHOTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(SHOTS / f"{name}.png"))


def wait_until(condition, timeout=10.0, what="the condition"):
    """Poll `condition` every 20 ms until it is truthy (its value) or fail after
    `timeout` seconds."""
    deadline = time.monotonic() + timeout
    while True:
        value = condition()
        if value:
            return value
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out waiting for {what}")
        time.sleep(0.02)
