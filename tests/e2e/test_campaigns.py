"""In the browser: an operator starts a campaign on the Versions tab, watches
its progress bar reach the end, reads the estimates with the covered paths and the SVG energy
histogram, and is offered per-goal probabilities; a second campaign is cancelled."""

from __future__ import annotations

import json
import re

import pytest
from playwright.sync_api import Page, expect

from .conftest import Server, _api_import
from .screens import tables_fit_each_screen
from .test_roles import sign_in
from .test_vehicle_registry import client, exemplar


def test_operator_runs_reads_and_cancels_campaigns(
        page: Page, server: Server, tmp_path_factory: pytest.TempPathFactory) -> None:
    data = exemplar()
    data["id"] = "e2e-campaigns"
    mission = _api_import(server, json.dumps(data).encode(), "application/json")
    with client(server, "operator") as operator:
        assert operator.post(f"/api/missions/{mission}/versions").status_code == 201

    sign_in(page, "operator")
    page.goto(f"/missions/{mission}")
    page.get_by_role("tab", name=re.compile("^Versions")).click()
    panel = page.get_by_role("region", name="Rehearsal campaigns")
    panel.get_by_role("spinbutton", name="Simulations").fill("3")
    panel.get_by_label("nav_drift").check()
    panel.get_by_role("button", name="Start campaign").click()
    row = panel.get_by_role("row").nth(1)
    expect(row).to_contain_text("finished", timeout=240_000)
    expect(row).to_contain_text("3 / 3")
    # The bar and its count are one figure: "3 / 3" on one line beside the bar, at 1024 too.
    page.set_viewport_size({"width": 1024, "height": 768})
    lines = row.locator(".campaign-progress").evaluate(
        "e => { const r = document.createRange(); r.selectNodeContents(e);"
        " return new Set([...r.getClientRects()].map(b => Math.round(b.bottom))).size; }")
    assert lines == 1, f"the progress cell wraps onto {lines} lines"
    row.get_by_role("button", name="Results").click()
    results = panel.get_by_role("region", name=re.compile("^Campaign "))
    expect(results).to_contain_text(re.compile(r"Paths covered: \d+ of 75"))
    expect(results.get_by_role("img", name=re.compile("Energy used"))).to_be_visible()
    expect(results.locator("svg rect").first).to_be_visible()
    estimates = results.get_by_role("table", name="Estimated probabilities (95% Wilson intervals)")
    expect(estimates.locator("tfoot th")).to_have_text("Any violation")
    tables_fit_each_screen(page, tmp_path_factory, "campaign-results",
                           [(panel.locator("table.campaigns"), panel), (estimates, panel)])
    # Per-goal probabilities are offered only from runs that took more than one path.
    covered = re.search(r"Paths covered: (\d+) of 75", results.inner_text())
    assert covered, results.inner_text()
    if int(covered.group(1)) > 1:
        results.get_by_role("button", name="Offer per-goal probabilities").click()
        expect(results.locator("pre.offered-p")).to_contain_text('"succeed"')
    else:
        expect(results.get_by_test_id("no-offer")).to_be_visible()

    panel.get_by_role("spinbutton", name="Simulations").fill("5000")
    panel.get_by_role("button", name="Start campaign").click()
    running = panel.get_by_role("row").nth(1)
    expect(running).to_contain_text("/ 5000")
    running.get_by_role("button", name="Cancel").click()
    expect(running).to_contain_text("cancelled")
