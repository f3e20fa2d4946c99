"""In the rehearsal, at 1024x768 and 1280x800: a refined mission rehearses as its flat
form; the mission graph beside the scene lists the refined goal's steps inside its card
(`G1/G1.1` and its title), the current-goal card names the goal inside and its breadcrumb
(G1 › G1.2), the s/f/c keys and the buttons decide the goals inside one by one, and the
time-out that ends G1's loop after six goals is shown. The graph, its steps and the card inside
the window and their column, apart and readable; axe-core clean; screenshots in the artifacts
folder.

One rehearsal: the window is resized to each screen (the layout is CSS only) while it waits at
G1's first goal inside, and again at the time-out."""

from __future__ import annotations

import itertools
import json

import pytest
from playwright.sync_api import Locator, Page, expect

from countersign.orders.examples import example_bytes

from .conftest import Server, _api_import, expect_accessible
from .screens import SCREENS, box, font_px, inside
from .test_rehearsal_screen import scene_fits_its_frame
from .test_roles import sign_in


def test_rehearsal_marks_the_step_inside_a_refined_goal(
        page: Page, server: Server, tmp_path_factory: pytest.TempPathFactory) -> None:
    page.set_viewport_size({"width": SCREENS[0][0], "height": SCREENS[0][1]})
    data = json.loads(example_bytes("search-and-sample-refined"))
    data["id"] = "rehearse-refined"
    mission = _api_import(server, json.dumps(data).encode(), "application/json")
    sign_in(page, "operator")
    page.goto(f"/missions/{mission}?tab=rehearse")
    page.get_by_test_id("rehearsal-speed").fill("5000")
    page.get_by_test_id("start-rehearsal").click()
    # Generous timeouts: a viser server and the simulation start on a loaded machine.
    expect(page.get_by_test_id("rehearsal-state")).to_have_text("Waiting for the outcome",
                                                                 timeout=90_000)
    expect(page.get_by_test_id("graph-current")).to_contain_text("G1")
    # The live rehearsal asks for the outcome of G1's first goal inside (G1/G1.1#1): its card
    # says so with the breadcrumb, and the graph marks that step (stepPlace, rehearsalOrder.ts).
    expect(page.get_by_test_id("graph-current")).to_contain_text(
        "G1/G1.1 Move to the next unvisited cell")
    expect(page.get_by_test_id("graph-current-step")).to_contain_text("G1/G1.1")
    crumbs = page.get_by_test_id("refined-breadcrumb").locator("li")
    expect(crumbs).to_have_text(["G1", "G1.1"])
    expect(page.get_by_test_id("refined-current")).to_contain_text(
        "G1/G1.1#1 Move to the next unvisited cell of Area A inside Search Area A")

    refinement = page.get_by_test_id("rehearsal-refinement-G1")
    steps = refinement.locator(":scope > li")
    expect(steps).to_have_count(len(data["goals"][0]["refines"]["goals"]))
    graph = page.get_by_test_id("rehearsal-graph")
    shots = tmp_path_factory.getbasetemp() / "artifacts"
    shots.mkdir(exist_ok=True)
    for width, height in SCREENS:
        page.set_viewport_size({"width": width, "height": height})
        # Framed as the page frames a rehearsal it starts (its block at the top of the window),
        # as the screenshots were when the page was opened at each size.
        page.get_by_test_id("rehearsal").evaluate("e => e.scrollIntoView({block: 'start'})")
        scene_fits_its_frame(page)
        at = f"at {width}x{height}"
        card_geometry(page, "the goal inside G1")
        card = box(page.locator("main"))
        inside(box(graph), card, f"mission graph inside the card {at}")
        boxes = [box(steps.nth(i)) for i in range(steps.count())]
        for i, b in enumerate(boxes):
            inside(b, box(graph.get_by_test_id("graph-current")),
                   f"step {i} inside G1's card {at}")
            assert b["x"] + b["width"] <= width, (f"step past the window {at}", i)
            assert font_px(steps.nth(i)) >= 12, (at, i)
        for a, b in itertools.pairwise(boxes):
            assert a["y"] + a["height"] <= b["y"] + 0.5, (f"steps overlap {at}", a, b)

        page.get_by_test_id("refined-goal").scroll_into_view_if_needed()
        page.screenshot(path=str(shots / f"rehearsal-refined-card-{width}x{height}.png"),
                        timeout=120_000)
        expect_accessible(page, f"the goal inside a refinement {at}",
                          include="[data-testid='rehearsal']")
        graph.scroll_into_view_if_needed()
        page.screenshot(path=str(shots / f"rehearsal-refined-{width}x{height}.png"),
                        timeout=120_000)
        expect_accessible(page, f"the rehearsal of a refined mission {at}",
                          include="[data-testid='rehearsal-graph']")

    # Six goals inside G1, decided by key and by button in turn: succeed, fail, ... The
    # seventh may not commence (within: 6 steps), so G1 ends with its on_timeout (fail) -> G3.
    for step, (outcome, local) in enumerate([("succeed", "G1.1"), ("fail", "G1.2")] * 3):
        expect(page.get_by_test_id("rehearsal-step")).to_have_text(str(step))
        expect(page.get_by_test_id("rehearsal-state")).to_have_text("Waiting for the outcome",
                                                                     timeout=60_000)
        expect(crumbs).to_have_text(["G1", local])
        expect(page.get_by_test_id("refined-current")).to_contain_text(f"G1/{local}#{step + 1}")
        if step % 2:
            page.get_by_test_id(f"outcome-{outcome}").click()
        else:
            page.keyboard.press(outcome[0])
    expect(page.get_by_test_id("rehearsal-step")).to_have_text("6")
    expect(page.get_by_test_id("rehearsal-state")).to_have_text("Waiting for the outcome",
                                                                 timeout=60_000)
    expect(page.get_by_test_id("graph-current")).to_contain_text("G3")
    timeout = page.get_by_test_id("refined-timeout")
    expect(timeout).to_contain_text("Time-out: Search Area A (G1) ended its refinement with Fail")
    expect(page.get_by_test_id("refined-current")).to_contain_text("on the mission's level")
    for width, height in SCREENS:
        page.set_viewport_size({"width": width, "height": height})
        scene_fits_its_frame(page)
        card_geometry(page, "the time-out of G1")
        page.get_by_test_id("refined-goal").scroll_into_view_if_needed()
        page.screenshot(path=str(shots / f"rehearsal-refined-timeout-{width}x{height}.png"),
                        timeout=120_000)
        expect_accessible(page, f"the time-out of a refinement at {width}x{height}",
                          include="[data-testid='rehearsal']")
    page.get_by_test_id("stop-rehearsal").click()
    expect(page.get_by_test_id("viser-frame")).to_have_count(0)


def card_geometry(page: Page, what: str) -> None:
    """The current-goal card inside the controls column and the window; its lines apart and
    readable (>= 12 px). Failures name the window's size."""
    size = page.viewport_size
    assert size is not None
    what = f"{what} at {size['width']}x{size['height']}"
    card = page.get_by_test_id("refined-goal")
    card_box = box(card)
    inside(card_box, box(page.locator(".rehearsal-controls")), f"{what}: card in its column")
    assert card_box["x"] >= 0 and card_box["x"] + card_box["width"] <= size["width"], what
    parts: list[Locator] = [card.locator(":scope > *").nth(i)
                            for i in range(card.locator(":scope > *").count())]
    boxes = [box(p) for p in parts]
    for p, b in zip(parts, boxes, strict=True):
        inside(b, card_box, f"{what}: a line inside the card")
        assert font_px(p) >= 12, (what, font_px(p))
    for a, b in itertools.pairwise(boxes):
        assert a["y"] + a["height"] <= b["y"] + 0.5, (what, "lines overlap", a, b)
