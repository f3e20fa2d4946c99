"""Issue 37 in the rehearsal, at 1024x768 and 1280x800: a refined mission rehearses as its flat
form; the mission graph beside the scene lists the refined goal's steps inside its card
(`G1/G1.1` and its title). The graph and its steps inside the window and the
card, apart and readable; axe-core clean; screenshots in the artifacts folder."""

from __future__ import annotations

import itertools
import json

import pytest
from playwright.sync_api import Page, expect

from countersign.orders.examples import example_bytes

from .conftest import Server, _api_import, expect_accessible
from .test_review_screen import SCREENS, box, font_px, inside
from .test_roles import sign_in


@pytest.mark.parametrize(("width", "height"), SCREENS)
def test_rehearsal_marks_the_step_inside_a_refined_goal(
        page: Page, server: Server, width: int, height: int,
        tmp_path_factory: pytest.TempPathFactory) -> None:
    page.set_viewport_size({"width": width, "height": height})
    data = json.loads(example_bytes("search-and-sample-refined"))
    data["id"] = f"rehearse-refined-{width}"
    mission = _api_import(server, json.dumps(data).encode(), "application/json")
    sign_in(page, "operator")
    page.goto(f"/missions/{mission}?tab=rehearse")
    page.get_by_test_id("rehearsal-speed").fill("5000")
    page.get_by_test_id("start-rehearsal").click()
    # Generous timeouts: a viser server and the simulation start on a loaded machine.
    expect(page.get_by_test_id("rehearsal-state")).to_have_text("Waiting for the outcome",
                                                                 timeout=90_000)
    expect(page.get_by_test_id("graph-current")).to_contain_text("G1", timeout=30_000)
    # The live rehearsal asks for G1's outcome as one decision (its steps are listed; a log
    # that names a step, G1/G1.1#1, marks that step: stepPlace in rehearsalOrder.ts).
    expect(page.get_by_test_id("graph-current")).to_contain_text(
        "G1/G1.1 Move to the next unvisited cell")

    refinement = page.get_by_test_id("rehearsal-refinement-G1")
    steps = refinement.locator(":scope > li")
    expect(steps).to_have_count(len(data["goals"][0]["refines"]["goals"]))
    graph = page.get_by_test_id("rehearsal-graph")
    card = box(page.locator("main"))
    inside(box(graph), card, "mission graph inside the card")
    size = page.viewport_size
    assert size is not None
    boxes = [box(steps.nth(i)) for i in range(steps.count())]
    for i, b in enumerate(boxes):
        inside(b, box(graph.get_by_test_id("graph-current")), f"step {i} inside G1's card")
        assert b["x"] + b["width"] <= size["width"], ("step past the window", i)
        assert font_px(steps.nth(i)) >= 12
    for a, b in itertools.pairwise(boxes):
        assert a["y"] + a["height"] <= b["y"] + 0.5, ("steps overlap", a, b)

    shots = tmp_path_factory.getbasetemp() / "artifacts"
    shots.mkdir(exist_ok=True)
    graph.scroll_into_view_if_needed()
    page.screenshot(path=str(shots / f"rehearsal-refined-{width}x{height}.png"))
    expect_accessible(page, f"the rehearsal of a refined mission at {width} px",
                      include="[data-testid='rehearsal-graph']")

    page.get_by_test_id("outcome-succeed").click()
    expect(page.get_by_test_id("rehearsal-step")).to_have_text("1", timeout=30_000)
    expect(page.get_by_test_id("graph-current")).to_contain_text("G2", timeout=30_000)
    page.get_by_test_id("stop-rehearsal").click()
    expect(page.get_by_test_id("viser-frame")).to_have_count(0, timeout=30_000)
