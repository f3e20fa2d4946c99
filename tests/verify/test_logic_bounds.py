"""Bounds propagation (verify/logic/bounds.py) answers only what z3 answers, and a core proven
the only one (unique.py) is the one the z3 route names: on random missions whose constraints
and norms are random expressions over real, integer and Boolean quantities, behaviours, areas
and tags."""

from __future__ import annotations

import gc
import random
from typing import Any

import pytest
import z3
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from countersign.orders.model import Orders
from countersign.verify.expressions import Translator
from countersign.verify.graph import build_graph
from countersign.verify.logic import LogicCache, LogicModel, LogicRun, check_logic
from countersign.verify.logic import run as logic_run
from countersign.verify.logic.bounds import Decider
from countersign.verify.logic.limits import Limits
from countersign.verify.logic.unique import UniqueCores
from countersign.verify.properties import check_properties

TAGS = ["t1", "t2", "t3"]
BEHAVIORS = ["a", "b", "c"]
NUMBERS = ["0", "1", "2", "2.5", "3", "4", "5", "6", "-1", "0.1", "7", "9", "10"]
TERMS = ["x", "n", "k", "r", "x + n", "2 * x - n", "x / 2", "-x", "r - x", "(x + 1) * 3",
         "n - k", "x * n", "x / 0"]


def _atom(rng: random.Random) -> str:
    kind = rng.randrange(6)
    if kind <= 1:
        op = rng.choice(["<", "<=", ">", ">=", "==", "!="])
        return f"{rng.choice(TERMS)} {op} {rng.choice(NUMBERS)}"
    if kind == 2:
        return rng.choice(["flag", "not flag"])
    if kind == 3:
        return f"behavior {rng.choice(['==', '!='])} '{rng.choice(BEHAVIORS)}'"
    if kind == 4:
        return f"area == 'A{rng.randrange(3)}'"
    return f"context('{rng.choice(TAGS)}')"


def _expr(rng: random.Random, depth: int = 0) -> str:
    if depth >= 2 or rng.random() < 0.4:
        return _atom(rng)
    shape = rng.randrange(4)
    left, right = _expr(rng, depth + 1), _expr(rng, depth + 1)
    if shape == 0:
        return f"({left}) and ({right})"
    if shape == 1:
        return f"({left}) or ({right})"
    if shape == 2:
        return f"not ({left})"
    return f"({left}) implies ({right})"


def random_orders(seed: int, goals: int, constraints: int, norms: int) -> Orders:
    rng = random.Random(seed)
    areas = [{"id": f"A{i}", "contexts": rng.sample(TAGS, rng.randint(0, 2))} for i in range(3)]
    items = []
    for i in range(goals):
        # Bounds that the expressions' numbers meet (and single points), where a strict or a
        # non-strict comparison decides.
        envelope: dict[str, list[float]] = {"x": sorted([rng.choice([-5, 0, 1, 2.5, 3, 6]),
                                                         rng.choice([0, 3, 6, 9])])}
        if rng.random() < 0.5:
            envelope["n"] = sorted([rng.choice([0, 1, 2, 3]), rng.choice([2, 5, 8])])
        if rng.random() < 0.4:
            envelope["flag"] = rng.choice([[0, 0], [1, 1], [0, 1]])
        if rng.random() < 0.3:
            envelope["k"] = sorted([rng.choice([-2.5, 0.5, 3]), rng.choice([0.5, 4, 9.5])])
        nxt = {"succeed": f"G{i + 1}" if i + 1 < goals else "COMPLETE", "fail": "ABORT",
               "violate": "ABORT"}
        items.append({"id": f"G{i}", "behavior": rng.choice(BEHAVIORS),
                      "area": f"A{rng.randrange(3)}" if rng.random() < 0.9 else None,
                      "envelope": envelope, "next": nxt})
    cons = []
    for j in range(constraints):
        scope: Any = "mission" if rng.random() < 0.4 else sorted(
            {f"G{rng.randrange(goals)}" for _ in range(rng.randint(1, 3))})
        cons.append({"id": f"C{j}", "applies_to": scope, "expr": _expr(rng)})
    norm_items = []
    for j in range(norms):
        modality = rng.choice(["forbidden", "obligated", "permitted"])
        context = rng.choice([*TAGS, _expr(rng, 1)])
        norm_items.append({"id": f"N{j}", "context": context, modality: _expr(rng, 1)})
    return Orders.model_validate({
        "id": "bounds", "start": "G0", "vehicle": "v", "goals": items, "constraints": cons,
        "norms": norm_items, "areas": areas,
        "quantities": {"x": {"min": -10, "max": 10}, "n": {"type": "integer", "min": 0,
                                                          "max": 20},
                       "k": {"type": "integer"}, "flag": {"type": "boolean"}, "r": {}},
        "vehicles": [{"id": "v", "envelope": {"x": [-8, 8], "r": [0, 3.5]}}],
    })


def z3_status(model: LogicModel, items: list[Any]) -> str:
    translator = Translator(model.quantities)
    texts = "".join(f"(assert {i.formula(translator)})" for i in items)
    solver = z3.Solver()
    solver.add(z3.parse_smt2_string(translator.declarations() + texts))
    return str(solver.check())


def unit_checks(orders: Orders, rng: random.Random) -> list[tuple[list[Any], frozenset[Any]]]:
    """The item sets the logic check asks about for each goal (with and without its norms,
    each breach, random parts of them), with the base each is asked with."""
    model = LogicModel(orders)
    run = LogicRun(model, None, Limits.start(2000, 60))
    base = run.block(frozenset())
    out: list[tuple[list[Any], frozenset[Any]]] = []
    for goal in model.goals.values():
        norms = model.relevant_norms(goal)
        items, _ = run.goal_items(goal, frozenset(), [model.norm_reads(n) for n in norms])
        pairs = [model.norm_items(n) for n in norms]
        out.append((items, base))
        out.append((items + [rule for rule, _ in pairs], base))
        out.extend(([*items, breach], base) for _, breach in pairs)
        every = items + [i for pair in pairs for i in pair]
        out.extend((rng.sample(every, rng.randint(1, len(every))), frozenset())
                   for _ in range(6))
    return out


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 10**6), goals=st.integers(1, 6), constraints=st.integers(0, 8),
       norms=st.integers(0, 4))
def test_bounds_answers_what_z3_answers(seed: int, goals: int, constraints: int,
                                        norms: int) -> None:
    orders = random_orders(seed, goals, constraints, norms)
    model = LogicModel(orders)
    decider = Decider(model.quantities)
    for items, base in unit_checks(orders, random.Random(seed)):
        rest = [i for i in items if i not in base]
        verdict = decider.status(rest, base)
        if verdict is not None:
            assert verdict == z3_status(model, items), [i.key for i in items]


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 10**6), goals=st.integers(1, 8), constraints=st.integers(0, 10),
       norms=st.integers(0, 5))
def test_fast_route_finds_what_the_z3_route_finds(seed: int, goals: int, constraints: int,
                                                  norms: int) -> None:
    """Findings, subjects, cores and witnesses: the same with bounds propagation and unique
    cores (GROUP_CHECKS) as with one z3 session check at a time."""
    orders = random_orders(seed, goals, constraints, norms)
    found = []
    with pytest.MonkeyPatch.context() as patch:
        for grouped in (True, False):
            patch.setattr(logic_run, "GROUP_CHECKS", grouped)
            cache = LogicCache()
            findings = check_logic(orders, cache) + check_properties(
                orders, build_graph(orders), cache)
            found.append([f.to_json() for f in findings])
    assert found[0] == found[1]


def test_the_bounds_route_decides_most_units() -> None:
    """Not a timing: the route exists for the common units (bounds, facts, disjunctions)."""
    orders = random_orders(7, 6, 8, 4)
    model = LogicModel(orders)
    decider = Decider(model.quantities)
    checks = unit_checks(orders, random.Random(7))
    answered = sum(decider.status([i for i in items if i not in base], base) is not None
                   for items, base in checks)
    assert answered > len(checks) // 2


def _one_goal(forbidden: str, contexts: list[str], norms: int = 1) -> tuple[LogicRun, list[Any]]:
    orders = Orders.model_validate({
        "id": "u", "start": "G0", "goals": [{
            "id": "G0", "behavior": "a", "area": "A0", "envelope": {"x": [0, 1]},
            "next": {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"}}],
        "areas": [{"id": "A0", "contexts": contexts}],
        "norms": [{"id": f"N{j}", "context": forbidden, "forbidden": "behavior == 'a'"}
                  for j in range(norms)],
        "quantities": {"x": {}},
    })
    model = LogicModel(orders)
    run = LogicRun(model, None, Limits.start(2000, 60))
    goal = model.goals["G0"]
    norm_list = model.relevant_norms(goal)
    items, _ = run.goal_items(goal, frozenset(), [model.norm_reads(n) for n in norm_list])
    return run, items + [model.norm_items(n)[0] for n in norm_list]


def test_a_core_is_taken_only_when_it_is_the_only_one() -> None:
    # One norm, one tag: {N0, behaviour, t1} is the only core.
    run, items = _one_goal("t1", ["t1"])
    unique = UniqueCores(run.screen.decider, {})
    core = unique.core(items, frozenset())
    assert core is not None and sorted(i.key for i in core) == [
        "beh:G0", "ctx:G0:t1", "norm:N0"]
    # Forbidden in t1 or t2 and the area has both: two cores ({N0, behaviour, t1} and
    # {N0, behaviour, t2}); which one z3 names is its choice, so none is taken here.
    run, items = _one_goal("context('t1') or context('t2')", ["t1", "t2"])
    assert UniqueCores(run.screen.decider, {}).core(items, frozenset()) is None
    # Two norms forbid the same: two cores, none taken.
    run, items = _one_goal("t1", ["t1"], norms=2)
    assert UniqueCores(run.screen.decider, {}).core(items, frozenset()) is None


def _verdicts(envelope: dict[str, list[float]], exprs: list[str]) -> tuple[str | None, str]:
    """(bounds.py's answer, z3's) for one goal under mission-wide constraints."""
    orders = Orders.model_validate({
        "id": "p", "start": "G0", "goals": [{
            "id": "G0", "behavior": "a", "envelope": envelope,
            "next": {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"}}],
        "constraints": [{"id": f"C{j}", "applies_to": "mission", "expr": e}
                        for j, e in enumerate(exprs)],
        "quantities": {"x": {}, "n": {"type": "integer"}, "flag": {"type": "boolean"}},
    })
    model = LogicModel(orders)
    run = LogicRun(model, None, Limits.start(2000, 60))
    items, _ = run.goal_items(model.goals["G0"], frozenset())
    base = run.block(frozenset())
    return (Decider(model.quantities).status([i for i in items if i not in base], base),
            z3_status(model, items))


@pytest.mark.parametrize(("envelope", "exprs"), [
    ({"x": [3, 3]}, ["(x < 3) or (x > 3)"]),
    ({"x": [3, 3]}, ["(x < 3) or not flag", "flag"]),
    ({"x": [3, 3]}, ["(x <= 3) and (x >= 3)"]),
    ({"x": [3, 3]}, ["x != 3 or flag", "not flag"]),
    ({"x": [0, 3]}, ["x + n > 3 or flag", "not flag", "n <= 0"]),
    ({"x": [0, 3]}, ["x + n >= 3 or flag", "not flag", "n <= 0"]),
    ({"n": [1, 2]}, ["n / 2 > 1 or n < 1"]),
    ({"n": [1, 2]}, ["2 * n == 3 or flag", "not flag"]),
    ({"x": [0, 1]}, ["(x > 0.5) implies (x < 0.25)", "x >= 0.5"]),
])
def test_bounds_at_the_edges(envelope: dict[str, list[float]], exprs: list[str]) -> None:
    """Strict and non-strict bounds that meet, integers between values, implications."""
    ours, theirs = _verdicts(envelope, exprs)
    assert ours is not None and ours == theirs


def test_bounds_leave_no_reference_cycles() -> None:
    """Thousands of goals ask bounds.py several questions each: what a question makes is
    freed when it is answered, not left in cycles for the collector (the logic check pauses
    it, and its one collection at the end walks everything made meanwhile)."""
    orders = random_orders(11, 6, 8, 4)
    model = LogicModel(orders)
    checks = unit_checks(orders, random.Random(11))
    gc.collect()
    gc.disable()
    try:
        decider = Decider(model.quantities)
        answered = sum(decider.status([i for i in items if i not in base], base) is not None
                       for items, base in checks)
        left = gc.collect()
    finally:
        gc.enable()
    assert answered > 0 and left == 0


def test_a_base_is_known_by_what_it_states() -> None:
    """Another set of the same statements (the base's first twins, unique.py) asks what the
    goal asked already: its statements are not propagated again."""
    orders = random_orders(3, 2, 8, 2)
    model = LogicModel(orders)
    run = LogicRun(model, None, Limits.start(2000, 60))
    base = run.block(frozenset())
    items, _ = run.goal_items(model.goals["G0"], frozenset())
    rest = [i for i in items if i not in base]
    decider = Decider(model.quantities)
    first = decider.status(rest, base)
    made = decider.propagated
    assert made == 1 and base
    again = frozenset(list(base))  # another object (frozenset(base) is base itself)
    assert again is not base and decider.status(rest, again) == first
    assert decider.propagated == made
