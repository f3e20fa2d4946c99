"""Energy and time over every path (seed 001: verification against resource bounds).

Each step of a path costs its goal and the leg of the edge it takes, as verify/costs.py
prices them. The worst path per quantity comes from one pass over the DAG (longest path), never
from enumeration; BUDGET reports it when it exceeds the vehicle's budget.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from fractions import Fraction

from ..orders.findings import Finding, error, warning
from ..orders.model import BUDGET_QUANTITIES, OUTCOMES, Orders
from .costs import exact_costs, graph_costs, mission_costs

# The prices of one goal and one leg, under the names checks have long imported from here.
from .costs import goal_cost as goal_cost
from .costs import leg_cost as leg_cost
from .graph import MissionGraph
from .legs import MissionLegs
from .paths import topological_order

UNITS = {"energy_wh": ("Wh", "energy"), "duration_s": ("s", "time")}


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


def reportable_total(total: float | Fraction) -> float:
    """A path's total as a report can carry it: finite costs can still sum past the largest
    double (two of 1e308 Wh), and JSON has no infinity, so such a total reads as the largest
    number there is."""
    return float(min(total, Fraction(sys.float_info.max)))


def worst_paths(orders: Orders, graph: MissionGraph, legs: MissionLegs | None = None
                ) -> dict[str, WorstPath] | None:
    """The costliest path per budget quantity, or None when paths cannot be counted."""
    order = topological_order(graph)
    if order is None or graph.start is None:
        return None
    vehicle = orders.target_vehicle()
    costs = mission_costs(orders, legs)
    result: dict[str, WorstPath] = {}
    for quantity in BUDGET_QUANTITIES:
        priced = graph_costs(orders, graph, quantity, costs, order)
        exact = exact_costs(priced)
        best: dict[int, int] = {}
        choice: dict[int, int] = {}
        for node in order:  # successors come first
            options = [
                (best.get(target, 0) if target < graph.goal_count else 0) + exact.leg[node][k]
                for k, target in enumerate(graph.succ[node])
            ]
            k = max(range(3), key=lambda i: (options[i], -i))
            choice[node] = k
            best[node] = exact.goal[node] + options[k]
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
            reportable_total(Fraction(best[graph.start], exact.scale)),
            tuple(goals),
            tuple(outcomes),
            graph.node_id(node),
            budget,
            tuple(graph.goal_ids[n] for n in priced.unknown),
            tuple(graph.goal_ids[n] for n in priced.estimated),
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
