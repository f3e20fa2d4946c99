"""A team rehearsal's outcome source per vehicle, at 1024x768 and 1280x800: the Rehearse tab
of team orders lists every vehicle with "Simulate" or "Replay path" and, when replayed, its
path number; the start sends them as `member_paths`. A path beyond the member's count is
refused naming the member and the path; vehicle 2 replaying path 19 (it aborts before Area C)
leaves vehicle 1 waiting at meeting R1. Boxes inside the window and the card, apart, readable
(>= 12 px); axe-core clean; screenshots in the artifacts folder.

The form is filled in once and looked at on each screen by resizing the window; the refused and
the accepted start run once."""

from __future__ import annotations

import itertools
import json

import pytest
from playwright.sync_api import Page, expect

from countersign.orders.examples import example_bytes

from .conftest import Server, _api_import, expect_accessible
from .screens import SCREENS, box, font_px, inside, no_page_scroll_sideways
from .test_roles import sign_in


def test_each_vehicle_simulates_or_replays_a_path(
        page: Page, server: Server, tmp_path_factory: pytest.TempPathFactory) -> None:
    page.set_viewport_size({"width": SCREENS[0][0], "height": SCREENS[0][1]})
    errors: list[str] = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    data = json.loads(example_bytes("search-and-sample-team"))
    data["id"] = "team-sources"
    mission = _api_import(server, json.dumps(data).encode(), "application/json")
    sign_in(page, "operator")
    page.goto(f"/missions/{mission}?tab=rehearse")

    rows = page.get_by_test_id("team-source")
    expect(rows).to_have_count(2)
    expect(rows.nth(0)).to_contain_text("remus-100")
    expect(rows.nth(1)).to_contain_text("vehicle-2")
    kinds = page.get_by_test_id("team-source-kind")
    expect(kinds.nth(0)).to_have_value("simulate")
    expect(page.get_by_test_id("team-source-path")).to_have_count(0)
    kinds.nth(1).select_option("replay")
    path = rows.nth(1).get_by_test_id("team-source-path")
    expect(path).to_have_value("1")
    path.fill("99")

    # Geometry, on each screen: the fieldset inside the window and the card, its rows apart,
    # each control inside its row, readable.
    fieldset = page.get_by_test_id("team-sources")
    shots = tmp_path_factory.getbasetemp() / "artifacts"
    shots.mkdir(exist_ok=True)
    for width, height in SCREENS:
        page.set_viewport_size({"width": width, "height": height})
        at = f"at {width}x{height}"
        fieldset.scroll_into_view_if_needed()
        card = box(page.locator("main"))
        window = {"x": 0.0, "y": -1e6, "width": float(width), "height": 2e6}
        inside(box(fieldset), card, f"the vehicles' sources inside the card {at}")
        inside(box(fieldset), window, f"the vehicles' sources inside the window {at}")
        row_boxes = [box(rows.nth(i)) for i in range(rows.count())]
        for i, row in enumerate(row_boxes):
            inside(row, box(fieldset), f"a vehicle's row inside the fieldset {at}")
            parts = [rows.nth(i).locator("label").first, kinds.nth(i)]
            if i == 1:
                parts.append(path)
            part_boxes = [box(p) for p in parts]
            for part in part_boxes:
                inside(part, row, f"a control inside its vehicle's row {at}")
            for a, b in itertools.pairwise(part_boxes):
                assert (a["x"] + a["width"] <= b["x"] + 0.5
                        or a["y"] + a["height"] <= b["y"] + 0.5), (f"controls overlap {at}", a, b)
            for p in parts:
                assert font_px(p) >= 12, (at, p)
        for a, b in itertools.pairwise(row_boxes):
            assert a["y"] + a["height"] <= b["y"] + 0.5, (f"vehicle rows overlap {at}", a, b)
        no_page_scroll_sideways(page)
        page.screenshot(path=str(shots / f"rehearsal-team-sources-{width}x{height}.png"),
                        timeout=120_000)
        expect_accessible(page, f"the team's sources {at}",
                          include="[data-testid='team-sources']")

    # Beyond vehicle 2's paths: refused, naming the member and the path.
    page.get_by_test_id("rehearsal-speed").fill("5000")
    page.get_by_test_id("start-rehearsal").click()
    expect(page.get_by_role("alert")).to_contain_text(
        "member vehicle-2: path index must be between 1 and 19, not 99", timeout=60_000)

    # Path 19 aborts before Area C: vehicle 1 is left waiting at the meeting.
    path.fill("19")
    page.get_by_test_id("start-rehearsal").click()
    # Generous timeouts: a viser server and two simulations on a loaded machine.
    expect(page.get_by_test_id("rehearsal-state")).to_have_text("Finished", timeout=180_000)
    expect(page.get_by_test_id("team-joint-end")).to_contain_text(
        "remus-100:waiting + vehicle-2:ABORT")
    page.get_by_test_id("stop-rehearsal").click()
    expect(page.get_by_test_id("viser-frame")).to_have_count(0)
    assert not errors, errors
