"""A canvas operators can work in, at 1024 and 1280 px.

Geometry is read from the page: node boxes, handle boxes, the canvas and the minimap, and the
title's font size times the zoom React Flow applied (its viewport transform). The operator
signs in once for the module (each test's fresh context is given that session; the two-browser
test signs its browsers in itself). Each test makes its missions once; then, at each width, the
editor is opened in a window of that width and the graph laid out there (the layout wraps long
chains to the canvas's aspect ratio, the view is fitted to the canvas), and what that shows is
checked."""

from __future__ import annotations

import time

import pytest
from playwright.sync_api import Browser, Page, StorageState, expect

from .conftest import AVCL, PATIENCE_MS, Server, _api_import
from .test_editor import _chain
from .test_roles import sign_in

PIRATES = AVCL / "PiratesSeizingMerchantDefense.xml"
WIDTHS = (1024, 1280)

_GEOMETRY = """() => {
    const canvas = document.querySelector('.editor-canvas .react-flow').getBoundingClientRect();
    const minimap = document.querySelector('.react-flow__minimap')?.getBoundingClientRect() ?? null;
    const viewport = document.querySelector('.react-flow__viewport');
    const zoom = new DOMMatrixReadOnly(getComputedStyle(viewport).transform).a;
    const boxes = [...document.querySelectorAll('.react-flow__node')].map(n => {
        const r = n.getBoundingClientRect();
        return {id: n.dataset.id, x: r.x, y: r.y, w: r.width, h: r.height};
    });
    const overlaps = [];
    for (let i = 0; i < boxes.length; i++) for (let j = i + 1; j < boxes.length; j++) {
        const a = boxes[i], b = boxes[j];
        if (a.x < b.x + b.w && b.x < a.x + a.w && a.y < b.y + b.h && b.y < a.y + a.h)
            overlaps.push(a.id + '/' + b.id);
    }
    const inside = (r, c) => r.left >= c.left - 1 && r.right <= c.right + 1 && r.top >= c.top - 1
                             && r.bottom <= c.bottom + 1;
    const hits = (r, c) => c && r.left < c.right && c.left < r.right && r.top < c.bottom
                           && c.top < r.bottom;
    const outside = [], covered = [];
    for (const h of document.querySelectorAll('.react-flow__node .react-flow__handle')) {
        const r = h.getBoundingClientRect();
        const name = h.dataset.nodeid + ':' + h.dataset.handleid;
        if (!inside(r, canvas)) outside.push(name);
        if (hits(r, minimap)) covered.push(name);
    }
    const fonts = [...document.querySelectorAll('.react-flow__node .node-title')]
        .map(t => parseFloat(getComputedStyle(t).fontSize) * zoom);
    return {nodes: boxes.length, overlaps, outside, covered, zoom,
            smallest: Math.min(...fonts)};
}"""


def _token(page: Page) -> str:
    token: str = page.request.get("/api/auth/me").json()["csrf_token"]
    return token


def _create(page: Page, orders: dict[str, object]) -> str:
    answer = page.request.post("/api/missions", headers={"X-CSRF-Token": _token(page)},
                               data=orders)
    assert answer.status == 201, answer.text()
    return str(orders["id"])


def _revision(page: Page, mission: str) -> int:
    return int(page.request.get(f"/api/missions/{mission}").json()["revision"])


def _auto_layout(page: Page) -> float:
    started = time.monotonic()
    page.get_by_role("button", name="Auto layout").click()
    expect(page.get_by_test_id("editor-canvas")).to_have_attribute("data-ready", "true")
    return (time.monotonic() - started) * 1000


def _check_readable(page: Page, what: str) -> None:
    shape = page.evaluate(_GEOMETRY)
    print(f"{what}: {shape['nodes']} nodes at zoom {shape['zoom']:.2f}, smallest title "
          f"{shape['smallest']:.1f} px")
    assert shape["nodes"] > 0
    assert shape["overlaps"] == [], (what, shape["overlaps"][:10])
    assert shape["outside"] == [], (what, shape["outside"][:10])
    assert shape["covered"] == [], (what, shape["covered"][:10])
    assert shape["smallest"] >= 11, (what, shape["smallest"])


def _drop_on_body(page: Page, source: str, outcome: str, target: str) -> None:
    """Drags from an outcome handle and lets go in the middle of the target node's body."""
    handle = page.get_by_test_id(f"handle-{source}-{outcome}")
    handle.hover()
    page.mouse.down()
    box = page.get_by_test_id(f"node-{target}").bounding_box()
    assert box, target
    page.mouse.move(box["x"] + box["width"] * 0.6, box["y"] + box["height"] * 0.6, steps=12)
    page.mouse.up()


def test_ten_goals_added_connected_and_laid_out_stay_readable(
        page: Page, server: Server, operator_session: StorageState) -> None:
    """The goals are added and wired once, at 1024 px: a new goal is placed beside the selected
    one in the graph's own coordinates, at the zoom the view has, so what is added does not
    depend on the window's width, and 1024 is where the canvas is narrowest and a dragged wire's
    target nearest the inspector. Then, at each width, the editor is opened afresh (its view
    fitted to that canvas, its layout worker new) and the graph laid out and checked there."""
    del server
    page.set_viewport_size({"width": WIDTHS[0], "height": 800})
    page.context.add_cookies(operator_session["cookies"])
    mission = _create(page, {"format": "countersign.orders/1", "id": "canvas-ten",
                             "title": "Ten", "goals": []})
    page.goto(f"/missions/{mission}?tab=editor")
    expect(page.get_by_test_id("editor-canvas")).to_have_attribute("data-ready", "true")
    opened = _revision(page, mission)
    assert opened == 1, "opening the editor bumped the revision"
    for n in range(1, 11):
        page.get_by_role("button", name="Add goal").click()
        expect(page.get_by_test_id(f"node-G{n}")).to_be_visible()
    for width in WIDTHS:
        page.set_viewport_size({"width": width, "height": 800})
        _check_no_overlap(page, f"ten goals added, at {width}x800")
    page.set_viewport_size({"width": WIDTHS[0], "height": 800})
    for n in range(1, 10):
        # The Go button, not Enter: with "G1" typed, Chromium's suggestion list offers G1 and
        # G10 and now and then takes the Enter to close itself instead of submitting.
        page.get_by_label("Go to node").fill(f"G{n}")
        page.get_by_role("button", name="Go", exact=True).click()
        _drop_on_body(page, f"G{n}", "succeed", f"G{n + 1}")
        expect(page.locator(f'.react-flow__edge[data-id="G{n}:succeed:G{n + 1}"]')).to_have_count(1)
    _drop_on_body(page, "G10", "succeed", "COMPLETE")
    expect(page.get_by_test_id("save-state")).to_have_text("Saved")
    edited = _revision(page, mission)
    for width in WIDTHS:
        _open_at(page, mission, width)
        _auto_layout(page)
        expect(page.get_by_test_id("save-state")).to_have_text("Saved")
        _check_readable(page, f"ten goals at {width}x800")
        page.wait_for_timeout(500)
        assert _revision(page, mission) == edited, f"laying out at {width}x800 created a revision"
    detail = page.request.get(f"/api/missions/{mission}").json()
    assert set(detail["layout"]) >= {f"G{n}" for n in range(1, 11)}


def _check_no_overlap(page: Page, what: str) -> None:
    shape = page.evaluate(_GEOMETRY)
    assert shape["overlaps"] == [], (what, shape["overlaps"])


def _hundred(mission: str) -> dict[str, object]:
    orders = _chain(mission, 100)
    for n, goal in enumerate(orders["goals"], start=1):  # type: ignore[attr-defined]
        if n % 7 == 0 and n + 3 <= 100:
            goal["next"]["fail"] = f"G{n + 3}"
    return orders


def _open_at(page: Page, mission: str, width: int) -> float:
    """Opens the mission's editor in a window `width` px wide; the milliseconds it took."""
    page.set_viewport_size({"width": width, "height": 800})
    started = time.monotonic()
    page.goto(f"/missions/{mission}?tab=editor")
    expect(page.get_by_test_id("editor-canvas")).to_have_attribute("data-ready", "true")
    return (time.monotonic() - started) * 1000


def _open_lay_out_and_check(page: Page, name: str, mission: str) -> None:
    """At each width: opens the editor (its view fitted to that canvas, its layout worker new),
    lays the graph out (wrapped to that canvas's aspect ratio) and checks it; neither changes
    the revision."""
    before = _revision(page, mission)
    for width in WIDTHS:
        opened = _open_at(page, mission, width)
        print(f"{name} at {width} px: graph editor open {opened:.0f} ms")
        layout_ms = _auto_layout(page)
        print(f"{name} at {width} px: auto layout {layout_ms:.0f} ms")
        _check_readable(page, f"{name} at {width}x800")
        expect(page.get_by_test_id("save-state")).to_have_text("Saved")
        page.wait_for_timeout(300)
        assert _revision(page, mission) == before, (
            f"{name}: open and layout at {width}x800 changed the revision")


def test_real_missions_lay_out_readable(page: Page, server: Server, seeded_mission: str,
                                        operator_session: StorageState) -> None:
    del server
    page.context.add_cookies(operator_session["cookies"])
    hundred = "canvas-hundred"
    _create(page, _hundred(hundred))
    for name, mission in (("exemplar", seeded_mission), ("100 goals", hundred)):
        _open_lay_out_and_check(page, name, mission)


@pytest.mark.skipif(not PIRATES.exists(), reason=f"{PIRATES} is not here")
def test_pirates_lays_out_readable(page: Page, server: Server,
                                   operator_session: StorageState) -> None:
    page.context.add_cookies(operator_session["cookies"])
    pirates = "piratesseizingmerchantdefense"  # imported by another test, or here
    if page.request.get(f"/api/missions/{pirates}").status != 200:
        pirates = _api_import(server, PIRATES.read_bytes(), "application/xml")
    _open_lay_out_and_check(page, "Pirates", pirates)


_FRAMES = """() => new Promise(resolve => {
    const gaps = []; let last = performance.now(); let running = true;
    const tick = now => {
        gaps.push(now - last); last = now; if (running) requestAnimationFrame(tick);
    };
    requestAnimationFrame(tick);
    window.__stopFrames = () => { running = false; resolve(Math.max(...gaps)); };
})"""


# Counts what the page asks of its layout worker, what the worker answers, and the workers the
# page gave up on (terminated once its patience ran out, for the linear layout instead).
_COUNT_LAYOUT_WORKER = """(() => {
    const Real = window.Worker;
    const seen = {posted: 0, answered: 0, terminated: 0};
    window.__layoutWorker = seen;
    window.Worker = class extends Real {
        constructor(url, options) {
            super(url, options);
            this.addEventListener("message", () => { seen.answered += 1; });
        }
        postMessage(message, transfer) {
            seen.posted += 1;
            return super.postMessage(message, transfer);
        }
        terminate() { seen.terminated += 1; return super.terminate(); }
    };
})();"""


def test_every_layout_in_a_page_is_answered_by_the_worker(
        page: Page, server: Server, seeded_mission: str, operator_session: StorageState) -> None:
    """Auto layout three times in one page: each request is answered by the layout worker, none
    waited out (elkjs once took the worker's message handler over after its first layout, and
    every later layout waited the client's 10 s before falling back to the linear one)."""
    del server
    page.context.add_cookies(operator_session["cookies"])
    page.add_init_script(_COUNT_LAYOUT_WORKER)
    page.goto(f"/missions/{seeded_mission}?tab=editor")
    expect(page.get_by_test_id("editor-canvas")).to_have_attribute("data-ready", "true")
    for _ in range(3):
        _auto_layout(page)
    # Each request ends answered or waited out (the client's timer); only then is it counted.
    page.wait_for_function("() => { const s = window.__layoutWorker; return s.posted >= 3 && "
                           "s.answered + s.terminated >= s.posted; }")
    seen = page.evaluate("() => window.__layoutWorker")
    assert seen["terminated"] == 0 and seen["answered"] == seen["posted"], seen


def test_five_hundred_goals_open_and_lay_out_without_blocking(
        page: Page, server: Server, operator_session: StorageState) -> None:
    """Made once; opened (a large draft opens at its start goal, sized to the window) and laid
    out afresh at each width, so that each width's page loads its own layout worker."""
    del server
    page.context.add_cookies(operator_session["cookies"])
    mission = _create(page, _chain("canvas-500", 500))
    for width in WIDTHS:
        opened = _open_at(page, mission, width)
        print(f"500 goals at {width} px: open and laid out {opened:.0f} ms")
        page.evaluate("() => { window.__frames = (" + _FRAMES + ")(); }")
        layout_ms = _auto_layout(page)
        worst = page.evaluate("() => { window.__stopFrames(); return window.__frames; }")
        print(f"500 goals at {width} px: auto layout {layout_ms:.0f} ms, "
              f"longest frame during it {worst:.0f} ms")
        # The layout was computed in the worker (its script was loaded), not on the page's thread.
        assert page.evaluate("() => performance.getEntriesByType('resource')"
                             ".some(e => /layout\\.worker/.test(e.name))"), (
            f"no layout worker at {width}x800")


def _open(browser: Browser, server: Server, mission: str) -> Page:
    context = browser.new_context(base_url=server.url, viewport={"width": 1280, "height": 900})
    context.set_default_timeout(PATIENCE_MS)
    page = context.new_page()
    sign_in(page, "operator")
    page.goto(f"/missions/{mission}?tab=editor")
    expect(page.get_by_test_id("editor-canvas")).to_have_attribute("data-ready", "true")
    return page


def _set_title(page: Page, goal: str, title: str) -> None:
    page.get_by_label("Go to node").fill(goal)
    page.get_by_label("Go to node").press("Enter")
    page.get_by_test_id(f"node-{goal}").click()
    page.locator("#goal-title").fill(title)


def test_two_browsers_edit_one_draft(page: Page, browser: Browser, server: Server) -> None:
    sign_in(page, "operator")
    mission = _create(page, _chain("canvas-two", 4))
    first, second = _open(browser, server, mission), _open(browser, server, mission)
    try:
        # Different goals: both edits survive, no dialog.
        _set_title(first, "G1", "First's title")
        expect(first.get_by_test_id("save-state")).to_have_text("Saved")
        _set_title(second, "G3", "Second's title")
        expect(second.get_by_test_id("save-state")).to_have_text("Saved")
        expect(second.get_by_role("alertdialog")).to_have_count(0)
        expect(second.get_by_test_id("editor-notice")).to_contain_text("merged")
        goals = {g["id"]: g for g in page.request.get(f"/api/missions/{mission}").json()
                 ["orders"]["goals"]}
        assert goals["G1"]["title"] == "First's title" and goals["G3"]["title"] == "Second's title"

        # The same goal: the side-by-side dialog shows both; the choice keeps one, and the
        # other is still in the dialog's record (and undo brings it back).
        # The first also changes G4: that edit merges beside the conflict, and is kept too.
        _set_title(first, "G4", "First's G4")
        expect(first.get_by_test_id("save-state")).to_have_text("Saved")
        _set_title(first, "G2", "First wins?")
        expect(first.get_by_test_id("save-state")).to_have_text("Saved")
        _set_title(second, "G2", "Second wins?")
        dialog = second.get_by_role("alertdialog")
        expect(dialog).to_be_visible()
        expect(dialog.get_by_test_id("conflict-mine-goals:G2")).to_contain_text("Second wins?")
        expect(dialog.get_by_test_id("conflict-theirs-goals:G2")).to_contain_text("First wins?")
        dialog.get_by_role("button", name="Apply these choices").click()
        expect(dialog).to_have_count(0)
        expect(second.get_by_test_id("save-state")).to_have_text("Saved")
        goals = {g["id"]: g for g in page.request.get(f"/api/missions/{mission}").json()
                 ["orders"]["goals"]}
        assert goals["G2"]["title"] == "Second wins?"
        assert goals["G1"]["title"] == "First's title" and goals["G3"]["title"] == "Second's title"
        assert goals["G4"]["title"] == "First's G4"
        # Nothing lost: the first browser, on its next edit, merges the second's choice in.
        _set_title(first, "G1", "First again")
        expect(first.get_by_test_id("save-state")).to_have_text("Saved")
        goals = {g["id"]: g for g in page.request.get(f"/api/missions/{mission}").json()
                 ["orders"]["goals"]}
        assert goals["G2"]["title"] == "Second wins?" and goals["G4"]["title"] == "First's G4"
        assert goals["G1"]["title"] == "First again"
    finally:
        first.context.close()
        second.context.close()
