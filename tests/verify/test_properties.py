"""Path properties (PROPERTY): state properties and resource bounds over every path, with the
shortest counterexample, checked against brute-force enumeration of all paths."""

from __future__ import annotations

import copy
import json
from collections.abc import Callable
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from countersign.orders.examples import example_bytes, example_names, load_example
from countersign.orders.model import OUTCOMES, Orders
from countersign.verify.costs import mission_costs
from countersign.verify.graph import build_graph
from countersign.verify.logic import LogicCache, check_logic
from countersign.verify.paths import count_paths, iter_paths
from countersign.verify.properties import check_properties, shortest_exceeding_path

HARBOR: dict[str, Any] = json.loads(example_bytes("harbor-approach-survey"))
EXEMPLAR: dict[str, Any] = json.loads(example_bytes("search-and-sample"))


def with_properties(props: list[dict[str, Any]], base: dict[str, Any] = HARBOR,
                    change: Callable[[dict[str, Any]], None] | None = None) -> Orders:
    data = copy.deepcopy(base)
    data["properties"] = props
    if change is not None:
        change(data)
    return Orders.model_validate(data)


@pytest.mark.parametrize("name", example_names())
def test_examples_have_no_property_findings(name: str) -> None:
    assert check_properties(load_example(name)) == []


def test_never_surface_in_the_lane_fails_with_the_shortest_counterexample() -> None:
    def surfacing_in_lane(data: dict[str, Any]) -> None:
        next(g for g in data["goals"] if g["id"] == "G7")["area"] = "LANE"

    orders = with_properties(
        [{"id": "P1", "text": "No surfacing in the ship channel",
          "always": "not (behavior == 'surface_report' and context('shipping_lane'))"}],
        change=surfacing_in_lane,
    )
    [finding] = check_properties(orders)
    assert finding.code == "PROPERTY" and finding.severity == "error"
    assert finding.subjects == ("G1", "G7", "ABORT")
    assert finding.details["path"] == {"goals": ["G1", "G7"], "outcomes": ["violate", "fail"],
                                       "terminal": "ABORT"}
    assert finding.message.startswith(
        "P1 (No surfacing in the ship channel) fails at G7: G7 Surface clear of the channel and "
        "report position has behavior 'surface_report' and San Diego Bay main ship channel is "
        "a shipping lane, but P1 requires not (behavior is 'surface_report' and in a shipping "
        "lane) always."
    )
    assert finding.message.endswith("Shortest counterexample: G1 violate, G7 fail -> ABORT.")
    # As ordered (G7 in the holding box), the property holds on every path.
    assert check_properties(with_properties(
        [{"id": "P1", "never": "behavior == 'surface_report' and context('shipping_lane')"}]
    )) == []


def test_quantity_property_uses_the_goal_states_the_orders_allow() -> None:
    orders = with_properties([{"id": "P2", "always": "depth_m <= 19"}])
    [finding] = check_properties(orders)
    # G3 (12-20 m) is the only goal whose orders allow more than 19 m.
    assert finding.details["goal"] == "G3"
    assert finding.details["failing_goals"] == ["G3"]
    assert float(finding.details["witness"]["depth_m"]) > 19
    assert finding.details["path"]["goals"][:3] == ["G1", "G2", "G3"]
    # Constraints in scope bound the states too: a wider envelope for the channel crossing G4
    # still keeps 10 m or more, because C5 (depth >= 10 on G4) ends the goal otherwise.
    lane_depth = [{"id": "P3", "never": "depth_m < 10 and context('shipping_lane')"}]

    def wider(data: dict[str, Any]) -> None:
        next(g for g in data["goals"] if g["id"] == "G4")["envelope"]["depth_m"] = [5, 14]

    assert check_properties(with_properties(lane_depth, change=wider)) == []

    def unmonitored(data: dict[str, Any]) -> None:
        wider(data)
        next(c for c in data["constraints"] if c["id"] == "C5")["applies_to"] = ["G8"]

    [finding] = check_properties(with_properties(lane_depth, change=unmonitored))
    assert finding.details["goal"] == "G4"


def test_resource_bound_finds_the_shortest_path_over_the_bound() -> None:
    orders = with_properties([{"id": "P4", "text": "Energy within 2.5 kWh",
                               "max": {"energy_wh": 2500}}])
    [finding] = check_properties(orders)
    assert finding.details["shortest"] is True
    assert finding.details["total"] > 2500
    graph = build_graph(orders)
    counts = count_paths(graph)
    assert counts is not None
    # Each path costs its goals and the legs it takes, as BUDGET charges them.
    costs, goals = mission_costs(orders), orders.goal_index()
    totals = {p.index: sum(costs.step(goals[g], o, "energy_wh")
                           for g, o in zip(p.goals, p.outcomes, strict=True))
              for p in iter_paths(graph, counts)}
    over = [p for p in iter_paths(graph, counts) if totals[p.index] > 2500]
    assert len(finding.details["path"]["goals"]) == min(len(p.goals) for p in over)
    shown = next(p for p in over if list(p.goals) == finding.details["path"]["goals"]
                 and list(p.outcomes) == finding.details["path"]["outcomes"])
    assert finding.details["total"] == round(totals[shown.index], 6)
    assert any(sum(goals[g].cost.energy_wh or 0 for g in p.goals  # type: ignore[union-attr]
                   ) <= 2500 for p in over), "the legs decide some path"
    assert check_properties(with_properties([{"id": "P4", "max": {"energy_wh": 5000}}])) == []


def test_bad_properties_are_expr_findings() -> None:
    orders = with_properties([
        {"id": "P1", "always": "depth_m >="},
        {"id": "P2", "max": {"fuel_l": 3}},
        {"id": "P3", "max": {"energy_wh": -1}},
        {"id": "P4", "text": "nothing"},
        {"id": "P5", "never": "depht_m < 3"},
    ])
    messages = [f.message for f in check_properties(orders)]
    assert messages == [
        "P1 always, column 11: expected a value after '>='",
        "P5 never, column 1: unknown quantity 'depht_m' (did you mean 'depth_m'?)",
        "P2 max: unknown resource 'fuel_l'; use energy_wh or duration_s.",
        "P3 max: the bound for energy_wh must be a number of at least 0.",
        "P4 states nothing: give 'always', 'never' or 'max'.",
    ]


def test_property_results_share_the_logic_cache() -> None:
    orders = with_properties([{"id": "P2", "always": "depth_m <= 19"}])
    cache = LogicCache()
    check_logic(orders, cache)
    first = check_properties(orders, cache=cache)
    misses = cache.misses
    assert check_properties(orders, cache=cache) == first
    assert cache.misses == misses


# Against brute force on random DAGs -------------------------------------------------------------


@st.composite
def random_mission(draw: st.DrawFn) -> Orders:
    size = draw(st.integers(2, 9))
    goals = []
    for index in range(size):
        nxt: dict[str, str] = {}
        for k, outcome in enumerate(OUTCOMES):
            later = list(range(index + 1, size))
            if later and draw(st.integers(0, 3)) > 0:
                nxt[outcome] = f"G{draw(st.sampled_from(later))}"
            else:
                nxt[outcome] = "COMPLETE" if k == 0 else "ABORT"
        goals.append({
            "id": f"G{index}", "behavior": draw(st.sampled_from(["transit", "surface"])),
            "area": draw(st.sampled_from(["LANE", "OPEN"])),
            "envelope": {"depth_m": [draw(st.integers(0, 10)), draw(st.integers(10, 30))]},
            "cost": {"energy_wh": draw(st.integers(0, 100))}, "next": nxt,
        })
    return Orders.model_validate({
        "id": "random", "start": "G0", "goals": goals,
        # Places and a vehicle with a speed and a power: the edges between them have legs.
        "areas": [{"id": "LANE", "contexts": ["shipping_lane"],
                   "polygon": [[36.75, -121.95], [36.75, -121.94], [36.745, -121.94],
                               [36.745, -121.95]]},
                  {"id": "OPEN", "polygon": [[36.70, -121.90], [36.70, -121.89],
                                             [36.695, -121.89], [36.695, -121.90]]}],
        "vehicle": "auv", "vehicles": [{"id": "auv", "speed_mps": 1.5, "power_w": 110}],
        "properties": [
            {"id": "P1", "never": "behavior == 'surface' and context('shipping_lane')"},
            {"id": "P2", "always": f"depth_m <= {draw(st.integers(10, 30))}"},
            {"id": "P3", "max": {"energy_wh": draw(st.integers(0, 400))}},
        ],
    })


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(random_mission())
def test_counterexamples_match_brute_force(orders: Orders) -> None:
    graph = build_graph(orders)
    counts = count_paths(graph)
    assert counts is not None
    paths = list(iter_paths(graph, counts))
    goals = orders.goal_index()
    lane = {g.id for g in orders.goals if g.area == "LANE"}
    bound_p2 = float(orders.properties[1].always.split("<=")[1])  # type: ignore[union-attr]

    def surfaces_in_lane(gid: str) -> bool:
        return goals[gid].behavior == "surface" and gid in lane

    def too_deep(gid: str) -> bool:
        return goals[gid].envelope["depth_m"][1] > bound_p2

    bad: dict[str, Callable[[str], bool]] = {"P1": surfaces_in_lane, "P2": too_deep}
    costs = mission_costs(orders)

    def energy(path: Any) -> float:
        return sum(costs.step(goals[g], o, "energy_wh")
                   for g, o in zip(path.goals, path.outcomes, strict=True))

    bound_p3 = orders.properties[2].model_extra["max"]["energy_wh"]  # type: ignore[index]
    findings = {f.details["property"]: f for f in check_properties(orders)}
    for pid, fails in bad.items():
        failing = [p for p in paths if any(fails(g) for g in p.goals)]
        assert (pid in findings) == bool(failing), pid
        if failing:
            path = findings[pid].details["path"]
            assert any(fails(g) for g in path["goals"])
            assert len(path["goals"]) == min(len(p.goals) for p in failing)
            assert any(list(p.goals) == path["goals"] and list(p.outcomes) == path["outcomes"]
                       for p in failing)
    over = [p for p in paths if energy(p) > bound_p3]
    assert ("P3" in findings) == bool(over)
    if over:
        path = findings["P3"].details["path"]
        assert len(path["goals"]) == min(len(p.goals) for p in over)
        shown = next(p for p in over if list(p.goals) == path["goals"]
                     and list(p.outcomes) == path["outcomes"])
        assert energy(shown) > bound_p3


def test_shortest_exceeding_path_falls_back_on_huge_graphs(monkeypatch: pytest.MonkeyPatch
                                                          ) -> None:
    from countersign.verify import properties

    orders = with_properties([], base=EXEMPLAR)
    graph = build_graph(orders)
    costs = [g.cost.energy_wh if g.cost and g.cost.energy_wh else 0.0 for g in graph.goals]
    exact = shortest_exceeding_path(graph, costs, 300)
    assert exact is not None and exact[2] is True
    monkeypatch.setattr(properties, "MAX_LAYER_WORK", 0)
    fallback = shortest_exceeding_path(graph, costs, 300)
    assert fallback is not None and fallback[2] is False and fallback[1] > 300
    assert shortest_exceeding_path(graph, costs, 10_000) is None
