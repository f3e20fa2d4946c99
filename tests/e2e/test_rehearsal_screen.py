"""On a real screen (1024x768 and 1280x800): when a rehearsal starts, the 3D
view and the outcome buttons are on screen together without scrolling, side by side and not
overlapping; the goal cards read in the order the mission is flown; the s, f and c keys answer
the prompt; a fault notice does not outlive the mission; axe-core finds no serious or critical
violation on the running rehearsal. Screenshots go to the artefact folder.

One rehearsal is started (at the first screen) and the window is then resized to each screen in
turn while it waits for G1's outcome; the layout is CSS only, so it follows the window."""

from __future__ import annotations

import itertools
import re

import pytest
from playwright.sync_api import Page, expect

from .conftest import expect_accessible
from .screens import SCREENS, box, font_px, inside, no_page_scroll_sideways, shot
from .test_roles import sign_in

# viser's WebGL canvas (the one with a drawing buffer; an empty overlay canvas sits over it) takes
# its frame's size, and redraws at it, a moment after the window is resized. A scene that has not
# drawn yet has nothing stale to show and is not waited for.
SCENE_FITS_JS = """() => {
  const drawn = [...document.querySelectorAll("canvas")].filter((c) => c.width > 0);
  return drawn.every((c) => {
    const r = c.getBoundingClientRect();
    return Math.abs(r.width - innerWidth) <= 1
      && Math.abs(c.width - r.width * devicePixelRatio) <= 1;
  });
}"""


def scene_fits_its_frame(page: Page) -> None:
    """Waits until viser's scene, if it has drawn, has followed the window to its frame's new
    size, so that what is measured or photographed next is the scene at this size (not a stale,
    partly black canvas of the previous one)."""
    handle = page.get_by_test_id("viser-frame").element_handle()
    content = handle.content_frame() if handle else None
    assert content is not None, "no 3D view"
    content.wait_for_function(SCENE_FITS_JS)


def test_scene_and_outcome_controls_share_the_screen(
        page: Page, own_exemplar: str, tmp_path_factory: pytest.TempPathFactory) -> None:
    first_width, first_height = SCREENS[0]
    page.set_viewport_size({"width": first_width, "height": first_height})
    sign_in(page, "operator")
    page.goto(f"/missions/{own_exemplar}?tab=rehearse")
    page.get_by_test_id("rehearsal-speed").fill("5000")
    page.get_by_test_id("start-rehearsal").click()
    expect(page.get_by_test_id("rehearsal-state")).to_have_text("Waiting for the outcome",
                                                                 timeout=90_000)

    # Goal cards in the order the exemplar is flown.
    graph = page.get_by_test_id("rehearsal-graph")
    assert graph.locator(":scope > li > code").all_inner_texts() == ["G1", "G2", "G3", "G4", "G5"]

    for width, height in SCREENS:
        page.set_viewport_size({"width": width, "height": height})
        # What the page does itself when a rehearsal starts (RehearsalPage.tsx scrolls the
        # rehearsal block to the top of the window), as it would have done had it been opened at
        # this size; the test scrolls no further.
        page.get_by_test_id("rehearsal").evaluate("e => e.scrollIntoView({block: 'start'})")
        scene_fits_its_frame(page)
        at = f"at {width}x{height}"
        view = {"x": 0, "y": 0, "width": width, "height": height}
        scene = box(page.get_by_test_id("viser-frame"))
        buttons = [box(page.get_by_test_id(f"outcome-{o}"))
                   for o in ("succeed", "fail", "violate")]
        # On screen together, as the page left them (no scrolling by the test).
        for b in buttons:
            inside(b, view, f"an outcome button in the window {at}")
            assert b["x"] + b["width"] <= scene["x"], (f"button overlaps the 3D view {at}", b,
                                                       scene)
            assert font_px(page.get_by_test_id("outcome-succeed")) >= 12, at
        visible_scene = min(scene["y"] + scene["height"], height) - max(scene["y"], 0)
        assert scene["y"] >= 0 and visible_scene >= 300, (
            f"3D view shows {visible_scene} px {at}: {scene}")
        assert scene["x"] + scene["width"] <= width, (at, scene)
        inside(box(page.get_by_test_id("rehearsal-question")), view,
               f"the prompt in the window {at}")
        no_page_scroll_sideways(page)

        cards = graph.locator(":scope > li")
        tops = [box(cards.nth(i)) for i in range(cards.count())]
        for a, b in itertools.pairwise(tops):  # left to right, then the next line
            assert (a["y"], a["x"]) < (b["y"], b["x"]), (at, a, b)
            assert a["x"] + a["width"] <= b["x"] + 0.5 or a["y"] + a["height"] <= b["y"] + 0.5, (
                at, a, b)

        shot(page, tmp_path_factory, f"rehearsal-{width}")
        expect_accessible(page, f"the running rehearsal {at}")

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
