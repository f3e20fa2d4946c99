"""A goal as a plan of waypoints and its priced work: the operating depth, the waypoints of
its behaviour in its place, their geodesic lengths, and the speed and rates its cost allows."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ..orders.model import Goal
from ..verify.costs import goal_cost
from ..verify.legs import geod
from .sim_model import (
    DEFAULT_DEPTH_M,
    HOLD_BEHAVIORS,
    RECOVERY_BEHAVIORS,
    Waypoint,
)

if TYPE_CHECKING:
    from .sim import Simulation


def operating_depth(sim: Simulation, goal: Goal) -> float:
    depth = goal.params.get("depth_m")
    if isinstance(depth, int | float) and not isinstance(depth, bool) and depth >= 0:
        wanted = float(depth)
    elif "depth_m" in goal.envelope:
        low, high = goal.envelope["depth_m"]
        wanted = low + 0.3 * (high - low)
    else:
        wanted = DEFAULT_DEPTH_M
    vehicle = sim.orders.target_vehicle()
    if vehicle and "depth_m" in vehicle.envelope:
        low, high = vehicle.envelope["depth_m"]
        wanted = min(max(wanted, low), high)
    return max(0.0, min(wanted, sim.world.floor_base_m - 25.0))


def plan(sim: Simulation, goal: Goal) -> list[Waypoint]:
    depth = operating_depth(sim, goal)
    area = sim.world.areas.get(goal.area) if goal.area else None
    behavior = (goal.behavior or "").lower()
    recovery = behavior in RECOVERY_BEHAVIORS or (
        area is not None and area.centre == sim.world.recovery
    )
    # A recovery goal ends at the recovery point; surfacing for pick-up follows the
    # terminal, outside every goal's constraints (C7 of the exemplar holds until then).
    if sim.vehicle.forced_surface:
        depth = 0.0
    if area is None:
        hold = float(goal.params.get("duration_s", 60.0) or 60.0)
        x, y = sim.world.recovery if recovery else sim.vehicle.xy
        return [Waypoint(x, y, 0.0 if recovery else depth, min(hold, 3_600.0), "hold")]
    # Where the goal runs is the verifier's place (verify/legs.py): its sweep or its
    # station, so the leg flown into it is the leg that was checked.
    place = sim.world.places.get(goal.id)
    points: list[Waypoint] = []
    if place is not None and place.track is not None:
        kind = "transect" if behavior == "transect" else "search"
        points = [Waypoint(float(x), float(y), depth, 0.0, kind)
                  for x, y in place.track.coords]
    else:
        cx, cy = place.start if place is not None else area.centre
        if behavior in HOLD_BEHAVIORS:
            hold = goal.params.get("duration_s", HOLD_BEHAVIORS[behavior])
            hold_s = float(hold) if isinstance(hold, int | float) and hold >= 0 else \
                HOLD_BEHAVIORS[behavior]
            points = [Waypoint(cx, cy, depth, min(hold_s, 6 * 3_600.0), behavior)]
        else:
            points = [Waypoint(cx, cy, depth, 0.0, "transit")]
    if sim.vehicle.forced_surface:
        for p in points:
            p.depth = 0.0
    first = points[0]
    if math.dist(sim.vehicle.xy, (first.x, first.y)) > 1.0:
        points = [Waypoint(first.x, first.y, first.depth, 0.0, "leg"), *points]
    return measured(sim, points)


def measured(sim: Simulation, points: list[Waypoint]) -> list[Waypoint]:
    """Each segment's geodesic length (one projection call per plan): the vehicle flies
    the frame's straight line but counts metres on the ellipsoid, as the legs do."""
    xs = [sim.vehicle.x, *(p.x for p in points)]
    ys = [sim.vehicle.y, *(p.y for p in points)]
    lats, lons = sim.world.frame.to_latlon(xs, ys)
    _, _, metres = geod().inv(lons[:-1], lats[:-1], lons[1:], lats[1:])
    for k, p in enumerate(points):
        planar = math.dist((xs[k], ys[k]), (xs[k + 1], ys[k + 1]))
        p.geo_m = float(metres[k]) if planar > 1e-9 else 0.0
        p.scale = p.geo_m / planar if planar > 1e-9 else 1.0
    return points


def priced_work(sim: Simulation, goal: Goal, waypoints: list[Waypoint], work_m: float
                ) -> tuple[float, float, float]:
    """(speed, Wh per metre, hold watts) of the goal's own work, from the verifier's cost
    of the goal (verify/costs.goal_cost): its duration bounds the work's time (holds
    shortened and the work sped up in proportion when the plan at cruise would take
    longer), its energy is spread over the work in proportion to time. Without a cost
    the vehicle's profile prices it (cruise power moving, 40% of it holding)."""
    vehicle = sim.orders.target_vehicle()
    areas = sim.orders.area_index()
    duration, _ = goal_cost(goal, "duration_s", vehicle, areas)
    energy, _ = goal_cost(goal, "energy_wh", vehicle, areas)
    holds = sum(w.hold_s for w in waypoints)
    cruise_s = work_m / sim.speed + holds
    factor = 1.0
    if duration is not None and cruise_s > duration:
        factor = duration / cruise_s  # 0 when the goal is said to take no time
        for w in waypoints:
            w.hold_s *= factor
    speed = sim.speed / factor if factor > 1e-9 else math.inf
    if energy is None:
        return speed, sim.leg_rate_wh_per_m, sim.power_w * 0.4
    work_s = work_m / speed if math.isfinite(speed) else 0.0
    total_s = work_s + holds * factor
    if total_s <= 0.0:
        return speed, 0.0, 0.0  # no work to charge (a station goal with no hold)
    rate = energy * work_s / total_s / work_m if work_m > 0 else 0.0
    hold_w = energy * 3600.0 / total_s
    return speed, rate, hold_w


def is_recovery(sim: Simulation, goal: Goal) -> bool:
    behavior = (goal.behavior or "").lower()
    area = sim.world.areas.get(goal.area or "")
    return behavior in RECOVERY_BEHAVIORS or bool(area and area.centre == sim.world.recovery)
