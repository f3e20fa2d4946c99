"""In the browser: from the mission page's Versions tab the submitting operator
attaches a rehearsal record of exactly the submitted version; a record of another version is
refused with a message naming both; the approval then cites the record (not "None")."""

from __future__ import annotations

import json

import httpx
import pytest
from playwright.sync_api import Page, expect

from .conftest import Server, _api_import
from .screens import tables_fit_each_screen
from .test_roles import sign_in
from .test_vehicle_registry import approve, client, exemplar

MISSION = "e2e-attach"


def short(digest: str, keep: int = 12) -> str:
    """As the page shortens a digest (format.ts shortDigest)."""
    return f"sha256:{digest[7:7 + keep]}…"


def _record(operator: httpx.Client, number: int) -> str:
    """A stored record of version `number`: a simulated rehearsal started and stopped."""
    started = operator.post(f"/api/missions/{MISSION}/rehearsals",
                            json={"source": "simulate", "version": number, "speed": 100000,
                                  "seed": number})
    assert started.status_code == 201, started.text
    stopped = operator.post(f"/api/rehearsals/{started.json()['id']}/stop")
    assert stopped.status_code == 200, stopped.text
    digest: str = stopped.json()["digest"]
    return digest


def test_operator_attaches_a_record_of_that_exact_version(
        page: Page, server: Server, tmp_path_factory: pytest.TempPathFactory) -> None:
    data = exemplar()
    data["id"] = MISSION
    _api_import(server, json.dumps(data).encode(), "application/json")
    with client(server, "operator") as operator:
        operator.post(f"/api/missions/{MISSION}/versions").raise_for_status()
        data["title"] = "Search and sample, second version"
        etag = operator.get(f"/api/missions/{MISSION}").headers["ETag"]
        saved = operator.put(f"/api/missions/{MISSION}/draft", json={"orders": data},
                             headers={"If-Match": etag})
        assert saved.status_code == 200, saved.text
        operator.post(f"/api/missions/{MISSION}/versions").raise_for_status()
        submission = operator.post(f"/api/missions/{MISSION}/versions/2/submit").json()["id"]
        of_v1 = _record(operator, 1)
        of_v2 = _record(operator, 2)

    sign_in(page, "operator")
    page.goto(f"/missions/{MISSION}?tab=versions")
    citation = page.get_by_test_id("rehearsal-citation")
    expect(citation.get_by_test_id("cited-rehearsal")).to_have_text(
        "Rehearsal record: none attached")
    expect(citation.get_by_test_id("rehearsal-record-row")).to_have_count(2)
    tables_fit_each_screen(page, tmp_path_factory, "rehearsal-records",
                           [(citation.locator("table.records-table"),
                             page.get_by_test_id("rehearsal-citation"))])

    citation.get_by_role("button", name=f"Attach record {short(of_v1)} (v1)").click()
    refusal = citation.get_by_role("alert")
    expect(refusal).to_contain_text(f"the record {of_v1} rehearsed orders")
    expect(refusal).to_contain_text(f"but version 2 of {MISSION}")
    expect(citation.get_by_test_id("cited-rehearsal")).to_have_text(
        "Rehearsal record: none attached")

    citation.get_by_role("button", name=f"Attach record {short(of_v2)} (v2)").click()
    expect(page.get_by_role("status").filter(
        has_text=f"Rehearsal record {short(of_v2)} attached to submission {submission}.")
    ).to_be_visible()
    expect(citation.get_by_test_id("cited-rehearsal")).to_contain_text(short(of_v2, 16))
    expect(citation.get_by_role("button", name=f"Attached record {short(of_v2)} (v2)")
           ).to_have_text("Attached")

    approval = approve(server, submission)
    page.context.clear_cookies()
    sign_in(page, "auditor")
    page.goto(f"/audit/{approval}")
    expect(page.get_by_test_id("rehearsal")).not_to_have_text("None.")
    # The record page shows the record as a table, its digest shortened.
    expect(page.get_by_test_id("rehearsal")).to_contain_text(short(of_v2, 16))
