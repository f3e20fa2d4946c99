from __future__ import annotations

from typing import Any

from countersign.orders.examples import load_example
from countersign.orders.model import Orders
from countersign.verify.report import validate


def _mission(budget: dict[str, float], costs: dict[str, dict[str, float] | None]) -> Orders:
    edges = {"G1": ("G2", "G3", "ABORT"), "G2": ("COMPLETE", "G3", "ABORT"),
             "G3": ("COMPLETE", "ABORT", "ABORT")}
    goals: list[dict[str, Any]] = []
    for gid, (s, f, v) in edges.items():
        goal: dict[str, Any] = {"id": gid, "next": {"succeed": s, "fail": f, "violate": v}}
        if costs.get(gid) is not None:
            goal["cost"] = costs[gid]
        goals.append(goal)
    return Orders.model_validate({
        "id": "b", "start": "G1", "vehicle": "v", "goals": goals,
        "vehicles": [{"id": "v", "budget": budget}],
    })


def test_worst_path_exceeding_budget_is_the_counterexample() -> None:
    orders = _mission({"energy_wh": 100},
                      {"G1": {"energy_wh": 10}, "G2": {"energy_wh": 50}, "G3": {"energy_wh": 45}})
    report = validate(orders)
    budget = [f for f in report.findings if f.code == "BUDGET"]
    assert len(budget) == 1 and budget[0].severity == "error"
    # G1 -> G2 -> G3 costs 105 Wh: the only path over budget.
    assert budget[0].subjects == ("G1", "G2", "G3", "COMPLETE")
    assert budget[0].details["path"]["outcomes"] == ["succeed", "fail", "succeed"]
    assert "105 Wh" in budget[0].message and "100 Wh" in budget[0].message
    assert report.costs is not None and report.costs["energy_wh"].total == 105


def test_within_budget_has_no_finding() -> None:
    orders = _mission({"energy_wh": 105},
                      {"G1": {"energy_wh": 10}, "G2": {"energy_wh": 50}, "G3": {"energy_wh": 45}})
    assert [f for f in validate(orders).findings if f.code == "BUDGET"] == []


def test_unknown_costs_are_a_warning() -> None:
    orders = _mission({"duration_s": 100}, {"G1": {"duration_s": 10}, "G2": None, "G3": None})
    findings = [f for f in validate(orders).findings if f.code == "BUDGET"]
    assert [(f.severity, f.subjects) for f in findings] == [("warning", ("G2", "G3"))]


def test_costs_estimated_from_area_and_vehicle() -> None:
    orders = Orders.model_validate({
        "id": "e", "start": "G1", "vehicle": "v",
        "goals": [{"id": "G1", "area": "A", "behavior": "transit",
                   "next": {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"}}],
        "areas": [{"id": "A", "polygon": [[36.7, -121.9], [36.7, -121.89], [36.69, -121.89],
                                          [36.69, -121.9]]}],
        "vehicles": [{"id": "v", "speed_mps": 2.0, "power_w": 100,
                      "budget": {"energy_wh": 1}}],
    })
    report = validate(orders)
    assert report.costs is not None
    worst = report.costs["duration_s"]
    # Perimeter of a ~890 m x ~1110 m box is about 4 km: about 2,000 s at 2 m/s.
    assert 1900 < worst.total < 2100 and worst.estimated == ("G1",)
    assert any(f.code == "BUDGET" and f.severity == "error" for f in report.findings)


def test_exemplar_is_within_budget() -> None:
    report = validate(load_example("search-and-sample"))
    assert report.ok and report.costs is not None
    assert report.costs["energy_wh"].goals == ("G1", "G2", "G3", "G4", "G5")
