"""Teams (DESIGN.md "Refinement and teams"): orders whose `team` holds one MEA per vehicle.

A goal with `"meet": "R1"` in two or more members' orders is one meeting. This module holds
what the model and the writers share: which members meet where, each member's digest, and
the read errors of a team that cannot be one. The joint check is `verify/team.py`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from .canonical import digest
from .model import Orders, TeamMember
from .plain import Names, plain_orders


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


def _one_line(text: str) -> str:
    return " ".join(text.split())


def _meeting_table(members: list[TeamMember]) -> list[str]:
    """The meeting points side by side: one row per meeting, one column per vehicle."""
    names = {m.vehicle: Names(m.orders) for m in members}
    titles = {m.vehicle: m.orders.goal_index() for m in members}
    header = ["Meeting", *(m.vehicle for m in members)]
    rows = [header]
    for meet, places in meetings(members).items():
        cells = dict.fromkeys(header[1:], "-")
        for place in places:
            cells[place.vehicle] = "; ".join(
                f"{names[place.vehicle].goal(g)} ({_one_line(titles[place.vehicle][g].label)})"
                for g in place.goals)
        rows.append([meet, *cells.values()])
    widths = [max(len(row[c]) for row in rows) for c in range(len(header))]
    return [" | ".join(cell.ljust(w) for cell, w in zip(row, widths, strict=True)).rstrip()
            for row in rows]


def plain_team(orders: Orders, member_text: Callable[[Orders], str] = plain_orders) -> str:
    """The team's plain orders: the vehicles, the meeting points side by side, then each
    vehicle's own plain orders (`member_text`) under its name and digest."""
    assert orders.team is not None
    members = list(orders.team)
    vehicles = []
    for member in members:
        profile = member.orders.target_vehicle()
        title = _one_line(profile.title) if profile is not None else ""
        vehicles.append(f"{title} ({member.vehicle})" if title else member.vehicle)
    blocks = ["\n".join([f"Team orders {orders.id}: {_one_line(orders.title) or orders.id}",
                         f"Vehicles: {', '.join(vehicles)}"])]
    if orders.description:
        blocks.append(_one_line(orders.description))
    blocks.append("Meeting points")
    if meetings(members):
        blocks.append("\n".join(_meeting_table(members)))
        blocks.append("A meeting completes only when every vehicle that names it is there; "
                      "they leave it with one shared outcome, each to what its own orders "
                      "name for that outcome.")
    else:
        blocks.append("No goal names a meeting: the vehicles never wait for each other.")
    text = "\n\n".join(blocks) + "\n"
    for number, member in enumerate(members, start=1):
        text += (f"\n{'=' * 72}\nVehicle {number} of {len(members)}: {member.vehicle}, "
                 f"orders {digest(member.orders)}\n{'=' * 72}\n\n")
        text += member_text(member.orders)
    return text
