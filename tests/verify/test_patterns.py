"""Temporal patterns over every path, against brute-force enumeration on random graphs; bounds
are measured from the `p` event to the `s` event (DESIGN.md)."""

from __future__ import annotations

import itertools
import json
import math
import random
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from countersign.orders.examples import example_bytes
from countersign.orders.model import OUTCOMES, Orders, PathProperty
from countersign.orders.pattern_words import pattern_sentence
from countersign.orders.plain import plain_orders
from countersign.verify.budget import goal_cost, leg_cost
from countersign.verify.graph import MissionGraph, build_graph
from countersign.verify.legs import geod, leg_lengths
from countersign.verify.patterns import (
    Counterexample,
    Position,
    check_pattern,
    matches,
)
from countersign.verify.report import validate

from .prob_oracles import all_paths, random_orders

PATTERNS = ("absence", "existence", "universality", "precedence", "response",
            "bounded_response")
SCOPES = ("globally", "before", "after", "between")


def _positions(graph: MissionGraph, goals: list[int], outs: list[int], terminal: int
               ) -> list[Position]:
    steps = [Position(graph.goal_ids[g], OUTCOMES[k], graph.goals[g].behavior, None, None)
             for g, k in zip(goals, outs, strict=True)]
    end = graph.terminal(terminal)
    return [*steps, Position(None, None, None, end.id, end.kind)]


def _segments(prop: PathProperty, at: list[Position]) -> list[tuple[int, int]]:
    q = [matches(prop.q, x) for x in at]
    r = [matches(prop.r, x) for x in at]
    n = len(at)
    if prop.scope == "globally":
        return [(0, n)]
    if prop.scope == "before":
        return [(0, r.index(True))] if True in r else []
    if prop.scope == "after":
        return [(q.index(True), n)] if True in q else []
    segments, start = [], None
    for i in range(n):
        if start is None:
            if q[i] and not r[i]:
                start = i
        elif r[i]:
            segments.append((start, i))
            start = None
    return segments


Costs = tuple[list[float], list[list[float]]]


def event_costs(orders: Orders, graph: MissionGraph, prop: PathProperty) -> Costs:
    """Per goal node, its own cost and the cost of the leg of each outcome, priced as the
    DESIGN's one cost model prices them (budget.goal_cost, budget.leg_cost over the legs'
    geodesic lengths); in steps a goal is 1 and a leg 0."""
    within = prop.within
    if within is None or within.steps is not None:
        return [1.0] * graph.goal_count, [[0.0] * 3 for _ in graph.goals]
    name = "duration_s" if within.duration_s is not None else "energy_wh"
    vehicle = orders.target_vehicle()
    areas = orders.area_index()
    lengths = leg_lengths(orders)
    return ([goal_cost(g, name, vehicle, areas)[0] or 0.0 for g in graph.goals],
            [[leg_cost(lengths.get((g.id, o)), name, vehicle) for o in OUTCOMES]
             for g in graph.goals])


def spent(costs: Costs, goals: list[int], outs: list[int], i: int, j: int) -> float:
    """What lies between the event at position i and the one at position j >= i of a path:
    the leg out of i, then each later goal up to and including j and the leg after it (the
    terminal, one past the last goal, costs nothing and has no leg)."""
    own, legs = costs
    total = 0.0
    for x in range(i, j):
        total += legs[goals[x]][outs[x]]
        if x + 1 < len(goals):
            total += own[goals[x + 1]]
    return total


def violates(prop: PathProperty, graph: MissionGraph, goals: list[int], outs: list[int],
             terminal: int, costs: Costs | None = None) -> bool:
    """Dwyer's finite-trace semantics, written directly on the list of positions; a bound is
    measured from the `p` event to the `s` event (DESIGN.md)."""
    at = _positions(graph, goals, outs, terminal)
    limit = None
    if prop.within is not None:
        limit = next(float(v) for v in (prop.within.steps, prop.within.duration_s,
                                        prop.within.energy_wh) if v is not None)
    for a, b in _segments(prop, at):
        p = [matches(prop.p, x) for x in at[a:b]]
        s = [matches(prop.s, x) for x in at[a:b]]
        if prop.pattern == "absence" and any(p):
            return True
        if prop.pattern == "existence" and not any(p):
            return True
        if prop.pattern == "universality" and not all(p):
            return True
        if prop.pattern == "precedence" and any(
                p[i] and not any(s[: i + 1]) for i in range(len(p))):
            return True
        for i in range(len(p)):
            if not p[i] or prop.pattern not in ("response", "bounded_response"):
                continue
            answered = False
            for j in range(i, len(p)):
                if s[j]:
                    answered = prop.pattern == "response" or (
                        limit is not None and costs is not None
                        and spent(costs, goals, outs, a + i, a + j) <= limit)
                    break
            if not answered:
                return True
    return False


def _event(rng: random.Random, goals: int) -> dict[str, Any]:
    choice = rng.randrange(5)
    if choice == 0:
        return {"goal": f"G{rng.randrange(goals)}"}
    if choice == 1:
        return {"outcome": rng.choice(OUTCOMES)}
    if choice == 2:
        return {"goal": [f"G{rng.randrange(goals)}", f"G{rng.randrange(goals)}"],
                "outcome": rng.choice(OUTCOMES)}
    if choice == 3:
        return {"kind": rng.choice(("complete", "abort"))}
    return {"behavior": rng.choice(("survey", "transit"))}


def random_property(rng: random.Random, goals: int) -> PathProperty:
    pattern = rng.choice(PATTERNS)
    data: dict[str, Any] = {"id": "P1", "pattern": pattern, "scope": rng.choice(SCOPES),
                            "p": _event(rng, goals), "s": _event(rng, goals),
                            "q": _event(rng, goals), "r": _event(rng, goals)}
    if pattern == "bounded_response":
        data["within"] = rng.choice(({"steps": rng.randint(0, 4)},
                                     {"energy_wh": rng.randint(0, 15)},
                                     {"duration_s": rng.choice((1.5, 60, 90))}))
    return PathProperty.model_validate(data)


def _with_behaviours(orders: Orders, rng: random.Random) -> Orders:
    data = orders.model_dump(mode="json", by_alias=True, exclude_none=True)
    for goal in data["goals"]:
        goal["behavior"] = rng.choice(("survey", "transit"))
    return Orders.model_validate(data)


def _is_path(graph: MissionGraph, found: Counterexample) -> tuple[list[int], list[int], int]:
    goals = [graph.goal_ids.index(g) for g in found.goals]
    outs = [OUTCOMES.index(o) for o in found.outcomes]  # type: ignore[arg-type]
    assert goals[0] == graph.start
    for i, (g, k) in enumerate(zip(goals, outs, strict=True)):
        target = graph.succ[g][k]
        expected = goals[i + 1] if i + 1 < len(goals) else None
        if expected is None:
            assert graph.is_terminal(target) and graph.node_id(target) == found.terminal
        else:
            assert target == expected
    return goals, outs, graph.succ[goals[-1]][outs[-1]]


def assert_equals_brute_force(orders: Orders, graph: MissionGraph, prop: PathProperty) -> None:
    """The verifier's verdict is the enumeration's, and its counterexample is a real path that
    violates the property, as short as any that does."""
    costs = event_costs(orders, graph, prop)
    violating = [len(g) for g, o, t in all_paths(graph)
                 if violates(prop, graph, g, o, t, costs)]
    verdict = check_pattern(orders, graph, prop)
    assert not isinstance(verdict, str)
    if not violating:
        assert verdict is None
        return
    assert verdict is not None
    assert violates(prop, graph, *_is_path(graph, verdict), costs)
    assert len(verdict.goals) == min(violating)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 2**32), st.integers(1, 12))
def test_verdicts_equal_brute_force_and_counterexamples_are_shortest_real_paths(
        seed: int, goals: int) -> None:
    rng = random.Random(seed)
    orders = _with_behaviours(random_orders(rng, goals, kinds=("none",)), rng)
    graph = build_graph(orders)
    prop = random_property(rng, goals)
    assert_equals_brute_force(orders, graph, prop)


def exemplar() -> dict[str, Any]:
    data: dict[str, Any] = json.loads(example_bytes("search-and-sample"))
    return data


def test_the_exemplar_response_pattern_and_its_sentence() -> None:
    data = exemplar()
    # After a violation the vehicle reaches Return to Base (G5) within 2 goals.
    data["properties"] = [{"id": "P7", "pattern": "bounded_response", "p": {"outcome": "violate"},
                           "s": {"goal": "G5"}, "within": {"steps": 1}},
                          {"id": "P8", "pattern": "existence", "p": {"goal": "G5"}}]
    orders = Orders.model_validate(data)
    report = validate(orders)
    failing = [f for f in report.findings if f.code == "PROPERTY"]
    # G1 violate -> G4 -> G5: two goals after the violation, more than one.
    assert [f.subjects[0] for f in failing] == ["P7"]
    assert failing[0].details["path"]["goals"][:2] == ["G1", "G4"]
    sentence = pattern_sentence(orders.properties[0])
    assert sentence == ("On every path, whenever a goal ends with a violation, then goal G5 "
                        "within 1 goals.")
    assert sentence in plain_orders(orders)
    assert "On every path, at some point goal G5." in plain_orders(orders)


def test_a_pattern_missing_its_events_is_an_expr_finding() -> None:
    data = exemplar()
    data["properties"] = [{"id": "P9", "pattern": "response", "scope": "between",
                           "p": {"goal": "G1"}}]
    findings = validate(Orders.model_validate(data)).findings
    assert any(f.code == "EXPR" and f.subjects == ("P9",) and "'s', 'q', 'r'" in f.message
               for f in findings)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 2**32), st.integers(1, 12), st.integers(0, 60))
def test_cost_bounded_responses_equal_brute_force_near_their_limit(
        seed: int, goals: int, limit: int) -> None:
    # Pending costs that cannot pass the limit before the end are merged into one state
    # (for speed): the verdict must not move, least of all at the limit.
    rng = random.Random(seed)
    orders = _with_behaviours(random_orders(rng, goals, kinds=("none",)), rng)
    graph = build_graph(orders)
    data = random_property(rng, goals).model_dump(mode="json", exclude_none=True)
    data.update(pattern="bounded_response", within={"energy_wh": limit},
                scope=rng.choice(SCOPES))
    data.setdefault("s", _event(rng, goals))
    assert_equals_brute_force(orders, graph, PathProperty.model_validate(data))


def _chain(costs: list[float], prop: dict[str, Any]) -> Counterexample | str | None:
    """The verdict on one path G0 G1 ... (every outcome leads on) without legs."""
    goals = [{"id": f"G{i}", "cost": {"energy_wh": c, "duration_s": c},
              "next": dict.fromkeys(OUTCOMES, f"G{i + 1}" if i + 1 < len(costs) else "COMPLETE")}
             for i, c in enumerate(costs)]
    orders = Orders.model_validate({"id": "chain", "start": "G0", "goals": goals})
    return check_pattern(orders, build_graph(orders),
                         PathProperty.model_validate({"id": "P1", "pattern": "bounded_response",
                                                      **prop}))


def test_a_bound_counts_from_the_p_goals_end_to_the_s_goals_end() -> None:
    # G0 answers with G3: between G0 ending and G3 ending lie G1, G2 and G3 (2 + 4 + 8 Wh);
    # G0's own 500 Wh were spent before it ended.
    costs = [500.0, 2.0, 4.0, 8.0, 1000.0]
    late = _chain(costs, {"p": {"goal": "G0"}, "s": {"goal": "G3"}, "within": {"energy_wh": 13}})
    assert isinstance(late, Counterexample) and late.goals[:4] == ("G0", "G1", "G2", "G3")
    assert _chain(costs, {"p": {"goal": "G0"}, "s": {"goal": "G3"},
                          "within": {"energy_wh": 14}}) is None
    assert _chain(costs, {"p": {"goal": "G0"}, "s": {"goal": "G3"},
                          "within": {"duration_s": 14}}) is None
    # Goals ended after G0, up to and including G3: three.
    assert _chain(costs, {"p": {"goal": "G0"}, "s": {"goal": "G3"},
                          "within": {"steps": 3}}) is None
    assert isinstance(_chain(costs, {"p": {"goal": "G0"}, "s": {"goal": "G3"},
                                     "within": {"steps": 2}}), Counterexample)
    # The mission ends when G4 does: 2 + 4 + 8 + 1000 Wh after G0, five goals... four ended.
    end = {"p": {"goal": "G0"}, "s": {"kind": "complete"}}
    assert _chain(costs, {**end, "within": {"energy_wh": 1014}}) is None
    assert isinstance(_chain(costs, {**end, "within": {"energy_wh": 1013.5}}), Counterexample)
    assert _chain(costs, {**end, "within": {"steps": 4}}) is None
    assert isinstance(_chain(costs, {**end, "within": {"steps": 3}}), Counterexample)
    # An `s` at the `p` position answers at once, whatever the `p` goal cost.
    assert _chain(costs, {"p": {"goal": "G0"}, "s": {"goal": "G0"},
                          "within": {"energy_wh": 0}}) is None


def test_after_a_long_goal_violates_the_next_goal_answers_within_its_own_cost() -> None:
    # "After G2 ends in violation, G9 within 200 Wh": G2 spends 900 Wh, then G7 (52 Wh) and
    # G9 (80 Wh) run: 132 Wh lie between the two events.
    goals = [{"id": "G2", "cost": {"energy_wh": 900},
              "next": {"succeed": "COMPLETE", "fail": "COMPLETE", "violate": "G7"}},
             {"id": "G7", "cost": {"energy_wh": 52}, "next": dict.fromkeys(OUTCOMES, "G9")},
             {"id": "G9", "cost": {"energy_wh": 80}, "next": dict.fromkeys(OUTCOMES, "ABORT")}]
    orders = Orders.model_validate({"id": "g9", "start": "G2", "goals": goals})

    def verdict(limit: float) -> Counterexample | str | None:
        prop = PathProperty.model_validate({
            "id": "P1", "pattern": "bounded_response", "p": {"goal": "G2", "outcome": "violate"},
            "s": {"goal": "G9"}, "within": {"energy_wh": limit}})
        return check_pattern(orders, build_graph(orders), prop)

    assert verdict(200) is None
    assert verdict(132) is None
    late = verdict(131.9)
    assert isinstance(late, Counterexample) and late.goals == ("G2", "G7", "G9")


def test_the_legs_between_the_events_count() -> None:
    # G0 in A, G1 in B about a kilometre north, G2 back in A: two legs of about 20 Wh each
    # lie between G0 ending and G2 ending, beside G1's and G2's own 10 Wh.
    def square(area: str, lat: float) -> dict[str, Any]:
        return {"id": area, "polygon": [[lat, -121.9], [lat, -121.899], [lat + 0.001, -121.899],
                                        [lat + 0.001, -121.9]]}

    goals = [{"id": f"G{i}", "behavior": "transit", "area": area, "cost": {"energy_wh": 10},
              "next": dict.fromkeys(OUTCOMES, f"G{i + 1}" if i < 2 else "COMPLETE")}
             for i, area in enumerate("ABA")]
    orders = Orders.model_validate({
        "id": "legs", "start": "G0", "goals": goals, "vehicle": "auv",
        "areas": [square("A", 36.70), square("B", 36.709)],
        "vehicles": [{"id": "auv", "speed_mps": 1.5, "power_w": 110}]})
    metres = leg_lengths(orders)
    there, back = metres[("G0", "succeed")], metres[("G1", "succeed")]
    centres = geod().inv(-121.8995, 36.7005, -121.8995, 36.7095)[2]
    assert abs(there - centres) < 1 and abs(back - centres) < 1
    between = 20 + (there + back) / 1.5 * 110 / 3600
    assert between > 55

    def verdict(limit: float) -> Counterexample | str | None:
        prop = PathProperty.model_validate({
            "id": "P1", "pattern": "bounded_response", "p": {"goal": "G0"},
            "s": {"goal": "G2"}, "within": {"energy_wh": limit}})
        return check_pattern(orders, build_graph(orders), prop)

    assert verdict(between + 1e-6) is None
    assert isinstance(verdict(between - 1e-6), Counterexample)


def _legged_orders(rng: random.Random, goals: int) -> Orders:
    """A random DAG whose goals run in small areas a few hundred metres apart, so that every
    edge between two goals has a leg the vehicle pays for in time and energy."""
    orders = random_orders(rng, goals, kinds=("none",))
    data = orders.model_dump(mode="json", by_alias=True, exclude_none=True)
    areas = []
    for k in range(4):
        lat, lon = 36.70 + rng.uniform(-0.006, 0.006), -121.90 + rng.uniform(-0.006, 0.006)
        size = rng.choice((0.001, 0.003))
        areas.append({"id": f"A{k}", "polygon": [[lat, lon], [lat, lon + size],
                                                [lat + size, lon + size], [lat + size, lon]]})
    for i, goal in enumerate(data["goals"]):
        later = [f"G{j}" for j in range(i + 1, goals)]
        # Mostly on to another goal, so that the ways between two events have legs.
        goal["next"] = {o: rng.choice(later) if later and rng.random() < 0.8
                        else rng.choice(("T0", "T1")) for o in OUTCOMES}
        goal["behavior"] = rng.choice(("survey", "transit"))
        goal["area"] = rng.choice(areas)["id"]
        goal["cost"] = {"energy_wh": rng.randint(0, 30), "duration_s": rng.choice((0, 90, 600))}
    data.update(areas=areas, vehicle="auv",
                vehicles=[{"id": "auv", "speed_mps": 1.5, "power_w": 110}])
    return Orders.model_validate(data)


QUANTITIES = ("steps", "duration_s", "energy_wh")


def _limit_near_an_interval(rng: random.Random, orders: Orders, graph: MissionGraph,
                            prop: PathProperty) -> float:
    """A bound at, just under, or around what lies between a `p` event and the next `s` event
    on some path (most often the longest such), so that the verdicts are tested where they
    turn."""
    costs = event_costs(orders, graph, prop)
    answers = []
    for goals, outs, terminal in all_paths(graph):
        at = _positions(graph, goals, outs, terminal)
        for i, j in itertools.combinations_with_replacement(range(len(at)), 2):
            if matches(prop.p, at[i]) and matches(prop.s, at[j]) and not any(
                    matches(prop.s, x) for x in at[i:j]):
                answers.append(spent(costs, goals, outs, i, j))
    # The longest answer decides whether every `p` is answered in time: try it most often.
    value = rng.choice((max, rng.choice))(answers) if answers else rng.uniform(0, 100)
    if prop.within is not None and prop.within.steps is not None:
        return float(max(0, int(value) - rng.randint(0, 1)))
    return rng.choice((value, max(0.0, math.nextafter(value, -math.inf)),
                       value * rng.uniform(0.5, 1.5)))


def _check_with_legs(pattern: str, scope: str, seed: int, goals: int, quantity: str) -> None:
    rng = random.Random(seed)
    orders = _legged_orders(rng, goals)
    graph = build_graph(orders)
    data = random_property(rng, goals).model_dump(mode="json", exclude_none=True)
    data.update(pattern=pattern, scope=scope)
    data.pop("within", None)
    # A `p` at one goal and an `s` that most paths reach later (the end, or two of the three
    # outcomes) leave the verdict to the bound more often than to a `p` never answered.
    data["p"] = rng.choice((data["p"], {"goal": f"G{rng.randrange(goals)}"}))
    data["s"] = rng.choice((data["s"], {"terminal": ["T0", "T1"]},
                            {"outcome": rng.sample(OUTCOMES, 2)}))
    if pattern == "bounded_response":
        draft = PathProperty.model_validate({**data, "within": {quantity: 0}})
        limit = _limit_near_an_interval(rng, orders, graph, draft)
        data["within"] = {quantity: int(limit) if quantity == "steps" else limit}
    assert_equals_brute_force(orders, graph, PathProperty.model_validate(data))


@pytest.mark.parametrize(("pattern", "scope"), list(itertools.product(PATTERNS[:-1], SCOPES)))
@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**32), goals=st.integers(2, 7))
def test_every_pattern_and_scope_with_legs_equals_brute_force(
        pattern: str, scope: str, seed: int, goals: int) -> None:
    _check_with_legs(pattern, scope, seed, goals, "steps")


@pytest.mark.parametrize(("scope", "quantity"), list(itertools.product(SCOPES, QUANTITIES)))
@settings(max_examples=50, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**32), goals=st.integers(2, 7))
def test_bounded_responses_in_steps_seconds_and_watt_hours_equal_brute_force(
        scope: str, quantity: str, seed: int, goals: int) -> None:
    # Bounds over goals and legs, against the enumeration of every path with what lies
    # between two events priced from the definition, at and around where verdicts turn.
    _check_with_legs("bounded_response", scope, seed, goals, quantity)


def _readme_pattern() -> dict[str, Any]:
    """The temporal pattern the README shows, read from the README itself."""
    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text(encoding="utf-8")
    section = readme[readme.index("### Outcome probabilities and temporal patterns"):]
    block = section[section.index("```json") + len("```json"):]
    found: dict[str, Any] = json.loads(block[:block.index("```")])
    return found


def test_the_readme_pattern_holds_on_the_example_it_names() -> None:
    data: dict[str, Any] = json.loads(example_bytes("harbor-approach-survey"))
    data["properties"] = [_readme_pattern()]
    orders = Orders.model_validate(data)
    assert not [f for f in validate(orders).findings if f.code in ("PROPERTY", "EXPR")]
    prop = orders.properties[0]
    assert prop.pattern == "bounded_response" and prop.within is not None
    limit = prop.within.energy_wh
    assert limit is not None
    graph = build_graph(orders)
    assert_equals_brute_force(orders, graph, prop)
    # It holds although a goal whose violation it answers spends far more than the bound
    # before it ends, which the bound therefore must not count ...
    own, _ = event_costs(orders, graph, prop)
    answered = [n for n in range(graph.goal_count) if matches(
        prop.p, Position(graph.goal_ids[n], "violate", graph.goals[n].behavior, None, None))]
    assert max(own[n] for n in answered) > 3 * limit
    # ... and it is tight: the longest way from a violation to G7's end (G3's 90 Wh leg and
    # G7's 150 Wh) lies just under it, so the legs count.
    tighter = prop.model_copy(update={"within": prop.within.model_copy(
        update={"energy_wh": 240.0})})
    late = check_pattern(orders, graph, tighter)
    assert isinstance(late, Counterexample) and late.goals[-2:] == ("G3", "G7")
