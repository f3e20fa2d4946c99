"""On the review page: a version whose Goal 1 is a library procedure lists the
procedure with its pinned digest and says whether every procedure it uses is an approved
version, before and after a supervisor signs the procedure's approval. axe-core clean."""

from __future__ import annotations

import json
from importlib import resources
from typing import Any

from playwright.sync_api import Page, expect

from countersign.approvals import dsse
from countersign.orders.procedure import procedure_from_data

from .conftest import PASSWORD, Server, _api_import, expect_accessible
from .test_roles import sign_in
from .test_vehicle_registry import client

EXAMPLES = resources.files("countersign.orders.examples") / "procedures"
NAME = "e2e-cell-search"
MISSION = "e2e-review-procedure"


def _procedure() -> dict[str, Any]:
    data: dict[str, Any] = json.loads((EXAMPLES / "library" / "cell-search-1.json").read_text())
    return data | {"name": NAME}


def _mission(server: Server) -> str:
    orders = json.loads((EXAMPLES / "search-and-sample-procedure.json").read_text())
    orders["id"] = MISSION
    goal = next(g for g in orders["goals"] if g["id"] == "G1")
    goal["refines"] = procedure_from_data(_procedure()).reference()
    with client(server, "operator") as operator:
        saved = operator.post("/api/procedures", json=_procedure())
        assert saved.status_code in (201, 409), saved.text
    created = _api_import(server, json.dumps(orders).encode(), "application/json")
    with client(server, "operator") as operator:
        answer = operator.post(f"/api/missions/{created}/versions")
        assert answer.status_code in (201, 409), answer.text
    return created


def _approve(server: Server) -> None:
    base = f"/api/procedures/{NAME}/versions/1"
    key = dsse.generate_key()
    with client(server, "supervisor") as supervisor:
        registered = supervisor.post("/api/keys", json={
            "public_key": dsse.public_text(key), "name": "procedures",
            "password": PASSWORD["supervisor"]})
        assert registered.status_code == 201, registered.text
        key_id = registered.json()["key_id"]
        prepared = supervisor.post(f"{base}/statement", json={
            "decision": "approved", "reason": "", "key_id": key_id})
        if prepared.status_code == 409:  # decided by an earlier run of this test
            return
        assert prepared.status_code == 200, prepared.text
        payload = dsse.unb64(prepared.json()["payload"], "payload")
        envelope = json.dumps(dsse.sign_envelope(payload, key))
        decided = supervisor.post(f"{base}/decision", json={
            "envelope": envelope, "password": PASSWORD["supervisor"]})
        assert decided.status_code == 201, decided.text


def test_review_says_whether_every_procedure_is_approved(page: Page, server: Server) -> None:
    mission = _mission(server)
    sign_in(page, "supervisor")
    page.goto(f"/missions/{mission}/versions/1/review")
    section = page.get_by_test_id("review-procedures")
    digest = procedure_from_data(_procedure()).digest
    expect(section.get_by_role("heading", name="Procedures")).to_be_visible()
    row = section.get_by_test_id("procedure-use")
    expect(row).to_have_count(1)
    expect(row).to_contain_text(NAME)
    expect(row.locator("code")).to_have_attribute("title", digest)
    expect(row).to_contain_text("not approved")
    expect(section.get_by_test_id("procedures-verdict")).to_have_text(
        "Not every procedure these orders use is an approved version.")
    expect(page.get_by_test_id("review-plain")).to_contain_text(
        f"carried out by procedure {NAME} version 1 ({digest})")
    expect_accessible(page, "review with procedures", include="[data-testid=review-procedures]")

    _approve(server)
    page.reload()
    section = page.get_by_test_id("review-procedures")
    expect(section.get_by_test_id("procedures-verdict")).to_have_text(
        "Every procedure these orders use is a version a supervisor approved.")
    expect(section.get_by_test_id("procedure-use")).to_contain_text("supervisor")


def test_review_of_orders_without_procedures_has_no_procedure_section(
        page: Page, server: Server, seeded_mission: str) -> None:
    with client(server, "operator") as operator:
        answer = operator.post(f"/api/missions/{seeded_mission}/versions")
        assert answer.status_code in (201, 409), answer.text
    sign_in(page, "auditor")
    page.goto(f"/missions/{seeded_mission}/versions/1/review")
    expect(page.get_by_test_id("review-plain")).to_be_visible()
    expect(page.get_by_test_id("review-procedures")).to_have_count(0)
