"""The page as the studio serves it: the project drawn with `gutta-cc ladder`'s classes,
the toolbar with every command of issue 27, the status bar in EDIT, a clicked element
`selected`, the `window.guttaStudio` API the other scripts use, LAD/STL."""

from conftest import shoot, wait_until

COMMANDS = ["contact-no", "contact-nc", "coil", "coil-set", "coil-reset", "box", "branch",
            "delete", "network-new", "undo", "redo", "save", "view-stl", "simulate", "stop",
            "online", "download", "test"]


def test_the_project_is_drawn_and_a_click_selects(page):
    assert page.locator("g.network").count() >= 3
    assert page.locator(".status").inner_text().startswith("EDIT")
    contact = page.locator('.contact[data-operand="I0.0"]').first
    contact.click()
    assert "selected" in (contact.get_attribute("class") or "")
    # A click elsewhere moves the selection: one element is selected at a time.
    coil = page.locator('.coil[data-operand="Q0.0"]').first
    coil.click()
    assert "selected" in (coil.get_attribute("class") or "")
    assert "selected" not in (contact.get_attribute("class") or "")
    assert page.locator(".contact.selected, .coil.selected, .box.selected").count() == 1
    shoot(page, "studio-page")


def test_every_command_is_a_button_and_the_status_bar_has_its_spans(page):
    for name in COMMANDS:
        assert page.locator(f'button[data-command="{name}"]').count() == 1, name
    for span in ["mode", "run", "where", "updated"]:
        assert page.locator(f".status .{span}").count() == 1, span
    assert page.locator(".status .mode").inner_text() == "EDIT"
    assert page.locator("body").get_attribute("data-mode") == "EDIT"
    # The sidebar lists the project: its file, block, symbols and tests.
    side = page.locator(".sidebar").inner_text()
    for shown in ["src/main.lad", "MAIN", "Running", "Lamp", "tests/main.gtest"]:
        assert shown in side, shown


def test_the_page_script_api(page):
    api = page.evaluate("""async () => {
        const g = window.guttaStudio;
        const names = ['api', 'command', 'run', 'mode', 'setMode', 'status', 'file',
                       'networks', 'onRedraw', 'panel', 'notify', 'reload'];
        const missing = names.filter(n => typeof g[n] !== 'function');
        const project = await (await g.api('/api/project')).json();
        const edit = await g.api('/api/complete?kind=mnemonic&element=box&prefix=TO');
        let called = 0;
        g.command('test', () => { called += 1; });
        await g.run('test');
        g.setMode('SIMULATE');
        g.status({run: 'RUN', where: 'scan 12', updated: Date.now()});
        const shown = document.querySelector('.status').innerText;
        const modeNow = g.mode();
        g.setMode('EDIT');
        g.status({run: '', where: ''});
        const p1 = g.panel('watch', 'Watch'); const p2 = g.panel('watch', 'Watch');
        let redraws = 0;
        g.onRedraw(() => { redraws += 1; });
        await g.reload();
        return {missing, name: project.name, status: edit.status, called, shown, modeNow,
                same: p1 === p2, panels: document.querySelectorAll('.panel').length,
                keys: Array.from(g.networks().keys()), file: g.file(), redraws};
    }""")
    assert api["missing"] == []
    assert api["name"] == "demo"
    assert api["status"] == 200
    assert api["called"] == 1
    assert api["modeNow"] == "SIMULATE"
    assert "RUN" in api["shown"] and "scan 12" in api["shown"] and "SIMULATE" in api["shown"]
    assert api["same"] and api["panels"] == 1
    assert api["keys"] == ["MAIN/1", "MAIN/2", "MAIN/3"]
    assert api["file"] == "src/main.lad"
    assert api["redraws"] == 1
    assert page.locator("g.network").count() == 3


def test_view_stl_toggles_lad_and_stl(page):
    page.locator('button[data-command="view-stl"]').click()
    stl = page.locator(".stl-view").first
    stl.wait_for(state="visible")
    assert "ORGANIZATION_BLOCK MAIN:OB1" in stl.inner_text()
    assert "AN     Stop" in stl.inner_text()
    assert not page.locator("g.network").first.is_visible()
    shoot(page, "studio-stl")
    page.keyboard.press("F3")
    wait_until(lambda: page.locator("g.network").first.is_visible(), what="LAD again")
