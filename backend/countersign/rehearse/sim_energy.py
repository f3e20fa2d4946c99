"""Energy for the way home (seed 001): the reserve, the consumption learnt so far, and the
choice to give up a goal that can no longer be finished."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from .sim_model import (
    RESERVE_FRACTION,
    ActiveGoal,
)
from .sim_plans import is_recovery

if TYPE_CHECKING:
    from .sim import Simulation


def reserve_wh(sim: Simulation) -> float:
    return RESERVE_FRACTION * sim.capacity_wh


def learned_factor(sim: Simulation) -> float:
    """Seed 001's linear model: measured over expected consumption so far."""
    if sim.expected_used_wh < 1e-6:
        return 1.0
    return max(0.5, min(4.0, sim.energy_used_wh / sim.expected_used_wh))


def transit_rate(sim: Simulation) -> float:
    if sim._priced_m < 100.0:
        return sim.power_w / sim.speed / 3600.0
    return sim._priced_wh / sim._priced_m


def home_wh(sim: Simulation) -> float:
    distance = math.dist(sim.vehicle.xy, sim.world.recovery)
    return distance * transit_rate(sim) * learned_factor(sim)


def energy_choice(sim: Simulation, active: ActiveGoal) -> tuple[str, dict[str, Any]] | None:
    if is_recovery(sim, active.goal):
        return None  # going home is never given up for energy
    factor = learned_factor(sim)
    rest = remaining_plan_m(sim, active) * active.rate_wh_per_m * factor
    home = home_after(sim, active) * transit_rate(sim) * factor
    needed = rest + home + reserve_wh(sim)
    remaining = sim.energy_remaining_wh
    if remaining >= needed:
        return None
    data = {"remaining_wh": round(remaining, 3), "goal_rest_wh": round(rest, 3),
            "home_wh": round(home, 3), "reserve_wh": round(reserve_wh(sim), 3),
            "consumption_factor": round(factor, 3)}
    home_and_reserve = home + reserve_wh(sim)
    return (f"energy: {remaining:.0f} Wh left cannot cover the rest of the goal "
            f"({rest:.0f} Wh) and the way home with the reserve ({home_and_reserve:.0f}"
            " Wh); goal given up", data)


def remaining_plan_m(sim: Simulation, active: ActiveGoal) -> float:
    x, y = sim.vehicle.xy
    total = 0.0
    for w in active.waypoints[active.index:]:
        total += math.dist((x, y), (w.x, w.y))
        x, y = w.x, w.y
    return total


def home_after(sim: Simulation, active: ActiveGoal) -> float:
    if not active.waypoints:
        return math.dist(sim.vehicle.xy, sim.world.recovery)
    last = active.waypoints[-1]
    return math.dist((last.x, last.y), sim.world.recovery)
