"""Refined orders over the API: validation, the paths pages and traces read the flat
mission, and an unbounded loop inside a refinement is a REFINE finding, not a 500."""

from __future__ import annotations

import json

from countersign.orders.examples import example_bytes

from .conftest import World

REFINED = "search-and-sample-refined"


def test_validate_and_paths_of_refined_orders(world: World) -> None:
    client = world.client("operator")
    orders = json.loads(example_bytes(REFINED))
    report = client.post("/api/validate", json=orders).json()
    assert report["ok"] is True and report["paths"]["count"] == 867
    assert client.post("/api/missions", json=orders).status_code == 201
    page = client.get(f"/api/missions/{REFINED}/paths", params={"limit": 1}).json()
    assert page["count"] == 867
    assert page["items"][0]["goals"][:2] == ["G1/G1.1#1", "G1/G1.2#2"]
    trace = client.get(f"/api/missions/{REFINED}/paths", params={"format": "trace", "limit": 1})
    assert "\n  Commence: Move to the next unvisited cell of Area A.\n" in trace.text


def test_unbounded_loop_is_a_finding(world: World) -> None:
    orders = json.loads(example_bytes(REFINED))
    refinement = orders["goals"][0]["refines"]
    del refinement["within"], refinement["on_timeout"]
    response = world.client("operator").post("/api/validate", json=orders)
    assert response.status_code == 200
    report = response.json()
    assert report["ok"] is False and report["paths"] is None
    assert any(f["code"] == "REFINE" and f["severity"] == "error" for f in report["findings"])


def test_a_bad_time_out_is_422_naming_where(world: World) -> None:
    orders = json.loads(example_bytes(REFINED))
    orders["goals"][0]["refines"]["within"] = {"steps": 0}
    response = world.client("operator").post("/api/validate", json=orders)
    assert response.status_code == 422
    assert "within" in response.text and "steps" in response.text
