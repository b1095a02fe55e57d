"""The `test` command: the project's .gtest files run on the session's current program
(docs/studio.md, "Tests"): the demo's two tests pass; an edit not saved (Lamp moved to
Q0.1) fails the blink test, shown with its line and detail; the disk never changes."""

from conftest import cc, shoot

LAMP_ELSEWHERE = {
    "op": "set_operands",
    "at": "blocks[0].networks[1].rung.series[2]",
    "operands": ["Q0.1"],
}


def test_the_demo_tests_pass_then_an_unsaved_edit_fails_one(page, project):
    panel = page.locator('.panel[data-panel="tests"]')
    page.click('button[data-command="test"]')
    page.wait_for_selector('.panel[data-panel="tests"] .tests-summary.passed')
    assert panel.locator(".tests-summary").inner_text() == "2 passed, 0 failed"
    passed = panel.locator('.test[data-status="passed"]')
    assert passed.count() == 2
    assert [passed.nth(i).get_attribute("data-test") for i in range(2)] == [
        "start_latches_and_stop_releases", "lamp_blinks_while_running"]
    assert panel.locator(".test-file").get_attribute("data-file") == "tests/main.gtest"
    shoot(page, "studio-tests-passed")

    # An edit in the page (not saved): Lamp's coil writes Q0.1 now.
    answer = page.evaluate("""async (edit) => {
        const g = window.guttaStudio;
        const r = await g.api('/api/edit', {json: {file: g.file(), edit: edit}});
        await g.reload();
        return r.status;
    }""", LAMP_ELSEWHERE)
    assert answer == 200
    page.wait_for_selector('.coil[data-operand="Q0.1"]')
    page.click('button[data-command="test"]')
    page.wait_for_selector('.panel[data-panel="tests"] .tests-summary.failed')
    assert panel.locator(".tests-summary").inner_text() == "1 passed, 1 failed"
    failed = panel.locator('.test[data-status="failed"]')
    assert failed.count() == 1
    assert failed.get_attribute("data-test") == "lamp_blinks_while_running"
    assert failed.locator(".test-status").inner_text() == "FAIL"
    assert failed.locator(".test-line").inner_text() == "tests/main.gtest:22"
    assert "UNTIL did not hold within 100 scans" in failed.locator(".test-message").inner_text()
    detail = failed.locator(".test-detail").inner_text()
    assert "22 |   UNTIL   Lamp = 1 WITHIN 100 SCANS" in detail, detail
    assert "expected  Lamp (Q0.0) = 1" in detail, detail
    assert "actual    Lamp (Q0.0) = 0" in detail, detail
    shoot(page, "studio-tests-failed")
    # The disk still holds the passing program.
    assert "Q0.1" not in (project / "src" / "main.lad").read_text()
    cc("test", cwd=project)


def test_a_program_with_errors_runs_no_test_and_says_its_code(page):
    page.evaluate("""async () => {
        const g = window.guttaStudio;
        await g.api('/api/edit', {json: {file: g.file(), edit: {
            op: 'set_operands', at: 'blocks[0].networks[1].rung.series[2]',
            operands: ['NoSuchLamp']}}});
        await g.reload();
    }""")
    page.click('button[data-command="test"]')
    summary = page.locator('.panel[data-panel="tests"] .tests-summary.error')
    summary.wait_for()
    code = summary.get_attribute("data-code")
    assert code and code.startswith("E"), code
    assert "NoSuchLamp" in summary.inner_text()
