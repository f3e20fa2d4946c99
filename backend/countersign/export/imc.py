"""IMC (LSTS Neptus/DUNE) plan written from orders: one PlanSpecification, serialised by imcpy.

Goals become maneuvers named by goal id (a goal inside a refinement by its flat id, which
carries the hierarchy: G1/G1.2#2/G1.2.1 runs in G1.2's 2nd copy inside G1; its custom field
names the refined goals and their titles), terminals become surface station-keeping maneuvers
with no way out, and each goal has one transition per outcome. DUNE's plan engine fires
`ManeuverIsDone` by itself; the fail and violate conditions name events the vehicle's own
monitors must raise, which a note says. A team member's meeting goal is a maneuver without an
end (duration 0) whose custom field names the meeting and the partners it waits for."""

from __future__ import annotations

import json
import math
from typing import Any
from urllib.parse import quote

import imcpy

from ..orders.model import OUTCOMES, Orders
from .common import (
    Placement,
    duration_s,
    flat_with_nesting,
    lane_width,
    placements,
    require_sound,
    speed_of,
    uncarried,
)
from .notes import ExportError, ExportFile, ExportNote, VehicleExport
from .provenance import Provenance
from .team import Meeting, Member

MEDIA_TYPE = "application/vnd.lsts.imc"
MAX_MESSAGE_BYTES = 65_535
# Ranges IMC.xml (5.4.x) gives the fields we fill from orders; a strict reader refuses a
# message with any field outside them.
MAX_SECONDS = 65_535  # uint16_t durations
MAX_RADIUS_M = 100_000.0  # Loiter radius and length (both at least 1 m)
CONDITIONS = {"succeed": "ManeuverIsDone", "fail": "ManeuverFailed",
              "violate": "ConstraintViolated"}
OUTCOME_OF = {v: k for k, v in CONDITIONS.items()}


_PRINTABLE_SAFE = "".join(chr(c) for c in range(0x20, 0x7F) if chr(c) not in "%;=")


def _tuple_list(values: dict[str, Any]) -> str:
    """IMC TupleList text (`k=v;k=v`); user text is percent-escaped so it cannot add keys, and
    so is anything outside printable ASCII, which is all an IMC plaintext field may hold."""
    def escape(text: str) -> str:
        return quote(text, safe=_PRINTABLE_SAFE)
    return ";".join(f"{escape(k)}={escape(str(v))}" for k, v in values.items())


def _seconds(place: Placement) -> int:
    seconds = duration_s(place.goal)
    if seconds > MAX_SECONDS:
        raise ExportError(f"goal {place.goal.id} lasts {seconds:,} s; an IMC maneuver's "
                          f"duration is at most {MAX_SECONDS:,} s: split the goal")
    return seconds


def _depth(maneuver: Any, depth: float | None) -> None:
    maneuver.z = 0.0 if depth is None else depth
    maneuver.z_units = imcpy.ZUnits.DEPTH


def _maneuver(place: Placement, speed: float,
              inside: tuple[tuple[str, str], ...] = (), meeting: Meeting | None = None) -> Any:
    goal, box = place.goal, place.box
    if place.kind == "here" or box is None:
        elevator = imcpy.Elevator()
        elevator.flags = int(imcpy.Elevator.FlagsBits.CURR_POS)
        elevator.start_z = elevator.end_z = place.depth_m or 0.0
        elevator.start_z_units = elevator.end_z_units = imcpy.ZUnits.DEPTH
        elevator.speed, elevator.speed_units = speed, imcpy.SpeedUnits.METERS_PS
        elevator.radius = 20.0
        maneuver: Any = elevator
    elif place.kind == "rows":
        maneuver = imcpy.Rows()
        maneuver.lat, maneuver.lon = math.radians(box.south), math.radians(box.west)
        maneuver.bearing = 0.0  # rows run north from the south-west corner
        maneuver.length, maneuver.width = box.height_m, box.width_m
        maneuver.hstep = lane_width(goal)
        maneuver.cross_angle = 0.0
        maneuver.alternation = 100
    else:
        lat, lon = box.centre
        if place.kind == "loiter":
            maneuver = imcpy.Loiter()
            maneuver.type = int(imcpy.Loiter.LoiterTypeEnum.CIRCULAR)
            maneuver.radius = min(MAX_RADIUS_M, max(20.0, min(box.width_m, box.height_m) / 2))
            # A circular loiter ignores the racetrack length, but IMC.xml bounds it to
            # [1, 100000] m, so the diameter's worth (bounded too) stands in for it.
            maneuver.length = min(MAX_RADIUS_M, 2 * maneuver.radius)
            maneuver.duration = _held(place, meeting)
            maneuver.direction = int(imcpy.Loiter.DirectionEnum.CLOCKW)
        elif place.kind == "station":
            maneuver = imcpy.StationKeeping()
            maneuver.radius = 20.0
            maneuver.duration = _held(place, meeting)
        else:
            maneuver = imcpy.Goto()
        maneuver.lat, maneuver.lon = math.radians(lat), math.radians(lon)
    if place.kind != "here":
        _depth(maneuver, place.depth_m)
        maneuver.speed, maneuver.speed_units = speed, imcpy.SpeedUnits.METERS_PS
    custom: dict[str, Any] = {"goal": goal.id, "behavior": goal.behavior or "",
                              "title": goal.title}
    if inside:
        # A goal inside refinements: the refined goals it runs in (flat ids, outermost first)
        # and their titles, which its id (G1/G1.2#2/G1.2.1) names only by id.
        custom["inside"] = "/".join(flat_id for flat_id, _ in inside)
        custom["inside.title"] = " / ".join(label for _, label in inside)
    if meeting is not None:
        custom["meet"] = meeting.meet
        custom["meet.partners"] = ",".join(meeting.partners)
    custom.update({f"param.{k}": json.dumps(v) for k, v in sorted(goal.params.items())})
    maneuver.custom = _tuple_list(custom)
    return maneuver


def _held(place: Placement, meeting: Meeting | None) -> int:
    # IMC's 0 is "no time limit": a meeting ends when every member is there, not on a clock.
    return 0 if meeting is not None else _seconds(place)


def _terminal(kind: str, title: str, terminal_id: str) -> Any:
    popup = imcpy.PopUp()
    popup.flags = int(imcpy.PopUp.FlagsBits.CURR_POS) | int(
        imcpy.PopUp.FlagsBits.STATION_KEEP) | int(imcpy.PopUp.FlagsBits.WAIT_AT_SURFACE)
    popup.z, popup.z_units = 0.0, imcpy.ZUnits.DEPTH
    popup.radius = 20.0
    popup.custom = _tuple_list({"terminal": terminal_id, "kind": kind, "title": title})
    return popup


def _constraints(orders: Orders, plan: Any, notes: list[ExportNote]) -> None:
    for index, constraint in enumerate(orders.constraints):
        variable = imcpy.PlanVariable()
        variable.name = f"constraint.{constraint.id}"
        scope = constraint.applies_to if isinstance(constraint.applies_to, str) else \
            ",".join(constraint.applies_to)
        variable.value = json.dumps({"expr": constraint.expr, "applies_to": scope})
        variable.type = int(imcpy.PlanVariable.TypeEnum.TEXT)
        variable.access = int(imcpy.PlanVariable.AccessTypeEnum.LOCAL)
        plan.variables.append(variable)
        notes.append(ExportNote(
            "MONITOR", f"/constraints/{index}", f"constraint {constraint.id} travels as plan "
            "variable text; DUNE has no monitor for it, so the vehicle's own monitor must raise "
            "ConstraintViolated"))


def build_plan(orders: Orders, provenance: Provenance,
               member: Member | None = None) -> tuple[Any, list[ExportNote]]:
    notes: list[ExportNote] = []
    orders, nesting = flat_with_nesting(orders, notes)
    require_sound(orders, notes)
    parents = nesting.parents if nesting is not None else {}
    speed = speed_of(orders, notes)
    plan = imcpy.PlanSpecification()
    plan.plan_id = provenance.plan_id
    plan.description = json.dumps(provenance.to_json(), sort_keys=True)
    plan.start_man_id = str(orders.start)
    for place in placements(orders, notes):
        step = imcpy.PlanManeuver()
        step.maneuver_id = place.goal.id
        meeting = member.meeting_of(place.goal.meet) if member is not None else None
        step.data = _maneuver(place, speed, parents.get(place.goal.id, ()), meeting)
        plan.maneuvers.append(step)
        if meeting is not None:
            notes.append(ExportNote(
                "MEET", f"/goals/{place.index}", f"goal {place.goal.id} is meeting "
                f"{meeting.meet} with {', '.join(meeting.partners) or 'no other member'}: a "
                "maneuver without end "
                "(custom meet, meet.partners); the team's coordinator ends it with the shared "
                "outcome once every member has arrived"))
    for terminal in orders.effective_terminals:
        step = imcpy.PlanManeuver()
        step.maneuver_id = terminal.id
        step.data = _terminal(terminal.kind, terminal.label, terminal.id)
        plan.maneuvers.append(step)
    for goal in orders.goals:
        for outcome in OUTCOMES:
            transition = imcpy.PlanTransition()
            transition.source_man = goal.id
            transition.dest_man = goal.successors(outcome)[0]
            transition.conditions = CONDITIONS[outcome]
            plan.transitions.append(transition)
    notes.append(ExportNote("OUTCOME", "/goals", "DUNE fires ManeuverIsDone itself; "
                            "ManeuverFailed and ConstraintViolated must be raised by the "
                            "vehicle's monitors"))
    _constraints(orders, plan, notes)
    uncarried(orders, "IMC", notes)
    return plan, notes


def export_imc(orders: Orders, provenance: Provenance,
               member: Member | None = None) -> VehicleExport:
    plan, notes = build_plan(orders, provenance, member)
    try:
        data = bytes(plan.serialize())
    except RuntimeError as exc:
        # An IMC message carries a 16-bit payload size: a few hundred goals at most.
        raise ExportError(f"the IMC plan does not fit in one IMC message of at most "
                          f"{MAX_MESSAGE_BYTES:,} bytes ({exc}); split the mission") from None
    return VehicleExport("imc", (ExportFile(f"{orders.id}.imc", MEDIA_TYPE, data),),
                         tuple(notes))
