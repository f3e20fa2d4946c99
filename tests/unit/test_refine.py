"""Refinement (issue 37): the refined mission's paths, traces and budgets equal a brute-force
run of the nested orders (tests/unit/refine_brute.py), and REFINE holds its rules."""

from __future__ import annotations

import copy
import json
import math
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from countersign.orders.examples import example_bytes, load_example
from countersign.orders.model import OUTCOMES, Orders
from countersign.orders.reader import read_json
from countersign.verify.budget import worst_paths
from countersign.verify.paths import count_paths, iter_paths, trace_text
from countersign.verify.refine import base_id, checked_form, flatten
from countersign.verify.report import validate

from .refine_brute import Legs, runs

REFINED = "search-and-sample-refined"


def _orders(data: dict[str, Any]) -> Orders:
    return read_json(json.dumps(data).encode())


def _assert_equal_to_brute_force(orders: Orders, legs: bool = True) -> int:
    flat_orders, graph = checked_form(orders)
    counts = count_paths(graph)
    assert counts is not None
    brute = list(runs(orders))
    assert counts.total == len(brute)
    by_terminal = {t: sum(r.terminal == t for r in brute) for t in counts.by_terminal}
    assert counts.by_terminal == by_terminal
    for path, run in zip(iter_paths(graph, counts), brute, strict=True):
        assert tuple(base_id(g) for g in path.goals) == run.goals
        assert path.outcomes == run.outcomes and path.terminal == run.terminal
        assert trace_text(graph, path) == run.trace(path.index)
    worst = worst_paths(flat_orders, graph)
    assert worst is not None
    priced = Legs(orders)
    for quantity, found in worst.items():
        expected = max(priced.total(run, quantity) for run in brute)
        assert math.isclose(found.total, expected, rel_tol=1e-9, abs_tol=1e-9), quantity
    return len(brute)


def test_refined_exemplar_equals_brute_force() -> None:
    orders = load_example(REFINED)
    assert _assert_equal_to_brute_force(orders) == 867


def test_refined_exemplar_report() -> None:
    report = validate(load_example(REFINED))
    assert report.ok, [f.message for f in report.findings]
    assert report.paths is not None and report.paths.total == 867
    assert report.paths.by_terminal == {"COMPLETE": 289, "ABORT": 578}


def _search_loop(within: dict[str, Any] | None) -> dict[str, Any]:
    data = json.loads(example_bytes(REFINED))
    refinement = data["goals"][0]["refines"]
    if within is None:
        del refinement["within"], refinement["on_timeout"]
    else:
        refinement["within"] = within
    return data


def test_unbounded_loop_is_refine_and_not_counted() -> None:
    report = validate(_orders(_search_loop(None)))
    refine = [f for f in report.findings if f.code == "REFINE"]
    assert refine and all(f.severity == "error" for f in refine)
    assert any("G1/G1.1" in f.subjects and "time-out" in f.message for f in refine)
    assert report.paths is None


@pytest.mark.parametrize("steps", [1, 2, 3, 5])
def test_loop_with_steps_is_counted_as_its_unrolling(steps: int) -> None:
    orders = _orders(_search_loop({"steps": steps}))
    report = validate(orders)
    assert not [f for f in report.findings if f.code == "REFINE"]
    assert report.paths is not None
    assert report.paths.total == _assert_equal_to_brute_force(orders)


def test_loop_with_duration_is_counted_as_its_unrolling() -> None:
    orders = _orders(_search_loop({"duration_s": 1500}))
    report = validate(orders)
    assert not [f for f in report.findings if f.code == "REFINE"], report.findings
    assert report.paths is not None
    assert report.paths.total == _assert_equal_to_brute_force(orders)
    # G1.1 (300 s) and G1.2 (600 s) end after 900 s: a third goal still commences, as the
    # time-out is checked before each goal; after 1,500 s none does.
    assert any("@900s" in g for g in flatten(orders).orders.goal_index())


def test_terminal_that_returns_nothing_or_an_unused_outcome() -> None:
    data = _search_loop({"steps": 3})
    terminals = data["goals"][0]["refines"]["terminals"]
    del terminals[0]["returns"]
    terminals[1]["returns"] = "explode"
    report = validate(_orders(data))
    messages = [f.message for f in report.findings if f.code == "REFINE"]
    assert any("G1/FOUND returns no outcome" in m for m in messages)
    assert any("'explode', which is not an outcome" in m for m in messages)
    data = _search_loop({"steps": 3})
    data["goals"][0]["next"].pop("violate")
    messages = [f.message for f in validate(_orders(data)).findings if f.code == "REFINE"]
    assert any("G1/HALT returns violate, but G1 names no successor" in m for m in messages)


def test_time_out_needs_an_outcome_and_durations() -> None:
    data = _search_loop({"duration_s": 600})
    refinement = data["goals"][0]["refines"]
    del refinement["on_timeout"]
    del refinement["goals"][2]["cost"], refinement["goals"][2]["area"]  # nothing to estimate
    codes = [(f.code, f.subjects) for f in validate(_orders(data)).findings]
    assert ("REFINE", ("G1",)) in codes
    assert ("REFINE", ("G1/G1.3", "G1")) in codes


def test_inner_structure_is_checked_as_orders() -> None:
    data = _search_loop({"steps": 3})
    refinement = data["goals"][0]["refines"]
    refinement["goals"][0]["next"]["fail"] = "NOWHERE"
    refinement["goals"][2]["next"].pop("violate")
    findings = validate(_orders(data)).findings
    assert any(f.code == "G3" and "G1/G1.1" in f.subjects for f in findings)
    assert any(f.code == "SINK" and "G1/G1.3" in f.subjects for f in findings)


def test_parent_constraints_apply_inside() -> None:
    flat = flatten(load_example(REFINED))
    c4 = next(c for c in flat.representative.constraints if c.id == "C4")
    assert isinstance(c4.applies_to, list)
    assert {"G1/G1.1", "G1/G1.2", "G1/G1.3", "G2"} <= set(c4.applies_to)
    assert "G1" not in c4.applies_to


def test_inner_goal_needs_the_vehicle_capability() -> None:
    data = _search_loop({"steps": 3})
    data["goals"][0]["refines"]["goals"][1]["requires"] = ["magic"]
    findings = validate(_orders(data)).findings
    assert any(f.code == "M7" and "G1/G1.2" in f.subjects for f in findings)


def test_unrolling_is_bounded() -> None:
    data = _search_loop({"steps": 10_000})
    # Nest the loop so that its unrolling multiplies past the bound.
    inner = copy.deepcopy(data["goals"][0]["refines"])
    data["goals"][0]["refines"]["goals"][1]["refines"] = inner
    report = validate(_orders(data))
    assert any(f.code == "REFINE" and "more than" in f.message for f in report.findings)
    assert report.paths is None


# --- random small refinements against the brute force -------------------------------------

def _level(draw: Any, prefix: str, depth: int, used: list[str]) -> dict[str, Any]:
    size = draw(st.integers(1, 3))
    ids = [f"{prefix}{i}" for i in range(1, size + 1)]
    terminal_count = draw(st.integers(1, 3))
    terminals = [{"id": f"T{prefix}{j}", "kind": draw(st.sampled_from(["complete", "abort"])),
                  "returns": draw(st.sampled_from(used))} for j in range(terminal_count)]
    kind = draw(st.sampled_from(["none", "steps", "duration"]))
    goals = []
    for i, goal_id in enumerate(ids):
        later = ids[i + 1:] if kind == "none" else ids
        targets = [*later, *(t["id"] for t in terminals)]
        goal: dict[str, Any] = {
            "id": goal_id, "title": f"Goal {goal_id}",
            "next": {o: draw(st.sampled_from(targets)) for o in OUTCOMES},
            "cost": {"energy_wh": draw(st.integers(0, 9)), "duration_s": draw(st.integers(1, 5))},
        }
        if depth < 2 and kind != "duration" and draw(st.integers(0, 4)) == 0:
            del goal["cost"]
            goal["refines"] = _level(draw, goal_id + ".", depth + 1,
                                     [o for o in OUTCOMES if goal["next"][o]])
        goals.append(goal)
    refinement: dict[str, Any] = {"start": ids[0], "goals": goals, "terminals": terminals}
    if kind == "steps":
        refinement["within"] = {"steps": draw(st.integers(1, 4))}
    elif kind == "duration":
        refinement["within"] = {"duration_s": draw(st.integers(1, 8))}
    if kind != "none":
        refinement["on_timeout"] = draw(st.sampled_from(["fail", "violate"]))
    return refinement


@st.composite
def refined_orders(draw: Any) -> Orders:
    size = draw(st.integers(1, 3))
    ids = [f"G{i}" for i in range(1, size + 1)]
    goals = []
    for i, goal_id in enumerate(ids):
        targets = [*ids[i + 1:], "COMPLETE", "ABORT"]
        goal: dict[str, Any] = {"id": goal_id, "title": f"Top {goal_id}",
                                "next": {o: draw(st.sampled_from(targets)) for o in OUTCOMES},
                                "cost": {"energy_wh": draw(st.integers(0, 9)),
                                         "duration_s": draw(st.integers(1, 5))}}
        if i == 0 or draw(st.booleans()):
            del goal["cost"]
            goal["refines"] = _level(draw, goal_id + ".", 1, list(OUTCOMES))
        goals.append(goal)
    return _orders({"format": "countersign.orders/1", "id": "random", "start": "G1",
                    "goals": goals})


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(refined_orders())
def test_random_refinements_equal_brute_force(orders: Orders) -> None:
    _assert_equal_to_brute_force(orders)
