"""The validation report of orders with a team: every member's own report, scoped by member,
then TEAM (verify/team.py) and the joint counts.

Each member's orders are checked exactly as orders of one vehicle (structure, paths, budget
and norms against its own profile), so a member's findings are those it would have alone;
their subjects read `auv-1/G3` and their messages start `auv-1: `.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from ..orders.canonical import digest
from ..orders.findings import Finding, warning
from ..orders.model import Orders
from .graph import build_graph
from .logic.limits import THREAD_CLOCKS, Clocks
from .paths import PathCounts
from .team import JointCounts, TeamMemberGraph, check_team

if TYPE_CHECKING:
    from .logic import LogicCache
    from .parts import PartsCache
    from .report import Report


@dataclass(frozen=True)
class MemberReport:
    vehicle: str
    report: Report

    def to_json(self) -> dict[str, Any]:
        data = self.report.to_json()
        return {"vehicle": self.vehicle, "mission": data["mission"], "digest": data["digest"],
                "ok": data["ok"], "paths": data["paths"], "costs": data["costs"],
                **({"probabilities": data["probabilities"]} if "probabilities" in data else {})}


@dataclass(frozen=True)
class TeamSummary:
    members: tuple[MemberReport, ...]
    meetings: dict[str, tuple[str, ...]]
    joint: JointCounts | None

    def to_json(self) -> dict[str, Any]:
        return {
            "members": [m.to_json() for m in self.members],
            "meetings": {m: list(v) for m, v in self.meetings.items()},
            "joint": self.joint.to_json() if self.joint is not None else None,
        }


def scoped(vehicle: str, finding: Finding) -> Finding:
    """A member's finding as the team reports it."""
    return Finding(finding.code, finding.severity,
                   tuple(f"{vehicle}/{s}" for s in finding.subjects),
                   f"{vehicle}: {finding.message}", finding.details)


def validate_team(
    orders: Orders,
    reader_findings: Sequence[Finding] = (),
    logic_cache: LogicCache | None = None,
    *,
    solver_budget_s: float,
    solver_wall_cap_s: float | None = None,
    solver_clocks: Clocks = THREAD_CLOCKS,
    parts: PartsCache | None = None,
    orders_digest: str | None = None,
) -> Report:
    from .report import Report, validate

    assert orders.team is not None
    # The whole validation keeps the one solver budget: members share it.
    share = solver_budget_s / len(orders.team)
    cap_share = None if solver_wall_cap_s is None else solver_wall_cap_s / len(orders.team)
    findings = list(reader_findings)
    members: list[MemberReport] = []
    graphs: list[TeamMemberGraph] = []
    blocked: list[str] = []
    for member in orders.team:
        graph = build_graph(member.orders)
        report = validate(member.orders, graph=graph, logic_cache=logic_cache,
                          solver_budget_s=share, solver_wall_cap_s=cap_share,
                          solver_clocks=solver_clocks, parts=parts)
        members.append(MemberReport(member.vehicle, report))
        findings.extend(scoped(member.vehicle, f) for f in report.findings)
        graphs.append(TeamMemberGraph(member.vehicle, graph))
        if report.paths is None:
            blocked.append(member.vehicle)
    joint: JointCounts | None = None
    meetings: dict[str, tuple[str, ...]] = {}
    if blocked:
        findings.append(warning(
            "TEAM", blocked,
            f"The team's meetings cannot be checked until the paths of {', '.join(blocked)} "
            "can be counted (see the errors above)."))
    else:
        checked = check_team(graphs)
        findings.extend(checked.findings)
        joint, meetings = checked.counts, checked.meetings
    paths = (PathCounts(joint.total, joint.by_key(), ()) if joint is not None else None)
    return Report(orders.id, orders_digest or digest(orders), findings, paths, None, orders,
                  None, TeamSummary(tuple(members), meetings, joint))


def summary_lines(team: TeamSummary) -> list[str]:
    """The team's figures for `countersign validate`: each member's paths and worst costs,
    the meetings, and the joint executions by where each member ends."""
    lines = [f"Team of {len(team.members)}: {', '.join(m.vehicle for m in team.members)}"]
    for member in team.members:
        report = member.report
        if report.paths is None:
            paths = "paths not countable until its errors are fixed"
        else:
            parts = ", ".join(f"{n} to {t}" for t, n in report.paths.by_terminal.items())
            paths = f"{report.paths.total} paths ({parts})"
        costs = "".join(
            f"; worst {q} {w.total:g}" + (f" of budget {w.budget:g}" if w.budget is not None
                                          else "")
            for q, w in (report.costs or {}).items())
        lines.append(f"  {member.vehicle} ({report.mission}, {report.digest}): {paths}{costs}")
    if team.meetings:
        lines.append("Meetings: " + "; ".join(f"{m} ({', '.join(v)})"
                                              for m, v in team.meetings.items()))
    else:
        lines.append("Meetings: none (no goal names a meet)")
    joint = team.joint
    if joint is None:
        lines.append("Joint executions: not counted (see TEAM above).")
        return lines
    lines.append(f"Joint executions: {joint.total} ({joint.deadlocked} deadlocked)")
    width = len(str(max((n for _, n in joint.by_ends), default=0)))
    for ends, n in joint.by_ends:
        where = ", ".join(f"{v} {end or 'left waiting'}"
                          for v, end in zip(joint.vehicles, ends, strict=True))
        lines.append(f"  {n:>{width}}  {where}")
    for meet, vehicle, n in joint.waiting:
        lines.append(f"  {vehicle} waits at {meet} for ever in {n}")
    return lines
