"""The graph editor on a real screen, at 1024x768 and 1280x800.

Geometry is read from the page: the canvas, the inspector and the findings each inside the
window and the page's card (the tab panel), none overlapping another, no horizontal scroll,
and every node's label rendered at 11 px or more (font size times React Flow's zoom), whole
and apart from the others, at the fit of the
exemplar, Pirates (49 goals) and a generated 100-goal mission. Screenshots of each go to the
run's `artifacts` folder, to be looked at."""

from __future__ import annotations

from typing import Any

import pytest
from playwright.sync_api import Page, expect

from .conftest import AVCL, SCREENS, Server, _api_import
from .test_roles import sign_in

PIRATES = AVCL / "PiratesSeizingMerchantDefense.xml"

# Boxes of the editor's parts, the card, the window, and the smallest rendered label: the
# text a person reads on each node (its title near, its id far) times the canvas's zoom.
GEOMETRY = """() => {
    const box = sel => { const e = document.querySelector(sel); if (!e) return null;
        const r = e.getBoundingClientRect();
        return {left: r.left, top: r.top, right: r.right, bottom: r.bottom}; };
    const viewport = document.querySelector('.editor-canvas .react-flow__viewport');
    const zoom = new DOMMatrixReadOnly(getComputedStyle(viewport).transform).a;
    const sizes = [], labels = [];
    for (const n of document.querySelectorAll('.editor-canvas .react-flow__node')) {
        const shown = [...n.querySelectorAll('.node-title, .node-id')].filter(t =>
            t.getClientRects().length > 0 && getComputedStyle(t).visibility !== 'hidden');
        sizes.push(shown.length === 0 ? 0 : Math.max(...shown.map(t =>
            parseFloat(getComputedStyle(t).fontSize) * zoom)));
        for (const t of shown) {
            // Clipped: its box (overflow hidden) holds less than its text.
            const r = t.getBoundingClientRect(), box = n.getBoundingClientRect();
            const clipped = getComputedStyle(t.closest('.graph-node')).overflow === 'hidden'
                && (r.right > box.right + 1 || r.bottom > box.bottom + 1);
            labels.push({id: n.dataset.id, clipped, x: r.left, y: r.top, w: r.width, h: r.height});
        }
    }
    const clashes = [];
    for (let i = 0; i < labels.length; i++) for (let j = i + 1; j < labels.length; j++) {
        const a = labels[i], b = labels[j];
        if (a.id !== b.id && a.x < b.x + b.w - 1 && b.x < a.x + a.w - 1
            && a.y < b.y + b.h - 1 && b.y < a.y + a.h - 1) clashes.push(a.id + '/' + b.id);
    }
    return {
        window: {left: 0, top: 0, right: window.innerWidth, bottom: window.innerHeight},
        scrollWidth: document.documentElement.scrollWidth,
        clientWidth: document.documentElement.clientWidth,
        card: box('.tabpanel'), canvas: box('.editor-canvas'), inspector: box('.editor-inspector'),
        findings: box('.editor-findings-panel'), minimap: box('.side-minimap svg'),
        minimapNodes: document.querySelectorAll('.side-minimap .react-flow__minimap-node').length,
        nodes: sizes.length, smallest: Math.min(...sizes), zoom, clashes,
        clipped: labels.filter(l => l.clipped).map(l => l.id),
    };
}"""


def _inside(inner: dict[str, float], outer: dict[str, float]) -> bool:
    return (inner["left"] >= outer["left"] - 1 and inner["right"] <= outer["right"] + 1
            and inner["top"] >= outer["top"] - 1 and inner["bottom"] <= outer["bottom"] + 1)


def _overlap(a: dict[str, float], b: dict[str, float]) -> bool:
    return (a["left"] < b["right"] - 1 and b["left"] < a["right"] - 1
            and a["top"] < b["bottom"] - 1 and b["top"] < a["bottom"] - 1)


def hundred_goals(mission: str) -> dict[str, object]:
    """A generated 100-goal mission with branches: succeed goes on, fail skips ahead by 2-4,
    violate of every fifth goal rejoins 7 goals on, the rest abort (the same rule as
    frontend/src/editor/crossings.test.ts)."""
    size = 100

    def goal(n: int) -> str:
        return f"G{n}" if n <= size else "COMPLETE"

    goals = [{"id": f"G{n}", "title": f"Leg {n}: transit to waypoint {n}", "behavior": "transit",
              "next": {"succeed": goal(n + 1), "fail": goal(n + 2 + n % 3),
                       "violate": goal(n + 7) if n % 5 == 0 else "ABORT"}}
             for n in range(1, size + 1)]
    return {"format": "countersign.orders/1", "id": mission, "title": "One hundred goals",
            "start": "G1", "goals": goals,
            "vehicle": "auv", "vehicles": [{"id": "auv", "behaviors": ["transit"]}]}


def _create(page: Page, orders: dict[str, object]) -> str:
    token = page.evaluate("() => fetch('/api/auth/me').then(r => r.json()).then(j => j.csrf_token)")
    answer = page.request.post("/api/missions", headers={"X-CSRF-Token": token}, data=orders)
    assert answer.status in (201, 409), answer.text()
    return str(orders["id"])


def open_editor(page: Page, mission: str) -> dict[str, Any]:
    page.goto(f"/missions/{mission}?tab=editor")
    canvas = page.get_by_test_id("editor-canvas")
    expect(canvas).to_have_attribute("data-ready", "true", timeout=60_000)
    # The findings of the draft are listed (the minimap and markers follow them).
    expect(page.get_by_test_id("editor-verdict")).to_be_visible(timeout=60_000)
    shape: dict[str, Any] = page.evaluate(GEOMETRY)
    return shape


def check_screen(shape: dict[str, Any], what: str) -> None:
    print(f"{what}: {shape['nodes']} nodes at zoom {shape['zoom']:.2f}, smallest label "
          f"{shape['smallest']:.1f} px, minimap nodes {shape['minimapNodes']}")
    assert shape["scrollWidth"] <= shape["clientWidth"], (what, "horizontal scroll",
                                                          shape["scrollWidth"])
    parts = ("canvas", "inspector", "findings")
    for name in parts:
        assert shape[name] is not None, (what, name, "missing")
        assert _inside(shape[name], shape["window"]), (what, name, shape[name], shape["window"])
        assert _inside(shape[name], shape["card"]), (what, name, shape[name], shape["card"])
    for i, a in enumerate(parts):
        for b in parts[i + 1:]:
            assert not _overlap(shape[a], shape[b]), (what, a, b, shape[a], shape[b])
    # The canvas uses the height it can: at least half the window.
    height = shape["canvas"]["bottom"] - shape["canvas"]["top"]
    assert height >= shape["window"]["bottom"] * 0.5, (what, "canvas height", height)
    assert shape["minimapNodes"] >= min(shape["nodes"], 5), (what, "minimap draws no graph")
    assert shape["nodes"] > 0 and shape["smallest"] >= 11, (what, shape["smallest"])
    # Readable means whole and apart: no label cut off by its node, none over another.
    assert shape["clipped"] == [], (what, "clipped labels", shape["clipped"][:10])
    assert shape["clashes"] == [], (what, "overlapping labels", shape["clashes"][:10])


@pytest.fixture(scope="module")
def missions(server: Server, seeded_mission: str) -> dict[str, str]:
    found = {"exemplar": seeded_mission}
    if PIRATES.exists():
        found["pirates"] = _api_import(server, PIRATES.read_bytes(), "application/xml")
    return found


@pytest.mark.parametrize(("width", "height"), SCREENS)
def test_editor_fits_the_screen_and_every_goal_reads(
        page: Page, missions: dict[str, str], width: int, height: int,
        tmp_path_factory: pytest.TempPathFactory) -> None:
    page.set_viewport_size({"width": width, "height": height})
    sign_in(page, "operator")
    named = {**missions, "hundred": _create(page, hundred_goals("screen-hundred"))}
    shots = tmp_path_factory.getbasetemp() / "artifacts"
    shots.mkdir(exist_ok=True)
    for name, mission in named.items():
        shape = open_editor(page, mission)
        shot = shots / f"editor-{name}-{width}x{height}.png"
        page.screenshot(path=str(shot))
        print(f"screenshot: {shot}")
        check_screen(shape, f"{name} at {width}x{height}")
