"""Draft orders from a plan: ordinary `countersign.orders/1` that go through the same
validation and approval as orders drafted by hand (seed 001 section 6.3: nothing a planner
produces is trusted until the verified model accepts it).

One survey goal per chosen area, in plan order: succeed or fail go on to the next area (the
last one to recovery), violate goes straight to recovery; a final recovery goal ends the
mission (succeed COMPLETE, fail or violate ABORT). Each survey goal costs the transit leg into
its area plus the survey of the chosen pass; the recovery goal costs the leg from the last
area. The vehicle's energy budget is the battery less the reserve, so the costliest path that
`validate` finds is exactly the plan's energy (every other path is a prefix of it plus the
recovery goal) and there is no BUDGET finding when the plan is feasible.

Leaving early (violate in an earlier area) means a different, possibly longer, leg home than
the planned last one; `abort_wh` in the goal parameters gives the energy of that route (via
the area's planned exit) so a supervisor sees it, and the reserve is what covers it.
"""

from __future__ import annotations

import math
from typing import Any

from ..orders.model import Orders
from .model import PlanProblem
from .solver import Plan

VEHICLE_ID = "planned-vehicle"


def orders_from_plan(
    problem: PlanProblem,
    plan: Plan,
    mission_id: str = "survey-plan",
    title: str = "Survey plan",
) -> Orders:
    if not plan.feasible:
        raise ValueError("an infeasible plan has no orders")
    goals = _survey_goals(problem, plan)
    planned = ", ".join(f"{s.area} (pass {s.pass_index})" for s in plan.steps) or "no area"
    data = {
        "format": "countersign.orders/1",
        "id": mission_id,
        "title": title,
        "description": (
            f"Drafted by countersign plan (level {problem.level}): {planned}; reward "
            f"{plan.reward:g}, energy {plan.energy_wh:,.1f} Wh of {plan.limit_wh:,.1f} Wh "
            f"(battery {problem.vehicle.battery_wh:g} Wh less reserve "
            f"{problem.vehicle.reserve_wh:g} Wh)."
        ),
        "vehicle": VEHICLE_ID,
        "start": "G1",
        "goals": goals,
        "vehicles": [
            {
                "id": VEHICLE_ID,
                "title": "Planned vehicle",
                "behaviors": ["area_search", "transit"],
                "budget": {"energy_wh": _budget(plan, goals)},
            }
        ],
    }
    return Orders.model_validate(data)


def _survey_goals(problem: PlanProblem, plan: Plan) -> list[dict[str, Any]]:
    """One goal per planned pass, in plan order, then the return to the recovery point (where
    a violated goal goes)."""
    areas = {area.id: area for area in problem.areas}
    rate = problem.vehicle.transit_wh_per_m
    recovery_id = f"G{len(plan.steps) + 1}"
    goals: list[dict[str, Any]] = []
    spent = 0.0
    for index, step in enumerate(plan.steps, start=1):
        area = areas[step.area]
        pass_ = area.passes[step.pass_index]
        spent += step.energy_wh
        following = f"G{index + 1}"
        suffix = f" (pass {step.pass_index})" if len(area.passes) > 1 else ""
        goals.append(
            {
                "id": f"G{index}",
                "title": f"Survey {area.label}{suffix}",
                "behavior": "area_search",
                "params": {
                    "plan_area": area.id,
                    "pass": step.pass_index,
                    "entry": list(pass_.entry),
                    "exit": list(pass_.exit),
                    "reward": area.reward,
                    "mandatory": area.mandatory,
                    "abort_wh": round(spent + rate * math.dist(pass_.exit, problem.recovery), 6),
                },
                "cost": {"energy_wh": step.energy_wh},
                "next": {"succeed": following, "fail": following, "violate": recovery_id},
            }
        )
    goals.append(
        {
            "id": recovery_id,
            "title": "Return to recovery point",
            "behavior": "transit",
            "params": {"destination": list(problem.recovery)},
            "cost": {"energy_wh": plan.return_wh},
            "next": {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"},
        }
    )
    return goals


def _budget(plan: Plan, goals: list[dict[str, Any]]) -> float:
    """The vehicle's energy budget: the plan's limit, unless the goals' costs added along the
    path exceed it by rounding only. validate adds the costs in its own order; the last bits
    of floating-point rounding must not refuse a plan exactly at the limit."""
    along_path = 0.0
    for goal in goals:
        along_path += goal["cost"]["energy_wh"]
    budget = plan.limit_wh
    if budget < along_path <= budget * (1 + 1e-12) + 1e-9:
        budget = along_path
    return budget


