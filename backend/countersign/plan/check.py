"""Untrusted plans (seed 001 section 6.3): a plan from any other source is checked against
the problem, condition by condition, and the first violated condition is explained."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ..orders.reader import Problem
from .model import PlanProblem, PlanReadError
from .solver import plan_energy


@dataclass(frozen=True)
class CheckResult:
    ok: bool
    message: str
    reward: float = 0.0
    energy_wh: float = 0.0

    def to_json(self) -> dict[str, Any]:
        return {"ok": self.ok, "message": self.message, "reward": self.reward,
                "energy_wh": round(self.energy_wh, 6)}


def plan_from_data(data: Any) -> tuple[list[str], dict[str, int]]:
    """`order` and `passes` of a plan (the output of `countersign plan` reads as one)."""
    if not isinstance(data, dict):
        raise PlanReadError([Problem("$", "a plan must be a JSON object with 'order'")])
    order = data.get("order")
    if not isinstance(order, list) or not all(isinstance(i, str) for i in order):
        raise PlanReadError([Problem("$.order", "must be a list of area ids")])
    passes = data.get("passes", {})
    if not isinstance(passes, dict):
        raise PlanReadError([Problem("$.passes", "must map area ids to pass indices")])
    for key, value in passes.items():
        if not isinstance(value, int) or isinstance(value, bool):
            raise PlanReadError([Problem(f"$.passes.{key}", "must be a pass index (0, 1, ...)")])
    return list(order), dict(passes)


def check_plan(problem: PlanProblem, order: list[str], passes: dict[str, int]) -> CheckResult:
    areas = {area.id: area for area in problem.areas}
    seen: set[str] = set()
    for position, area_id in enumerate(order, start=1):
        if area_id not in areas:
            return CheckResult(False, f"step {position}: {area_id!r} is not an area of the problem")
        if area_id in seen:
            return CheckResult(False, f"step {position}: area {area_id} is surveyed twice")
        seen.add(area_id)
    for area_id, index in passes.items():
        if area_id not in seen:
            return CheckResult(
                False, f"a pass is given for {area_id}, which the plan never surveys"
            )
        available = len(problem.passes_of(areas[area_id]))
        if not 0 <= index < available:
            rule = " (level 1 uses each area's first pass)" if problem.level == 1 else ""
            return CheckResult(
                False, f"area {area_id} has no pass {index}: choose 0 to {available - 1}{rule}"
            )
    missing = [a.id for a in problem.areas if a.mandatory and a.id not in seen]
    if missing:
        return CheckResult(False, f"mandatory areas are not surveyed: {', '.join(missing)}")
    energy = plan_energy(problem, order, passes)
    reward = sum(areas[a].reward for a in order)
    limit = problem.vehicle.limit_wh
    if energy > limit:
        return CheckResult(
            False,
            f"the plan needs {energy:,.1f} Wh, more than the {limit:,.1f} Wh the vehicle may use "
            f"(battery {problem.vehicle.battery_wh:g} Wh less reserve "
            f"{problem.vehicle.reserve_wh:g} Wh)",
            reward, energy,
        )
    return CheckResult(
        True, f"feasible: reward {reward:g}, energy {energy:,.1f} Wh of {limit:,.1f} Wh",
        reward, energy,
    )
