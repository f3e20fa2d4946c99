"""Independent oracles for the probability and pattern checks: path enumeration, the vertices
of each goal's probability polytope, and Storm (stormpy) on the same Markov chain, with the
cost model's goal costs as state rewards and its legs as transition rewards."""

from __future__ import annotations

import itertools
import json
import random
from collections.abc import Iterator
from fractions import Fraction
from typing import Any

from countersign.orders.model import OUTCOMES, Orders
from countersign.verify.costs import graph_costs
from countersign.verify.graph import MissionGraph, build_graph

Dist = tuple[Fraction, Fraction, Fraction]
Legs = tuple[Fraction, Fraction, Fraction]


def priced(orders: Orders, quantity: str = "energy_wh") -> tuple[list[Fraction], list[Legs]]:
    """The cost model's goal costs and legs (per outcome edge) for every goal, each the decimal
    its float prints as."""
    costs = graph_costs(orders, build_graph(orders), quantity)
    return ([Fraction(repr(c)) for c in costs.goal],
            [(Fraction(repr(a)), Fraction(repr(b)), Fraction(repr(c))) for a, b, c in costs.leg])


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


def enumerate_figures(graph: MissionGraph, dists: list[Dist], costs: list[Fraction],
                      legs: list[Legs] | None = None) -> dict[str, Any]:
    """Terminal probabilities, violation probability, expected cost and the cost distribution
    by summing over every path; a path costs its goals and the legs of the edges it takes.
    Also the costliest path's total ("worst")."""
    terminals: dict[str, Fraction] = {t.id: Fraction(0) for t in graph.terminals}
    violation = Fraction(0)
    expected = Fraction(0)
    distribution: dict[Fraction, Fraction] = {}
    worst: Fraction | None = None
    for goals, outs, terminal in all_paths(graph):
        p = Fraction(1)
        for g, k in zip(goals, outs, strict=True):
            p *= dists[g][k]
        terminals[graph.node_id(terminal)] += p
        if 2 in outs:
            violation += p
        total = sum((costs[g] for g in goals), Fraction(0))
        if legs is not None:
            total += sum((legs[g][k] for g, k in zip(goals, outs, strict=True)), Fraction(0))
        worst = total if worst is None else max(worst, total)
        expected += p * total
        if p:
            distribution[total] = distribution.get(total, Fraction(0)) + p
    return {"terminals": terminals, "violation": violation, "expected": expected,
            "distribution": distribution, "worst": worst}


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


def random_area(rng: random.Random, name: str) -> dict[str, Any]:
    """A small box a few kilometres around one point off Monterey."""
    lat, lon = 36.7 + rng.uniform(-0.05, 0.05), -121.9 + rng.uniform(-0.05, 0.05)
    height, width = rng.uniform(0.002, 0.01), rng.uniform(0.002, 0.01)
    return {"id": name, "polygon": [[lat, lon], [lat, lon + width], [lat - height, lon + width],
                                    [lat - height, lon]]}


def random_orders(rng: random.Random, goals: int, *, kinds: tuple[str, ...] = ("point",),
                  terminals: int = 2, costs: bool = True, places: bool = False) -> Orders:
    """A random DAG: each outcome names a later goal or a terminal; probabilities in twentieths
    (point), intervals, or none. With `places` each goal runs in one of a few random areas
    with a random behaviour, for a vehicle with a speed and a power, so that the outcome
    edges have legs and goals without a given cost are estimated."""
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
        if costs and not (places and rng.random() < 0.5):
            item["cost"] = {"energy_wh": rng.randint(0, 9), "duration_s": rng.choice((1.5, 60))}
        if places:
            item["area"] = f"A{rng.randrange(3)}"
            item["behavior"] = rng.choice(("area_search", "transect", "sample", "loiter"))
        items.append(item)
    data: dict[str, Any] = {
        "id": "random", "start": "G0", "goals": items,
        "terminals": [{"id": t, "kind": "complete" if j == 0 else "abort"}
                      for j, t in enumerate(terminal_ids)]}
    if places:
        data["areas"] = [random_area(rng, f"A{j}") for j in range(3)]
        data["vehicle"] = "auv"
        data["vehicles"] = [{"id": "auv", "speed_mps": rng.choice((1.0, 1.5, 2.5)),
                             "power_w": rng.choice((60.0, 110.0))}]
    return Orders.model_validate(data)


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
    """Storm's reachability probabilities and expected energy and time on the DTMC of the
    orders.

    States are (node, violated so far): every goal twice, every terminal twice, each terminal
    absorbing; the violate outcome moves to the violated copy. Each goal's cost is its states'
    reward, each leg the reward of its transitions (two outcomes into one successor share a
    transition: it carries their legs weighted by their probabilities)."""
    import stormpy
    from stormpy import datastructures, models

    graph = build_graph(orders)
    nodes = graph.goal_count + len(graph.terminals)
    state = {(n, v): n + v * nodes for n in range(nodes) for v in (0, 1)}
    rows: list[dict[int, float]] = [{} for _ in range(2 * nodes)]
    leg_mass: dict[str, list[dict[int, float]]] = {
        q: [{} for _ in range(2 * nodes)] for q in ("energy_wh", "duration_s")}
    costs = {q: graph_costs(orders, graph, q) for q in leg_mass}
    for node, goal in enumerate(graph.goals):
        assert goal.p is not None
        dist = [float(goal.p.bounds()[k][0]) for k in range(3)]
        for flag in (0, 1):
            for k, target in enumerate(graph.succ[node]):
                to = state[(target, 1 if k == 2 else flag)]
                row = rows[state[(node, flag)]]
                row[to] = row.get(to, 0.0) + dist[k]
                for q, mass in leg_mass.items():
                    cell = mass[state[(node, flag)]]
                    cell[to] = cell.get(to, 0.0) + dist[k] * costs[q].leg[node][k]
    for t in range(graph.goal_count, nodes):
        for flag in (0, 1):
            rows[state[(t, flag)]][state[(t, flag)]] = 1.0
    def sparse(cells: list[dict[int, float]]) -> Any:
        builder = datastructures.SparseMatrixBuilder(
            rows=0, columns=0, entries=0, force_dimensions=False,
            has_custom_row_grouping=False)
        for r, row in enumerate(cells):
            for c in sorted(row):
                builder.add_next_value(r, c, cells[r][c])
        return builder.build()

    matrix = sparse(rows)
    # The reward of a transition: its legs' probability mass over the transition's probability.
    leg_rewards = {q: [{c: (mass[r].get(c, 0.0) / rows[r][c] if rows[r][c] else 0.0)
                        for c in rows[r]}
                       for r in range(2 * nodes)] for q, mass in leg_mass.items()}
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
    own = {q: [0.0] * (2 * nodes) for q in leg_mass}
    for q, vector in own.items():
        for node in range(graph.goal_count):
            for flag in (0, 1):
                vector[state[(node, flag)]] = costs[q].goal[node]
    components = models.SparseModelComponents(transition_matrix=matrix, state_labeling=labels)
    components.reward_models = {
        name: models.SparseRewardModel(optional_state_reward_vector=own[q],
                                       optional_transition_reward_matrix=sparse(leg_rewards[q]))
        for name, q in (("energy", "energy_wh"), ("time", "duration_s"))}
    model = models.SparseDtmc(components)
    init = state[(graph.start, 0)]

    def check(formula: str) -> float:
        prop = stormpy.parse_properties(formula)[0]
        result = stormpy.model_checking(model, prop)
        return float(result.get_value(init))

    figures = {f"t_{t.id}": check(f'P=? [F "t{j}"]') for j, t in enumerate(graph.terminals)}
    figures["violated"] = check('P=? [F "violated"]')
    figures["energy"] = check('R{"energy"}=? [F "done"]')
    figures["time"] = check('R{"time"}=? [F "done"]')
    return figures
