"""A real chart, at 1024x768 and 1280x800 in Debian's Chromium.

The editor's areas chart and the mission's plan view are one MapLibre map (WebGL, software
rendered here) over Natural Earth land bundled with the app. What must hold, measured as
geometry rather than presence: the map inside the viewport and the page's card; a click at a
pixel adds a vertex that is drawn back at that pixel; a typed vertex is drawn at once, inside
the map; areas and legs labelled; legend, scale and graticule shown; axe-core finds no serious
or critical violation. Screenshots go to the run's artefact folder (`artifacts/`).

The operator signs in once for the module; each page is a fresh context carrying that session.
The plan view is opened once per size (the map is fitted to its box as it opens) in one page.
The areas chart test stays one run per size: its clicks and typed vertices go where the map,
fitted to that window, puts them, so the whole edit depends on the size from the start."""

from __future__ import annotations

import json
import re
import secrets
from pathlib import Path
from typing import Any

import pytest
from playwright.sync_api import Browser, Locator, Page, StorageState, expect

from .conftest import PATIENCE_MS, REPO, Server, _api_import

SIZES = [(1024, 768), (1280, 800)]
AXE = REPO / "frontend" / "node_modules" / "axe-core" / "axe.min.js"
Box = dict[str, float]


def _exemplar(server: Server) -> str:
    from countersign.orders.examples import example_bytes

    orders = json.loads(example_bytes("search-and-sample"))
    orders["id"] = f"chart-{secrets.token_hex(4)}"
    return _api_import(server, json.dumps(orders).encode(), "application/json")


def _page(browser: Browser, server: Server, size: tuple[int, int],
          session: StorageState) -> tuple[Page, list[str]]:
    """A fresh context of the given viewport with the operator's session, and the page errors it
    will collect."""
    context = browser.new_context(base_url=server.url, storage_state=session,
                                  viewport={"width": size[0], "height": size[1]})
    context.set_default_timeout(PATIENCE_MS)
    page = context.new_page()
    problems: list[str] = []
    page.on("pageerror", lambda error: problems.append(str(error)))
    return page, problems


def _box(locator: Locator) -> Box:
    box = locator.bounding_box()
    assert box is not None, f"{locator} has no box"
    return {"x": box["x"], "y": box["y"], "width": box["width"], "height": box["height"]}


def _centre(locator: Locator) -> tuple[float, float]:
    """The centre of a map marker, read in the page at once (a marker is replaced when the data
    it shows changes, so two separate reads could see two elements)."""
    for _ in range(50):
        locator.wait_for(state="attached")
        centre: list[float] | None = locator.evaluate(
            """e => { if (!e.isConnected) return null; const r = e.getBoundingClientRect();
                      return [r.x + r.width / 2, r.y + r.height / 2]; }""")
        if centre is not None:
            return centre[0], centre[1]
    raise AssertionError(f"{locator} kept being replaced")


def _inside(inner: Box, outer: Box, slack: float = 1.0) -> bool:
    return (inner["x"] >= outer["x"] - slack and inner["y"] >= outer["y"] - slack
            and inner["x"] + inner["width"] <= outer["x"] + outer["width"] + slack
            and inner["y"] + inner["height"] <= outer["y"] + outer["height"] + slack)


def _point_in(x: float, y: float, box: Box) -> bool:
    return box["x"] <= x <= box["x"] + box["width"] and box["y"] <= y <= box["y"] + box["height"]


def _outline_near(page: Page, x: float, y: float, reach: int = 4) -> bool:
    """Whether the pixels around (x, y) include the selected area's dark-blue outline."""
    from io import BytesIO

    from PIL import Image

    png = page.screenshot(clip={"x": x - reach, "y": y - reach,
                                "width": 2 * reach + 1, "height": 2 * reach + 1})
    image = Image.open(BytesIO(png)).convert("RGB")
    pixels = [image.getpixel((i, j)) for i in range(image.width) for j in range(image.height)]
    return any(isinstance(p, tuple) and p[2] - p[0] > 80 and p[0] < 120 for p in pixels)


def _map_holds(page: Page, chart: Locator, size: tuple[int, int]) -> Box:
    """The map is drawn, inside the viewport (no horizontal scroll) and inside the page's card."""
    expect(chart).to_have_attribute("data-ready", "true")
    expect(chart).to_have_attribute("data-land", "natural-earth-50m")
    where = f"at {size[0]}x{size[1]}"
    box = _box(chart.locator("canvas"))
    assert box["width"] >= 300 and box["height"] >= 250, (where, box)
    assert _inside(box, {"x": 0, "y": 0, "width": size[0], "height": 1e9}), (where, box)
    assert _inside(box, _box(page.locator("main"))), (where, box, _box(page.locator("main")))
    scroll = page.evaluate("document.documentElement.scrollWidth")
    assert scroll <= size[0], f"the page scrolls sideways {where}: {scroll} > {size[0]}"
    return box


def _chrome_present(page: Page, wrap: Locator, chart: Locator, where: str) -> None:
    """Scale bar (metres), graticule labels inside the map, a legend."""
    scale = chart.locator(".maplibregl-ctrl-scale")
    expect(scale).to_have_text(re.compile(r"^\d+(\.\d+)?\s?k?m$"))
    assert _inside(_box(scale), _box(chart)), f"the scale bar is outside the map {where}"
    grid = chart.locator("[data-grid]:not(.map-label-hidden)")
    assert grid.count() >= 2, f"{grid.count()} graticule labels shown {where}"
    expect(wrap.get_by_role("list", name="Legend")).to_be_visible()


def _axe(page: Page, where: str, *selectors: str) -> None:
    """axe-core in the page (its source evaluated through the DevTools protocol, which the page's
    CSP does not govern); serious and critical violations fail. Each part is scrolled into view
    first: axe can only judge the contrast of text it sees on the screen."""
    assert AXE.is_file(), f"{AXE} is missing: cd frontend && npm ci"
    page.evaluate(AXE.read_text() + "\n;0")
    for selector in selectors:
        page.locator(selector).first.scroll_into_view_if_needed()
        result: dict[str, Any] = page.evaluate(
            "sel => axe.run(document.querySelector(sel), {resultTypes: ['violations']})",
            selector)
        bad = [(v["id"], v["impact"], [n["target"] for n in v["nodes"]][:5])
               for v in result["violations"] if v["impact"] in ("serious", "critical")]
        assert not bad, (where, selector, bad)


def _artefact(page: Page, base: Path, name: str) -> None:
    folder = base / "artifacts"
    folder.mkdir(exist_ok=True)
    page.screenshot(path=str(folder / name), full_page=False)
    print(f"screenshot: {folder / name}")


@pytest.mark.parametrize("size", SIZES, ids=[f"{w}x{h}" for w, h in SIZES])
def test_areas_chart_adds_vertices_where_clicked_and_draws_typed_ones_at_once(
        browser: Browser, server: Server, size: tuple[int, int], operator_session: StorageState,
        tmp_path_factory: pytest.TempPathFactory) -> None:
    mission = _exemplar(server)
    page, problems = _page(browser, server, size, operator_session)
    try:
        page.goto(f"/missions/{mission}?tab=editor")
        tab = page.get_by_role("tab", name="Areas", exact=True)
        tab.click()
        panel = page.locator(".areas-panel")
        chart = page.get_by_test_id("area-chart")
        box = _map_holds(page, chart, size)
        chart.scroll_into_view_if_needed()
        box = _box(chart.locator("canvas"))

        # Every area labelled, inside the map; the selected one (A) with its 4 vertex handles.
        for area in ("A", "B", "C", "LANE", "BASE"):
            label = chart.locator(f'[data-testid="plan-area-{area}"]')
            expect(label).to_be_attached()
            assert _point_in(*_centre(label), box), (area, _centre(label), box)
        expect(chart.locator('[data-testid="plan-area-LANE"]')).to_have_attribute(
            "data-style", "lane")
        expect(chart.locator("[data-testid^='vertex-A-']")).to_have_count(4)
        _chrome_present(page, panel, chart, f"at {size[0]}x{size[1]}")

        # A click at a pixel adds a vertex there: its handle is drawn back at that pixel.
        panel.get_by_role("button", name="Add vertices to A by clicking").click()
        v1 = _centre(chart.locator('[data-testid="vertex-A-1"]'))
        v2 = _centre(chart.locator('[data-testid="vertex-A-2"]'))
        x, y = box["x"] + box["width"] * 0.3, box["y"] + box["height"] * 0.75
        page.mouse.click(x, y)
        added = chart.locator('[data-testid="vertex-A-5"]')
        expect(added).to_be_attached()
        ax, ay = _centre(added)
        assert abs(ax - x) <= 3 and abs(ay - y) <= 3, ((ax, ay), (x, y))
        lat = float(panel.get_by_label("Vertex 5 latitude").input_value())
        lon = float(panel.get_by_label("Vertex 5 longitude").input_value())
        # Not the old 8 m square at 0,0: the exemplar is in Monterey Bay.
        assert 36 < lat < 37.5 and -122.5 < lon < -121, (lat, lon)
        panel.get_by_role("button", name="Stop adding vertices to A").click()

        # A typed vertex is drawn at once (no tab change), between the vertices it lies between.
        panel.get_by_role("button", name="Add vertex").click()
        a = panel.get_by_label("Vertex 1 latitude").input_value(), panel.get_by_label(
            "Vertex 1 longitude").input_value()
        b = panel.get_by_label("Vertex 2 latitude").input_value(), panel.get_by_label(
            "Vertex 2 longitude").input_value()
        mid = [(float(a[k]) + float(b[k])) / 2 for k in (0, 1)]
        panel.get_by_label("Vertex 6 latitude").fill(f"{mid[0]:.6f}")
        panel.get_by_label("Vertex 6 longitude").fill(f"{mid[1]:.6f}")
        typed = chart.locator('[data-testid="vertex-A-6"]')
        expect(typed).to_be_attached()
        # Typing scrolled the page to the table: measure again, on the screen as it is now.
        chart.scroll_into_view_if_needed()
        box = _box(chart.locator("canvas"))
        v1 = _centre(chart.locator('[data-testid="vertex-A-1"]'))
        v2 = _centre(chart.locator('[data-testid="vertex-A-2"]'))
        tx, ty = _centre(typed)
        assert _point_in(tx, ty, box), ((tx, ty), box)
        assert abs(tx - (v1[0] + v2[0]) / 2) <= 3 and abs(ty - (v1[1] + v2[1]) / 2) <= 3, (
            (tx, ty), v1, v2)
        expect(chart.locator('[data-testid="plan-area-A"]')).to_have_attribute(
            "data-vertices", "6")

        # A vertex typed far outside the view moves the view so that it is drawn inside the map.
        panel.get_by_role("button", name="Add vertex").click()
        panel.get_by_label("Vertex 7 latitude").fill("37.4")
        far = chart.locator('[data-testid="vertex-A-7"]')
        expect(far).to_be_attached()
        chart.scroll_into_view_if_needed()
        box = _box(chart.locator("canvas"))
        page.wait_for_function(
            """([sel, b]) => { const r = document.querySelector(sel)?.getBoundingClientRect();
                 return r && r.x >= b.x && r.y >= b.y && r.right <= b.x + b.width
                   && r.bottom <= b.y + b.height; }""",
            arg=['[data-testid="vertex-A-7"]', box])
        # The polygon itself is redrawn through the typed vertex: its outline (the selected
        # area's, dark blue) crosses the middle of the new edge 6-7 on the canvas.
        mid = [(a + b) / 2 for a, b in zip(_centre(chart.locator('[data-testid="vertex-A-6"]')),
                                          _centre(far), strict=True)]
        assert _outline_near(page, mid[0], mid[1]), mid

        # A title is text on the map, never markup.
        title = '<img src=x onerror="window.pwned=1">Zone <b>A</b>'
        panel.get_by_label("Area title").fill(title)
        label = chart.locator('[data-testid="plan-area-A"]')
        expect(label).to_contain_text(title)
        expect(label.locator("img, b")).to_have_count(0)
        assert page.evaluate("window.pwned === undefined")

        _artefact(page, tmp_path_factory.getbasetemp(), f"chart-areas-{size[0]}x{size[1]}.png")
        _axe(page, f"at {size[0]}x{size[1]}", ".areas-panel", ".areas-panel .chart-map",
             ".areas-panel .chart-legend")
        assert not problems, problems
    finally:
        page.context.close()


def test_plan_view_is_the_same_map_with_labelled_legs_and_a_legend(
        browser: Browser, server: Server, operator_session: StorageState,
        tmp_path_factory: pytest.TempPathFactory) -> None:
    mission = _exemplar(server)
    page, problems = _page(browser, server, SIZES[0], operator_session)
    try:
        for size in SIZES:
            where = f"at {size[0]}x{size[1]}"
            page.set_viewport_size({"width": size[0], "height": size[1]})
            # Opened at this size: the map fits the mission to its box as the page opens.
            page.goto(f"/missions/{mission}?tab=plan")
            view = page.locator(".chart-plan-view")
            chart = page.get_by_test_id("plan-map")
            _map_holds(page, chart, size)
            chart.scroll_into_view_if_needed()
            box = _box(chart.locator("canvas"))
            _artefact(page, tmp_path_factory.getbasetemp(), f"chart-plan-{size[0]}x{size[1]}.png")
            legs = chart.locator("[data-leg]")
            expect(legs).to_have_count(12)
            # Legs along one segment share a label; labels that would overlap an area's are
            # hidden until the map is zoomed in (declutter), the others are drawn inside the map.
            shown = chart.locator(".map-label-leg:not(.map-label-hidden) [data-leg]")
            assert shown.count() >= 4, (where, shown.count())
            for i in range(shown.count()):
                assert _point_in(*_centre(shown.nth(i)), box), (where, i, _centre(shown.nth(i)))
            for area in ("A", "B", "C"):
                label = chart.locator(f'[data-testid="plan-area-{area}"]')
                assert _point_in(*_centre(label), box), (where, area, _centre(label), box)
            assert int(chart.get_attribute("data-coastline-segments") or "0") >= 0
            _chrome_present(page, view, chart, where)
            legend = view.get_by_role("list", name="Legend")
            for words in ("leg on succeed", "leg on fail", "leg on constraint", "Shipping lane"):
                expect(legend).to_contain_text(words)

            _axe(page, where, ".chart-plan-view", ".chart-plan-view .chart-map",
                 ".chart-plan-view .chart-legend")

            # Search: an area by name moves the view onto it.
            view.get_by_label("Find an area, chart or country").fill("Area B")
            view.get_by_role("button", name="Find").click()
            expect(view.locator("output")).to_have_text("Area B")
            _artefact(page, tmp_path_factory.getbasetemp(),
                      f"chart-plan-found-{size[0]}x{size[1]}.png")
        assert not problems, problems
    finally:
        page.context.close()
