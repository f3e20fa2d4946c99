"""The vehicle registry on a real screen (1024x768 and 1280x800): the registry's table, empty
or not, draws its header cells on one line (a column of buttons once sat lower than the others),
and the profile form keeps each label with its input (a label once ended a row with its input
wrapped to the next). Inside the window and the card, accessible; screenshots in the artifacts
folder."""

from __future__ import annotations

import itertools
import json
from typing import Any

import pytest
from playwright.sync_api import Locator, Page, Route, expect

from .conftest import expect_accessible
from .screens import box, inside, no_page_scroll_sideways, shot
from .test_roles import sign_in

# Answered in place of the registry's list, so that the table is empty (or holds these) whatever
# vehicles other tests of the session registered.
LISTED = [{"id": "remus-100", "title": "REMUS 100", "behaviors": ["transit", "area_search"]},
          {"id": "glider-7", "title": "Slocum glider", "behaviors": ["transit"]}]
# The profile form at these widths too: its rows wrap at other points than at the two screens.
FORM_WIDTHS = (1280, 1024, 900, 800, 700)


def _shot(page: Page, tmp_path_factory: pytest.TempPathFactory, name: str) -> None:
    size = page.viewport_size or {"width": 0, "height": 0}
    shot(page, tmp_path_factory, f"{name}-{size['width']}x{size['height']}", full_page=True)


def _registry(page: Page, vehicles: list[dict[str, Any]]) -> Locator:
    """The registry page with `vehicles` listed; its table once drawn."""
    def answer(route: Route) -> None:
        route.fulfill(status=200, content_type="application/json", body=json.dumps(vehicles))

    page.route("**/api/vehicles", answer)
    page.goto("/vehicles")
    table = page.locator("table.vehicles")
    expect(table.locator("tbody tr")).to_have_count(max(1, len(vehicles)))
    return table


def _one_line(cells: Locator, what: str) -> None:
    boxes = [box(cells.nth(i)) for i in range(cells.count())]
    assert len(boxes) >= 4, boxes
    tops = [round(b["y"], 1) for b in boxes]
    assert max(tops) - min(tops) <= 1, (f"{what}: the cells' tops differ", tops)
    for a, b in itertools.pairwise(boxes):
        assert a["x"] + a["width"] <= b["x"] + 0.5, (f"{what}: cells overlap", a, b)


def test_the_registry_table_draws_its_headers_on_one_line(
        screen: Page, tmp_path_factory: pytest.TempPathFactory) -> None:
    page = screen
    sign_in(page, "admin")
    width = page.viewport_size["width"] if page.viewport_size else 0
    for listed, name in (([], "vehicles-empty"), (LISTED, "vehicles-listed")):
        table = _registry(page, listed)
        if not listed:
            expect(table).to_contain_text("The registry has no vehicles yet.")
        _one_line(table.locator("thead th"), f"{name}: header row")
        if listed:
            _one_line(table.locator("tbody tr").first.locator("td"), f"{name}: first row")
        inside(box(table), box(page.locator("main")), f"{name}: table inside the page's card")
        assert box(table)["x"] >= 0 and box(table)["x"] + box(table)["width"] <= width
        no_page_scroll_sideways(page)
        _shot(page, tmp_path_factory, name)
        expect_accessible(page, f"the vehicle registry ({name}) at {width} px")


# Each label of the form and its input: (label box, input box, the label's text).
PAIRS_JS = """form => [...form.querySelectorAll('label[for]')].map(label => {
    const input = document.getElementById(label.htmlFor);
    const box = e => { const r = e.getBoundingClientRect();
                       return {x: r.x, y: r.y, width: r.width, height: r.height}; };
    return [box(label), box(input), label.textContent];
})"""


def _beside_or_under(label: dict[str, float], field: dict[str, float]) -> bool:
    """The input on its label's line, after it; or on the next line, directly under it."""
    label_middle = label["y"] + label["height"] / 2
    beside = (field["y"] <= label_middle <= field["y"] + field["height"]
              and field["x"] >= label["x"] + label["width"] - 1)
    under = (field["y"] >= label["y"] + label["height"] - 1
             and field["y"] - (label["y"] + label["height"]) <= 16
             and abs(field["x"] - label["x"]) <= 2)
    return beside or under


def test_the_profile_form_keeps_each_label_with_its_input(
        screen: Page, tmp_path_factory: pytest.TempPathFactory) -> None:
    page = screen
    size = page.viewport_size or {"width": 1024, "height": 768}
    sign_in(page, "admin")
    _registry(page, LISTED)
    page.get_by_role("button", name="New vehicle").click()
    form = page.get_by_test_id("profile-form")
    expect(form.get_by_label("Time budget (s)")).to_be_visible()
    for width in (size["width"], *[w for w in FORM_WIDTHS if w != size["width"]]):
        page.set_viewport_size({"width": width, "height": size["height"]})
        pairs = form.evaluate(PAIRS_JS)
        assert len(pairs) >= 7, pairs
        apart = [text for label, field, text in pairs if not _beside_or_under(label, field)]
        assert not apart, f"at {width} px these labels are apart from their inputs: {apart}"
        card = box(page.locator("form.panel-box"))
        inside(box(form), card, f"profile form inside its card at {width} px")
        assert card["x"] >= 0 and card["x"] + card["width"] <= width, (width, card)
        no_page_scroll_sideways(page)
    page.set_viewport_size(size)
    form.scroll_into_view_if_needed()
    _shot(page, tmp_path_factory, "vehicle-form")
    expect_accessible(page, f"the vehicle profile form at {size['width']} px")
