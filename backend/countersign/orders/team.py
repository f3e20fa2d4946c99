"""Teams (DESIGN.md "Refinement and teams"): orders whose `team` holds one MEA per vehicle.

A goal with `"meet": "R1"` in two or more members' orders is one meeting. This module holds
what the model and the writers share: which members meet where, each member's digest, and
the read errors of a team that cannot be one. The joint check is `verify/team.py`.
"""

from __future__ import annotations

from dataclasses import dataclass

from .canonical import digest
from .model import Orders, TeamMember


@dataclass(frozen=True)
class MeetingPlace:
    """Where one member meets: the goals of its orders that name the meeting."""

    vehicle: str
    goals: tuple[str, ...]


def team_read_problems(orders: Orders) -> str | None:
    """Why these orders cannot be read as a team, naming where; None when they can."""
    assert orders.team is not None
    # A team's goals live in its members' orders: goals here too would be a second MEA
    # that no vehicle runs.
    for field in ("goals", "start", "vehicle", "vehicles", "terminals", "constraints", "norms",
                  "areas", "charts", "quantities", "properties", "rules"):
        if getattr(orders, field):
            return (f"{field}: orders with a team carry their {field} in each member's orders "
                    f"(team[i].orders.{field}), not beside the team")
    seen: dict[str, int] = {}
    for index, member in enumerate(orders.team):
        if member.vehicle in seen:
            return (f"team[{index}].vehicle: {member.vehicle!r} is already team member "
                    f"{seen[member.vehicle]}; give each vehicle one member")
        seen[member.vehicle] = index
        if member.orders.team is not None:
            return f"team[{index}].orders.team: a team member cannot itself be a team"
        if member.orders.vehicle != member.vehicle:
            return (f"team[{index}].orders.vehicle: {member.orders.vehicle!r} is not the "
                    f"member's vehicle {member.vehicle!r}")
    return None


def meetings(members: list[TeamMember]) -> dict[str, list[MeetingPlace]]:
    """Each meeting id (sorted) with the members that name it, in team order."""
    places: dict[str, list[MeetingPlace]] = {}
    for member in members:
        by_meeting: dict[str, list[str]] = {}
        for goal in member.orders.goal_index().values():
            if goal.meet is not None:
                by_meeting.setdefault(goal.meet, []).append(goal.id)
        for meet, goals in by_meeting.items():
            places.setdefault(meet, []).append(MeetingPlace(member.vehicle, tuple(goals)))
    return dict(sorted(places.items()))


def member_digests(orders: Orders) -> dict[str, str]:
    """Every member's orders digest by vehicle: what one approval of the team signs."""
    return {member.vehicle: digest(member.orders) for member in orders.team or ()}
