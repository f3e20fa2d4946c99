"""The costliest-path passes that an edit's budget and energy-bound checks run (the exact
integer pass of BUDGET, the float pass of a `max` property) give what enumerating every path
gives, and the outcome the loop they replaced chose (the first of the costliest).

Random DAGs whose costs repeat and tie (zeros, equal legs) and reach past the largest double.
"""

from __future__ import annotations

from fractions import Fraction

from hypothesis import given, settings
from hypothesis import strategies as st

from countersign.verify.budget import _costliest_onward
from countersign.verify.costs import ExactCosts, GraphCosts, exact_costs
from countersign.verify.graph import MissionGraph
from countersign.verify.paths import topological_order
from countersign.verify.properties import _worst_and_longest

COSTS = st.sampled_from([0.0, 0.1, 0.2, 0.3, 1.0, 2.5, 7.0, 1e308])


@st.composite
def priced_graphs(draw: st.DrawFn) -> tuple[MissionGraph, GraphCosts]:
    """A DAG of goals whose outcomes lead to later goals or to one of two terminals."""
    n = draw(st.integers(1, 8))
    succ = tuple(
        tuple(draw(st.integers(node + 1, n + 1)) for _ in range(3))  # type: ignore[misc]
        for node in range(n))
    graph = MissionGraph(tuple(f"G{i}" for i in range(n)), (), (), succ, {}, 0)  # type: ignore[arg-type]
    priced = GraphCosts("energy_wh", tuple(draw(COSTS) for _ in range(n)),
                        tuple((draw(COSTS), draw(COSTS), draw(COSTS)) for _ in range(n)), (), ())
    return graph, priced


def _every_path(graph: MissionGraph, node: int) -> list[list[tuple[int, int]]]:
    """Every path from a goal to a terminal, as (goal, outcome) steps."""
    paths = []
    for k, target in enumerate(graph.succ[node]):
        if target >= graph.goal_count:
            paths.append([(node, k)])
        else:
            paths.extend([(node, k), *rest] for rest in _every_path(graph, target))
    return paths


def _reference_choice(graph: MissionGraph, order: list[int], exact: ExactCosts) -> list[int]:
    """The loop the exact pass replaced: per goal, the outcome max() picks by (total, -k)."""
    best: dict[int, int] = {}
    choice = [0] * graph.goal_count
    for node in order:
        options = [(best.get(t, 0) if t < graph.goal_count else 0) + exact.leg[node][k]
                   for k, t in enumerate(graph.succ[node])]
        k = max(range(3), key=lambda i: (options[i], -i))
        choice[node] = k
        best[node] = exact.goal[node] + options[k]
    return choice


@settings(max_examples=300, deadline=None)
@given(priced_graphs())
def test_the_exact_pass_is_the_costliest_of_every_path(
        case: tuple[MissionGraph, GraphCosts]) -> None:
    graph, priced = case
    order = topological_order(graph)
    assert order is not None
    exact = exact_costs(priced)
    best, choice = _costliest_onward(graph, order, exact)
    for node in order:
        totals = [sum(exact.goal[g] + exact.leg[g][k] for g, k in path)
                  for path in _every_path(graph, node)]
        assert best[node] == max(totals)
    assert choice == _reference_choice(graph, order, exact)
    assert Fraction(best[0], exact.scale) == max(
        sum(Fraction(repr(priced.goal[g])) + Fraction(repr(priced.leg[g][k])) for g, k in path)
        for path in _every_path(graph, 0))


@settings(max_examples=300, deadline=None)
@given(priced_graphs())
def test_the_float_pass_is_the_costliest_and_longest_of_every_path(
        case: tuple[MissionGraph, GraphCosts]) -> None:
    graph, priced = case
    order = topological_order(graph)
    assert order is not None
    worst, longest = _worst_and_longest(order, graph.succ, priced.goal, priced.leg,
                                        graph.goal_count)
    for node in order:
        paths = _every_path(graph, node)
        # Summed from the terminal back, as the pass adds: the goal's cost to the leg and the
        # rest. Rounding is monotonic, so the largest such sum is the pass's.
        totals = []
        for path in paths:
            total = 0.0
            for g, k in reversed(path):
                total = priced.goal[g] + (priced.leg[g][k] + total)
            totals.append(total)
        assert worst[node] == max(totals)
        assert longest[node] == max(len(path) for path in paths)
