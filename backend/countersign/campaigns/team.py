"""One campaign simulation of a team: the team rehearsal (every member's simulation in one
world clock, meetings joint) run headless to its end, reduced to what the joint statistics
need: the joint end, the meetings that completed or deadlocked, each member's path and
terminal.

The verifier's joint counts (verify/team.py, exact on the product of the members' MEAs) say
which joint ends are possible; `team_stats` holds every run's joint end against them.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any

from ..orders.model import Orders
from ..rehearse.fault_reach import FaultReach, fault_reach
from ..rehearse.team import TeamSimulation
from ..verify.team import JointCounts, TeamMemberGraph, check_team
from .simulate import CAMPAIGN_LIMITS, RUN_SECONDS, Mission

# The team clock's bound: as long as one member's own step bound lets it run.
TEAM_RUN_SECONDS = CAMPAIGN_LIMITS.max_steps * CAMPAIGN_LIMITS.step_s


class TeamMission:
    """Team orders with each member's path numbering and the verifier's joint counts, built
    once per worker."""

    def __init__(self, orders: Orders) -> None:
        if orders.team is None:
            raise ValueError("these orders are one vehicle's, not a team's")
        self.orders = orders
        self.vehicles = tuple(m.vehicle for m in orders.team)
        self.members = {m.vehicle: Mission(m.orders) for m in orders.team}
        self.joint = _joint_counts(orders, self.members)
        self.meetings: dict[str, tuple[str, ...]] = {}
        for member in orders.team:
            for meet in sorted({g.meet for g in member.orders.goal_index().values() if g.meet}):
                self.meetings[meet] = (*self.meetings.get(meet, ()), member.vehicle)

    @property
    def possible(self) -> dict[str, int] | None:
        """Joint end -> joint executions the verifier counts there; None when they were not
        counted (a member's paths cannot be counted, or the product exceeds its bounds): then
        no run's end can be held against them."""
        if self.joint is None:
            return None
        return {key: n for key, n in self.joint.by_key().items() if n > 0}


def _joint_counts(orders: Orders, members: Mapping[str, Mission]) -> JointCounts | None:
    # As validation does: the meetings are checked only when every member's paths count.
    if any(m.counts is None for m in members.values()):
        return None
    return check_team([TeamMemberGraph(m.vehicle, members[m.vehicle].graph)
                       for m in orders.team or ()]).counts


def simulate_team(mission: TeamMission, index: int, seed: int, faults: tuple[str, ...],
                  paths: Mapping[str, int] | None = None) -> dict[str, Any]:
    """Simulation `index` of the campaign. `paths` replays those members' own paths (fixed
    outcomes per goal: what the tests compare with a brute-force oracle)."""
    sim = TeamSimulation(mission.orders, seed=seed, faults=faults, limits=CAMPAIGN_LIMITS,
                         source="simulate", paths=paths, max_team_s=TEAM_RUN_SECONDS)
    sim.advance(RUN_SECONDS)
    # From the members' states, not the events: a campaign keeps few events.
    deadlocks = [{"meet": m.meets.get(m.sim.current_goal or ""), "vehicle": m.vehicle}
                 for m in sim.members if m.state == "deadlocked"]
    members = []
    for member in sim.members:
        run = member.sim.run
        members.append({
            "vehicle": member.vehicle,
            "state": member.state,
            "terminal": member.end,
            "path": mission.members[member.vehicle].path_index(run.goals, run.outcomes),
            "goals": list(run.goals),
            "outcomes": list(run.outcomes),
            "energy_wh": round(member.sim.energy_used_wh, 3),
        })
    return {
        "index": index,
        "seed": seed,
        "faults": list(faults),
        "joint_end": sim.joint_end(),
        "meetings": [{"meet": m.id, "outcome": m.outcome} for m in sim.meetings],
        "deadlocks": deadlocks,
        "members": members,
        "sim_time_s": round(sim.time_s, 3),
        # False when a bound (the team clock, a member's steps) stopped it: then its joint end
        # is no member's real end and is not held against the verifier's.
        "finished": all(m.state == "deadlocked" or m.end is not None for m in sim.members),
    }


def sweep_fault_reach(orders: Orders, faults: Iterable[str]) -> list[FaultReach]:
    """Whether each fault of a sweep can change an outcome (rehearse/fault_reach.py); a team's
    fault reacts when it does in some member it is injected into (`VEHICLE:FAULT`: that one)."""
    if orders.team is None:
        return fault_reach(orders, faults)
    out: list[FaultReach] = []
    for name in dict.fromkeys(faults):
        vehicle, _, fault = name.rpartition(":")
        found = [(m.vehicle, r) for m in orders.team if vehicle in ("", m.vehicle)
                 for r in fault_reach(m.orders, [fault])]
        if not found:
            continue  # "none", an unknown name or vehicle: the spec names those
        reacting = [f"{v}: {r.because}" for v, r in found if r.reacts]
        out.append(FaultReach(name, True, "; ".join(reacting)) if reacting else FaultReach(
            name, False, f"{name}: no rule or constraint of "
            f"{', '.join(v for v, _ in found)} reacts to it, so it cannot change any outcome"))
    return out
