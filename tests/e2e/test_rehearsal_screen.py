"""On a real screen (1024x768 and 1280x800): when a rehearsal starts, the 3D
view and the outcome buttons are on screen together without scrolling, side by side and not
overlapping; the goal cards read in the order the mission is flown; the s, f and c keys answer
the prompt; a fault notice does not outlive the mission; axe-core finds no serious or critical
violation on the running rehearsal. Screenshots go to the artefact folder."""

from __future__ import annotations

import itertools
import re

import pytest
from playwright.sync_api import Page, expect

from .conftest import expect_accessible
from .screens import box, font_px, inside, no_page_scroll_sideways
from .test_roles import sign_in


def test_scene_and_outcome_controls_share_the_screen(
        screen: Page, own_exemplar: str, tmp_path_factory: pytest.TempPathFactory) -> None:
    page = screen
    sign_in(page, "operator")
    page.goto(f"/missions/{own_exemplar}?tab=rehearse")
    page.get_by_test_id("rehearsal-speed").fill("5000")
    page.get_by_test_id("start-rehearsal").click()
    expect(page.get_by_test_id("rehearsal-state")).to_have_text("Waiting for the outcome",
                                                                 timeout=90_000)
    width, height = page.viewport_size["width"], page.viewport_size["height"]  # type: ignore[index]
    view = {"x": 0, "y": 0, "width": width, "height": height}
    scene = box(page.get_by_test_id("viser-frame"))
    buttons = [box(page.get_by_test_id(f"outcome-{o}")) for o in ("succeed", "fail", "violate")]
    # On screen together, as the page left them (no scrolling by the test).
    for b in buttons:
        inside(b, view, "an outcome button in the window")
        assert b["x"] + b["width"] <= scene["x"], ("button overlaps the 3D view", b, scene)
        assert font_px(page.get_by_test_id("outcome-succeed")) >= 12
    visible_scene = min(scene["y"] + scene["height"], height) - max(scene["y"], 0)
    assert scene["y"] >= 0 and visible_scene >= 300, f"3D view shows {visible_scene} px: {scene}"
    assert scene["x"] + scene["width"] <= width
    inside(box(page.get_by_test_id("rehearsal-question")), view, "the prompt in the window")
    no_page_scroll_sideways(page)

    # Goal cards in the order the exemplar is flown.
    graph = page.get_by_test_id("rehearsal-graph")
    assert graph.locator(":scope > li > code").all_inner_texts() == ["G1", "G2", "G3", "G4", "G5"]
    cards = graph.locator(":scope > li")
    tops = [box(cards.nth(i)) for i in range(cards.count())]
    for a, b in itertools.pairwise(tops):  # left to right, then the next line
        assert (a["y"], a["x"]) < (b["y"], b["x"]), (a, b)
        assert a["x"] + a["width"] <= b["x"] + 0.5 or a["y"] + a["height"] <= b["y"] + 0.5

    shots = tmp_path_factory.getbasetemp() / "artifacts"
    shots.mkdir(exist_ok=True)
    page.screenshot(path=str(shots / f"rehearsal-{width}.png"))
    expect_accessible(page, f"the running rehearsal at {width} px")

    # A fault sent now is queued for the next goal; its notice must not outlive the mission.
    page.get_by_test_id("fault-leak").click()
    expect(page.get_by_test_id("fault-notice")).to_be_visible()
    # The keys answer the prompt: s five times flies G1..G5 to COMPLETE (or ABORT if the leak
    # makes the simulation end the mission earlier; either way it ends).
    for step in range(1, 6):
        expect(page.get_by_test_id("outcome-succeed")).to_be_enabled(timeout=90_000)
        page.keyboard.press("s")
        expect(page.get_by_test_id("rehearsal-step")).to_have_text(str(step), timeout=90_000)
        if page.get_by_test_id("rehearsal-state").inner_text() == "Finished":
            break
    expect(page.get_by_test_id("rehearsal-state")).to_have_text("Finished", timeout=90_000)
    expect(page.get_by_test_id("fault-notice")).to_have_count(0)
    expect(page.get_by_test_id("rehearsal-faults")).not_to_contain_text(re.compile("queued"))
    page.get_by_test_id("stop-rehearsal").click()
    expect(page.get_by_test_id("viser-frame")).to_have_count(0)
