"""In the browser: after v2 is rejected the mission page says "v1 approved;
v2 rejected", not only "Rejected"."""

from __future__ import annotations

import json
import re

from playwright.sync_api import Page, expect

from .conftest import Server, _api_import, expect_accessible
from .test_roles import sign_in
from .test_vehicle_registry import approve, client, exemplar


def test_status_shows_the_approved_version_and_the_latest_decision(page: Page,
                                                                    server: Server) -> None:
    data = exemplar()
    data["id"] = "e2e-standing"
    mission = _api_import(server, json.dumps(data).encode(), "application/json")
    submissions = []
    with client(server, "operator") as operator:
        for _ in range(2):
            number = operator.post(f"/api/missions/{mission}/versions").json()["number"]
            submitted = operator.post(f"/api/missions/{mission}/versions/{number}/submit")
            assert submitted.status_code == 201, submitted.text
            submissions.append(submitted.json()["id"])
            if len(submissions) == 1:
                approve(server, submissions[0])
    approve(server, submissions[1], "rejected", "the rendezvous is too close to the lane")

    sign_in(page, "operator")
    page.goto(f"/missions/{mission}")
    expect(page.get_by_test_id("mission-standing")).to_have_text("v1 approved; v2 rejected")
    # the status itself does not say only "Rejected" while v1 stands approved,
    # and the package is offered for the approved version only (v2's would be a 409).
    expect(page.get_by_test_id("mission-status")).to_have_text("v1 approved; v2 rejected")
    page.get_by_role("tab", name=re.compile("^Versions")).click()
    rows = page.locator("table.versions tbody tr")
    expect(rows).to_have_count(2)
    newest, oldest = rows.nth(0), rows.nth(1)
    expect(oldest.get_by_test_id("approved-package")).to_be_visible()
    expect(newest.get_by_test_id("no-package")).to_have_text("no package: v2 is not approved")
    expect(newest.get_by_role("link", name="Approved package")).to_have_count(0)
    package = page.request.get(oldest.get_by_test_id("approved-package").get_attribute("href")
                               or "")
    assert package.status == 200, package.text()[:200]
    expect_accessible(page, "the mission's Versions tab")
