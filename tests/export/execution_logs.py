"""Execution logs with the evidence a "no deviation" verdict needs, for the exemplar
(search-and-sample): start and end times of every goal run and a reading of every quantity its
constraints C1-C7 name, each within bounds."""

from __future__ import annotations

import json
from collections.abc import Iterable

# A value for every quantity C1-C7 of the exemplar reads, each within its bound.
READINGS: dict[str, float | bool] = {
    "nav_error_m": 2.0, "safety_equipment_ok": True, "mission_systems_ok": True,
    "lane_distance_m": 2000.0, "depth_m": 25.0, "contact_detection_range_m": 6000.0,
    "contact_distance_m": 2000.0}


def evidenced_log(steps: Iterable[tuple[str, str]], *, step_s: float = 10.0,
                  drop: Iterable[str] = ()) -> str:
    """NDJSON of `steps` (goal, outcome) in relative seconds with every reading but `drop`."""
    readings = {k: v for k, v in READINGS.items() if k not in set(drop)}
    return "".join(
        json.dumps({"goal": goal, "outcome": outcome, "start": f"{i * step_s:g}",
                    "time": f"{(i + 1) * step_s:g}", "readings": readings}) + "\n"
        for i, (goal, outcome) in enumerate(steps))
