"""A team member's meetings in its MOOS-IvP community: hold at the meeting point, say so, and
leave only when every member is there.

A meeting goal's mode keeps the vehicle at the point (BHV_Loiter on a small circle and no
duration, so it never ends by itself; circling, not station keeping, because an AUV that
stops cannot hold its depth) and posts MEET_<id>_ARRIVED = <vehicle> once inside the point's
box. Its outcome relays wait for MEET_<id>_ALL = true, which the bridge between the members'
communities posts when every member has arrived; the one shared outcome then arrives as
GOAL_OUTCOME, as for any goal. A broken constraint while waiting becomes GOAL_OUTCOME =
violate rather than a move, so no member leaves a meeting alone. pShare is MOOS-IvP's bridge;
its block names what to share."""

from __future__ import annotations

import re
from dataclasses import dataclass

from .team import Member

_UNSAFE = re.compile(r"[^A-Za-z0-9_]")
# The circle a vehicle holds on at the meeting point, and half the side of the square around
# the point inside which it has arrived: the circle with room for the turns.
HOLD_RADIUS_M = 30.0
ARRIVAL_M = 2 * HOLD_RADIUS_M
# Where the bridges listen by default (pShare routes): the coordinator first, then each member
# in team order; a deployment sets its own hosts and ports.
COORDINATOR_PORT = 9300


@dataclass(frozen=True)
class MeetingVars:
    """The MOOS variables of one meeting in one member's community."""

    meet: str
    arrived: str
    all: str
    vehicle: str  # the value this member posts as arrived
    partners: tuple[str, ...]


def meeting_vars(member: Member) -> dict[str, MeetingVars]:
    """Meeting id -> its variables; names made of the id, made unique if two ids differ only
    in characters MOOS names cannot hold."""
    out: dict[str, MeetingVars] = {}
    used: set[str] = set()
    for meeting in member.meetings:
        base = _UNSAFE.sub("_", meeting.meet)
        name, n = base, 1
        while name in used:
            n += 1
            name = f"{base}_{n}"
        used.add(name)
        out[meeting.meet] = MeetingVars(meeting.meet, f"MEET_{name}_ARRIVED", f"MEET_{name}_ALL",
                                        _UNSAFE.sub("_", member.vehicle), meeting.partners)
    return out


def initial(meets: dict[str, MeetingVars]) -> list[str]:
    return [f"initialize {v.all} = false" for v in meets.values()]


def header(meets: dict[str, MeetingVars]) -> list[str]:
    """The .bhv's comment on what a meeting needs from outside the helm."""
    if not meets:
        return []
    lines = ["// Meetings: a meeting goal holds at its point and posts MEET_<id>_ARRIVED =",
             "// <vehicle> there; it leaves only after MEET_<id>_ALL = true (every member",
             "// arrived, posted by the bridge), with the shared outcome as GOAL_OUTCOME."]
    for v in meets.values():
        lines.append(f"//   meeting {v.meet}: posts {v.arrived} = {v.vehicle}, waits for "
                     f"{v.all} = true (partners: {', '.join(v.partners) or 'none'})")
    return [*lines, ""]


def hold(x: float | None, y: float | None, speed: float) -> tuple[str, list[str]]:
    """The behaviour and parameters that hold the vehicle at (x, y), or where it is."""
    if x is None or y is None:
        return "BHV_StationKeep", ["center_activate = true", "inner_radius = 5",
                                   "outer_radius = 20"]
    return "BHV_Loiter", [f"speed = {speed:g}", f"polygon = format=radial, x={x:g}, y={y:g}, "
                          f"radius={HOLD_RADIUS_M:g}, pts=8"]


def arrival_condition(x: float | None, y: float | None) -> list[str]:
    """Helm conditions that hold once the vehicle is within the meeting point's box."""
    if x is None or y is None:
        return []
    return [f"condition = NAV_X >= {x - ARRIVAL_M:g}", f"condition = NAV_X <= {x + ARRIVAL_M:g}",
            f"condition = NAV_Y >= {y - ARRIVAL_M:g}", f"condition = NAV_Y <= {y + ARRIVAL_M:g}"]


def logged(meets: dict[str, MeetingVars]) -> list[str]:
    return [name for v in meets.values() for name in (v.arrived, v.all)]


def pshare(member: Member, meets: dict[str, MeetingVars]) -> list[str]:
    """The bridge's configuration and which variables cross it; pShare is not launched by the
    ANTLER block (add `Run = pShare` where it is installed)."""
    if not meets:
        return []
    own = COORDINATOR_PORT + 1 + member.team.index(member.vehicle)
    lines = [
        "// Bridge between the members' communities (MOOS-IvP pShare). Every member's",
        "// arrival goes to a coordinator (shoreside), which posts MEET_<id>_ALL = true and the",
        "// meeting's one shared outcome as GOAL_OUTCOME into every member once all arrived:",
    ]
    for v in meets.values():
        lines.append(f"//   meeting {v.meet}: out {v.arrived}; in {v.all}, GOAL_OUTCOME; "
                     f"members {', '.join(sorted((member.vehicle, *v.partners)))}")
    lines += [f"// Routes: coordinator localhost:{COORDINATOR_PORT}, this member "
              f"localhost:{own} (team order); set a deployment's hosts here.",
              "ProcessConfig = pShare", "{", "  AppTick = 4", "  CommsTick = 4",
              f"  input = route = localhost:{own}"]
    lines += [f"  output = src_name = {v.arrived}, dest_name = {v.arrived}_{v.vehicle}, "
              f"route = localhost:{COORDINATOR_PORT}" for v in meets.values()]
    return [*lines, "}", ""]
