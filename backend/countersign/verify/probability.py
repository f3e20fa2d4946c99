"""How likely each ending is: exact outcome probabilities over the mission DAG.

Each goal's outcomes carry probabilities (on the goal, or on the vehicle's profile for its
behaviour); the mission is then a discrete-time Markov chain whose states are the goals and
whose absorbing states are the terminals. Every figure comes from one pass over the DAG in
reverse topological order, never from enumerating paths. The expected energy and time (and
their quantiles) charge what BUDGET charges (verify/costs.py): each goal's own cost as a state
reward and the leg of each outcome edge as a transition reward.

Exactness without slow fractions: every probability is a multiple of 1/Q for one integer Q (the
least common denominator of the decimals the author wrote), so a node's value is an integer
over Q^L, where L is the node's height (the most goals from it to a terminal). Big-integer sums
and small-integer products stay linear in the number of digits; a fraction with a gcd on every
addition would be quadratic and take seconds at 10,000 goals.

That exact pass is quadratic on deep DAGs (a chain of n goals: n numbers of up to n digits),
so every figure is first computed in fixed point, an integer over 2^FIXED_BITS per node with
each division by Q rounded down: every node's value is then at most its height units of
2^-FIXED_BITS below the exact one (each floor loses less than a unit, and a node's error is a
convex combination of its successors' plus one). When both ends of that enclosure round to the
same reported double, the double is the exact figure's; only otherwise (a figure within about
2^-100 of a rounding boundary) is the exact pass run. Reports stay byte-identical.

Where a goal's probabilities are intervals or missing (any distribution), the minimum and the
maximum of each figure follow from the same pass: the choices at different goals are
independent and every figure is a nonnegative combination of the successors' values, so each
goal picks the extreme point of its box-constrained simplex greedily (the fractional knapsack
solution of a linear programme over `lo <= p <= hi, sum p = 1`).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from fractions import Fraction

from ..orders.model import BUDGET_QUANTITIES, Orders, OutcomeProbabilities
from .budget import reportable_total
from .costs import Edges, exact_costs, graph_costs, mission_costs
from .graph import MissionGraph
from .legs import MissionLegs
from .paths import topological_order

# Bounds (lo, hi) per outcome in units of 1/Q.
Box = tuple[tuple[int, int], tuple[int, int], tuple[int, int]]
QUANTILES: tuple[str, ...] = ("0.5", "0.9", "0.95", "0.99")
# The cost distribution is kept per goal as {total: probability} in exact fractions; past this
# many (total, probability) updates over the whole mission the quantiles are not computed (the
# expectation still is, exactly): the number of distinct totals can grow with the paths.
MAX_DISTRIBUTION_WORK = 50_000
# Fixed-point precision of the fast pass: its error (at most the mission's height in units of
# 2^-FIXED_BITS) must be far below a double's spacing for the enclosure to decide the double.
FIXED_BITS = 160


@dataclass(frozen=True)
class Bound:
    """The least and the greatest value of a figure, each a fraction whose double is that of
    the exact value (the report's precision; see _Scaled.figure)."""

    low: Fraction
    high: Fraction

    @property
    def exact(self) -> float | None:
        """The figure's double when it has one value (point probabilities), else None."""
        low, high = reportable_total(self.low), reportable_total(self.high)
        return low if low == high else None

    def to_json(self) -> dict[str, float]:
        return {"min": reportable_total(self.low), "max": reportable_total(self.high)}


@dataclass(frozen=True)
class Expectation:
    bound: Bound
    quantiles: dict[str, float] | None
    unknown: tuple[str, ...]  # goals whose cost is unknown, counted as zero

    def to_json(self) -> dict[str, object]:
        return {**self.bound.to_json(), "quantiles": self.quantiles,
                "unknown_cost": list(self.unknown)}


@dataclass(frozen=True)
class Probabilities:
    terminals: dict[str, Bound]
    violation: Bound  # some goal on the path ends with a constraint violation
    expected: dict[str, Expectation]
    unknown: tuple[str, ...]  # reachable goals with no probabilities at all
    intervals: tuple[str, ...]  # reachable goals with interval probabilities

    @property
    def exact(self) -> bool:
        return not self.unknown and not self.intervals

    def to_json(self) -> dict[str, object]:
        return {
            "exact": self.exact,
            "terminals": {t: b.to_json() for t, b in self.terminals.items()},
            "violation": self.violation.to_json(),
            "expected": {q: e.to_json() for q, e in self.expected.items()},
            "unknown": list(self.unknown),
            "intervals": list(self.intervals),
        }


def goal_probabilities(orders: Orders, graph: MissionGraph) -> list[OutcomeProbabilities | None]:
    """Each goal's outcome probabilities: its own, else its vehicle's for the behaviour."""
    vehicle = orders.target_vehicle()
    by_behavior = (vehicle.p or {}) if vehicle is not None else {}
    result: list[OutcomeProbabilities | None] = []
    for goal in graph.goals:
        given = goal.p
        if given is None and goal.behavior is not None:
            given = by_behavior.get(goal.behavior)
        result.append(given)
    return result


UNKNOWN_BOUNDS = ((Fraction(0), Fraction(1)),) * 3


def fraction_boxes(
    given: Sequence[OutcomeProbabilities | None],
) -> list[tuple[tuple[Fraction, Fraction], ...]]:
    """Exact tightened (lo, hi) per outcome: lo_k >= 1 - sum of the other highs, and so on, so
    that every bound is attained by some distribution."""
    boxes: list[tuple[tuple[Fraction, Fraction], ...]] = []
    for p in given:
        raw = UNKNOWN_BOUNDS if p is None else p.bounds()
        if p is not None and not isinstance(p.succeed, tuple) and not isinstance(
                p.fail, tuple) and not isinstance(p.violate, tuple):
            boxes.append(raw)  # a point: nothing to tighten
            continue
        low_sum = sum(b[0] for b in raw)
        high_sum = sum(b[1] for b in raw)
        boxes.append(tuple(
            (max(lo, 1 - (high_sum - hi)), min(hi, 1 - (low_sum - lo))) for lo, hi in raw))
    return boxes


def _common_denominator(values: Sequence[Fraction]) -> int:
    q = 1
    for value in values:
        q = math.lcm(q, value.denominator)
    return q


def _units(value: Fraction, q: int) -> int:
    return value.numerator * (q // value.denominator)


class _Scaled:
    """The DAG with integer probabilities over Q and each node's height."""

    def __init__(self, graph: MissionGraph, order: list[int],
                 boxes: Sequence[tuple[tuple[Fraction, Fraction], ...]],
                 fast: bool = True) -> None:
        self.graph = graph
        self.fast = fast
        self.order = order
        goal_count = graph.goal_count
        self.q = _common_denominator([f for n in order for b in boxes[n] for f in b])
        q = self.q
        self.box: list[Box | None] = [None] * goal_count
        for node in order:
            (a, b), (c, d), (e, f) = boxes[node]
            self.box[node] = ((_units(a, q), _units(b, q)), (_units(c, q), _units(d, q)),
                              (_units(e, q), _units(f, q)))
        height = [0] * (goal_count + len(graph.terminals))
        for node in order:
            height[node] = 1 + max(height[t] for t in graph.succ[node])
        self.height = height
        self._powers = [1]
        self._coefficients: list[tuple[tuple[int, int, int], ...] | None] | None = None

    @property
    def coefficients(self) -> list[tuple[tuple[int, int, int], ...] | None]:
        """Per goal with point probabilities, (successor, a_k * Q^(gap)) for each outcome:
        then a node's value is a sum of small-integer multiples of its successors' values,
        with no per-node choice (shared by every exact pass; built on the first one only, as
        the powers of Q are the quadratic part)."""
        if self._coefficients is None:
            height = self.height
            coefficients: list[tuple[tuple[int, int, int], ...] | None] = (
                [None] * self.graph.goal_count)
            for node in self.order:
                bounds = self.box[node]
                assert bounds is not None
                if any(lo != hi for lo, hi in bounds):
                    continue
                top = height[node] - 1
                coefficients[node] = tuple(
                    (k, target, bounds[k][0] * self.power(top - height[target]))
                    for k, target in enumerate(self.graph.succ[node]) if bounds[k][0])
            self._coefficients = coefficients
        return self._coefficients

    def figure(self, leaf: Callable[[int], int], maximise: bool,
               extra: Sequence[int] | None = None, zero_violate: bool = False,
               edges: Sequence[Edges] | None = None,
               reported: Callable[[Fraction], Fraction] = lambda x: x) -> Fraction:
        """`reported(run(...))` for a monotone `reported`, to the precision a report carries:
        a fraction whose double (reportable_total) is that of the exact figure, from the
        fixed-point pass when its enclosure decides the double, else from the exact pass."""
        if self.fast:
            value, slack = self.fixed(leaf, maximise, extra, zero_violate, edges)
            unit = 1 << FIXED_BITS
            low = reported(Fraction(value, unit))
            high = reported(Fraction(value + slack, unit))
            if reportable_total(low) == reportable_total(high):
                return low
        return reported(self.run(leaf, maximise, extra, zero_violate, edges))

    def fixed(self, leaf: Callable[[int], int], maximise: bool,
              extra: Sequence[int] | None = None, zero_violate: bool = False,
              edges: Sequence[Edges] | None = None) -> tuple[int, int]:
        """The recurrence of `run` in units of 2^-FIXED_BITS, each node's sum divided by Q
        rounded down: (V, slack) with the exact start value in [V, V + slack] units."""
        graph = self.graph
        goal_count = graph.goal_count
        bits = FIXED_BITS
        value: list[int] = [0] * goal_count
        value.extend(leaf(t) << bits
                     for t in range(goal_count, goal_count + len(graph.terminals)))
        succ = graph.succ
        box = self.box
        q = self.q
        for node in self.order:
            bounds = box[node]
            assert bounds is not None
            a, b, c = succ[node]
            wa, wb = value[a], value[b]
            wc = 0 if zero_violate else value[c]
            if edges is not None:
                ea, eb, ec = edges[node]
                wa += ea << bits
                wb += eb << bits
                if not zero_violate:
                    wc += ec << bits
            (la, ha), (lb, hb), (lc, hc) = bounds
            if la == ha and lb == hb and lc == hc:
                total = la * wa + lb * wb + lc * wc
            else:
                total = _extreme([wa, wb, wc], bounds, q, maximise)
            total //= q
            if extra is not None and extra[node]:
                total += extra[node] << bits
            value[node] = total
        start = graph.start
        assert start is not None
        return value[start], self.height[start]

    def power(self, exponent: int) -> int:
        powers = self._powers
        while len(powers) <= exponent:
            powers.append(powers[-1] * self.q)
        return powers[exponent]

    def run(self, leaf: Callable[[int], int], maximise: bool,
            extra: Sequence[int] | None = None, zero_violate: bool = False,
            edges: Sequence[Edges] | None = None) -> Fraction:
        """The extreme (max or min) value at the start of
        X(v) = extra(v) + sum_k p_k (edges(v)_k + X(s_k)), with X(terminal) = leaf(terminal);
        `zero_violate` counts the violate successor as 0."""
        graph = self.graph
        goal_count = graph.goal_count
        height = self.height
        power = self.power
        value: list[int] = [0] * goal_count
        value.extend(leaf(t) for t in range(goal_count, goal_count + len(graph.terminals)))
        succ = graph.succ
        box = self.box
        coefficients = self.coefficients
        q = self.q
        for node in self.order:
            top = height[node] - 1
            point = coefficients[node]
            edge = edges[node] if edges is not None else None
            if point is not None:
                total = 0
                for k, target, coefficient in point:
                    if not (k == 2 and zero_violate):
                        total += coefficient * value[target]
                if edge is not None and any(edge):
                    bounds = box[node]
                    assert bounds is not None
                    total += sum(bounds[k][0] * edge[k] for k in range(3)) * power(top)
            else:
                weights = [0, 0, 0]
                for k, target in enumerate(succ[node]):
                    if k == 2 and zero_violate:
                        continue
                    x = value[target]
                    if x:
                        weights[k] = x * power(top - height[target])
                    if edge is not None and edge[k]:
                        weights[k] += edge[k] * power(top)
                bounds = box[node]
                assert bounds is not None
                total = _extreme(weights, bounds, q, maximise)
            if extra is not None and extra[node]:
                total += extra[node] * power(top + 1)
            value[node] = total
        start = graph.start
        assert start is not None
        return Fraction(value[start], power(height[start]))


def _divided(value: Fraction, scale: int) -> Fraction:
    return value / scale


def _indicator(node: int, t: int) -> int:
    return 1 if t == node else 0


def _extreme(weights: list[int], bounds: Box, q: int, maximise: bool) -> int:
    """max (or min) of sum_k a_k w_k over integers lo_k <= a_k <= hi_k with sum a_k = q."""
    (l0, h0), (l1, h1), (l2, h2) = bounds
    if l0 == h0 and l1 == h1 and l2 == h2:
        return l0 * weights[0] + l1 * weights[1] + l2 * weights[2]
    amounts = [l0, l1, l2]
    highs = (h0, h1, h2)
    rest = q - l0 - l1 - l2
    ranking = sorted(range(3), key=weights.__getitem__, reverse=maximise)
    for k in ranking:
        if rest <= 0:
            break
        add = min(rest, highs[k] - amounts[k])
        amounts[k] += add
        rest -= add
    return amounts[0] * weights[0] + amounts[1] * weights[1] + amounts[2] * weights[2]


def outcome_probabilities(orders: Orders, graph: MissionGraph, legs: MissionLegs | None = None,
                          *, fast: bool = True) -> Probabilities | None:
    """Every figure, or None when paths cannot be counted (no start, a loop, a dangling or
    missing successor reachable from the start). `fast=False` runs only the exact pass (the
    reference the tests compare the fixed-point pass with)."""
    order = topological_order(graph)
    if order is None or graph.start is None:
        return None
    given = goal_probabilities(orders, graph)
    boxes = fraction_boxes(given)
    scaled = _Scaled(graph, order, boxes, fast)
    goal_count = graph.goal_count

    def both(leaf: Callable[[int], int], extra: Sequence[int] | None = None,
             zero_violate: bool = False, edges: Sequence[Edges] | None = None,
             reported: Callable[[Fraction], Fraction] = lambda x: x) -> Bound:
        low = scaled.figure(leaf, False, extra, zero_violate, edges, reported)
        high = (scaled.figure(leaf, True, extra, zero_violate, edges, reported)
                if not exact else low)
        return Bound(low, high)

    reachable = sorted(order)
    unknown = tuple(graph.goal_ids[n] for n in reachable if given[n] is None)
    intervals = tuple(graph.goal_ids[n] for n in reachable
                      if given[n] is not None and any(lo != hi for lo, hi in boxes[n]))
    exact = not unknown and not intervals

    terminals: dict[str, Bound] = {}
    for index, terminal in enumerate(graph.terminals):
        terminals[terminal.id] = both(functools.partial(_indicator, goal_count + index))
    # 1 - P(no violation): the enclosure is checked on the figure reported, not on P.
    clean = both(lambda t: 1, zero_violate=True, reported=lambda x: 1 - x)
    violation = Bound(clean.high, clean.low)

    mission = mission_costs(orders, legs)
    expected: dict[str, Expectation] = {}
    for quantity in BUDGET_QUANTITIES:
        priced = graph_costs(orders, graph, quantity, mission, order)
        exact_units = exact_costs(priced)  # BUDGET's costs, as BUDGET sums them
        scale, ints, edges = exact_units.scale, exact_units.goal, exact_units.leg
        bound = both(lambda t: 0, extra=ints, edges=edges,
                     reported=functools.partial(_divided, scale=scale))
        quantiles = cost_quantiles(scaled, ints, edges, scale) if exact else None
        expected[quantity] = Expectation(
            bound, quantiles, tuple(graph.goal_ids[n] for n in priced.unknown))
    return Probabilities(terminals, violation, expected, unknown, intervals)


def cost_distribution(scaled: _Scaled, costs: Sequence[int], edges: Sequence[Edges]
                      ) -> dict[int, Fraction] | None:
    """{total cost: probability} from the start (point probabilities only), where a path's
    total is its goals' `costs` and the `edges` it takes, or None when it would take more than
    MAX_DISTRIBUTION_WORK updates. Weights are integers over Q^height as in `_Scaled.run`."""
    graph = scaled.graph
    goal_count = graph.goal_count
    height = scaled.height
    power = scaled.power
    dist: list[dict[int, int] | None] = [None] * goal_count
    finished: dict[int, int] = {0: 1}
    work = 0
    for node in scaled.order:
        top = height[node] - 1
        bounds = scaled.box[node]
        assert bounds is not None
        merged: dict[int, int] = {}
        for k, target in enumerate(graph.succ[node]):
            p = bounds[k][0]
            if not p:
                continue
            tail = finished if target >= goal_count else dist[target]
            assert tail is not None
            work += len(tail)
            if work > MAX_DISTRIBUTION_WORK:
                return None
            factor = p * power(top - height[target])
            leg = edges[node][k]
            for total, weight in tail.items():
                merged[total + leg] = merged.get(total + leg, 0) + factor * weight
        own = costs[node]
        dist[node] = {own + total: weight for total, weight in merged.items()}
    start = graph.start
    assert start is not None
    result = dist[start]
    assert result is not None
    scale = power(height[start])
    return {total: Fraction(weight, scale) for total, weight in result.items()}


def quantile(distribution: dict[int, Fraction], level: Fraction) -> int:
    """The smallest total whose cumulative probability reaches the level."""
    cumulative = Fraction(0)
    totals = sorted(distribution)
    for total in totals:
        cumulative += distribution[total]
        if cumulative >= level:
            return total
    return totals[-1]


def cost_quantiles(scaled: _Scaled, costs: Sequence[int], edges: Sequence[Edges], scale: int
                   ) -> dict[str, float] | None:
    distribution = cost_distribution(scaled, costs, edges)
    if distribution is None:
        return None
    return {level: reportable_total(Fraction(quantile(distribution, Fraction(level)), scale))
            for level in QUANTILES}


def path_probability_bounds(
    orders: Orders, graph: MissionGraph,
) -> list[tuple[tuple[float, float], ...]]:
    """Per goal, (lo, hi) per outcome as floats, for the probability of one path (a product:
    its bounds are the products of the tightened per-outcome bounds)."""
    boxes = fraction_boxes(goal_probabilities(orders, graph))
    return [tuple((float(lo), float(hi)) for lo, hi in box) for box in boxes]


def _figure(bound: Bound) -> str:
    low, high = reportable_total(bound.low), reportable_total(bound.high)
    return f"{low:.6g}" if low == high else f"{low:.6g} to {high:.6g}"


def summary_lines(figures: Probabilities) -> list[str]:
    """The figures as plain lines for the command line."""
    kind = "exact" if figures.exact else "bounds: some goals give intervals or nothing"
    lines = [f"Outcome probabilities ({kind}):"]
    lines.extend(f"  P({terminal}) = {_figure(b)}" for terminal, b in figures.terminals.items())
    lines.append(f"  P(any violation) = {_figure(figures.violation)}")
    for quantity, expectation in figures.expected.items():
        line = f"  Expected {quantity} = {_figure(expectation.bound)}"
        if expectation.quantiles:
            line += " (" + ", ".join(f"p{float(level) * 100:g} {value:g}"
                                     for level, value in expectation.quantiles.items()) + ")"
        lines.append(line)
    if figures.unknown:
        lines.append(f"  Goals without probabilities: {', '.join(figures.unknown[:20])}")
    return lines
