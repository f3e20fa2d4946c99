"""In the browser: the printable approval document of a version, reached from
the Versions tab. Changing only a condition (depth_m >= 20 to >= 0.5 under the same text)
changes the plain orders, the review and the document; printing shows the document alone
(print CSS, checked with Chromium's print media and its PDF)."""

from __future__ import annotations

import json

from playwright.sync_api import Page, expect

from .conftest import Server, _api_import
from .test_roles import sign_in
from .test_vehicle_registry import approve, client, exemplar

TWENTY = "(`depth_m >= 20`)"
HALF = "(`depth_m >= 0.5`)"


def _mission(server: Server, mission: str, expr: str) -> tuple[int, str]:
    data = exemplar()
    data["id"] = mission
    data["constraints"][6]["expr"] = expr  # its text still says 20 meters
    _api_import(server, json.dumps(data).encode(), "application/json")
    with client(server, "operator") as operator:
        made = operator.post(f"/api/missions/{mission}/versions")
        assert made.status_code == 201, made.text
        submitted = operator.post(f"/api/missions/{mission}/versions/1/submit")
        assert submitted.status_code == 201, submitted.text
        return int(submitted.json()["id"]), str(made.json()["digest"])


def test_changing_only_a_condition_changes_orders_review_and_document(
        page: Page, server: Server) -> None:
    twenty, twenty_digest = _mission(server, "e2e-doc-20", "depth_m >= 20")
    _half, half_digest = _mission(server, "e2e-doc-half", "depth_m >= 0.5")
    approve(server, twenty, reason="depth limit checked")

    sign_in(page, "supervisor")
    page.goto("/missions/e2e-doc-20?tab=versions")
    page.get_by_role("link", name="Printable approval document of v1").click()
    document = page.get_by_test_id("approval-document")
    expect(document.get_by_role("heading", name="Approval document: e2e-doc-20 v1")).to_be_visible()
    expect(document.get_by_role("region", name="Version")).to_contain_text(twenty_digest)
    orders = document.get_by_role("region", name="Plain-language orders")
    expect(orders).to_contain_text(TWENTY)
    expect(orders).not_to_contain_text(HALF)
    expect(document.get_by_role("region", name="Paths by terminal")).to_contain_text("path(s)")
    expect(document.get_by_role("region", name="Rehearsal")).to_contain_text("None")
    expect(document.get_by_role("region", name="Decision")).to_contain_text("Approved")
    expect(document.get_by_role("region", name="Decision")).to_contain_text("depth limit checked")
    signer = document.get_by_role("region", name="Signer")
    expect(signer).to_contain_text("Signed by supervisor")
    expect(signer).to_contain_text("Key fingerprint")

    # Print: the app's header and the page's buttons are hidden, the document is shown.
    page.emulate_media(media="print")
    expect(page.get_by_role("navigation", name="Main")).to_be_hidden()
    expect(page.get_by_role("button", name="Print")).to_be_hidden()
    expect(orders).to_be_visible()
    pdf = page.pdf(format="A4")
    assert pdf.startswith(b"%PDF") and len(pdf) > 5000
    page.emulate_media(media="screen")

    page.goto("/missions/e2e-doc-half/versions/1/document")
    orders = page.get_by_test_id("approval-document").get_by_role(
        "region", name="Plain-language orders")
    expect(orders).to_contain_text(HALF)
    expect(orders).not_to_contain_text(TWENTY)
    expect(page.get_by_role("region", name="Version")).to_contain_text(half_digest)
    expect(page.get_by_role("region", name="Findings")).to_contain_text("TEXT")
    expect(page.get_by_role("region", name="Decision")).to_contain_text("Not decided yet")

    page.goto("/missions/e2e-doc-half/versions/1/review")
    expect(page.get_by_test_id("review-plain")).to_contain_text(HALF)
    page.goto("/missions/e2e-doc-half?tab=orders")
    expect(page.get_by_test_id("plain-orders")).to_contain_text(HALF)
    page.goto("/missions/e2e-doc-20?tab=orders")
    expect(page.get_by_test_id("plain-orders")).to_contain_text(TWENTY)
