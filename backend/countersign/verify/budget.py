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
from .costs import ExactCosts, exact_costs, graph_costs, mission_costs

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
        best, choice = _costliest_onward(graph, order, exact)
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


def _costliest_onward(graph: MissionGraph, order: list[int], exact: ExactCosts
                      ) -> tuple[list[int], list[int]]:
    """The cost of the costliest way on from each goal of `order` (successors first, every
    target a goal of `order` or a terminal, in the units of `exact.scale`) and the outcome it
    takes: the first of the costliest outcomes.
    Integer sums, so exact; one pass with the three outcomes compared in line (the goals'
    loop is what an edit of a large mission pays for)."""
    n = graph.goal_count
    succ, leg, own = graph.succ, exact.leg, exact.goal
    best = [0] * n
    choice = [0] * n
    for node in order:
        first, second, third = succ[node]
        to_first, to_second, to_third = leg[node]
        if first < n:
            to_first += best[first]
        if second < n:
            to_second += best[second]
        if third < n:
            to_third += best[third]
        k, most = (0, to_first) if to_first >= to_second else (1, to_second)
        if to_third > most:
            k, most = 2, to_third
        choice[node] = k
        best[node] = own[node] + most
    return best, choice


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
