"""In the browser: the contingency rules of a mission in plain language, on the
review page (one sentence per rule) and in the plain orders of the mission's Orders tab."""

from __future__ import annotations

import httpx
from playwright.sync_api import Page, expect

from .conftest import PASSWORD, Server, _api_import, api_login
from .test_roles import sign_in

SENTENCE = ("S_leak_surface (safety rule): If 'safety sensor failure (leak)' is true, then "
            "surface now.")


def test_review_page_shows_the_rules_in_plain_language(page: Page, server: Server) -> None:
    from countersign.orders.examples import example_bytes

    mission = _api_import(server, example_bytes("search-and-sample-rules"), "application/json")
    with httpx.Client(base_url=server.url, timeout=30) as client:
        login = api_login(client, "operator", PASSWORD["operator"])
        login.raise_for_status()
        created = client.post(f"/api/missions/{mission}/versions",
                              headers={"X-CSRF-Token": login.json()["csrf_token"]})
        assert created.status_code == 201, created.text
        number = created.json()["number"]

    sign_in(page, "supervisor")
    page.goto(f"/missions/{mission}/versions/{number}/review")
    rules = page.get_by_test_id("contingency-rules")
    expect(rules.get_by_role("heading", name="Contingency rules")).to_be_visible()
    expect(rules.get_by_role("listitem")).to_have_count(12)
    expect(rules.get_by_role("listitem").filter(has_text=SENTENCE)).to_have_count(1)

    page.goto(f"/missions/{mission}?tab=orders")
    plain = page.get_by_test_id("plain-orders")
    expect(plain).to_contain_text("Contingency rules")
    expect(plain).to_contain_text(SENTENCE)
