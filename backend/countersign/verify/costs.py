"""The one cost model: what each goal and each leg between goals costs in energy and time.

A goal's own work costs what the orders give, or an estimate from its area's geometry and the
vehicle's speed and power. The leg of an outcome edge (verify/legs.py: from where the goal ends
to where its successor starts) costs its geodesic metres at the vehicle's speed and power.
A step of a path - one goal ending with one outcome - is charged the goal plus the leg of the
edge it takes. BUDGET's worst path, the expected energy and time of the probabilities (and
their quantiles), the execution check and the rehearsal's simulation all read their figures
from here (DESIGN.md: one cost model everywhere).
"""

from __future__ import annotations

import functools
import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction

from ..orders.model import OUTCOMES, Area, Goal, Orders, Vehicle
from .graph import MissionGraph
from .legs import MissionLegs, leg_lengths
from .legs import track_length_m as sweep_length_m

EARTH_RADIUS_M = 6_371_000.0
# A goal's three outcome edges' costs in integer units of one scale.
Edges = tuple[int, int, int]


def _local_metres(area: Area) -> list[tuple[float, float]]:
    lat0 = math.radians(sum(p[0] for p in area.polygon) / len(area.polygon))
    return [
        (
            math.radians(lon) * EARTH_RADIUS_M * math.cos(lat0),
            math.radians(lat) * EARTH_RADIUS_M,
        )
        for lat, lon in area.polygon
    ]


def track_length_m(goal: Goal, area: Area, areas: dict[str, Area] | None = None) -> float:
    """A nominal track: for searches and transects the sweep the rehearsal flies
    (verify/legs.py: the lawn-mower at the goal's swath in the mission's frame, or one run),
    otherwise once around the area's boundary."""
    track = sweep_length_m(goal, tuple((areas or {area.id: area}).values()), area)
    if track is not None:
        return track
    points = _local_metres(area)
    ring = [*points, points[0]]
    return sum(math.dist(a, b) for a, b in itertools.pairwise(ring))


def goal_cost(
    goal: Goal, quantity: str, vehicle: Vehicle | None, areas: dict[str, Area]
) -> tuple[float | None, bool]:
    """(cost, estimated) of one goal for one quantity; None when neither given nor estimable."""
    given = getattr(goal.cost, quantity, None) if goal.cost else None
    if given is not None:
        return float(given), False
    area = areas.get(goal.area) if goal.area else None
    if vehicle is None or vehicle.speed_mps is None or area is None or len(area.polygon) < 2:
        return None, False
    seconds = track_length_m(goal, area, areas) / vehicle.speed_mps
    if quantity == "duration_s":
        return seconds, True
    if quantity == "energy_wh" and vehicle.power_w is not None:
        return vehicle.power_w * seconds / 3600.0, True
    return None, False


def leg_cost(metres: float | None, quantity: str, vehicle: Vehicle | None) -> float:
    """What a leg of `metres` costs; nothing when the vehicle's speed (or, for energy, its
    power) is unknown, as the leg then cannot be priced."""
    if metres is None or vehicle is None or not vehicle.speed_mps:
        return 0.0
    seconds = metres / vehicle.speed_mps
    if quantity == "duration_s":
        return seconds
    if quantity == "energy_wh" and vehicle.power_w is not None:
        return vehicle.power_w * seconds / 3600.0
    return 0.0


@dataclass(frozen=True)
class MissionCosts:
    """Every goal's cost and every leg's length of one mission, looked up by goal id."""

    vehicle: Vehicle | None
    areas: dict[str, Area]
    lengths: dict[tuple[str, str], float]

    def goal(self, goal: Goal, quantity: str) -> tuple[float | None, bool]:
        return goal_cost(goal, quantity, self.vehicle, self.areas)

    def leg(self, goal_id: str, outcome: str, quantity: str) -> float:
        return leg_cost(self.lengths.get((goal_id, outcome)), quantity, self.vehicle)

    def step(self, goal: Goal, outcome: str, quantity: str) -> float:
        """A goal ending with `outcome`: its own cost (zero when unknown) and the leg taken."""
        own, _ = self.goal(goal, quantity)
        return (own or 0.0) + self.leg(goal.id, outcome, quantity)


def mission_costs(orders: Orders, legs: MissionLegs | None = None) -> MissionCosts:
    vehicle = orders.target_vehicle()
    # Legs are priced at the vehicle's speed: without one there is nothing to lay out.
    lengths = leg_lengths(orders, legs) if vehicle is not None and vehicle.speed_mps else {}
    return MissionCosts(vehicle, orders.area_index(), lengths)


@dataclass(frozen=True)
class GraphCosts:
    """One quantity's costs on the mission graph: per goal node its own cost (zero when
    unknown) and per outcome edge the leg's cost (zero where there is no leg)."""

    quantity: str
    goal: tuple[float, ...]
    leg: tuple[tuple[float, float, float], ...]
    unknown: tuple[int, ...]  # goal nodes whose cost is neither given nor estimable
    estimated: tuple[int, ...]

    def step(self, node: int, k: int) -> float:
        return self.goal[node] + self.leg[node][k]


def graph_costs(orders: Orders, graph: MissionGraph, quantity: str,
                costs: MissionCosts | None = None,
                nodes: Sequence[int] | None = None) -> GraphCosts:
    """The quantity's costs of the goal nodes `nodes` (default: every goal); other goals are
    left at zero and never reported unknown."""
    costs = costs if costs is not None else mission_costs(orders)
    own = [0.0] * graph.goal_count
    legs = [(0.0, 0.0, 0.0)] * graph.goal_count
    unknown: list[int] = []
    estimated: list[int] = []
    for node in range(graph.goal_count) if nodes is None else nodes:
        goal = graph.goals[node]
        cost, was_estimated = costs.goal(goal, quantity)
        if cost is None:
            unknown.append(node)
        elif was_estimated:
            estimated.append(node)
        own[node] = cost or 0.0
        if not costs.lengths:
            continue  # no legs laid out: every edge costs nothing
        legs[node] = (costs.leg(goal.id, OUTCOMES[0], quantity),
                      costs.leg(goal.id, OUTCOMES[1], quantity),
                      costs.leg(goal.id, OUTCOMES[2], quantity))
    return GraphCosts(quantity, tuple(own), tuple(legs), tuple(sorted(unknown)),
                      tuple(sorted(estimated)))


@dataclass(frozen=True)
class ExactCosts:
    """The same costs as integers over one `scale`, each the decimal its float prints as, so
    that sums over paths are exact: every figure derived from them (a worst path, an
    expectation, a quantile) is then rounded to a float once, and rounding keeps their order."""

    scale: int
    goal: tuple[int, ...]
    leg: tuple[Edges, ...]


@functools.lru_cache(maxsize=65_536, typed=True)
def _decimal(cost: float) -> Fraction:
    """The decimal a cost prints as, exactly. Kept: an edit prices the same costs again, and
    parsing their text was most of what exact costs took (typed: an int and the float equal to
    it can print as different decimals)."""
    return Fraction(repr(cost))


def exact_costs(priced: GraphCosts) -> ExactCosts:
    # Costs repeat (most legs are zero): convert each distinct value once.
    distinct = {*priced.goal, *itertools.chain(*priced.leg)}
    decimals = {c: _decimal(c) for c in distinct}
    scale = 1
    for value in decimals.values():
        scale = math.lcm(scale, value.denominator)
    units = {c: v.numerator * (scale // v.denominator) for c, v in decimals.items()}
    return ExactCosts(scale, tuple(units[c] for c in priced.goal),
                      tuple((units[a], units[b], units[c]) for a, b, c in priced.leg))
