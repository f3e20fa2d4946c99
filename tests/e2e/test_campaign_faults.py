"""In the browser: before a campaign runs, a fault nothing in the version reacts
to is named ("leak: no rule or constraint reacts to it"), one a constraint reads is not; axe-core
finds no serious or critical violation on the campaign form."""

from __future__ import annotations

import json
import secrets

import pytest
from playwright.sync_api import Page, Route, expect

from .conftest import Server, _api_import, expect_accessible
from .screens import box, inside, shot
from .test_roles import sign_in
from .test_vehicle_registry import client


def _versioned_mission(server: Server) -> str:
    from countersign.orders.examples import example_bytes

    data = json.loads(example_bytes("harbor-approach-survey"))
    data["id"] = f"e2e-faults-{secrets.token_hex(3)}"
    mission = _api_import(server, json.dumps(data).encode(), "application/json")
    with client(server, "operator") as operator:
        assert operator.post(f"/api/missions/{mission}/versions").status_code == 201
    return mission


def test_the_campaign_form_stays_put_while_the_submission_state_loads(
        screen: Page, server: Server, tmp_path_factory: pytest.TempPathFactory) -> None:
    """The submission panel above the campaign form shows its action row while the version's
    state loads: when the state arrives nothing below moves. It did, by 59 px, and a click
    aimed at a fault's checkbox as it moved (a loaded machine) missed it. At 1024x768 and
    1280x800, the row sits inside its card, axe-core finds nothing serious while loading, and
    a screenshot of each state is written (artifacts/submission-loading-WxH.png)."""
    page = screen
    mission = _versioned_mission(server)
    sign_in(page, "operator")
    held: list[Route] = []
    page.route("**/versions/1/review", lambda route: held.append(route))
    page.goto(f"/missions/{mission}?tab=versions")
    sweep = page.get_by_role("group", name="Faults of the sweep")
    panel = page.get_by_role("region", name="Submission for review")
    expect(panel.get_by_text("Loading the version's state")).to_be_visible()
    expect(panel.get_by_role("button", name="Submit version 1")).to_be_disabled()
    size = page.viewport_size
    assert size is not None
    row = panel.locator(".actions")
    inside(box(row), box(panel), "the action row while loading")
    panel.scroll_into_view_if_needed()
    shot(page, tmp_path_factory, f"submission-loading-{size['width']}x{size['height']}")
    expect_accessible(page, "the versions tab while the state loads")
    before = box(sweep)
    for route in held:
        route.continue_()
    page.unroute("**/versions/1/review")
    expect(panel.get_by_role("button", name="Submit version 1")).to_be_enabled()
    after = box(sweep)
    inside(box(row), box(panel), "the action row loaded")
    shot(page, tmp_path_factory, f"submission-loaded-{size['width']}x{size['height']}")
    assert abs(after["y"] - before["y"]) <= 2, (before, after)


def test_a_fault_nothing_reacts_to_is_named_before_the_run(page: Page, server: Server) -> None:
    mission = _versioned_mission(server)
    sign_in(page, "operator")
    page.goto(f"/missions/{mission}?tab=versions")
    sweep = page.get_by_role("group", name="Faults of the sweep")
    sweep.get_by_label("leak").check()
    sweep.get_by_label("contact_close").check()
    idle = page.get_by_test_id("idle-faults")
    expect(idle).to_contain_text("leak: no rule or constraint reacts to it")
    expect(idle.get_by_role("listitem")).to_have_count(1)
    expect(idle).not_to_contain_text("contact_close")
    sweep.get_by_label("leak").uncheck()
    expect(idle).to_have_count(0)
    expect_accessible(page, "the campaign form")
