"""Stored validation reports include the contingency-rule findings (RULES)."""

from __future__ import annotations

from .conftest import World


def test_mission_report_carries_rules_findings(world: World) -> None:
    client = world.client("operator")
    orders = client.get("/api/missions/search-and-sample").json()["orders"]
    orders["id"] = "with-rules"
    orders["rules"] = {
        "observables": ["leak"],
        "defaults": [{"id": "S1", "kind": "safety", "if": ["leak"], "then": "surfaced"}],
    }
    assert client.post("/api/missions", json=orders).status_code == 201
    report = client.get("/api/missions/with-rules/report").json()
    rules = [f for f in report["findings"] if f["code"] == "RULES"]
    assert ("error", ["S1"]) in [(f["severity"], f["subjects"]) for f in rules]
    assert report["ok"] is False
    assert client.get("/api/missions/search-and-sample/report").json()["ok"] is True
