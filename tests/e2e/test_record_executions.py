"""In the browser: the record page states each recorded execution of the approved
version ("approved, executed as path N, no deviation", or the deviation named), and operator
text in a deviation stays text."""

from __future__ import annotations

import json

from playwright.sync_api import Page, expect

from ..export.execution_logs import evidenced_log
from .conftest import Server, _api_import
from .test_roles import sign_in
from .test_vehicle_registry import approve, client, exemplar


def test_the_record_page_shows_executions(page: Page, server: Server) -> None:
    data = exemplar()
    data["id"] = "e2e-executions"
    mission = _api_import(server, json.dumps(data).encode(), "application/json")
    with client(server, "operator") as operator:
        number = operator.post(f"/api/missions/{mission}/versions").json()["number"]
        submitted = operator.post(f"/api/missions/{mission}/versions/{number}/submit")
        assert submitted.status_code == 201, submitted.text
        record = approve(server, submitted.json()["id"])
        base = f"/api/missions/{mission}/versions/{number}/executions"
        good = evidenced_log((("G1", "violate"), ("G4", "succeed"), ("G5", "succeed")))
        path = operator.post(base, json={"log": good}).json()["path"]
        planted = good.replace('"G4"', '"<b>G9</b>"')
        assert operator.post(base, json={"log": planted}).status_code == 201

    sign_in(page, "auditor")
    page.goto(f"/audit/{record}")
    statements = page.get_by_test_id("execution-statement")
    expect(statements).to_have_count(2)
    expect(statements.nth(0)).to_have_text(f"approved, executed as path {path}, no deviation")
    expect(statements.nth(1)).to_contain_text(
        "UNKNOWN-GOAL at step 2: <b>G9</b> is not a goal of the orders")
    expect(page.locator("[data-testid=executions] b")).to_have_count(0)
    expect(page.get_by_test_id("execution-evidence").nth(0)).to_have_text(
        "evidenced: start and end times of every goal run; readings for C1, C2, C3, C4, C5, "
        "C6, C7")
    expect(page.get_by_test_id("execution").nth(0)).to_contain_text("uploaded by ")
