"""The plan view shows each outcome edge's leg and highlights the GEO crossings of a
registry chart, drawn offline on the chart (MapLibre over bundled Natural Earth land). Its own
server: the chart would change what the shared server's other tests see of the exemplar."""

from __future__ import annotations

import json
import subprocess
from collections.abc import Iterator
from pathlib import Path

import pytest
from playwright.sync_api import Browser, expect

from .conftest import (
    PASSWORD,
    PATIENCE_MS,
    Server,
    _api_import,
    _cli,
    _server_env,
    running_server,
    submit_sign_in,
)

KEEP_OUT = {"type": "FeatureCollection", "features": [{
    "type": "Feature", "id": "RANGE",
    "properties": {"title": "Firing range", "kind": "keep_out", "contexts": ["keep_out"]},
    "geometry": {"type": "Polygon", "coordinates": [[
        [-121.845, 36.75], [-121.825, 36.75], [-121.825, 36.77], [-121.845, 36.77],
        [-121.845, 36.75]]]}}]}


@pytest.fixture(scope="module")
def charted_server(tmp_path_factory: pytest.TempPathFactory, server: Server) -> Iterator[Server]:
    data_dir = tmp_path_factory.mktemp("countersign-charts-e2e")
    chart = data_dir / "range.geojson"
    chart.write_text(json.dumps(KEEP_OUT))
    with running_server(data_dir, ["operator", "supervisor"]) as running:
        done = subprocess.run(_cli("charts", "import", str(chart), "--data-dir", str(data_dir)),
                              capture_output=True, text=True, env=_server_env(data_dir),
                              timeout=120)
        assert done.returncode == 0, done.stderr
        yield running


def test_plan_view_highlights_the_legs_that_cross_a_keep_out_chart(
    browser: Browser, charted_server: Server, tmp_path: Path
) -> None:
    from countersign.orders.examples import example_bytes

    mission = _api_import(charted_server, example_bytes("search-and-sample"), "application/json")
    context = browser.new_context(base_url=charted_server.url)
    context.set_default_timeout(PATIENCE_MS)
    page = context.new_page()
    problems: list[str] = []
    page.on("pageerror", lambda error: problems.append(str(error)))
    try:
        page.goto("/")
        submit_sign_in(page, "supervisor", PASSWORD["supervisor"])
        expect(page.get_by_test_id("current-role")).to_have_text("Supervisor")
        page.goto(f"/missions/{mission}?tab=plan")
        plan = page.get_by_role("region", name="Plan view: areas, charts and legs")
        expect(plan).to_have_attribute("data-ready", "true")
        expect(plan.locator("[data-leg]")).to_have_count(12)
        crossing = plan.locator("[data-leg].leg-crossing")
        expect(crossing).to_have_count(4)
        expect(plan.locator('.leg-crossing[data-leg="G4 succeed"]')).to_have_count(1)
        expect(plan.locator('[data-testid="chart-RANGE"][data-crossed="true"]')).to_have_count(1)
        expect(plan.locator('[data-testid="chart-RANGE"]')).to_have_attribute(
            "data-style", "keep_out")
        # The server's land-mask coastline is drawn beside the bundled Natural Earth land.
        assert int(plan.get_attribute("data-coastline-segments") or "0") > 0
        expect(plan).to_have_attribute("data-land", "natural-earth-50m")
        crossings = page.get_by_role("list", name="Crossings")
        expect(crossings.get_by_role("listitem")).to_have_count(4)
        expect(crossings).to_contain_text("chart RANGE (Firing range)")
        assert not problems, problems
    finally:
        context.close()
