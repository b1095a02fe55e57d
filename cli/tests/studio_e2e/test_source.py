"""STL and symbols in the page (docs/studio.md, "STL and symbols"): `view-stl` shows each
block's STL in an editable `textarea.stl-editor`; a bad operand applied with Ctrl-Enter is
listed under it with its line and code; fixed and applied by leaving it, back in LAD the
rung is drawn with the new operand; a network made not one rung is shown with its
reason and edited as STL in place; completion on Ctrl-Space; a symbol renamed in the
symbol table changes the drawings' operands and the file's text, and one added shows."""

from conftest import cc, shoot, wait_until

STL = "pre.stl-view.stl-editor"
NETWORK_STL = "textarea.stl-editor[data-n]"


def text_of(page):
    return page.evaluate(
        "async () => (await window.guttaStudio.api('/api/file?file=src/main.lad')).text()")


def buffer_of(page):
    return page.evaluate(
        "async () => (await (await window.guttaStudio.api('/api/stl/block?block=0')).json()).text")


def stl_text(area):
    return area.evaluate("a => a.innerText")


def symbols(page):
    """The symbols the drawings show above their operands' addresses."""
    return page.evaluate(
        "Array.from(document.querySelectorAll('g.network .operand .symbol'))"
        ".map(e => e.textContent)")


def test_a_network_edited_as_stl_shows_its_diagnostics_and_is_drawn_back_in_lad(page, project):
    page.click('button[data-command="view-stl"]')
    area = page.locator(STL).first
    area.wait_for(state="visible")
    wait_until(lambda: "Network 2" in stl_text(area), what="the block's STL in the editor")
    assert page.locator("g.network").first.is_hidden()
    original = stl_text(area)
    assert "=      Lamp" in original

    # A bad operand: applied with Ctrl-Enter, listed under the text with its line.
    area.fill(original.replace("=      Lamp", "=      Q99.7"))
    area.press("Control+Enter")
    diagnostic = page.locator(".stl-diagnostic.error").first
    diagnostic.wait_for()
    line = int(diagnostic.get_attribute("data-line"))
    assert "Q99.7" in stl_text(area).split("\n")[line - 1]
    assert diagnostic.get_attribute("data-code").startswith("E")
    assert "Q99.7" in buffer_of(page)
    shoot(page, "stl-diagnostics")

    # Fixed, applied by leaving the editor: no error left.
    area.fill(original.replace("=      Lamp", "=      Q0.7"))
    page.locator("section.block h2").first.click()
    wait_until(lambda: page.locator(".stl-diagnostic.error").count() == 0,
               what="the error to go")
    assert "=      Q0.7" in buffer_of(page)


    # Back to LAD: the rung drawn with the new operand.
    page.click('button[data-command="view-stl"]')
    page.locator('g.network [data-operand="Q0.7"]').first.wait_for()
    assert page.locator(STL).first.is_hidden()

    # A network that is not one rung: shown with its reason, edited as STL in place.
    page.click('button[data-command="view-stl"]')
    area.wait_for(state="visible")
    wait_until(lambda: "Q0.7" in stl_text(area), what="the STL again")
    area.fill(stl_text(area).replace("INCW   Blinks\n", "INCW   Blinks\nLD     I0.5\n=      Q0.5\n"))
    area.press("Control+Enter")
    wait_until(lambda: "Q0.5" in buffer_of(page), what="the STL applied")
    page.click('button[data-command="view-stl"]')
    odd = page.locator(".network-view:has(g.network[data-reason])").first
    odd.wait_for()
    odd.dblclick()
    network = page.locator(NETWORK_STL)
    network.wait_for()
    wait_until(lambda: "Q0.5" in network.input_value(), what="the network's STL")
    assert network.input_value().startswith("Network 3")
    # Completion on Ctrl-Space: the symbols of the program.
    at = network.input_value().index("INCW   Blinks") + len("INCW   Bl")
    network.evaluate("(a, at) => a.setSelectionRange(at, at)", at)
    network.press("Control+Space")
    page.locator(".stl-completion li").first.wait_for()
    labels = page.locator(".stl-completion li").all_inner_texts()
    assert any(label.startswith("Blinks") for label in labels), labels
    shoot(page, "stl-edit")
    network.press("Escape")
    wait_until(lambda: page.locator(".stl-completion").count() == 0,
               what="the completion closed")
    network.fill(network.input_value().replace("LD     I0.5\n=      Q0.5\n", ""))
    network.press("Control+Enter")
    wait_until(lambda: page.locator("g.network[data-reason]").count() == 0,
               what="the network drawn as a rung again")
    assert page.locator('g.network[data-network="3"] .box[data-mnemonic="INCW"]').count() == 1

    # Saved, it builds; undo takes back the last STL step exactly.
    before = buffer_of(page)
    page.click('button[data-command="save"]')
    wait_until(lambda: before in (project / "src/main.lad").read_text(), what="the file saved")
    assert text_of(page) == (project / "src/main.lad").read_text()
    cc("build", cwd=project)
    page.click('button[data-command="undo"]')
    wait_until(lambda: "Q0.5" in buffer_of(page), what="the undo")


def test_a_symbol_renamed_in_the_table_changes_the_drawings(page, project):
    page.click(".sidebar table.symbols")
    rows = page.locator(".symbols-panel tr.symbol")
    rows.first.wait_for()
    start = page.locator('.symbols-panel tr.symbol[data-name="Start"]')
    assert start.get_attribute("data-declared") == "table"
    assert "Start" in symbols(page)

    name = start.locator("input.symbol-name")
    name.fill("StartButton")
    name.press("Enter")
    wait_until(lambda: "StartButton" in symbols(page), what="the drawings renamed")
    assert "Start" not in symbols(page)
    assert "LD     StartButton" in buffer_of(page)
    page.locator(".symbols-panel .tables .dirty").wait_for()
    page.locator('.symbols-panel tr.symbol[data-name="StartButton"]').wait_for()
    page.locator(".symbols-panel:not([data-loading])").wait_for()

    # An address changed where it is declared (the file's SYMBOLS block).
    running = page.locator('.symbols-panel tr.symbol[data-name="Running"] input.symbol-address')
    running.fill("M0.3")
    running.press("Enter")
    wait_until(lambda: "Running : M0.3" in text_of(page), what="the address changed")
    page.locator(".symbols-panel:not([data-loading])").wait_for()

    # Added through the form.
    form = page.locator(".symbols-panel form.symbol-add")
    form.locator('input[name="name"]').fill("Horn")
    form.locator('input[name="address"]').fill("Q0.5")
    form.locator('input[name="comment"]').fill("sounds")
    form.locator('button[data-op="add"]').click()
    page.locator('.symbols-panel tr.symbol[data-name="Horn"]').wait_for()
    shoot(page, "symbols")

    # Saving writes the program and the table; the project builds.
    page.click('button[data-command="save"]')
    wait_until(lambda: "StartButton,I0.0" in (project / "symbols.csv").read_text(),
               what="the table saved")
    assert "Horn,Q0.5,sounds" in (project / "symbols.csv").read_text()
    cc("build", cwd=project)
