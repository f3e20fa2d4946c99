"""In the browser: a version only submitted, with `submissions.state` and
`missions.status` set to 'approved' behind the app, shows as Submitted on the mission list and
the mission page, with the forged rows named as a warning; the Versions tab shows the log's
state too."""

from __future__ import annotations

import json
import re

from playwright.sync_api import Page, expect

from .conftest import Server, _api_import
from .test_approval_flow import bypass
from .test_roles import sign_in
from .test_vehicle_registry import client, exemplar


def test_a_forged_approval_shows_as_submitted_and_is_named(page: Page, server: Server) -> None:
    data = exemplar()
    data["id"] = "e2e-forged-status"
    mission = _api_import(server, json.dumps(data).encode(), "application/json")
    with client(server, "operator") as operator:
        number = operator.post(f"/api/missions/{mission}/versions").json()["number"]
        submitted = operator.post(f"/api/missions/{mission}/versions/{number}/submit")
        assert submitted.status_code == 201, submitted.text
        submission = submitted.json()["id"]
    bypass(server, "submissions", "UPDATE submissions SET state = 'approved' WHERE id = ?",
           submission)
    bypass(server, "missions", "UPDATE missions SET status = 'approved' WHERE id = ?", mission)

    sign_in(page, "auditor")
    named = f"mission {mission}: the table says approved, the log says submitted"
    page.goto(f"/missions?q={mission}")
    row = page.get_by_role("row").filter(has_text=mission)
    expect(row.locator(".status")).to_have_text("Submitted")
    expect(row.get_by_test_id("status-integrity")).to_have_text(named)
    page.goto(f"/missions/{mission}")
    expect(page.locator(".facts .status")).to_have_text("Submitted")
    expect(page.get_by_test_id("integrity-warning").first).to_contain_text(named)
    page.get_by_role("tab", name=re.compile("^Versions")).click()
    expect(page.get_by_test_id("submission-state")).to_have_text("Submitted")
    expect(page.get_by_text(f"submission {submission}: the table says approved, the log says "
                            "submitted")).to_be_visible()
