"""A rehearsal record (`countersign.rehearsal/1`) as execution logs: a rehearsal is an execution
in simulation, so it goes through the same checker as a vehicle's log (issue 19).

One NDJSON log per run of the record (a tour has several). From the record's events when it
kept them all: each goal's start and outcome times (simulated seconds), its final depth as a
depth_m reading and the mission's cumulative energy as an energy_wh reading; otherwise from the
run's goals and outcomes alone (the checker then uses the cost model for the budget)."""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any

MAX_RUNS = 1000


@dataclass(frozen=True)
class RehearsalRun:
    claimed_path: int | None  # the path number the rehearsal says it ran
    terminal: str | None
    ndjson: str


def _from_events(events: list[dict[str, Any]]) -> list[list[dict[str, Any]]]:
    runs: list[list[dict[str, Any]]] = []
    started: dict[str, float] = {}
    used = 0.0
    for event in events:
        kind, goal, data = event.get("kind"), event.get("goal"), event.get("data") or {}
        if kind in ("goal", "outcome") and not runs:
            runs.append([])  # one run (not a tour): no "run" event opens it
        if kind == "run":
            runs.append([])
            started, used = {}, 0.0
        elif kind == "goal" and isinstance(goal, str):
            started[goal] = float(event.get("t") or 0.0)
        elif kind == "outcome" and isinstance(goal, str):
            step: dict[str, Any] = {"goal": goal, "outcome": data.get("outcome"),
                                    "time": f"{float(event.get('t') or 0.0):g}"}
            if goal in started:
                step["start"] = f"{started.pop(goal):g}"
            readings: dict[str, float] = {}
            position = data.get("position")
            if isinstance(position, list) and len(position) == 3:
                readings["depth_m"] = float(position[2])
            if isinstance(data.get("energy_wh"), int | float):
                used += float(data["energy_wh"])
                readings["energy_wh"] = round(used, 3)
            if readings:
                step["readings"] = readings
            runs[-1].append(step)
    return runs


def rehearsal_runs(record: dict[str, Any]) -> list[RehearsalRun]:
    """The record's runs as execution logs, in the order they ran."""
    runs = [r for r in record.get("runs") or [] if isinstance(r, dict)][:MAX_RUNS]
    if not runs and record.get("goals"):
        runs = [{"goals": record.get("goals"), "outcomes": record.get("outcomes"),
                 "terminal": record.get("terminal"), "path_index": None}]
    events = record.get("events") or []
    detailed = _from_events(events) if not record.get("events_dropped") else []
    result: list[RehearsalRun] = []
    for number, run in enumerate(runs):
        goals, outcomes = list(run.get("goals") or []), list(run.get("outcomes") or [])
        steps = detailed[number] if number < len(detailed) else []
        if [s["goal"] for s in steps] != goals[:len(outcomes)] or \
                [s["outcome"] for s in steps] != outcomes:
            steps = [{"goal": g, "outcome": o} for g, o in zip(goals, outcomes, strict=False)]
        path = run.get("path_index")
        result.append(RehearsalRun(path if isinstance(path, int) else None,
                                   run.get("terminal"),
                                   "".join(json.dumps(s, sort_keys=True) + "\n" for s in steps)))
    return result
