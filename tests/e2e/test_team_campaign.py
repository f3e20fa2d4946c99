"""A team's campaign in the browser: the Versions tab's campaign panel shows the joint table
(each joint end with its runs and the verifier's joint executions, the deadlock a fault makes
counted as that deadlock), the meetings and each member's ends, laid out inside the card at
1024x768 and 1280x800, readable and accessible; screenshots in the artifacts folder.

The campaign runs once; its results are looked at on each screen by resizing the window."""

from __future__ import annotations

import itertools
import json
import re

import pytest
from playwright.sync_api import Page, expect

from countersign.orders.examples import example_bytes

from .conftest import Server, _api_import, expect_accessible
from .screens import SCREENS, box, font_px, inside, no_page_scroll_sideways
from .test_roles import sign_in
from .test_vehicle_registry import client


def test_a_team_campaign_shows_its_joint_table(page: Page, server: Server,
                                               tmp_path_factory: pytest.TempPathFactory) -> None:
    page.set_viewport_size({"width": SCREENS[0][0], "height": SCREENS[0][1]})
    errors: list[str] = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    data = json.loads(example_bytes("search-and-sample-team"))
    data["id"] = "team-campaign"
    mission = _api_import(server, json.dumps(data).encode(), "application/json")
    with client(server, "operator") as operator:
        assert operator.post(f"/api/missions/{mission}/versions").status_code == 201

    sign_in(page, "operator")
    page.goto(f"/missions/{mission}?tab=versions")
    panel = page.get_by_role("region", name="Rehearsal campaigns")
    panel.get_by_role("spinbutton", name="Simulations").fill("2")
    # One member's fault beside "none" (which every member gets): vehicle 2 drifts and aborts
    # before Area C, so remus-100 is left waiting at the meeting.
    panel.get_by_label("One team member's faults").fill("vehicle-2:nav_drift")
    panel.get_by_role("button", name="Start campaign").click()
    row = panel.get_by_role("row").nth(1)
    expect(row).to_contain_text("vehicle-2:nav_drift")
    expect(row).to_contain_text("finished", timeout=240_000)
    row.get_by_role("button", name="Results").click()
    results = panel.get_by_role("region", name=re.compile("^Campaign "))
    expect(results).to_contain_text("2 simulations of a team (remus-100, vehicle-2)")
    table = results.get_by_test_id("joint-table")
    rows = table.locator("tbody tr")
    expect(rows).to_have_count(7)  # every joint end the verifier counts
    deadlock = rows.filter(has_text="remus-100: left waiting").filter(has_text="vehicle-2: ABORT")
    expect(deadlock).to_have_count(1)
    expect(deadlock.locator("td").first).to_have_text("1")
    expect(deadlock).to_contain_text("8 joint executions")
    expect(results.get_by_role("table", name="Meetings")).to_contain_text("R1")
    expect(results.get_by_test_id("joint-coverage")).to_contain_text("of 7 the verifier counts")

    # Geometry, on each screen: the results and their tables inside the card and the window;
    # the joint rows apart; text readable.
    shots = tmp_path_factory.getbasetemp() / "artifacts"
    shots.mkdir(exist_ok=True)
    for width, height in SCREENS:
        page.set_viewport_size({"width": width, "height": height})
        at = f"at {width}x{height}"
        results.scroll_into_view_if_needed()
        card = box(panel)
        inside(box(results), card, f"results inside the campaign card {at}")
        tables = [box(results.locator("table").nth(i)) for i in range(3)]
        for part in tables:
            inside(part, box(results), f"a table inside the results {at}")
            assert part["x"] >= 0 and part["x"] + part["width"] <= width, (at, part)
        for a, b in itertools.pairwise(tables):
            assert a["y"] + a["height"] <= b["y"] + 0.5, (f"tables overlap {at}", a, b)
        boxes = [box(rows.nth(i)) for i in range(rows.count())]
        for a, b in itertools.pairwise(boxes):
            assert a["y"] + a["height"] <= b["y"] + 0.5, (f"joint rows overlap {at}", a, b)
        for locator in (rows.nth(0).locator("th"), rows.nth(0).locator("td").first,
                        table.locator("caption"), results.get_by_test_id("joint-coverage")):
            assert font_px(locator) >= 12, (at, locator)
        no_page_scroll_sideways(page)

        page.screenshot(path=str(shots / f"team-campaign-{width}x{height}.png"),
                        full_page=True, timeout=120_000)
        expect_accessible(page, f"a team campaign's results {at}", include=".team-campaign")
    assert not errors, errors
