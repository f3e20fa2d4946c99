"""What a team campaign's simulations estimate: how many runs ended in each joint end (named as
the verifier's joint counts name them, `remus-100:waiting + vehicle-2:ABORT`), which meetings
completed or deadlocked, each member's terminals, and coverage against the verifier.

The verifier counts joint executions exactly (verify/team.py), so it knows every joint end
that can happen. A run that ends in a joint end it says is impossible means the simulation and
the model disagree: a TEAM finding naming the end and the first runs that reached it.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable
from typing import Any

from ..orders.model import OUTCOMES
from .stats import estimate
from .team import TeamMission

FINDING_RUNS = 5  # simulation indexes named per impossible joint end


def summarize_team(runs: Iterable[dict[str, Any]], mission: TeamMission) -> dict[str, Any]:
    """The estimates over the simulations (one result per index: the caller's guarantee)."""
    runs = sorted(runs, key=lambda r: int(r.get("index", 0)))
    n = len(runs)
    ends: Counter[str] = Counter()
    first: dict[str, list[int]] = {}
    completed: dict[str, Counter[str]] = {}
    deadlocked: Counter[str] = Counter()
    met: Counter[str] = Counter()
    terminals: dict[str, Counter[str]] = {v: Counter() for v in mission.vehicles}
    paths: dict[str, set[int]] = {v: set() for v in mission.vehicles}
    unfinished = 0
    for run in runs:
        for meeting in run.get("meetings", []):
            completed.setdefault(meeting["meet"], Counter())[meeting["outcome"]] += 1
        # A member's orders may name a meeting twice: runs are counted once, outcomes each time.
        for meet in {str(m["meet"]) for m in run.get("meetings", [])}:
            met[meet] += 1
        for meet in {str(d.get("meet")) for d in run.get("deadlocks", [])}:
            deadlocked[meet] += 1
        for member in run.get("members", []):
            left = "waiting" if member["state"] == "deadlocked" else "none"
            terminals.setdefault(member["vehicle"], Counter())[member["terminal"] or left] += 1
            if member.get("path") is not None:
                paths.setdefault(member["vehicle"], set()).add(int(member["path"]))
        if not run.get("finished"):
            unfinished += 1
            continue
        ends[run["joint_end"]] += 1
        first.setdefault(run["joint_end"], []).append(int(run["index"]))
    possible = mission.possible
    return {"simulations": n, "team": {
        "vehicles": list(mission.vehicles),
        "joint": _joint_rows(ends, n, possible),
        "unfinished": estimate(unfinished, n),
        "meetings": _meeting_rows(mission, completed, met, deadlocked, n),
        "members": _member_rows(mission, terminals, paths, n),
        "coverage": _coverage(ends, possible),
        "findings": _findings(ends, first, possible),
    }}


def _joint_rows(ends: Counter[str], n: int,
                possible: dict[str, int] | None) -> list[dict[str, Any]]:
    """Every joint end the verifier counts (reached or not), in its order, then any other end
    a run reached."""
    keys = list(possible or {}) + sorted(k for k in ends if k not in (possible or {}))
    return [{"end": key, **estimate(ends[key], n),
             "possible": None if possible is None else key in possible,
             "executions": (possible or {}).get(key)} for key in keys]


def _meeting_rows(mission: TeamMission, completed: dict[str, Counter[str]], met: Counter[str],
                  deadlocked: Counter[str], n: int) -> list[dict[str, Any]]:
    """Per meeting: the runs in which it completed (at least once) and deadlocked, and how
    often each shared outcome was decided."""
    meets = sorted(set(mission.meetings) | set(completed) | set(deadlocked))
    return [{"meet": meet, "vehicles": list(mission.meetings.get(meet, ())),
             "completed": estimate(met[meet], n),
             "deadlocked": estimate(deadlocked[meet], n),
             "outcomes": {o: completed.get(meet, Counter())[o] for o in OUTCOMES}}
            for meet in meets]


def _member_rows(mission: TeamMission, terminals: dict[str, Counter[str]],
                 paths: dict[str, set[int]], n: int) -> list[dict[str, Any]]:
    rows = []
    for vehicle, member in mission.members.items():
        counted = terminals.get(vehicle, Counter())
        names = [t.id for t in member.orders.effective_terminals]
        names += sorted(k for k in counted if k not in names)
        rows.append({"vehicle": vehicle,
                     "terminals": {t: estimate(counted[t], n) for t in names},
                     "total_paths": member.total_paths,
                     "covered_paths": len(paths.get(vehicle, ()))})
    return rows


def _coverage(ends: Counter[str], possible: dict[str, int] | None) -> dict[str, Any]:
    if possible is None:
        return {"checked": False, "possible": None, "reached": len(ends), "missed": []}
    return {"checked": True, "possible": len(possible),
            "reached": sum(1 for k in possible if ends[k]),
            "missed": [k for k in possible if not ends[k]]}


def _findings(ends: Counter[str], first: dict[str, list[int]],
              possible: dict[str, int] | None) -> list[dict[str, Any]]:
    if possible is None:
        return []
    out = []
    for key in sorted(k for k in ends if k not in possible):
        runs = first[key][:FINDING_RUNS]
        out.append({"code": "TEAM", "severity": "error", "end": key, "count": ends[key],
                    "runs": runs,
                    "message": f"{ends[key]} simulations ended at {key}, a joint end no joint "
                               f"execution of the orders reaches (the verifier's joint counts); "
                               f"first: simulation {', '.join(str(i) for i in runs)}. The "
                               "simulation and the orders disagree."})
    return out
