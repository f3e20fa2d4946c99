"""Incremental validation equals validation from scratch.

A generated mission is validated, then edited at random (a description, a goal's title, cost,
outcome probabilities, successor, requirements, envelope, behavior; a constraint's scope or
expression; a feature; a norm; a path property; the vehicle's budget) and validated again
after each edit, with one PartsCache and LogicCache kept across the sequence; every report
must equal a report from scratch (fresh caches): findings with their details, paths, costs and
probabilities alike.
"""

from __future__ import annotations

import copy
from typing import Any

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from countersign.orders.model import Orders
from countersign.verify.logic import LogicCache
from countersign.verify.parts import PartsCache, part_keys
from countersign.verify.report import validate

from ..bench.bench_meo import meo_mission

GOAL_EDITS = ("title", "description", "cost", "p", "next", "requires", "envelope", "behavior")
MISSION_EDITS = ("description", "title", "constraint_scope", "constraint_expr", "feature",
                 "norm", "property", "vehicle_budget")


def scratch(orders: Orders) -> dict[str, Any]:
    return validate(orders, logic_cache=LogicCache(), parts=PartsCache()).to_json()


def edit(draw: st.DrawFn, data: dict[str, Any]) -> None:
    goals = data["goals"]
    ids = [g["id"] for g in goals]
    if draw(st.booleans()):
        goal = goals[draw(st.integers(0, len(goals) - 1))]
        what = draw(st.sampled_from(GOAL_EDITS))
        if what in ("title", "description"):
            goal[what] = draw(st.sampled_from(["", "Survey the bay", "Goal x"]))
        elif what == "cost":
            goal["cost"] = {"energy_wh": draw(st.integers(0, 10**9)),
                            "duration_s": draw(st.integers(0, 5000))}
        elif what == "p":
            goal["p"] = draw(st.sampled_from([{"succeed": 0.8, "fail": 0.15, "violate": 0.05},
                                              {"succeed": 1, "fail": 0, "violate": 0}]))
        elif what == "next":
            outcome = draw(st.sampled_from(["succeed", "fail", "violate"]))
            goal["next"][outcome] = draw(st.sampled_from([*ids, "COMPLETE", "ABORT", "X"]))
        elif what == "requires":
            goal["requires"] = draw(st.lists(st.sampled_from(["transit", "sample", "tow"]),
                                             max_size=2))
        elif what == "envelope":
            goal["envelope"] = {"depth_m": draw(st.sampled_from([[0, 5], [30, 40], [0, 300]]))}
        else:
            goal["behavior"] = draw(st.sampled_from(["survey", "transit", "loiter"]))
        return
    what = draw(st.sampled_from(MISSION_EDITS))
    constraints = data["constraints"]
    if what in ("description", "title"):
        data[what] = draw(st.sampled_from(["", "Harbour survey", "Edited"]))
    elif what == "constraint_scope":
        constraints[draw(st.integers(0, len(constraints) - 1))]["applies_to"] = draw(
            st.one_of(st.just("mission"),
                      st.lists(st.sampled_from([*ids, "COMPLETE", "X"]), max_size=2)))
    elif what == "constraint_expr":
        constraints[draw(st.integers(0, len(constraints) - 1))]["expr"] = draw(st.sampled_from(
            ["depth_m >= 20", "depth_m <= 10", "speed_mps > 1", "depth_m >= 20 and depth_m < 5",
             "systems_ok"]))
    elif what == "feature":
        feature = data["vehicles"][0]["features"][draw(st.integers(0, 3))]
        feature["measures"] = draw(st.lists(st.sampled_from(
            ["depth_m", "nav_error_m", "lane_distance_m", "speed_mps"]), max_size=3))
        feature["fulfills"] = draw(st.lists(st.sampled_from(
            ["transit", "area_search", "sample", "rendezvous"]), max_size=3))
    elif what == "norm":
        data["norms"] = [{"id": "N1", "context": "true",
                          "forbidden": draw(st.sampled_from(["depth_m < 20", "depth_m > 1000"]))}]
    elif what == "property":
        data["properties"] = [{"id": "P1", "never": draw(st.sampled_from(
            ["depth_m < 0", "depth_m > 10"]))}]
    else:
        data["vehicles"][0]["budget"] = {"energy_wh": draw(st.sampled_from([1, 10**6]))}


@st.composite
def edit_sequences(draw: st.DrawFn) -> list[Orders]:
    data = meo_mission(draw(st.integers(3, 25)), seed=draw(st.integers(0, 5))).model_dump(
        mode="json", exclude_unset=True)
    versions = [Orders.model_validate(data)]
    for _ in range(draw(st.integers(1, 6))):
        data = copy.deepcopy(data)
        edit(draw, data)
        versions.append(Orders.model_validate(data))
    return versions


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(edit_sequences())
def test_incremental_reports_equal_reports_from_scratch(versions: list[Orders]) -> None:
    parts, logic = PartsCache(), LogicCache()
    for orders in versions:
        incremental = validate(orders, logic_cache=logic, parts=parts).to_json()
        assert incremental == scratch(orders)


def test_a_description_edit_hits_every_part_and_a_cost_edit_only_misses_core() -> None:
    data = meo_mission(20).model_dump(mode="json", exclude_unset=True)
    parts = PartsCache()
    validate(Orders.model_validate(data), parts=parts)
    data["description"] = "edited"
    data["goals"][3]["description"] = "edited too"
    before = parts.misses
    validate(Orders.model_validate(data), parts=parts)
    assert parts.misses == before
    data["goals"][3]["cost"] = {"energy_wh": 7}
    first = part_keys(Orders.model_validate(data))
    validate(Orders.model_validate(data), parts=parts)
    assert parts.misses == before + 1  # core only: MEO and logic read no costs
    assert part_keys(Orders.model_validate(data)) == first


def test_a_warm_cache_names_the_witness_a_cold_run_names() -> None:
    """Found by the property above: z3's model depends on the terms its context made before,
    so a witness solved in the shared session after a cache spared some units named depth 11 m
    where a cold run named 20 m. Witnesses are solved in a context of the unit's own."""
    data = meo_mission(3, seed=0).model_dump(mode="json", exclude_unset=True)
    versions = [Orders.model_validate(data)]
    data = copy.deepcopy(data)
    next(c for c in data["constraints"] if c["id"] == "health")["expr"] = "depth_m <= 10"
    versions.append(Orders.model_validate(data))
    data = copy.deepcopy(data)
    data["properties"] = [{"id": "P1", "never": "depth_m > 10"}]
    versions.append(Orders.model_validate(data))
    parts, logic = PartsCache(), LogicCache()
    for orders in versions:
        incremental = validate(orders, logic_cache=logic, parts=parts).to_json()
        assert incremental == scratch(orders)
    assert any(f["code"] == "PROPERTY" and "witness" in f["details"]
               for f in incremental["findings"])
