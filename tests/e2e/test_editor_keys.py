"""9 (the editor's parts): a new norm is valid as created, a change the
server refuses is shown beside its field and in Findings, the shortcuts are listed in a dialog,
Tab reaches the nodes before anything else on the canvas, and axe-core finds no serious or
critical violation on the editor (axe is injected from the front end's node_modules)."""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path

import pytest
from playwright.sync_api import Browser, Page, expect

from .conftest import PATIENCE_MS, REPO, SCREENS, Server
from .test_editor_screen import open_editor
from .test_roles import sign_in

AXE = REPO / "frontend" / "node_modules" / "axe-core" / "axe.min.js"


def _fresh_exemplar(page: Page, mission: str) -> str:
    from countersign.orders.examples import example_bytes

    orders = json.loads(example_bytes("search-and-sample"))
    orders["id"] = mission
    token = page.evaluate("() => fetch('/api/auth/me').then(r => r.json()).then(j => j.csrf_token)")
    answer = page.request.post("/api/missions", headers={"X-CSRF-Token": token}, data=orders)
    assert answer.status in (201, 409), answer.text()
    return mission


def _norms(page: Page, mission: str) -> list[dict[str, object]]:
    norms: list[dict[str, object]] = page.request.get(
        f"/api/missions/{mission}").json()["orders"].get("norms") or []
    return norms


@pytest.mark.parametrize(("width", "height"), SCREENS)
def test_new_norm_is_valid_and_a_refused_change_shows_beside_its_field(
        page: Page, server: Server, width: int, height: int) -> None:
    del server
    page.set_viewport_size({"width": width, "height": height})
    sign_in(page, "operator")
    mission = _fresh_exemplar(page, f"norms-{width}")
    open_editor(page, mission)
    page.get_by_role("tab", name="Norms").click()
    before = _norms(page, mission)
    page.get_by_role("button", name="Add norm").click()
    expect(page.get_by_test_id("save-state")).to_have_text("Saved")
    after = _norms(page, mission)
    assert len(after) == len(before) + 1
    norm = after[-1]
    name, index = norm["id"], len(after) - 1
    assert norm["context"] and norm.get("permitted") == "true", norm

    # A norm without a context is refused by the server: said beside the context field and in
    # Findings, not only at the top of the editor.
    context = page.get_by_label(f"Norm {name} context")
    context.fill("")
    beside = page.get_by_test_id(f"refused-norm-{name}-context")
    expect(beside).to_contain_text(f"Not saved: $.norms[{index}].context")
    expect(page.get_by_test_id("findings-refused")).to_contain_text("Not saved:")
    field = context.bounding_box()
    note = beside.bounding_box()
    assert field and note
    assert 0 <= note["y"] - (field["y"] + field["height"]) < 40, (field, note)
    assert note["x"] < width and note["y"] + note["height"] <= page.evaluate(
        "document.documentElement.scrollHeight")
    assert _norms(page, mission) == after  # nothing half-saved
    # Writing a context again saves, and the note goes.
    context.fill("harbour")
    expect(page.get_by_test_id("save-state")).to_have_text("Saved")
    expect(beside).to_have_count(0)
    expect(page.get_by_test_id("findings-refused")).to_have_count(0)


def test_shortcuts_dialog_and_tab_reaches_nodes_first(page: Page, seeded_mission: str) -> None:
    page.set_viewport_size({"width": 1280, "height": 800})
    sign_in(page, "operator")
    open_editor(page, seeded_mission)
    page.get_by_role("button", name="Keyboard shortcuts").click()
    dialog = page.get_by_role("dialog", name="Keyboard shortcuts of the graph editor")
    expect(dialog).to_be_visible()
    expect(dialog).to_contain_text("Ctrl+Z")
    expect(dialog).to_contain_text("Auto layout")
    page.keyboard.press("Escape")
    expect(dialog).to_have_count(0)

    canvas = page.get_by_test_id("editor-canvas")
    canvas.focus()
    page.keyboard.press("?")
    expect(dialog).to_be_visible()
    dialog.get_by_role("button", name="Close").click()

    # From the canvas, Tab walks the nodes (7 in the exemplar) and never stops on an edge.
    canvas.focus()
    seen = []
    for _ in range(7):
        page.keyboard.press("Tab")
        seen.append(page.evaluate("""() => {
            const e = document.activeElement;
            return e.closest('.react-flow__edge') ? 'edge:' + e.dataset.id
                 : e.closest('.react-flow__node') ? e.closest('.react-flow__node').dataset.id
                 : e.tagName;
        }"""))
    assert seen == ["G1", "G2", "G3", "G4", "G5", "COMPLETE", "ABORT"], seen


@pytest.fixture()
def axe_page(browser: Browser, server: Server) -> Iterator[Page]:
    """A page whose CSP lets the test inject axe-core (the app's own CSP forbids inline
    scripts, rightly)."""
    context = browser.new_context(base_url=server.url, viewport={"width": 1280, "height": 800},
                                  bypass_csp=True)
    context.set_default_timeout(PATIENCE_MS)
    try:
        yield context.new_page()
    finally:
        context.close()


def _axe(page: Page, path: Path) -> list[dict[str, object]]:
    page.add_script_tag(path=str(path))
    violations: list[dict[str, object]] = page.evaluate("""async () => {
        const result = await axe.run(document, {resultTypes: ['violations']});
        return result.violations.filter(v => v.impact === 'serious' || v.impact === 'critical')
            .map(v => ({id: v.id, impact: v.impact, nodes: v.nodes.length,
                        first: v.nodes[0].target.join(' ')}));
    }""")
    return violations


@pytest.mark.skipif(not AXE.exists(), reason=f"{AXE} is missing: npm ci in frontend/")
def test_axe_finds_no_serious_violation_on_the_editor(axe_page: Page, seeded_mission: str,
                                                      server: Server) -> None:
    del server
    sign_in(axe_page, "operator")
    open_editor(axe_page, seeded_mission)
    axe_page.get_by_test_id("node-G2").click()  # the inspector with a goal's fields
    expect(axe_page.locator("#goal-title")).to_be_visible()
    violations = _axe(axe_page, AXE)
    assert violations == [], violations
