"""Refinement: the refined mission's paths, traces and budgets equal a brute-force
run of the nested orders (tests/verify/refine_brute.py), and REFINE holds its rules."""

from __future__ import annotations

import copy
import json
import math
from fractions import Fraction
from typing import Any

import pytest
from hypothesis import HealthCheck, assume, given, settings
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


@settings(max_examples=60, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(refined_orders())
def test_random_refinements_equal_brute_force(orders: Orders) -> None:
    # Nested time-outs multiply paths: the brute force enumerates, so keep it small.
    counts = count_paths(checked_form(orders)[1])
    assert counts is not None
    assume(counts.total <= 3_000)
    _assert_equal_to_brute_force(orders)


# --- what else reads the refined mission ------------------------------------------------------

def _with_probabilities() -> Orders:
    data = json.loads(example_bytes(REFINED))
    for position, goal in enumerate(data["goals"]):
        goal["p"] = {"succeed": 0.7, "fail": 0.2, "violate": 0.1}
        for inner in goal.get("refines", {}).get("goals", []):
            inner["p"] = {"succeed": 0.5 - 0.1 * position, "fail": 0.4, "violate": 0.1}
    return _orders(data)


def test_probabilities_equal_brute_force() -> None:
    orders = _with_probabilities()
    report = validate(orders)
    assert report.probabilities is not None and report.probabilities.exact
    expected: dict[str, Fraction] = {}
    for run in runs(orders):
        weight = Fraction(1)
        for goal, outcome in zip(run.steps, run.outcomes, strict=True):
            assert goal.p is not None
            weight *= Fraction(repr(getattr(goal.p, outcome)))
        expected[run.terminal] = expected.get(run.terminal, Fraction(0)) + weight
    assert sum(expected.values()) == 1
    for terminal, bound in report.probabilities.terminals.items():
        # A report carries doubles: the exact figure's (verify/probability.py, Bound.exact).
        assert bound.exact == float(expected[terminal])


def _response_holds(run_goals: tuple[str, ...], run: Any, steps: int) -> bool:
    # Every transit goal that fails is followed by G3 within `steps` goals that end.
    for i, (goal, outcome) in enumerate(zip(run.steps, run.outcomes, strict=True)):
        window = range(i + 1, min(len(run_goals), i + 1 + steps))
        if goal.behavior == "transit" and outcome == "fail" \
                and not any(run_goals[j] == "G3" for j in window):
            return False
    return True


@pytest.mark.parametrize("steps", [1, 2, 4, 8])
def test_temporal_pattern_over_the_unrolling_equals_brute_force(steps: int) -> None:
    data = json.loads(example_bytes(REFINED))
    data["properties"] = [{"id": "P1", "pattern": "bounded_response",
                           "p": {"behavior": "transit", "outcome": "fail"},
                           "s": {"goal": "G3"}, "within": {"steps": steps}}]
    orders = _orders(data)
    holds = all(_response_holds(r.goals, r, steps) for r in runs(orders))
    failed = [f for f in validate(orders).findings if f.code == "PROPERTY"]
    assert (not failed) == holds, failed


def test_property_naming_a_refined_goal_is_refine() -> None:
    data = json.loads(example_bytes(REFINED))
    data["properties"] = [{"id": "P1", "pattern": "existence", "p": {"goal": "G1"}}]
    findings = validate(_orders(data)).findings
    assert any(f.code == "REFINE" and f.subjects == ("P1", "G1") for f in findings)


def test_geo_sees_legs_out_of_a_refinement() -> None:
    data = json.loads(example_bytes(REFINED))
    # A keep-out band between Area A and Area C: every leg from A to C crosses it.
    data["areas"].append({"id": "X", "title": "Range X", "contexts": ["keep_out"],
                          "polygon": [[36.708, -121.95], [36.708, -121.80],
                                      [36.703, -121.80], [36.703, -121.95]]})
    geo = [f for f in validate(_orders(data)).findings if f.code == "GEO"]
    subjects = {s for f in geo for s in f.subjects}
    assert {"G1/G1.1", "G1/G1.2", "G1/G1.3"} <= subjects
    assert not any("#" in s for s in subjects)  # once per goal, not per unrolled copy


def test_plain_orders_say_how_goal_1_is_carried_out() -> None:
    from countersign.orders.plain import plain_orders

    text = plain_orders(load_example(REFINED))
    assert ("Goal 1 is carried out as: 1.1 Move to the next unvisited cell of Area A, 1.2 Scan "
            "the cell for targets, and 1.3 Backtrack to the previous cell; it starts with "
            "Goal 1.1. Time-out: once 6 goals have commenced inside it, no further goal "
            "commences and Goal 1 fails.") in text
    assert ("Goal 1.2: Scan the cell for targets (behaviour: area search, in Area A). Next, if "
            "the goal succeeds, Goal 1 ends in success (Target found). If it fails, execute "
            "Goal 1.1.") in text


def _cli(argv: list[str], stdin: str = "") -> tuple[int, str]:
    import contextlib
    import io
    import sys

    from countersign.cli import main

    out = io.StringIO()
    old_stdin = sys.stdin
    sys.stdin = io.StringIO(stdin)
    try:
        with contextlib.redirect_stdout(out):
            code = main(argv)
    finally:
        sys.stdin = old_stdin
    return code, out.getvalue()


def test_cli_paths_name_the_unrolled_goals() -> None:
    code, out = _cli(["paths", f"example:{REFINED}", "--offset", "100", "--limit", "1"])
    assert code == 0
    path = json.loads(out)
    assert path["goals"][:3] == ["G1/G1.1#1", "G1/G1.2#2", "G1/G1.1#3"]
    assert path["index"] == 101


def _index_of(answers: str) -> int:
    """The 0-based index of the path the answers take (the trace to compare the run with)."""
    outcomes = [{"s": "succeed", "f": "fail", "c": "violate"}[a] for a in answers.split()]
    _, graph = checked_form(load_example(REFINED))
    counts = count_paths(graph)
    assert counts is not None
    return next(p.index - 1 for p in iter_paths(graph, counts)
                if list(p.outcomes) == outcomes[:len(p.outcomes)])


def test_cli_run_nests_the_refinement_and_times_out() -> None:
    # s, f, s, f, s, f: the 6th goal fails and the loop's time-out ends Goal 1 with fail.
    answers = "s\nf\ns\nf\ns\nf\ns\ns\ns\n"
    code, out = _cli(["run", f"example:{REFINED}"], answers)
    assert code == 0
    lines = out.splitlines()
    assert lines[1] == "Commence: Search Area A."
    assert lines[2] == "  Commence: Move to the next unvisited cell of Area A."
    assert lines[3] == "  Did goal Succeed (s), Fail (f), or end with a Constraint (c)? succeed."
    # The run prints what a trace of the same path prints.
    assert lines[:-1] == _cli(["paths", f"example:{REFINED}", "--format", "trace", "--offset",
                               str(_index_of(answers)), "--limit", "1"])[1].splitlines()[1:-1]
    at = lines.index("  Time-out: Search Area A.")
    assert lines[at + 1] == "Did goal Succeed (s), Fail (f), or end with a Constraint (c)? fail."
    assert lines[at + 2] == "Commence: Search Area B."
    assert lines[-1] == "Mission Complete!"


def _nested(depth: int) -> dict[str, Any]:
    """Orders whose G1 is refined `depth` levels deep, one goal per level."""
    inner: dict[str, Any] = {"id": "L", "title": f"Level {depth}",
                             "next": {o: "T" for o in OUTCOMES}}
    for level in range(depth, 0, -1):
        inner = {"id": "L", "title": f"Level {level - 1}", "next": {o: "T" for o in OUTCOMES},
                 "refines": {"start": "L", "goals": [inner],
                             "terminals": [{"id": "T", "kind": "complete",
                                            "returns": "succeed"}]}}
    inner["id"] = "G1"
    inner["next"] = {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"}
    return {"format": "countersign.orders/1", "id": "nested", "start": "G1", "goals": [inner]}


def test_nested_refinements_nest_their_traces() -> None:
    orders = _orders(_nested(2))
    _, graph = checked_form(orders)
    counts = count_paths(graph)
    assert counts is not None and counts.by_terminal == {"COMPLETE": 3, "ABORT": 0}
    path = next(iter_paths(graph, counts))
    assert path.goals == ("G1/L/L",)
    assert trace_text(graph, path).splitlines()[2:7] == [
        "Commence: Level 0.", "  Commence: Level 1.", "    Commence: Level 2.",
        "    Did goal Succeed (s), Fail (f), or end with a Constraint (c)? succeed.",
        "  Did goal Succeed (s), Fail (f), or end with a Constraint (c)? succeed."]
    assert _assert_equal_to_brute_force(orders) == 3


def test_refinements_nest_at_most_eight_deep() -> None:
    deepest = validate(_orders(_nested(8)))
    assert not [f for f in deepest.findings if f.code == "REFINE" and f.severity == "error"]
    # Each level returns only succeed, though its parent goes on for every outcome.
    assert any(f.code == "REFINE" and f.severity == "warning"
               and "never returns fail" in f.message for f in deepest.findings)
    assert deepest.paths is not None and deepest.paths.total == 3
    report = validate(_orders(_nested(9)))
    assert any(f.code == "REFINE" and "at most 8 deep" in f.message for f in report.findings)
    assert report.paths is None


def test_vehicle_exports_are_flat_and_refuse_a_broken_refinement() -> None:
    from countersign.export.notes import ExportError
    from countersign.export.vehicle import export_vehicle

    export = export_vehicle(load_example(REFINED), "moos", version=1)
    assert any(n.code == "REFINE" for n in export.notes)
    assert any(n.code == "NESTED" for n in export.notes)
    # The refined goal is a helm mode holding its goals' modes (ACTIVE:G1:G1_1_k1).
    assert b"set MODE = G1 {\n  MODE = ACTIVE\n" in export.primary.content
    assert b"set MODE = G1_1_k1 {\n  MODE = ACTIVE:G1\n" in export.primary.content
    with pytest.raises(ExportError, match=r"REFINE G1/G1\.1"):
        export_vehicle(_orders(_search_loop(None)), "imc", version=1)
