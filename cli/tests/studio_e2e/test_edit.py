"""Editing in the page (docs/studio.md, "Editing", "Keys"): a new network drawn by the
keyboard alone and another by the mouse (NO and NC contacts, a parallel branch, a TON
box with its timer and PT, a coil), saved, and `gutta-cc build` compiles it with only the new networks
changed on disk; undo and redo restore the exact text; a bad operand shows its
diagnostic on the rung and marks the element."""

from conftest import cc, shoot, wait_until

ASKED = "input.operand-editor"


class Editor:
    """The page's operand editor: each ask is a new `input.operand-editor` with a
    higher `data-seq`."""

    def __init__(self, page):
        self.page = page
        self.seen = 0

    def next(self):
        """The next editor to open, focused."""
        page, seen = self.page, self.seen
        page.wait_for_function(
            "seen => { const e = document.activeElement;"
            " return e && e.matches('input.operand-editor') && +e.dataset.seq > seen; }",
            arg=seen)
        self.seen = int(page.evaluate("document.activeElement.dataset.seq"))
        return page.locator(ASKED)

    def type(self, text):
        """Type `text` into the next editor with the keyboard, then Enter."""
        self.next()
        self.page.keyboard.type(text)
        self.page.keyboard.press("Enter")


def text_of(page):
    return page.evaluate(
        "async () => (await window.guttaStudio.api('/api/file?file=src/main.lad')).text()")


def contacts_on(page, operand):
    return page.locator(f'.contact[data-operand="{operand}"]').count()


def settle(page):
    """Wait until no command runs and no editor is open."""
    wait_until(lambda: page.locator(ASKED).count() == 0, what="the editor to close")
    page.wait_for_function("!document.querySelector('.operand-popup')")


def rung(page, number):
    return page.locator(f'g.network[data-network="{number}"]')


def element_paths(page, number):
    return page.evaluate(
        "n => Array.from(document.querySelectorAll("
        "`g.network[data-network=\"${n}\"] [data-path]`)).map(e => e.classList[0]"
        " + ' ' + (e.dataset.kind || e.dataset.mnemonic) + ' '"
        " + (e.dataset.operand || e.dataset.counted || e.querySelector('.title').textContent))",
        number)


def test_draw_by_keyboard_and_by_mouse_save_and_build(page, project):
    main = project / "src" / "main.lad"
    original = main.read_text()
    editor = Editor(page)

    # --- keyboard alone: the last network selected, a new one after it -----------
    for _ in range(3):
        page.keyboard.press("ArrowDown")
    assert page.evaluate("window.guttaStudio.selection().n") == 2
    page.keyboard.press("Insert")
    editor.type("I0.2")
    editor.type("Q0.1")
    wait_until(lambda: rung(page, 4).count() == 1, what="network 4")
    settle(page)
    assert "selected" in rung(page, 4).locator(".contact").first.get_attribute("class")
    page.keyboard.press("Shift+F4")
    editor.type("I0.3")
    wait_until(lambda: rung(page, 4).locator('.contact[data-kind="nc"]').count() == 1,
               what="the NC contact")
    settle(page)
    page.keyboard.press("F7")
    editor.type("I0.4")
    wait_until(lambda: rung(page, 4).locator(".contact").count() == 3, what="the branch")
    settle(page)
    for _ in range(6):
        if rung(page, 4).locator(".coil.selected").count():
            break
        page.keyboard.press("ArrowRight")
    assert rung(page, 4).locator(".coil.selected").count() == 1
    page.keyboard.press("F9")
    editor.type("TON")
    editor.type("T5")
    editor.type("100")
    wait_until(lambda: rung(page, 4).locator('.box[data-mnemonic="TON"]').count() == 1,
               what="the TON box")
    settle(page)
    drawn = element_paths(page, 4)
    assert sorted(drawn) == sorted(["contact no I0.2", "contact nc I0.3", "contact no I0.4",
                                    "coil out Q0.1", "box TON T5"]), drawn
    assert "100" in rung(page, 4).locator(".box").text_content()
    assert page.locator(".diagnostic").count() == 0
    shoot(page, "studio-keyboard")

    # --- by mouse: a network after network 4, commands from the toolbar ----------
    rung(page, 4).locator(".network-title").click()
    page.locator('button[data-command="network-new"]').click()
    editor.next()
    page.keyboard.type("Sta")
    # Completion from the editor analysis: the symbol Start, picked with the mouse.
    page.locator('.operand-popup li[data-label="Start"]').click()
    editor.type("Q1.0")
    wait_until(lambda: rung(page, 5).count() == 1, what="network 5")
    settle(page)
    rung(page, 5).locator(".contact").first.click()
    page.locator('button[data-command="contact-nc"]').click()
    editor.type("I1.1")
    wait_until(lambda: rung(page, 5).locator(".contact").count() == 2, what="the NC contact")
    settle(page)
    rung(page, 5).locator('.contact[data-kind="nc"]').click()
    page.locator('button[data-command="branch"]').click()
    editor.type("I1.2")
    wait_until(lambda: rung(page, 5).locator(".contact").count() == 3, what="the branch")
    settle(page)
    rung(page, 5).locator(".coil").click()
    page.locator('button[data-command="box"]').click()
    editor.type("TON")
    editor.type("T6")
    editor.type("50")
    wait_until(lambda: rung(page, 5).locator('.box[data-mnemonic="TON"]').count() == 1,
               what="the TON box")
    settle(page)
    drawn = element_paths(page, 5)
    assert sorted(drawn) == sorted(["contact no I0.0", "contact nc I1.1", "contact no I1.2",
                                    "coil out Q1.0", "box TON T6"]), drawn
    assert page.locator(".toolbar .dirty").inner_text() != ""
    assert page.title().startswith("* ")
    shoot(page, "studio-mouse")

    # --- save: only the new networks differ, and it builds ------------------------
    assert main.read_text() == original
    page.keyboard.press("Control+s")
    wait_until(lambda: main.read_text() != original, what="the save")
    wait_until(lambda: page.locator(".toolbar .dirty").inner_text() == "", what="clean")
    saved = main.read_text()
    end = original.index("END_ORGANIZATION_BLOCK")
    assert saved.startswith(original[:end])
    assert saved.endswith(original[end:])
    added = saved[end:len(saved) - len(original) + end]
    for line in ["LDN    I0.3", "TON    T5, 100", "LD     Start", "TON    T6, 50"]:
        assert line in added, added
    cc("build", cwd=project)


def test_undo_and_redo_restore_the_exact_text(page, project):
    editor = Editor(page)
    before = text_of(page)
    page.locator('.contact[data-operand="M0.0"]').first.click()
    page.keyboard.press("F4")
    editor.type("I0.5")
    wait_until(lambda: "I0.5" in text_of(page), what="the edit in the buffer")
    settle(page)
    after = text_of(page)
    page.keyboard.press("Control+z")
    wait_until(lambda: text_of(page) == before, what="the undo")
    # The server's buffer changes before the page has the answer and redraws.
    wait_until(lambda: contacts_on(page, "I0.5") == 0, what="the undo drawn")
    page.keyboard.press("Control+y")
    wait_until(lambda: text_of(page) == after, what="the redo")
    wait_until(lambda: contacts_on(page, "I0.5") == 1, what="the redo drawn")
    page.locator('button[data-command="undo"]').click()
    wait_until(lambda: text_of(page) == before, what="the undo by mouse")
    page.locator('button[data-command="redo"]').click()
    wait_until(lambda: text_of(page) == after, what="the redo by mouse")
    # Saved, the file on disk is the buffer; undo back to the start makes it dirty.
    page.locator('button[data-command="save"]').click()
    wait_until(lambda: (project / "src" / "main.lad").read_text() == after, what="the save")
    page.keyboard.press("Control+z")
    wait_until(lambda: page.title().startswith("* "), what="dirty again")


def test_a_bad_operand_shows_its_diagnostic_on_the_rung(page):
    editor = Editor(page)
    coil = page.locator('g.network[data-network="2"] .coil').first
    coil.click()
    page.keyboard.press("Enter")
    editor.next()
    page.keyboard.press("Control+a")
    page.keyboard.type("Q9.9")
    page.keyboard.press("Enter")
    diagnostic = page.locator('g.network[data-network="2"]').locator(
        "xpath=ancestor::div[contains(@class,'network-view')]").locator(".diagnostic[data-code]")
    diagnostic.first.wait_for()
    assert diagnostic.first.get_attribute("data-code").startswith("E")
    assert "bit" in diagnostic.first.inner_text()
    bad = page.locator('g.network[data-network="2"] .coil').first
    assert "error" in bad.get_attribute("class")
    assert page.locator(".status .diagnostics").inner_text() == "1 error"
    # Other networks show nothing.
    assert page.locator(".diagnostic").count() == 1
    shoot(page, "studio-diagnostic")
    # The fix takes the diagnostic away.
    page.locator('g.network[data-network="2"] .coil').first.dblclick()
    editor.next()
    page.keyboard.press("Control+a")
    page.keyboard.type("Q0.0")
    page.keyboard.press("Enter")
    wait_until(lambda: page.locator(".diagnostic").count() == 0, what="no diagnostic")
    assert page.locator(".error").count() == 0
    assert page.locator(".status .diagnostics").inner_text() == "0 errors"


def test_networks_move_retitle_copy_paste_and_delete(page, project):
    editor = Editor(page)

    def titles():
        texts = page.locator("g.network .network-title").all_text_contents()
        return [t.split(": ", 1)[1] if ": " in t else "" for t in texts]

    first = titles()
    page.locator('g.network[data-network="1"] .network-title').click()
    page.keyboard.press("Alt+ArrowDown")
    wait_until(lambda: titles() == [first[1], first[0], first[2]], what="the move")
    page.keyboard.press("F2")
    editor.next()
    page.keyboard.press("Control+a")
    page.keyboard.type("the latch, moved")
    page.keyboard.press("Enter")
    wait_until(lambda: titles()[1] == "the latch, moved", what="the title")
    settle(page)
    page.keyboard.press("Control+c")
    page.keyboard.press("Control+v")
    wait_until(lambda: len(titles()) == 4, what="the paste")
    assert titles() == [first[1], "the latch, moved", "the latch, moved", first[2]]
    page.keyboard.press("Delete")
    wait_until(lambda: len(titles()) == 3, what="the delete")
    assert titles() == [first[1], "the latch, moved", first[2]]
    assert page.evaluate("window.guttaStudio.selection() !== null")
    page.keyboard.press("Control+s")
    wait_until(lambda: "the latch, moved" in (project / "src" / "main.lad").read_text(),
               what="the save")
    cc("build", cwd=project)


def test_a_counter_box_asks_for_its_reset_path(page, project):
    """A box with power inputs beyond the first (a CTU's R) asks a contact for each after
    its operands, by the keyboard alone; saved, the file builds."""
    main = project / "src" / "main.lad"
    editor = Editor(page)
    for _ in range(3):
        page.keyboard.press("ArrowDown")
    page.keyboard.press("Insert")
    editor.type("I0.2")
    editor.type("Q0.1")
    wait_until(lambda: rung(page, 4).count() == 1, what="network 4")
    settle(page)
    for _ in range(6):
        if rung(page, 4).locator(".coil.selected").count():
            break
        page.keyboard.press("ArrowRight")
    assert rung(page, 4).locator(".coil.selected").count() == 1
    page.keyboard.press("F9")
    editor.type("CTU")
    editor.type("C1")
    editor.type("5")
    editor.next()
    label = page.locator(".operand-popup label").inner_text()
    assert label == "CTU R (contact)", label
    page.keyboard.type("I0.5")
    page.keyboard.press("Enter")
    wait_until(lambda: rung(page, 4).locator('.box[data-mnemonic="CTU"]').count() == 1,
               what="the CTU box")
    settle(page)
    drawn = element_paths(page, 4)
    assert "contact no I0.5" in drawn and "box CTU C1" in drawn, drawn
    page.keyboard.press("Control+s")
    wait_until(lambda: "CTU    C1, 5" in main.read_text(), what="the save")
    cc("build", cwd=project)
