"""The studio page bench's browser side (run by cli/benches/studio_page.rs): loads the
page 5 times and times each until interactive, then makes 50 edits through the page
and times each until its answer is drawn. Prints one JSON object."""

import json
import os
import shutil
import sys

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
    const times = [];
    for (let i = 0; i < count; i++) {
        const start = performance.now();
        const update = await g.edit({op: 'set_mnemonic', at: path,
                                     mnemonic: i % 2 === 0 ? 'LDN' : 'LD'});
        if (!update) throw new Error('the edit was refused');
        if (!document.querySelector('[data-path="' + path + '"]')) throw new Error('not redrawn');
        await new Promise(r => requestAnimationFrame(() => r()));
        times.push(performance.now() - start);
    }
    return times;
}"""


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
            page.wait_for_function("window.guttaStudioReady !== undefined")
            loads.append(page.evaluate("window.guttaStudioReady"))
        networks = page.locator("g.network").count()
        size = page.evaluate("document.documentElement.outerHTML.length")
        edits = page.evaluate(EDIT_LOOP, EDITS)
        browser.close()
    print(json.dumps({"load_ms": loads, "edit_ms": edits, "networks": networks, "bytes": size}))


main()
