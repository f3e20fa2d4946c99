"""The editor's "Go to node" field at 1024x768 and 1280x800: Enter with an exact id typed goes
to that node, even when another id starts with it (G1 beside G10) and the suggestions offer both.

Each size keeps a screenshot of the result (pytest's temporary directory, `screenshots/`)."""

from __future__ import annotations

import re

import pytest
from playwright.sync_api import Page, expect

from .conftest import SCREENS, Server
from .test_editor import _chain
from .test_editor_canvas import _create
from .test_roles import sign_in

# Whether a node's box lies inside the canvas (what "in view" means to an operator).
_IN_VIEW = """(id) => {
    const canvas = document.querySelector('.editor-canvas .react-flow').getBoundingClientRect();
    const node = document.querySelector(`.react-flow__node[data-id="${id}"]`);
    if (!node) return false;
    const r = node.getBoundingClientRect();
    return r.left >= canvas.left && r.right <= canvas.right && r.top >= canvas.top
        && r.bottom <= canvas.bottom;
}"""


@pytest.mark.parametrize("size", SCREENS, ids=[f"{w}x{h}" for w, h in SCREENS])
def test_enter_goes_to_the_exact_id_typed(page: Page, server: Server, size: tuple[int, int],
                                          tmp_path_factory: pytest.TempPathFactory) -> None:
    del server
    width, height = size
    page.set_viewport_size({"width": width, "height": height})
    sign_in(page, "operator")
    mission = _create(page, _chain(f"goto-{width}", 12))
    page.goto(f"/missions/{mission}?tab=editor")
    expect(page.get_by_test_id("editor-canvas")).to_have_attribute("data-ready", "true")
    field = page.get_by_label("Go to node")
    # G12 first: the view moves away from G1, so "in view" below is the field's doing.
    field.fill("G12")
    field.press("Enter")
    expect(page.locator('.react-flow__node[data-id="G12"]')).to_have_class(
        re.compile(r"\bselected\b"))
    # Cleared as an operator does, once the field has settled on G12's Enter (a fill("") at
    # load 20 was overtaken by that update and "G1" typed after "G12").
    expect(page.locator("#goto-node-menu")).to_be_hidden()
    field.press("Control+a")
    field.press("Backspace")
    expect(field).to_have_value("")
    # Typed key by key, as an operator does: the suggestions open with G1, G10, G11, G12, and
    # the pointer rests on G10 (the one a list takes an Enter for when it is highlighted).
    field.press_sequentially("G1", delay=50)
    expect(field).to_have_value("G1")
    suggestion = page.get_by_role("option", name="G10", exact=True)
    expect(suggestion).to_be_visible()
    suggestion.hover()
    expect(suggestion).to_have_class(re.compile(r"\bactive\b"))
    field.press("Enter")
    node = page.locator('.react-flow__node[data-id="G1"]')
    expect(node).to_have_class(re.compile(r"\bselected\b"))
    expect(page.locator(".react-flow__node.selected")).to_have_count(1)
    page.wait_for_function(_IN_VIEW, arg="G1")
    expect(page.get_by_test_id("editor-inspector")).to_contain_text("G1")
    shot = tmp_path_factory.getbasetemp() / "screenshots" / f"goto-{width}x{height}.png"
    shot.parent.mkdir(exist_ok=True)
    page.screenshot(path=str(shot))
    print(f"screenshot: {shot}")
