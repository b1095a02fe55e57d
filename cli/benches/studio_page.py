"""The studio page bench's browser side (run by cli/benches/studio_page.rs): loads the
page 5 times and times each until interactive, then makes 50 edits through the page
and times each until its answer is drawn, then 50 more as bare requests (the server's
part), then simulates the program and counts the live updates the page paints in 3 s
(the bar: 20 a second). Prints one JSON object."""

import json
import os
import shutil
import sys
import time

from playwright.sync_api import sync_playwright

URL = sys.argv[1]
LOADS = 5
EDITS = 50

EDIT_LOOP = """async (count) => {
    const g = window.guttaStudio;
    // The first NO contact at series[0] of the drawn network nearest the middle.
    const all = Array.from(document.querySelectorAll('.contact[data-kind="no"][data-path]'))
        .filter(e => e.dataset.path.endsWith('.rung.series[0]'));
    const target = all[Math.floor(all.length / 2)];
    const path = target.dataset.path;
    // The network's view stays; its drawing is replaced by each answer.
    const view = target.closest('.network-view');
    const times = [];
    const page = [];
    performance.setResourceTimingBufferSize(10000);
    for (let i = 0; i < count; i++) {
        performance.clearResourceTimings();
        const start = performance.now();
        const update = await g.edit({op: 'set_mnemonic', at: path,
                                     mnemonic: i % 2 === 0 ? 'LDN' : 'LD'});
        if (!update) throw new Error('the edit was refused');
        const drawn = view.querySelector('[data-path="' + path + '"]');
        if (!drawn || drawn.dataset.kind !== (i % 2 === 0 ? 'nc' : 'no')) throw new Error('not redrawn');
        const applied = performance.now();
        await new Promise(r => requestAnimationFrame(() => r()));
        times.push(performance.now() - start);
        const fetched = performance.getEntriesByType('resource').filter(e => e.name.includes('/api/edit'));
        if (fetched.length) page.push(applied - fetched[fetched.length - 1].responseEnd);
    }
    // The server's part alone: the same edits as requests, the answer read as JSON.
    const server = [];
    let bytes = 0;
    for (let i = 0; i < count; i++) {
        const start = performance.now();
        const answer = await g.api('/api/edit', {json: {file: g.file(), edit: {
            op: 'set_mnemonic', at: path, mnemonic: i % 2 === 0 ? 'LDN' : 'LD'}}});
        const text = await answer.text();
        JSON.parse(text);
        server.push(performance.now() - start);
        bytes = text.length;
    }
    return {times, server, bytes, page};
}"""


def until(page, predicate, timeout=60.0):
    """Evaluate `predicate` in the page every 20 ms until it is true."""
    deadline = time.monotonic() + timeout
    while not page.evaluate(predicate):
        if time.monotonic() > deadline:
            sys.exit(f"timed out waiting for {predicate}")
        time.sleep(0.02)


def main():
    executable = os.environ.get("GUTTA_CHROMIUM") or shutil.which("chromium")
    if not executable:
        sys.exit("Debian's chromium is not installed (apt install chromium)")
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=executable, args=["--no-sandbox"])
        context = browser.new_context(viewport={"width": 1400, "height": 900})
        loads = []
        page = None
        for _ in range(LOADS):
            if page:
                page.close()
            page = context.new_page()
            page.goto(URL)
            until(page, "() => window.guttaStudioReady !== undefined")
            loads.append(page.evaluate("window.guttaStudioReady"))
        networks = page.locator("g.network").count()
        size = page.evaluate("document.documentElement.outerHTML.length")
        edits = page.evaluate(EDIT_LOOP, EDITS)
        page.click('[data-command="simulate"]')
        # Polled from here: the page's CSP forbids the eval wait_for_function polls with.
        until(page, "() => document.querySelector('.status .run').textContent === 'RUN'")
        # Power flow shown on the rungs.
        until(page, "() => document.querySelectorAll('.on').length > 0")
        count = "Number(document.body.dataset.liveUpdates)"
        u0, t0 = page.evaluate(count), time.monotonic()
        time.sleep(3.0)
        u1, t1 = page.evaluate(count), time.monotonic()
        live = (u1 - u0) / (t1 - t0)
        browser.close()
    print(json.dumps({"load_ms": loads, "edit_ms": edits["times"], "server_ms": edits["server"],
                      "page_ms": edits["page"], "live_per_s": live,
                      "answer_bytes": edits["bytes"], "networks": networks, "bytes": size}))


main()
