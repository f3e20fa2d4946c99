"""What the vehicle senses: the quantities the constraint monitors read and the observations
the default rules read."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from .geo import contains
from .sim_energy import energy_choice, home_wh, reserve_wh
from .sim_model import (
    ALL_QUANTITIES,
    ALTITUDE_LOW_M,
    CONTACT_CLOSE_M,
    FIX_MEMORY_S,
    LOCALISATION_PRECISION_M,
    NAV_ERROR_HIGH_M,
    USBL_PERIOD_S,
)
from .sim_motion import current_mps

if TYPE_CHECKING:
    from .sim import Simulation


def values(sim: Simulation, lookahead_s: float = 0.0,
           needed: frozenset[str] | None = None) -> dict[str, float | bool | str]:
    """The quantities the constraint monitors read, now or extrapolated `lookahead_s`
    ahead along the current velocities (vehicle and contacts). Only `needed` quantities
    are computed when given: this runs every few simulated seconds."""
    v = sim.vehicle
    t = sim.time_s + lookahead_s
    x, y = v.x + v.vx * lookahead_s, v.y + v.vy * lookahead_s
    # Depth changes toward the waypoint's depth and stops there: extrapolating the dive
    # rate past it would report violations the plan never makes.
    change = min(abs(v.vz) * lookahead_s, abs(v.target_depth - v.depth))
    depth = max(0.0, v.depth + math.copysign(change, v.target_depth - v.depth))
    remaining = sim.energy_remaining_wh
    leak = "leak" in sim.active_faults
    want = needed if needed is not None else ALL_QUANTITIES
    out: dict[str, float | bool | str] = {
        "depth_m": depth,
        "speed_mps": math.hypot(v.vx, v.vy),
        "nav_error_m": v.nav_error_m,
        "energy_wh": sim.energy_used_wh,
        "energy_remaining_wh": remaining,
        "duration_s": t,
        "elapsed_s": t,
        "battery_pct": 100.0 * remaining / sim.capacity_wh,
        "battery_reserve_pct": 100.0 * max(0.0, remaining - reserve_wh(sim))
        / sim.capacity_wh,
        "contact_detection_range_m": sim.detection_range_m,
        "comms_ok": depth < 0.5 or v.usbl_now,
        "gps_fix": v.gps_now,
        "surfaced": depth < 0.5,
        "safety_equipment_ok": not leak,
        "mission_systems_ok": not leak,
        "heading_deg": math.degrees(v.heading) % 360.0,
    }
    if "altitude_m" in want:
        out["altitude_m"] = max(0.0, sim.world.seafloor_depth(x, y) - depth)
    if "latitude_deg" in want or "longitude_deg" in want:
        out["latitude_deg"], out["longitude_deg"] = sim.world.to_latlon((x, y))
    if "lane_distance_m" in want:
        out["lane_distance_m"] = sim.world.lane_distance((x, y))
    if "contact_distance_m" in want or "contact_range_m" in want:
        contact = sim.world.contact_distance((x, y), t)
        out["contact_distance_m"] = out["contact_range_m"] = contact
    if "contact_count" in want:
        out["contact_count"] = float(sum(1 for c in sim.world.contacts if c.start_s <= t))
    if "base_distance_m" in want:
        out["base_distance_m"] = math.dist((x, y), sim.world.recovery)
    if "current_mps" in want:
        out["current_mps"] = current_mps(sim)
    return out


def observations(sim: Simulation, planned_action: str | None = None) -> dict[str, bool]:
    """What the vehicle observes, in the words default theories use (seed 004 and the
    shipped examples); the contingency layer passes on only what a theory declares."""
    v = sim.vehicle
    t = sim.time_s
    remaining = sim.energy_remaining_wh
    leak = "leak" in sim.active_faults
    contact_close = sim.world.contact_distance(v.xy, t) < CONTACT_CLOSE_M
    low = remaining <= reserve_wh(sim) + home_wh(sim)
    usbl_now = t - v.last_usbl_s <= 2 * USBL_PERIOD_S
    floor = sim.world.seafloor_depth(v.x, v.y)
    budget = sim.orders.target_vehicle()
    time_limit = budget.budget.duration_s if budget and budget.budget else None
    obs = {
        "gps_captured": v.gps_now,
        "usbl_captured": usbl_now,
        "gps_was_captured": t - v.last_gps_s <= FIX_MEMORY_S,
        "usbl_was_captured": t - v.last_usbl_s <= FIX_MEMORY_S,
        "on_surface": v.depth < 0.5,
        "localisation_precision_low": v.nav_error_m > LOCALISATION_PRECISION_M,
        "nav_error_high": v.nav_error_m > NAV_ERROR_HIGH_M,
        "leak": leak,
        "safety_sensor_failure(leak)": leak,
        "mission_system_failure": False,
        "camera_fault": False,
        "low_energy": low,
        "battery_low": low,
        "battery_critical": remaining <= reserve_wh(sim) * 0.5,
        "altitude_low": floor - v.depth < ALTITUDE_LOW_M,
        "contact_close": contact_close,
        "surface_contact_close": contact_close,
        "contact_within_1000m": contact_close,
        "mission_time_over": time_limit is not None and t > time_limit,
    }
    for area_id, area in sim.world.areas.items():
        if contains(area.polygon, v.xy):
            obs[f"at({area_id.lower()})"] = True
    for area_id in sim._transect_areas:
        obs[f"transect_done({area_id.lower()})"] = area_id in sim._transects_done
    if planned_action is not None and sim.active is not None:
        obs[f"enough_energy({planned_action})"] = energy_choice(sim, sim.active) is None
    return obs
