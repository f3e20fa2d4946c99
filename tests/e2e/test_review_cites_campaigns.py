"""In the browser: a campaign attached to a submission is shown on the review,
with its record digest and estimates, above the decision that will cite it."""

from __future__ import annotations

import json
import secrets
import time

from playwright.sync_api import Page, expect

from .conftest import Server, _api_import
from .test_approval_flow import bypass
from .test_roles import sign_in
from .test_vehicle_registry import client, exemplar


def test_the_review_shows_the_campaigns_the_signature_cites(page: Page, server: Server) -> None:
    data = exemplar()
    data["id"] = f"e2e-cited-{secrets.token_hex(3)}"
    mission = _api_import(server, json.dumps(data).encode(), "application/json")
    with client(server, "operator") as operator:
        assert operator.post(f"/api/missions/{mission}/versions").status_code == 201
        started = operator.post(f"/api/missions/{mission}/versions/1/campaigns",
                                json={"simulations": 3})
        assert started.status_code == 201, started.text
        campaign = started.json()["id"]
        deadline = time.monotonic() + 600  # a generous wait for three simulations, not a bound
        while (body := operator.get(f"/api/campaigns/{campaign}").json())["state"] in (
                "queued", "running"):
            assert time.monotonic() < deadline, body
            time.sleep(0.5)
        assert body["state"] == "finished", body
        submitted = operator.post(f"/api/missions/{mission}/versions/1/submit")
        assert submitted.status_code == 201, submitted.text
        attached = operator.post(f"/api/submissions/{submitted.json()['id']}/campaigns",
                                 json={"campaign": campaign})
        assert attached.status_code == 201, attached.text

    sign_in(page, "supervisor")
    page.goto(f"/missions/{mission}/versions/1/review")
    cited = page.get_by_test_id("review-campaigns")
    expect(cited).to_contain_text(f"Campaign {campaign}, record sha256:")
    expect(cited.get_by_role("table")).to_contain_text("Any violation")
    expect(cited.get_by_role("button", name="Offer per-goal probabilities")).to_have_count(0)
    expect(page.get_by_test_id("review-rehearsal")).to_contain_text("none attached")

    # A database writer who is not the app edits the record: the review withholds the
    # results, says why, and shows no estimate the digest does not cover.
    bypass(server, "campaigns",
           "UPDATE campaigns SET record = json_set(record, '$.simulations', 1000) WHERE id = ?",
           campaign)
    page.reload()
    expect(cited.get_by_role("alert")).to_contain_text("does not hash to its digest")
    expect(cited.get_by_role("table")).to_have_count(0)
