"""The vehicle's motion (kinematics): one step along the plan, charging energy, the current,
and navigation error with its GPS and acoustic fixes."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from .sim_model import (
    DIVE_RATE_MPS,
    FAULT_DRIFT_PER_M,
    GPS_FIX_ERROR_M,
    NAV_DRIFT_PER_M,
    NORMAL_CURRENT_MPS,
    STRONG_CURRENT_FACTOR,
    STRONG_CURRENT_MPS,
    USBL_FIX_ERROR_M,
    USBL_PERIOD_S,
    USBL_RANGE_M,
    ActiveGoal,
    Waypoint,
)

if TYPE_CHECKING:
    from .sim import Simulation


def current_factor(sim: Simulation) -> float:
    active = sim.active
    if active and active.strong_current:
        begin, until = active.strong_current
        if begin <= sim.time_s < until:
            return STRONG_CURRENT_FACTOR
    return 1.0


def current_mps(sim: Simulation) -> float:
    return STRONG_CURRENT_MPS if current_factor(sim) > 1.0 else NORMAL_CURRENT_MPS


def move(sim: Simulation, active: ActiveGoal, dt: float) -> float:
    """One step of the plan. The step's time is spent waypoint after waypoint: time left
    when a waypoint is reached carries on to the next one (or its hold), so that a plan
    takes the time its metres and holds take, not a step more per waypoint. Returns the
    part of the step left over when the plan was done within it."""
    v = sim.vehicle
    _note_current(sim, active)
    if active.finished_plan:
        v.vx = v.vy = v.vz = 0.0
        return 0.0
    factor = current_factor(sim)
    target = 0.0 if v.forced_surface else active.waypoints[active.index].depth
    v.target_depth = target
    dz = target - v.depth
    rise = max(-DIVE_RATE_MPS * dt, min(DIVE_RATE_MPS * dt, dz))
    v.depth = max(0.0, v.depth + rise)
    v.vz = rise / dt
    x0, y0 = v.x, v.y
    left, energy = _follow_waypoints(sim, active, dt, factor)
    unused = left if active.finished_plan and left > 1e-9 else 0.0
    spent = dt - unused
    v.vx, v.vy = ((v.x - x0) / spent, (v.y - y0) / spent) if spent > 1e-9 else (0.0, 0.0)
    active.used_wh += energy
    sim.energy_used_wh += energy
    if not sim.trail or math.dist(sim.trail[-1][:2], v.xy) >= 25.0 \
            or abs(sim.trail[-1][2] - v.depth) >= 2.0:
        sim.trail.append((v.x, v.y, v.depth))
    return unused


def _note_current(sim: Simulation, active: ActiveGoal) -> None:
    """Say when a strong opposing current starts or passes."""
    strong = current_factor(sim) > 1.0
    if strong != sim._strong_current:
        sim._strong_current = strong
        sim._emit("current", "Strong opposing current: consumption doubled (seed 001)."
                  if strong else "The strong current has passed.", active.goal.id,
                  {"strong": strong})


def _follow_waypoints(sim: Simulation, active: ActiveGoal, dt: float,
                      factor: float) -> tuple[float, float]:
    """Spend `dt` seconds along the waypoints and their holds: (the seconds left, when the plan
    ended within the step; the energy used)."""
    v = sim.vehicle
    energy = 0.0
    left = dt
    while left > 1e-9 and not active.finished_plan:
        w = active.waypoints[active.index]
        dx, dy = w.x - v.x, w.y - v.y
        distance = math.hypot(dx, dy)
        if distance > 1e-6:
            left, used, arrived = _toward(sim, active, w, (dx, dy, distance), left, factor)
            energy += used
            if not arrived:
                break
        # Depth changes while the vehicle moves and holds, and never holds the plan up:
        # the verifier's costs charge metres and holds, no time for diving.
        if w.kind == "leg" and active.held_s == 0.0:
            leg_flown(sim, active, w)
        if active.held_s < w.hold_s:
            # A hold is charged for the part held, not the whole step.
            held = min(left, w.hold_s - active.held_s)
            active.held_s += held
            active.done_s += held
            left -= held
            hold_energy = active.hold_w * held / 3600.0
            energy += hold_energy * factor
            sim.expected_used_wh += hold_energy
        if active.held_s < w.hold_s:
            break
        active.index += 1
        active.held_s = 0.0
    return left, energy


def _toward(sim: Simulation, active: ActiveGoal, w: Waypoint,
            offset: tuple[float, float, float], left: float,
            factor: float) -> tuple[float, float, bool]:
    """Move toward waypoint `w` (at `offset`: dx, dy, distance) for at most `left` seconds:
    (the seconds left, the energy used, whether it was reached)."""
    v = sim.vehicle
    dx, dy, distance = offset
    speed = sim.speed if w.kind == "leg" else active.speed
    to_go_m = distance * w.scale  # geodesic metres
    moved_m = min(speed * left, to_go_m)
    arrived = moved_m >= to_go_m
    v.heading = math.atan2(dy, dx)
    if arrived:
        v.x, v.y = w.x, w.y
    else:
        moved = moved_m / w.scale
        v.x += dx / distance * moved
        v.y += dy / distance * moved
    left -= moved_m / speed if math.isfinite(speed) else 0.0
    active.done_s += moved_m / speed
    rate = sim.leg_rate_wh_per_m if w.kind == "leg" else active.rate_wh_per_m
    sim.expected_used_wh += moved_m * rate
    if w.kind == "leg":
        active.leg_m += moved_m
    return left, moved_m * rate * factor, arrived


def leg_flown(sim: Simulation, active: ActiveGoal, w: Waypoint) -> None:
    run = sim.run
    if len(run.goals) < 2 or len(sim.flown_legs) >= sim.limits.max_events:
        return  # the launch is no leg between goals
    sim.flown_legs.append({"from": run.goals[-2], "outcome": run.outcomes[-1],
                           "to": active.goal.id, "length_m": round(active.leg_m, 6),
                           "planned_m": round(w.geo_m, 6)})


def navigate(sim: Simulation, dt: float) -> None:
    v = sim.vehicle
    t = sim.time_s
    drift = FAULT_DRIFT_PER_M if "nav_drift" in sim.active_faults else NAV_DRIFT_PER_M
    v.nav_error_m += drift * math.hypot(v.vx, v.vy) * dt
    v.gps_now = v.depth < 0.5 and "gps_loss" not in sim.active_faults
    if v.gps_now:
        v.last_gps_s = t
        v.nav_error_m = min(v.nav_error_m, GPS_FIX_ERROR_M)
    # The acoustic (USBL) fix from the support vessel arrives periodically within range;
    # navigation drift is modelled as the loss of that link plus a faster drift.
    v.usbl_now = False
    if (
        "nav_drift" not in sim.active_faults
        and math.dist(v.xy, sim.world.recovery) <= USBL_RANGE_M
        and t - v.last_usbl_s >= USBL_PERIOD_S
        and v.depth >= 0.5
    ):
        v.usbl_now = True
        v.last_usbl_s = t
        v.nav_error_m = min(v.nav_error_m, USBL_FIX_ERROR_M)
