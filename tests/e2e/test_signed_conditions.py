"""In the browser: the review page and the mission's plain orders show each
constraint's checked condition, so changing only a condition changes what is read (and a
text that no longer matches its condition is a TEXT warning on the review)."""

from __future__ import annotations

import json

import httpx
from playwright.sync_api import Page, expect

from .conftest import PASSWORD, Server, _api_import, api_login
from .test_roles import sign_in

TWENTY = "Checked as: depth at least 20 m (`depth_m >= 20`)."
HALF = "Checked as: depth at least 0.5 m (`depth_m >= 0.5`)."


def _version(server: Server, mission: str) -> int:
    with httpx.Client(base_url=server.url, timeout=30) as client:
        login = api_login(client, "operator", PASSWORD["operator"])
        login.raise_for_status()
        created = client.post(f"/api/missions/{mission}/versions",
                              headers={"X-CSRF-Token": login.json()["csrf_token"]})
        assert created.status_code == 201, created.text
        number: int = created.json()["number"]
        return number


def test_changing_only_a_condition_changes_the_review(page: Page, server: Server) -> None:
    from countersign.orders.examples import example_bytes

    data = json.loads(example_bytes("search-and-sample"))
    data["id"] = "condition-20"
    first = _api_import(server, json.dumps(data).encode(), "application/json")
    data["id"] = "condition-half"
    data["constraints"][6]["expr"] = "depth_m >= 0.5"  # the text still says 20 meters
    second = _api_import(server, json.dumps(data).encode(), "application/json")
    numbers = {first: _version(server, first), second: _version(server, second)}

    sign_in(page, "supervisor")
    page.goto(f"/missions/{first}/versions/{numbers[first]}/review")
    plain = page.get_by_test_id("review-plain")
    expect(plain).to_contain_text(TWENTY)
    expect(plain).to_contain_text("Trusted behaviours: area search, sample, rendezvous, transit.")
    expect(plain).not_to_contain_text(HALF)

    page.goto(f"/missions/{second}/versions/{numbers[second]}/review")
    plain = page.get_by_test_id("review-plain")
    expect(plain).to_contain_text(HALF)
    expect(plain).not_to_contain_text(TWENTY)
    expect(page.get_by_text("TEXT").first).to_be_visible()

    page.goto(f"/missions/{second}?tab=orders")
    expect(page.get_by_test_id("plain-orders")).to_contain_text(HALF)
