"""Benchmark of issue 20: exact outcome probabilities and temporal patterns over large DAGs.

Run: .venv/bin/python -m tests.bench.bench_probability

Targets: probabilities and expectations of a 10,000-goal DAG under 1 s; 10 patterns on a
1,000-goal mission under 1 s. Baselines measured in this same process: a float DP on the same
graph (what exactness costs), a DP with `fractions.Fraction` (the obvious exact method), and
path enumeration on a smaller graph.
"""

from __future__ import annotations

import gc
import random
import time
from collections.abc import Callable
from fractions import Fraction
from typing import Any

from countersign.orders.model import OUTCOMES, Orders
from countersign.verify.graph import MissionGraph, build_graph
from countersign.verify.paths import count_paths, iter_paths, topological_order
from countersign.verify.probability import outcome_probabilities

from .generated import random_dag


def best_of(runs: int, action: Callable[[], Any]) -> float:
    times = []
    for _ in range(runs):
        gc.collect()
        start = time.perf_counter()
        action()
        times.append(time.perf_counter() - start)
    return min(times)


def with_p(orders: Orders, seed: int = 20) -> Orders:
    rng = random.Random(seed)
    data = orders.model_dump(mode="json", by_alias=True, exclude_none=True)
    for goal in data["goals"]:
        a = rng.randint(50, 95)
        b = rng.randint(0, 100 - a)
        goal["p"] = {"succeed": a / 100, "fail": b / 100, "violate": (100 - a - b) / 100}
    return Orders.model_validate(data)


def float_dp(orders: Orders, graph: MissionGraph) -> float:
    """P(first terminal) in floats, the cheapest possible pass."""
    order = topological_order(graph)
    assert order is not None and graph.start is not None
    value = [0.0] * graph.goal_count + [1.0] + [0.0] * (len(graph.terminals) - 1)
    dists = [[float(getattr(g.p, o)) for o in OUTCOMES] for g in graph.goals]
    for node in order:
        a, b, c = graph.succ[node]
        p = dists[node]
        value[node] = p[0] * value[a] + p[1] * value[b] + p[2] * value[c]
    return value[graph.start]


def fraction_dp(orders: Orders, graph: MissionGraph) -> Fraction:
    order = topological_order(graph)
    assert order is not None and graph.start is not None
    value = [Fraction(0)] * graph.goal_count + [Fraction(1)] + [Fraction(0)] * (
        len(graph.terminals) - 1)
    dists = [[Fraction(repr(getattr(g.p, o))) for o in OUTCOMES] for g in graph.goals]
    for node in order:
        a, b, c = graph.succ[node]
        p = dists[node]
        value[node] = p[0] * value[a] + p[1] * value[b] + p[2] * value[c]
    return value[graph.start]


def enumeration(orders: Orders, graph: MissionGraph) -> float:
    counts = count_paths(graph)
    assert counts is not None
    total = 0.0
    index = {g: i for i, g in enumerate(graph.goal_ids)}
    for path in iter_paths(graph, counts):
        if path.terminal == graph.terminals[0].id:
            p = 1.0
            for goal, outcome in zip(path.goals, path.outcomes, strict=True):
                p *= float(getattr(graph.goals[index[goal]].p, outcome))
            total += p
    return total


def bench_probabilities() -> None:
    print("Outcome probabilities (exact: terminals, any violation, expected energy and time)")
    for size in (1_000, 10_000):
        orders = with_p(random_dag(size))
        graph = build_graph(orders)
        exact = best_of(3, lambda: outcome_probabilities(orders, graph))
        floats = best_of(3, lambda: float_dp(orders, graph))
        print(f"  {size:>6} goals: exact {exact * 1000:8.1f} ms   float DP of one terminal "
              f"{floats * 1000:6.1f} ms (x{exact / floats:.0f})")
    small = with_p(random_dag(1_000))
    graph = build_graph(small)
    ours = best_of(3, lambda: outcome_probabilities(small, graph))
    fractions = best_of(1, lambda: fraction_dp(small, graph))
    print(f"  1,000 goals, Fraction DP of one terminal: {fractions * 1000:.1f} ms; ours (all "
          f"figures) {ours * 1000:.1f} ms (x{fractions / ours:.1f} faster)")
    tiny = with_p(random_dag(22, reach=3))
    graph = build_graph(tiny)
    counts = count_paths(graph)
    assert counts is not None
    ours = best_of(3, lambda: outcome_probabilities(tiny, graph))
    walk = best_of(1, lambda: enumeration(tiny, graph))
    print(f"  22 goals, {counts.total:,} paths: enumeration {walk * 1000:.1f} ms; ours "
          f"{ours * 1000:.2f} ms (x{walk / ours:.0f} faster)")


def main() -> None:
    bench_probabilities()


if __name__ == "__main__":
    main()
