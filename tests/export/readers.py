"""Independent readers of the vehicle exports: they know the file formats, not our exporter.

Each returns the mode/maneuver graph as start, terminals and {node: {outcome: target}}, and
`graph_paths` enumerates it depth first in the order succeed, fail, violate, as
`countersign paths` does, so the two enumerations compare path for path."""

from __future__ import annotations

import json
import re
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import imcpy

OUTCOMES = ("succeed", "fail", "violate")
NPS = Path(__file__).resolve().parents[2].parent / "shared" / "reference" / "nps-ethical-control"
AVCL = sorted((NPS / "missions" / "avcl").glob("*.xml")) if NPS.is_dir() else []


@dataclass
class Graph:
    start: str
    terminals: dict[str, str]  # id -> kind
    edges: dict[str, dict[str, str]]


def graph_paths(graph: Graph) -> Iterator[tuple[tuple[str, ...], tuple[str, ...], str]]:
    stack: list[tuple[str, tuple[str, ...], tuple[str, ...]]] = [(graph.start, (), ())]
    while stack:
        node, goals, outcomes = stack.pop()
        if node in graph.terminals:
            yield goals, outcomes, node
            continue
        for outcome in reversed(OUTCOMES):
            stack.append((graph.edges[node][outcome], (*goals, node), (*outcomes, outcome)))


# --- IMC, through imcpy -------------------------------------------------------------------
IMC_OUTCOME = {"ManeuverIsDone": "succeed", "ManeuverFailed": "fail",
               "ConstraintViolated": "violate"}


def read_imc(data: bytes) -> tuple[Any, Graph]:
    plan = imcpy.Packet.deserialize(data)
    assert plan.msg_name == "PlanSpecification"
    ids = [m.maneuver_id for m in plan.maneuvers]
    assert len(ids) == len(set(ids)), "maneuver ids repeat"
    terminals: dict[str, str] = {}
    for m in plan.maneuvers:
        custom = dict(kv.split("=", 1) for kv in m.data.custom.split(";") if kv)
        if "terminal" in custom:
            terminals[m.maneuver_id] = custom["kind"]
    edges: dict[str, dict[str, str]] = {i: {} for i in ids if i not in terminals}
    for t in plan.transitions:
        outcome = IMC_OUTCOME[t.conditions]
        assert outcome not in edges[t.source_man], f"two {outcome} transitions"
        assert t.dest_man in ids, f"transition to unknown maneuver {t.dest_man}"
        edges[t.source_man][outcome] = t.dest_man
    return plan, Graph(plan.start_man_id, terminals, edges)


# --- MOOS-IvP .bhv -------------------------------------------------------------------------
_SET = re.compile(r"^set\s+MODE\s*=\s*(\w+)\s*\{(.*?)\}\s*(\w*)", re.S | re.M)
_BEHAVIOR = re.compile(r"^Behavior\s*=\s*(\w+)\s*\{(.*?)^\}", re.S | re.M)


def _pairs(body: str) -> list[tuple[str, str]]:
    out = []
    for line in body.splitlines():
        line = line.split("//", 1)[0].strip()
        if "=" in line:
            key, value = line.split("=", 1)
            out.append((key.strip().lower(), value.strip()))
    return out


def read_bhv(text: str) -> Graph:
    """Modes from the hierarchical declarations, transitions from the flags of the behaviours
    conditioned on each mode."""
    initial = dict(
        (m.group(1), m.group(2).strip())
        for m in re.finditer(r"^initialize\s+(\w+)\s*=\s*(\S+)", text, re.M))
    mode_of_goal: dict[str, str] = {}  # MISSION_GOAL value -> mode name
    for m in _SET.finditer(text):
        pairs = dict(_pairs(m.group(2)))
        if pairs.get("mode", "").split(":")[0] == "ACTIVE" and "mission_goal" in pairs:
            mode_of_goal[pairs["mission_goal"]] = m.group(1)
    edges: dict[str, dict[str, str]] = {}
    terminals: dict[str, str] = {}
    for m in _BEHAVIOR.finditer(text):
        kind, pairs = m.group(1), _pairs(m.group(2))
        conditions = [v for k, v in pairs if k == "condition"]
        modes = [c.split("==", 1)[1].strip() for c in conditions if c.startswith("MODE ==")]
        if not modes:
            continue
        mode = modes[0].split(":")[-1]
        flags = [v for k, v in pairs if k in ("endflag", "runflag")]
        posts = dict(f.split("=", 1) for f in flags)
        posts = {k.strip(): v.strip() for k, v in posts.items()}
        if posts.get("DEPLOY") == "false":
            terminals[mode] = posts["MISSION_RESULT"]
            continue
        if "MISSION_GOAL" not in posts:
            continue
        target = mode_of_goal[posts["MISSION_GOAL"]]
        others = [c for c in conditions if not c.startswith("MODE ==")]
        if kind != "BHV_Timer":
            outcome = "succeed"
        elif others and others[0].startswith("GOAL_OUTCOME =="):
            outcome = others[0].split("==", 1)[1].strip()
        else:
            outcome = "violate"  # a broken constraint
        seen = edges.setdefault(mode, {})
        assert seen.get(outcome, target) == target, f"{mode}: two {outcome} targets"
        seen[outcome] = target
    return Graph(mode_of_goal[initial["MISSION_GOAL"]], terminals, edges)


def mode_map(text: str) -> dict[str, str]:
    """Mode name -> goal or terminal id, from the declarations' comments."""
    return {m.group(1): m.group(2) for m in re.finditer(
        r"^// mode (\w+) = (?:goal|terminal) (\S+?)(?:: | \()", text, re.M)}


def description(plan: Any) -> dict[str, Any]:
    return dict(json.loads(plan.description))
