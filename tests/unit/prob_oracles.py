"""Independent oracles for the probability and pattern checks: path enumeration, the vertices
of each goal's probability polytope, and Storm (stormpy) on the same Markov chain."""

from __future__ import annotations

import itertools
import json
import random
from collections.abc import Iterator
from fractions import Fraction
from typing import Any

from countersign.orders.model import OUTCOMES, Orders
from countersign.verify.graph import MissionGraph, build_graph

Dist = tuple[Fraction, Fraction, Fraction]


def all_paths(graph: MissionGraph) -> Iterator[tuple[list[int], list[int], int]]:
    """(goals, outcome indices, terminal node) of every path, by plain recursion."""
    assert graph.start is not None

    def walk(node: int, goals: list[int], outs: list[int]) -> Iterator[
            tuple[list[int], list[int], int]]:
        if graph.is_terminal(node):
            yield list(goals), list(outs), node
            return
        for k, target in enumerate(graph.succ[node]):
            yield from walk(target, [*goals, node], [*outs, k])

    yield from walk(graph.start, [], [])


def enumerate_figures(graph: MissionGraph, dists: list[Dist], costs: list[Fraction]
                      ) -> dict[str, Any]:
    """Terminal probabilities, violation probability, expected cost and the cost distribution
    by summing over every path."""
    terminals: dict[str, Fraction] = {t.id: Fraction(0) for t in graph.terminals}
    violation = Fraction(0)
    expected = Fraction(0)
    distribution: dict[Fraction, Fraction] = {}
    for goals, outs, terminal in all_paths(graph):
        p = Fraction(1)
        for g, k in zip(goals, outs, strict=True):
            p *= dists[g][k]
        terminals[graph.node_id(terminal)] += p
        if 2 in outs:
            violation += p
        total = sum((costs[g] for g in goals), Fraction(0))
        expected += p * total
        if p:
            distribution[total] = distribution.get(total, Fraction(0)) + p
    return {"terminals": terminals, "violation": violation, "expected": expected,
            "distribution": distribution}


def vertices(box: tuple[tuple[Fraction, Fraction], ...]) -> list[Dist]:
    """Every vertex of {lo <= p <= hi, sum p = 1}: two coordinates at a bound, the third free."""
    found: set[Dist] = set()
    for free in range(3):
        others = [k for k in range(3) if k != free]
        for a, b in itertools.product(box[others[0]], box[others[1]]):
            rest = 1 - a - b
            lo, hi = box[free]
            if lo <= rest <= hi:
                p = [Fraction(0)] * 3
                p[others[0]], p[others[1]], p[free] = a, b, rest
                found.add((p[0], p[1], p[2]))
    return sorted(found)


def random_orders(rng: random.Random, goals: int, *, kinds: tuple[str, ...] = ("point",),
                  terminals: int = 2, costs: bool = True) -> Orders:
    """A random DAG: each outcome names a later goal or a terminal; probabilities in twentieths
    (point), intervals, or none."""
    terminal_ids = [f"T{j}" for j in range(terminals)]
    items = []
    for i in range(goals):
        nxt = {}
        for outcome in OUTCOMES:
            later = [f"G{j}" for j in range(i + 1, goals)]
            nxt[outcome] = rng.choice(later + terminal_ids)
        item: dict[str, Any] = {"id": f"G{i}", "next": nxt}
        kind = rng.choice(kinds)
        if kind == "point":
            a = rng.randint(0, 20)
            b = rng.randint(0, 20 - a)
            item["p"] = {"succeed": a / 20, "fail": b / 20, "violate": (20 - a - b) / 20}
        elif kind == "interval":
            a = rng.randint(0, 100)
            b = rng.randint(0, 100 - a)
            point = (a, b, 100 - a - b)  # hundredths, summing to 1 exactly
            item["p"] = {o: [max(0, x - rng.choice((0, 10, 25))) / 100,
                             min(100, x + rng.choice((0, 10, 25))) / 100]
                         for o, x in zip(OUTCOMES, point, strict=True)}
        if costs:
            item["cost"] = {"energy_wh": rng.randint(0, 9), "duration_s": rng.choice((1.5, 60))}
        items.append(item)
    return Orders.model_validate({
        "id": "random", "start": "G0", "goals": items,
        "terminals": [{"id": t, "kind": "complete" if j == 0 else "abort"}
                      for j, t in enumerate(terminal_ids)]})


def with_probabilities(data: dict[str, Any], seed: int) -> Orders:
    """The orders with seeded point probabilities (hundredths) on every goal."""
    rng = random.Random(seed)
    data = json.loads(json.dumps(data))
    for goal in data.get("goals", []):
        a = rng.randint(1, 98)
        b = rng.randint(1, 99 - a)
        goal["p"] = {"succeed": a / 100, "fail": b / 100, "violate": (100 - a - b) / 100}
    return Orders.model_validate(data)


def storm_figures(orders: Orders) -> dict[str, float]:
    """Storm's reachability probabilities and expected energy on the DTMC of the orders.

    States are (node, violated so far): every goal twice, every terminal twice, each terminal
    absorbing; the violate outcome moves to the violated copy."""
    import stormpy
    from stormpy import datastructures, models

    graph = build_graph(orders)
    nodes = graph.goal_count + len(graph.terminals)
    state = {(n, v): n + v * nodes for n in range(nodes) for v in (0, 1)}
    rows: list[dict[int, float]] = [{} for _ in range(2 * nodes)]
    for node, goal in enumerate(graph.goals):
        assert goal.p is not None
        dist = [float(goal.p.bounds()[k][0]) for k in range(3)]
        for flag in (0, 1):
            for k, target in enumerate(graph.succ[node]):
                to = state[(target, 1 if k == 2 else flag)]
                row = rows[state[(node, flag)]]
                row[to] = row.get(to, 0.0) + dist[k]
    for t in range(graph.goal_count, nodes):
        for flag in (0, 1):
            rows[state[(t, flag)]][state[(t, flag)]] = 1.0
    builder = datastructures.SparseMatrixBuilder(
        rows=0, columns=0, entries=0, force_dimensions=False,
        has_custom_row_grouping=False)
    for r, row in enumerate(rows):
        for c in sorted(row):
            builder.add_next_value(r, c, row[c])
    matrix = builder.build()
    labels = models.StateLabeling(2 * nodes)
    for name in ("init", "violated", "done", *(f"t{j}" for j in range(len(graph.terminals)))):
        labels.add_label(name)
    assert graph.start is not None
    labels.add_label_to_state("init", state[(graph.start, 0)])
    for t in range(len(graph.terminals)):
        for flag in (0, 1):
            s = state[(graph.goal_count + t, flag)]
            labels.add_label_to_state(f"t{t}", s)
            labels.add_label_to_state("done", s)
            if flag:
                labels.add_label_to_state("violated", s)
    energy = [0.0] * (2 * nodes)
    for node, goal in enumerate(graph.goals):
        for flag in (0, 1):
            energy[state[(node, flag)]] = float(
                goal.cost.energy_wh if goal.cost and goal.cost.energy_wh else 0.0)
    components = models.SparseModelComponents(transition_matrix=matrix, state_labeling=labels)
    components.reward_models = {"energy": models.SparseRewardModel(
        optional_state_reward_vector=energy)}
    model = models.SparseDtmc(components)
    init = state[(graph.start, 0)]

    def check(formula: str) -> float:
        prop = stormpy.parse_properties(formula)[0]
        result = stormpy.model_checking(model, prop)
        return float(result.get_value(init))

    figures = {f"t_{t.id}": check(f'P=? [F "t{j}"]') for j, t in enumerate(graph.terminals)}
    figures["violated"] = check('P=? [F "violated"]')
    figures["energy"] = check('R{"energy"}=? [F "done"]')
    return figures
