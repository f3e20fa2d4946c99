"""One member of a team's orders as a vehicle exports it: its own orders, and for each meeting
its goals name, the partners it waits for (DESIGN.md "Refinement and teams").

A vehicle runs one MEA, so a team is exported a member at a time; what the member cannot know
alone (who else must stand at a meeting before it may leave) is what this adds."""

from __future__ import annotations

from dataclasses import dataclass

from ..orders.model import Orders
from ..orders.team import meetings
from .notes import ExportError


class MemberNeeded(ExportError):
    """A team's orders exported without naming the member whose vehicle files to write."""

    def __init__(self, vehicles: tuple[str, ...]) -> None:
        super().__init__("these are a team's orders (one MEA per vehicle): name the member to "
                         f"export, one of {', '.join(vehicles)}")
        self.vehicles = vehicles


class UnknownMember(ExportError):
    """A member named that the orders do not hold (or orders that are no team)."""

    def __init__(self, member: str, vehicles: tuple[str, ...]) -> None:
        held = (f"the team's members are {', '.join(vehicles)}" if vehicles
                else "these orders are one vehicle's, not a team's")
        super().__init__(f"member {member!r} is not in these orders: {held}")
        self.member, self.vehicles = member, vehicles


@dataclass(frozen=True)
class Meeting:
    """A meeting as one member sees it: the id, its own goals naming it, and its partners."""

    meet: str
    goals: tuple[str, ...]
    partners: tuple[str, ...]


@dataclass(frozen=True)
class Member:
    vehicle: str
    orders: Orders
    meetings: tuple[Meeting, ...]
    team: tuple[str, ...]  # every member's vehicle, in team order

    def meeting_of(self, meet: str | None) -> Meeting | None:
        """The meeting a goal's `meet` names (None: the goal is no meeting)."""
        return next((m for m in self.meetings if m.meet == meet), None)


def select_member(orders: Orders, vehicle: str | None) -> Member | None:
    """The member `vehicle` of team orders (None for one vehicle's orders and no member).
    Raises MemberNeeded for a team without a member, UnknownMember for a member the orders
    do not hold."""
    if orders.team is None:
        if vehicle is not None:
            raise UnknownMember(vehicle, ())
        return None
    vehicles = tuple(m.vehicle for m in orders.team)
    if vehicle is None:
        raise MemberNeeded(vehicles)
    member = next((m for m in orders.team if m.vehicle == vehicle), None)
    if member is None:
        raise UnknownMember(vehicle, vehicles)
    own: list[Meeting] = []
    for meet, places in meetings(orders.team).items():
        here = next((p for p in places if p.vehicle == vehicle), None)
        if here is not None:
            partners = tuple(p.vehicle for p in places if p.vehicle != vehicle)
            own.append(Meeting(meet, here.goals, partners))
    return Member(vehicle, member.orders, tuple(own), vehicles)
