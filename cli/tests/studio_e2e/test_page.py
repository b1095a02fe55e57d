"""The page as the studio serves it: the project drawn with `gutta-cc ladder`'s classes,
the status bar in EDIT, a clicked element `selected`."""

from conftest import shoot


def test_the_project_is_drawn_and_a_click_selects(page):
    assert page.locator("g.network").count() >= 3
    assert page.locator(".status").inner_text().startswith("EDIT")
    contact = page.locator('.contact[data-operand="I0.0"]').first
    contact.click()
    assert "selected" in (contact.get_attribute("class") or "")
    shoot(page, "studio-page")
