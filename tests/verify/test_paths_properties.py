"""Property tests: DP counts and lazy enumeration against brute force on random ternary graphs."""

from __future__ import annotations

import json
from collections import Counter

from hypothesis import given, settings
from hypothesis import strategies as st

from countersign.orders.model import OUTCOMES, Orders
from countersign.verify.graph import build_graph
from countersign.verify.paths import count_paths, iter_path_lines, iter_paths
from countersign.verify.report import validate
from countersign.verify.structure import check_structure

TERMINALS = {"COMPLETE", "ABORT"}


@st.composite
def ternary_orders(draw: st.DrawFn, allow_defects: bool = True) -> Orders:
    n = draw(st.integers(min_value=1, max_value=7))
    ids = [f"G{i}" for i in range(1, n + 1)]
    choices = [*ids, "COMPLETE", "ABORT"]
    if allow_defects:
        choices += ["NOWHERE", None]
    goals = []
    for gid in ids:
        nxt = {}
        for outcome in OUTCOMES:
            target = draw(st.sampled_from(choices))
            if target is not None:
                nxt[outcome] = target
        goals.append({"id": gid, "title": f"Goal {gid}", "next": nxt})
    return Orders.model_validate({"id": "random", "start": "G1", "goals": goals})


@st.composite
def acyclic_orders(draw: st.DrawFn) -> Orders:
    """Goals only point forward, so the graph is a DAG; every outcome is named."""
    n = draw(st.integers(min_value=1, max_value=9))
    ids = [f"G{i}" for i in range(1, n + 1)]
    goals = []
    for i, gid in enumerate(ids):
        later = [*ids[i + 1 :], "COMPLETE", "ABORT"]
        nxt = {o: draw(st.sampled_from(later)) for o in OUTCOMES}
        goals.append({"id": gid, "next": nxt})
    return Orders.model_validate({"id": "dag", "start": "G1", "goals": goals})


class Uncountable(Exception):
    pass


def brute_force(orders: Orders) -> list[tuple[tuple[str, ...], tuple[str, ...], str]]:
    """Every path by naive recursion; raises Uncountable on a loop or dangling outcome."""
    goals = {g.id: g for g in orders.goals}
    paths: list[tuple[tuple[str, ...], tuple[str, ...], str]] = []

    def visit(gid: str, trail: tuple[str, ...], outs: tuple[str, ...]) -> None:
        if gid in trail:
            raise Uncountable("loop")
        for outcome in OUTCOMES:
            target = goals[gid].next.get(outcome)
            if target is None or (target not in goals and target not in TERMINALS):
                raise Uncountable("dangling")
            assert isinstance(target, str)
            if target in TERMINALS:
                paths.append(((*trail, gid), (*outs, outcome), target))
            else:
                visit(target, (*trail, gid), (*outs, outcome))

    visit(str(orders.start), (), ())
    return paths


@settings(max_examples=300, deadline=None)
@given(ternary_orders())
def test_counts_equal_brute_force(orders: Orders) -> None:
    graph = build_graph(orders)
    counts = count_paths(graph)
    try:
        expected = brute_force(orders)
    except Uncountable:
        assert counts is None
        return
    assert counts is not None
    assert counts.total == len(expected)
    by_terminal = Counter(t for _, _, t in expected)
    assert {t: n for t, n in counts.by_terminal.items() if n} == dict(by_terminal)
    enumerated = [(p.goals, p.outcomes, p.terminal) for p in iter_paths(graph, counts)]
    assert enumerated == expected  # same paths, same order: succeed, fail, violate first


@settings(max_examples=300, deadline=None)
@given(ternary_orders())
def test_every_reported_loop_is_a_real_loop(orders: Orders) -> None:
    goals = {g.id: g for g in orders.goals}
    for finding in check_structure(orders):
        if finding.code != "G7" or finding.details.get("truncated"):
            continue
        cycle = list(finding.subjects)
        assert len(set(cycle)) == len(cycle)
        for position, gid in enumerate(cycle):
            following = cycle[(position + 1) % len(cycle)]
            assert following in goals[gid].next.values()


@settings(max_examples=300, deadline=None)
@given(ternary_orders())
def test_orders_without_findings_have_finite_paths_ending_in_terminals(orders: Orders) -> None:
    report = validate(orders)
    if report.findings:
        return
    paths = brute_force(orders)  # raises on a loop or dangling outcome
    assert paths and all(t in TERMINALS for _, _, t in paths)
    assert report.paths is not None and report.paths.total == len(paths)


@settings(max_examples=200, deadline=None)
@given(acyclic_orders(), st.integers(min_value=0, max_value=400), st.integers(0, 50))
def test_offset_and_limit_slice_the_enumeration(orders: Orders, offset: int, limit: int) -> None:
    graph = build_graph(orders)
    counts = count_paths(graph)
    assert counts is not None
    everything = list(iter_paths(graph, counts))
    window = list(iter_paths(graph, counts, offset, limit))
    assert window == everything[offset : offset + limit]
    lines = [json.loads(line) for line in iter_path_lines(graph, counts, offset, limit)]
    assert lines == [p.to_json() for p in window]
