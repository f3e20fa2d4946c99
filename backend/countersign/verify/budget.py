"""Energy and time over every path (seed 001: verification against resource bounds).

Each goal has a cost per quantity, given in the orders or estimated from its area's geometry
and the vehicle's speed and power. The worst path per quantity comes from one pass over the
DAG (longest path), never from enumeration; BUDGET reports it when it exceeds the vehicle's
budget.
"""

from __future__ import annotations

import itertools
import math
import sys
from dataclasses import dataclass

from ..orders.findings import Finding, error, warning
from ..orders.model import BUDGET_QUANTITIES, OUTCOMES, Area, Goal, Orders, Vehicle
from .graph import MissionGraph
from .legs import MissionLegs, leg_lengths
from .legs import track_length_m as sweep_length_m
from .paths import topological_order

UNITS = {"energy_wh": ("Wh", "energy"), "duration_s": ("s", "time")}
EARTH_RADIUS_M = 6_371_000.0


@dataclass(frozen=True)
class WorstPath:
    quantity: str
    total: float
    goals: tuple[str, ...]
    outcomes: tuple[str, ...]
    terminal: str
    budget: float | None
    # Goals on the mission whose cost for this quantity is unknown (counted as zero).
    unknown: tuple[str, ...]
    estimated: tuple[str, ...]

    def to_json(self) -> dict[str, object]:
        return {
            "worst": round(self.total, 6),
            "budget": self.budget,
            "path": {
                "goals": list(self.goals),
                "outcomes": list(self.outcomes),
                "terminal": self.terminal,
            },
            "unknown_cost": list(self.unknown),
            "estimated_cost": list(self.estimated),
        }


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
    if metres is None or vehicle is None or not vehicle.speed_mps:
        return 0.0
    seconds = metres / vehicle.speed_mps
    if quantity == "duration_s":
        return seconds
    if quantity == "energy_wh" and vehicle.power_w is not None:
        return vehicle.power_w * seconds / 3600.0
    return 0.0


def reportable_total(total: float) -> float:
    """A path's total as a report can carry it: finite costs can still sum past the largest
    double (two of 1e308 Wh), and JSON has no infinity, so such a total reads as the largest
    number there is (issue 15)."""
    return min(total, sys.float_info.max)


def worst_paths(orders: Orders, graph: MissionGraph, legs: MissionLegs | None = None
                ) -> dict[str, WorstPath] | None:
    """The costliest path per budget quantity, or None when paths cannot be counted."""
    order = topological_order(graph)
    if order is None or graph.start is None:
        return None
    vehicle = orders.target_vehicle()
    areas = orders.area_index()
    # The transit between goals costs too: the geodesic leg of each outcome edge (issue 21).
    lengths = leg_lengths(orders, legs) if vehicle is not None and vehicle.speed_mps else {}
    result: dict[str, WorstPath] = {}
    for quantity in BUDGET_QUANTITIES:
        costs: dict[int, float] = {}
        unknown: list[int] = []
        estimated: list[int] = []
        for node in order:
            cost, was_estimated = goal_cost(graph.goals[node], quantity, vehicle, areas)
            if cost is None:
                unknown.append(node)
            elif was_estimated:
                estimated.append(node)
            costs[node] = cost or 0.0
        best: dict[int, float] = {}
        choice: dict[int, int] = {}
        for node in order:  # successors come first
            goal = graph.goals[node]
            options = [
                (best.get(target, 0.0) if target < graph.goal_count else 0.0)
                + leg_cost(lengths.get((goal.id, OUTCOMES[k])), quantity, vehicle)
                for k, target in enumerate(graph.succ[node])
            ]
            k = max(range(3), key=lambda i: (options[i], -i))
            choice[node] = k
            best[node] = costs[node] + options[k]
        goals: list[str] = []
        outcomes: list[str] = []
        node = graph.start
        while node < graph.goal_count:
            goals.append(graph.goal_ids[node])
            outcomes.append(OUTCOMES[choice[node]])
            node = graph.succ[node][choice[node]]
        budget = getattr(vehicle.budget, quantity, None) if vehicle and vehicle.budget else None
        result[quantity] = WorstPath(
            quantity,
            reportable_total(best[graph.start]),
            tuple(goals),
            tuple(outcomes),
            graph.node_id(node),
            budget,
            tuple(graph.goal_ids[n] for n in sorted(unknown)),
            tuple(graph.goal_ids[n] for n in sorted(estimated)),
        )
    return result


def _amount(quantity: str, value: float) -> str:
    unit, _ = UNITS[quantity]
    return f"{value:,.1f} {unit}".replace(".0 ", " ")


def check_budget(worst: dict[str, WorstPath] | None) -> list[Finding]:
    findings: list[Finding] = []
    for quantity, path in (worst or {}).items():
        if path.budget is None:
            continue
        _, noun = UNITS[quantity]
        if path.total > path.budget:
            steps = ", ".join(f"{g} {o}" for g, o in zip(path.goals, path.outcomes, strict=True))
            findings.append(
                error(
                    "BUDGET",
                    [*path.goals, path.terminal],
                    f"On the path {steps} -> {path.terminal}, the vehicle needs "
                    f"{_amount(quantity, path.total)} of {noun}, more than its budget of "
                    f"{_amount(quantity, path.budget)}.",
                    quantity=quantity,
                    **path.to_json(),
                )
            )
        if path.unknown:
            findings.append(
                warning(
                    "BUDGET",
                    list(path.unknown),
                    f"The {noun} budget cannot be proven for every path: goals "
                    f"{', '.join(path.unknown)} have no {noun} cost and none can be estimated "
                    "(give a cost, or an area and the vehicle's speed and power).",
                    quantity=quantity,
                )
            )
    return findings
