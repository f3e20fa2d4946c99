"""Item 6 (the list), at 1024 and 1280 px.

- Goal pickers show id and title and find a goal by words of its title; the vehicle and the
  behaviour are picked from the registry and the vehicle's trusted behaviours (see also
  test_vehicle_registry.py); a constraint's scope is picked by clicking goals on the canvas.
- Arrow keys through a drop-down (native or picker) save nothing; Enter or a click saves once.
- The path explorer's rows show goal ids, titles and outcomes in aligned columns, and the
  path under the pointer is highlighted on the graph.
- The review lists all 75 paths of the exemplar by scrolling (pages fetched as it scrolls) and
  finds paths by a goal and by a terminal.

The operator signs in once for the module; each test's fresh context is given that session.
Each test works once, in a window 1024 px wide (the narrower screen: the least room for the
canvas, the inspector and its drop-downs); what depends on the width (the path columns lining
up, the review keeping only the rows in view in the page) is checked at 1024 and at 1280 px.
"""

from __future__ import annotations

import json
import re

import pytest
from playwright.sync_api import Page, StorageState, expect

from countersign.orders.examples import example_bytes

from .conftest import AVCL, Server, _api_import
from .test_editor import pick, select_node
from .test_editor_build_exemplar import panel, saved

WIDTHS = (1024, 1280)
HEIGHT = 860
PIRATES = AVCL / "PiratesSeizingMerchantDefense.xml"


def _exemplar(server: Server, mission: str) -> str:
    data = json.loads(example_bytes("search-and-sample"))
    data["id"] = mission
    return _api_import(server, json.dumps(data).encode(), "application/json")


def _titles() -> dict[str, str]:
    data = json.loads(example_bytes("search-and-sample"))
    return {g["id"]: g["title"] for g in data["goals"]}


@pytest.fixture()
def operator(page: Page, operator_session: StorageState) -> Page:
    """The page, signed in as the operator."""
    page.context.add_cookies(operator_session["cookies"])
    return page


@pytest.fixture()
def narrow(operator: Page) -> Page:
    """The operator's page, in a window of the narrower width."""
    operator.set_viewport_size({"width": WIDTHS[0], "height": HEIGHT})
    return operator


def _open_editor(page: Page, mission: str) -> None:
    page.goto(f"/missions/{mission}?tab=editor")
    expect(page.get_by_test_id("editor-canvas")).to_have_attribute("data-ready", "true")
    saved(page)


class Puts:
    """Counts the draft saves (PUT .../draft) the page sends."""

    def __init__(self, page: Page) -> None:
        self.count = 0
        page.on("request", self._seen)

    def _seen(self, request) -> None:  # type: ignore[no-untyped-def]
        if request.method == "PUT" and request.url.endswith("/draft"):
            self.count += 1


def _draft(page: Page, mission: str) -> dict:
    answer = page.request.get(f"/api/missions/{mission}")
    assert answer.ok, answer.text()
    return answer.json()


def test_goal_picker_finds_a_goal_by_its_title(narrow: Page, server: Server) -> None:
    page = narrow
    mission = _exemplar(server, "panels-picker")
    titles = _titles()
    _open_editor(page, mission)
    select_node(page, "G1")
    box = page.get_by_role("combobox", name=re.compile(r"Fail.*→ next"))
    box.click()
    menu = page.locator(f"[id='{box.get_attribute('aria-controls')}']")
    # Every choice reads "id: title".
    expect(menu.get_by_role("option", name=re.compile(rf"^G3: {re.escape(titles['G3'])}"))
           ).to_have_count(1)
    words = " ".join(titles["G3"].lower().split()[-2:])  # the title's last two words
    box.fill(words)
    found = menu.get_by_role("option")
    expect(found.first).to_have_text(re.compile(rf"^G3: {re.escape(titles['G3'])}"))
    found.first.click()
    saved(page)
    assert _draft(page, mission)["orders"]["goals"][0]["next"]["fail"] == "G3"
    expect(box).to_have_value(f"G3: {titles['G3']}")


def test_arrow_keys_through_drop_downs_save_nothing(narrow: Page, server: Server) -> None:
    page = narrow
    mission = _exemplar(server, "panels-arrows")
    _open_editor(page, mission)
    before = _draft(page, mission)["revision"]
    puts = Puts(page)
    select_node(page, "G2")
    # A native drop-down: each ArrowDown passes an option (Chromium fires "change" for each).
    area = page.get_by_label("Area", exact=True)
    start_area = area.input_value()
    area.focus()
    for _ in range(3):
        area.press("ArrowDown")
    area.press("ArrowUp")
    page.wait_for_timeout(800)  # longer than the typing pause before a save
    assert puts.count == 0, "the arrow keys saved the draft"
    assert area.input_value() != start_area  # the drop-down shows the option reached
    area.press("Enter")
    saved(page)
    assert puts.count == 1
    # A picker: the arrow keys only highlight; Escape keeps the saved value.
    box = page.get_by_role("combobox", name=re.compile(r"Succeed.*→ next"))
    box.focus()
    for _ in range(4):
        box.press("ArrowDown")
    box.press("Escape")
    box.press("Escape")
    page.wait_for_timeout(800)
    assert puts.count == 1, "arrowing through a picker saved the draft"
    for _ in range(2):
        box.press("ArrowDown")
    box.press("Enter")
    saved(page)
    assert puts.count == 2
    # The norm kind and the quantity type are drop-downs too: a click commits one save.
    panel(page, "Norms")
    kind = page.locator("select[id^='norm-'][id$='-kind']").first
    other = next(v for v in kind.locator("option").evaluate_all("os => os.map(o => o.value)")
                 if v != kind.input_value())
    kind.select_option(other)
    saved(page)
    assert puts.count == 3
    assert _draft(page, mission)["revision"] == before + 3


def test_scope_is_picked_by_clicking_goals(narrow: Page, server: Server) -> None:
    page = narrow
    mission = _exemplar(server, "panels-scope")
    _open_editor(page, mission)
    panel(page, "Constraints")
    constraint = _draft(page, mission)["orders"]["constraints"][0]
    cid = constraint["id"]
    before = constraint.get("applies_to", "mission")
    page.get_by_test_id(f"pick-scope-{cid}").click()
    expect(page.get_by_test_id(f"pick-scope-{cid}")).to_have_attribute("aria-pressed", "true")
    picked = [g for g in ("G2", "G4") if not (isinstance(before, list) and g in before)]
    for goal in picked:
        select_node(page, goal)  # a click on the node's body
        saved(page)
    applies = _draft(page, mission)["orders"]["constraints"][0]["applies_to"]
    assert set(picked) <= set(applies), applies
    for goal in picked:
        expect(page.locator(f'.react-flow__node[data-id="{goal}"]')).to_have_class(
            re.compile(r"\bin-scope\b"))
    expect(page.get_by_test_id("scope-pick-status")).to_contain_text("G2")
    # A second click takes a goal out again; Escape ends picking (clicks then only select).
    select_node(page, picked[0])
    saved(page)
    assert picked[0] not in _draft(page, mission)["orders"]["constraints"][0]["applies_to"]
    page.keyboard.press("Escape")
    expect(page.get_by_test_id(f"pick-scope-{cid}")).to_have_attribute("aria-pressed", "false")
    revision = _draft(page, mission)["revision"]
    select_node(page, picked[0])
    page.wait_for_timeout(500)
    assert _draft(page, mission)["revision"] == revision


def test_path_rows_align_ids_and_titles_and_hover_highlights(narrow: Page,
                                                            server: Server) -> None:
    page = narrow
    mission = _exemplar(server, "panels-rows")
    titles = _titles()
    _open_editor(page, mission)
    panel(page, "Path explorer")
    page.get_by_role("button", name="List paths").click()
    rows = page.get_by_test_id("editor-path-list").get_by_role("option")
    expect(rows.first).to_have_attribute("aria-label", re.compile(
        rf"^Path 1: G1 {re.escape(titles['G1'])}, succeeds; "))
    expect(rows.first.locator(".path-step").first).to_contain_text("G1")
    expect(rows.first.locator(".path-step").first).to_contain_text(titles["G1"])
    # Aligned: step k starts at the same x in every row shown, and so does the terminal.
    for width in WIDTHS:
        where = f"at {width}x{HEIGHT}"
        page.set_viewport_size({"width": width, "height": HEIGHT})
        shown = min(rows.count(), 6)
        assert shown >= 4, (where, shown)
        for k in range(2):
            lefts = {round(rows.nth(i).locator(".path-step").nth(k).bounding_box()["x"])
                     for i in range(shown) if rows.nth(i).locator(".path-step").count() > k}
            assert len(lefts) == 1, (where, k, lefts)
        ends = {round(rows.nth(i).locator(".path-terminal").bounding_box()["x"])
                for i in range(shown)}
        assert len(ends) == 1, (where, ends)
    page.set_viewport_size({"width": WIDTHS[0], "height": HEIGHT})
    # Hover: that path's nodes are highlighted on the graph; leaving clears it.
    row = rows.nth(2)
    label = row.get_attribute("aria-label") or ""
    on_path = set(re.findall(r"\b(G\d+) ", label))
    row.hover()
    expect(page.get_by_test_id("highlight-note")).to_contain_text("path #3")
    lit = page.locator(".react-flow__node.on-path")
    expect(lit).not_to_have_count(0)
    ids = {lit.nth(i).get_attribute("data-id") for i in range(lit.count())}
    assert on_path <= ids, (on_path, ids)
    page.mouse.move(5, 5)
    expect(page.get_by_test_id("highlight-note")).to_have_count(0)
    # A click keeps a path chosen, with its trace.
    rows.first.click()
    expect(rows.first).to_have_attribute("aria-selected", "true")
    expect(page.get_by_test_id("path-trace")).to_contain_text("Commence:")


def _review(page: Page, server: Server, mission: str) -> None:
    answer = page.request.get("/api/auth/me")
    token = answer.json()["csrf_token"]
    made = page.request.post(f"/api/missions/{mission}/versions",
                             headers={"X-CSRF-Token": token})
    assert made.status == 201, made.text()
    number = made.json()["number"]
    page.goto(f"/missions/{mission}/versions/{number}/review")
    expect(page.get_by_test_id("review-paths-status")).not_to_contain_text("Loading")


def _scroll_all(page: Page) -> dict[int, str]:
    """Scrolls the review's list to its end, a screen at a time; every row seen, by index."""
    box = page.get_by_test_id("review-paths")
    seen: dict[int, str] = {}
    for _ in range(200):
        for row in box.get_by_role("listitem").all():
            number = row.get_attribute("data-path")
            if number:
                seen[int(number)] = row.get_attribute("aria-label") or ""
        at_end = box.evaluate("el => el.scrollTop + el.clientHeight >= el.scrollHeight - 2")
        if at_end and not box.get_by_role("listitem").filter(has_text="Loading").count():
            break
        box.evaluate("el => el.scrollBy(0, el.clientHeight * 0.8)")
        page.wait_for_timeout(60)
    return seen


def test_review_lists_every_path_and_searches_by_goal_and_terminal(
        narrow: Page, server: Server) -> None:
    page = narrow
    mission = _exemplar(server, "panels-review")
    pages: list[str] = []
    page.on("request", lambda r: pages.append(r.url) if "/paths?" in r.url else None)
    _review(page, server, mission)
    expect(page.get_by_test_id("review-paths-status")).to_contain_text("All 75 paths")
    box = page.get_by_test_id("review-paths")
    # Only the rows in view are in the page, and not every page is fetched up front.
    for width in WIDTHS:
        page.set_viewport_size({"width": width, "height": HEIGHT})
        in_page = box.get_by_role("listitem").count()
        assert in_page < 40, f"{in_page} rows in the page at {width}x{HEIGHT}"
    page.set_viewport_size({"width": WIDTHS[0], "height": HEIGHT})
    seen = _scroll_all(page)
    assert sorted(seen) == list(range(1, 76))
    assert len(pages) >= 1
    assert all("version=" in u for u in pages)

    # By a goal (picked by its title): every row passes it, as many as the API counts.
    titles = _titles()
    pick(page, "Through goal", "G3")
    through = page.request.get(f"/api/missions/{mission}/paths",
                               params={"version": 1, "goal": "G3", "limit": 1}).json()
    expect(page.get_by_test_id("review-paths-status")).to_contain_text(
        f"{through['matching']} paths of 75 through G3")
    rows = _scroll_all(page)
    assert len(rows) == through["matching"]
    assert all(f"G3 {titles['G3']}" in text for text in rows.values())

    # By a terminal, with the goal still chosen, then alone.
    page.get_by_label("Ending at").select_option("COMPLETE")
    both = page.request.get(f"/api/missions/{mission}/paths",
                            params={"version": 1, "goal": "G3", "terminal": "COMPLETE"}).json()
    expect(page.get_by_test_id("review-paths-status")).to_contain_text(
        f"{both['matching']} path")
    pick(page, "Through goal", "", option="any goal")
    expect(page.get_by_test_id("review-paths-status")).to_contain_text(
        "25 paths of 75 ending at COMPLETE")
    rows = _scroll_all(page)
    assert len(rows) == 25 and all("then COMPLETE" in t for t in rows.values())


@pytest.mark.skipif(not PIRATES.exists(),
                    reason=f"{PIRATES} is absent (../shared NPS reference missions)")
def test_pirates_goals_are_found_by_title_and_its_loops_named(operator: Page,
                                                             server: Server) -> None:
    """Pirates loops (G7), so its paths cannot be counted or listed: the review says so rather
    than showing a partial list; its 49 goals are found in the pickers by title."""
    page = operator
    mission = _api_import(server, PIRATES.read_bytes(), "application/xml")
    _open_editor(page, mission)
    draft = _draft(page, mission)
    goal = draft["orders"]["goals"][5]
    select_node(page, draft["orders"]["goals"][0]["id"])
    box = page.get_by_role("combobox", name=re.compile(r"Fail.*→ next"))
    box.click()
    box.fill(goal["title"])
    menu = page.locator(f"[id='{box.get_attribute('aria-controls')}']")
    expect(menu.get_by_role("option").first).to_contain_text(goal["id"])
    box.press("Escape")
    made = page.request.post(f"/api/missions/{mission}/versions",
                             headers={"X-CSRF-Token": page.evaluate(
                                 "() => fetch('/api/auth/me').then(r => r.json())"
                                 ".then(j => j.csrf_token)")})
    assert made.status == 201, made.text()
    page.goto(f"/missions/{mission}/versions/{made.json()['number']}/review")
    expect(page.get_by_text("The paths cannot be counted until the structural errors are fixed.")
           ).to_be_visible()
    searched = page.request.get(f"/api/missions/{mission}/paths",
                                params={"goal": goal["id"]})
    assert searched.status == 409
