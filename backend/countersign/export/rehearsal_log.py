"""A rehearsal record (`countersign.rehearsal/1`) as execution logs: a rehearsal is an execution
in simulation, so it goes through the same checker as a vehicle's log.

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


class RehearsalRecordError(ValueError):
    """A record that cannot be read as asked (a team's without a member, or the reverse)."""


def record_members(record: dict[str, Any]) -> list[str]:
    """The vehicles of a team's record, in team order; empty for one vehicle's record."""
    team = record.get("team")
    members = team.get("members") if isinstance(team, dict) else None
    return [str(m.get("vehicle")) for m in members or [] if isinstance(m, dict)]


def member_record(record: dict[str, Any], member: str | None) -> dict[str, Any]:
    """The record as one vehicle's: a team's record holds each member's own run fields under
    `team.members` and its events, naming it, at the top (README "Teams"), so a team's record
    needs the member and one vehicle's record refuses one."""
    vehicles = record_members(record)
    if not vehicles:
        if member is not None:
            raise RehearsalRecordError(f"the record is one vehicle's, not a team's: it has no "
                                       f"member {member[:40]!r}")
        return record
    if member is None:
        raise RehearsalRecordError(f"the record is a team's ({', '.join(vehicles)}): name the "
                                   "member to read")
    found = next((m for m in record["team"]["members"]
                  if isinstance(m, dict) and m.get("vehicle") == member), None)
    if found is None:
        raise RehearsalRecordError(f"the team's record has no member {member[:40]!r} (members: "
                                   f"{', '.join(vehicles)})")
    if "goals" not in found:
        raise RehearsalRecordError(f"the team's record predates per-member runs: member "
                                   f"{member[:40]} has none to read")
    events = [{k: v for k, v in e.items() if k != "vehicle"} for e in record.get("events") or []
              if isinstance(e, dict) and e.get("vehicle") == member]
    return {**found, "events": events, "events_dropped": record.get("events_dropped")}


def rehearsal_runs(record: dict[str, Any], member: str | None = None) -> list[RehearsalRun]:
    """The record's runs as execution logs, in the order they ran: one vehicle's, or the team
    member's (`member`, a vehicle of a team's record)."""
    record = member_record(record, member)
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
