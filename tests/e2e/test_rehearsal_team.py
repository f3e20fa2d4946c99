"""In the rehearsal, at 1024x768 and 1280x800: a team's orders rehearse from the
mission's Rehearse tab, every vehicle in one scene; beside it the team panel lists each
vehicle (its scene colour, state, goal, energy), the meetings and the latest events naming
their vehicle, and the "Vehicle:" switcher shows that vehicle's goal cards. Boxes inside the
window and the card, apart, readable; the orders' text stays text; axe-core clean;
screenshots in the artifacts folder.

The team is rehearsed once; its finished rehearsal is then looked at on each screen by resizing
the window (the layout is CSS only), before and after the switch to vehicle 2."""

from __future__ import annotations

import itertools
import json

import pytest
from playwright.sync_api import Page, expect

from countersign.orders.examples import example_bytes

from .conftest import Server, _api_import, expect_accessible
from .screens import SCREENS, box, font_px, inside, no_page_scroll_sideways
from .test_rehearsal_screen import scene_fits_its_frame
from .test_roles import sign_in

MARKUP_TITLE = "<b>Search</b> Area A"


def test_team_rehearses_every_vehicle_with_a_switcher(
        page: Page, server: Server, tmp_path_factory: pytest.TempPathFactory) -> None:
    page.set_viewport_size({"width": SCREENS[0][0], "height": SCREENS[0][1]})
    errors: list[str] = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    data = json.loads(example_bytes("search-and-sample-team"))
    data["id"] = "rehearse-team"
    data["team"][0]["orders"]["goals"][0]["title"] = MARKUP_TITLE
    mission = _api_import(server, json.dumps(data).encode(), "application/json")
    sign_in(page, "operator")
    page.goto(f"/missions/{mission}?tab=rehearse")

    # A team's outcomes come from the simulation: that is the one source offered.
    expect(page.get_by_test_id("team-rehearsal-note")).to_be_visible()
    options = page.get_by_test_id("rehearsal-source").locator("option")
    expect(options).to_have_count(1)
    expect(options).to_have_text(["Decided by the simulation"])
    page.get_by_test_id("rehearsal-speed").fill("5000")
    page.get_by_test_id("start-rehearsal").click()
    # Generous timeouts: a viser server and two simulations on a loaded machine.
    rows = page.get_by_test_id("team-member-row")
    expect(rows).to_have_count(2, timeout=90_000)
    expect(rows.nth(0)).to_contain_text("remus-100")
    expect(rows.nth(1)).to_contain_text("vehicle-2")
    expect(page.get_by_test_id("rehearsal-state")).to_have_text("Finished", timeout=180_000)
    expect(page.get_by_test_id("team-meetings")).to_contain_text("Meeting R1")
    expect(page.get_by_test_id("team-meetings")).to_contain_text("remus-100 G4, vehicle-2 G2")
    expect(page.get_by_test_id("team-joint-end")).to_contain_text("remus-100:")
    events = page.get_by_test_id("team-events").locator(":scope > li")
    assert events.count() >= 1
    for i in range(events.count()):
        assert events.nth(i).inner_text().split(" ")[0].rstrip(":") in ("remus-100", "vehicle-2")

    # The orders' text is text: the title's markup is shown, not rendered.
    graph = page.get_by_test_id("rehearsal-graph")
    expect(graph).to_have_attribute("aria-label", "Mission graph of remus-100")
    assert graph.locator(":scope > li > code").all_inner_texts() == ["G1", "G2", "G3", "G4", "G5"]
    expect(graph.locator(":scope > li").first).to_contain_text(MARKUP_TITLE)
    assert graph.locator("b").count() == 0

    # Geometry, on each screen: the team panel inside the window and the controls column,
    # beside the scene; its rows apart and readable.
    shots = tmp_path_factory.getbasetemp() / "artifacts"
    shots.mkdir(exist_ok=True)
    panel = page.get_by_test_id("team-rehearsal")
    for width, height in SCREENS:
        page.set_viewport_size({"width": width, "height": height})
        scene_fits_its_frame(page)
        at = f"at {width}x{height}"
        page_column = {"x": 0.0, "y": -1e6, "width": float(width), "height": 2e6}
        panel.scroll_into_view_if_needed()
        controls = box(page.locator(".rehearsal-controls"))
        scene = box(page.get_by_test_id("viser-frame"))
        card = box(page.locator("main"))
        inside(box(panel), controls, f"team panel inside the controls column {at}")
        inside(controls, card, f"controls inside the card {at}")
        inside(scene, card, f"3D view inside the card {at}")
        assert controls["x"] + controls["width"] <= scene["x"] + 0.5, (
            f"controls overlap the scene {at}", controls, scene)
        assert scene["x"] + scene["width"] <= width, (at, scene)
        parts = [box(rows.nth(i)) for i in range(rows.count())]
        parts += [box(page.get_by_test_id("team-meetings")),
                  box(page.get_by_test_id("team-joint-end"))]
        for part in parts:
            inside(part, box(panel), f"a team row inside the panel {at}")
            assert part["x"] + part["width"] <= width, (at, part)
        for a, b in itertools.pairwise(parts):
            assert a["y"] + a["height"] <= b["y"] + 0.5, (f"team rows overlap {at}", a, b)
        for locator in (rows.nth(0), page.get_by_test_id("team-meetings"), events.nth(0)):
            assert font_px(locator) >= 12, (at, locator)
        inside(box(page.get_by_test_id("team-member")), page_column,
               f"switcher within the width {at}")
        no_page_scroll_sideways(page)

        page.get_by_test_id("rehearsal").scroll_into_view_if_needed()
        page.screenshot(path=str(shots / f"rehearsal-team-{width}x{height}.png"),
                        timeout=120_000)
        expect_accessible(page, f"the rehearsal of a team {at}",
                          include="[data-testid='rehearsal']")

    # The switcher shows the other vehicle's goal cards, inside the card and apart on each
    # screen.
    page.get_by_test_id("team-member").select_option("vehicle-2")
    expect(graph).to_have_attribute("aria-label", "Mission graph of vehicle-2")
    expect(graph.locator(":scope > li > code")).to_have_text(["G1", "G2", "G3"])
    cards = graph.locator(":scope > li")
    for width, height in SCREENS:
        page.set_viewport_size({"width": width, "height": height})
        scene_fits_its_frame(page)
        at = f"at {width}x{height}"
        card = box(page.locator("main"))
        boxes = [box(cards.nth(i)) for i in range(cards.count())]
        for b in boxes:
            inside(b, card, f"a goal card inside the card {at}")
        for a, b in itertools.pairwise(boxes):
            assert a["x"] + a["width"] <= b["x"] + 0.5 or a["y"] + a["height"] <= b["y"] + 0.5, (
                f"goal cards overlap {at}", a, b)
        graph.scroll_into_view_if_needed()
        page.screenshot(path=str(shots / f"rehearsal-team-vehicle-2-{width}x{height}.png"),
                        timeout=120_000)

    page.get_by_test_id("stop-rehearsal").click()
    expect(page.get_by_test_id("viser-frame")).to_have_count(0)
    assert not errors, errors
