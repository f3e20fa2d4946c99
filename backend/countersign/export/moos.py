"""MOOS-IvP helm behaviours (.bhv) and a uSimMarine community (.moos) written from orders.

One hierarchical helm mode per goal (`ACTIVE:<goal>`), selected by MISSION_GOAL. A refined goal
is a mode of its own holding the modes of the goals inside it: the helm's mode reads
`ACTIVE:G1:G1_1_k1` while goal G1/G1.1#1 runs; the parent mode is selected whenever
MISSION_GOAL names a goal inside it, so the transitions stay those of the flat automaton. A goal's
maneuver posts its succeed successor as an end flag; Timer behaviours relay an outcome posted
in GOAL_OUTCOME (by the vehicle's monitors) or a broken constraint to the successor of that
outcome. Terminal modes post MISSION_RESULT and DEPLOY = false, which parks the helm. A team
member's meeting goals hold and wait for their partners (moos_meeting)."""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from functools import cached_property

from ..orders.model import OUTCOMES, Orders
from ..verify.nesting import Nesting
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
from .geometry import bounding_box, local_xy
from .moos_condition import violation
from .moos_meeting import (
    MeetingVars,
    arrival_condition,
    header,
    hold,
    initial,
    logged,
    meeting_vars,
    pshare,
)
from .notes import ExportError, ExportFile, ExportNote, VehicleExport
from .provenance import Provenance
from .team import Member

BHV_MEDIA_TYPE = "text/plain; charset=utf-8"
# One Timer per goal and constraint in its scope: bound the file a request can make.
MAX_CONSTRAINT_RELAYS = 200_000
# Parent-mode conditions name every goal inside (times the depth): bounded the same way.
MAX_NESTED_SELECTORS = 200_000
_UNSAFE = re.compile(r"[^A-Za-z0-9_]")
LOGGED = ("DEPLOY", "MODE", "MISSION_GOAL", "GOAL_OUTCOME", "CONSTRAINT_VIOLATED",
          "MISSION_RESULT", "NAV_DEPTH", "NAV_ALTITUDE", "NAV_X", "NAV_Y", "DESIRED_DEPTH",
          "IVPHELM_STATE", "IVPHELM_ALLSTOP", "BHV_ERROR", "BHV_WARNING")


def _comment(text: str) -> str:
    # User text inside a comment: one line, so it cannot start a declaration.
    return " ".join(text.split())[:200]


def mode_names(ids: list[str]) -> dict[str, str]:
    """Helm mode name per goal or terminal id: MOOS names take letters, digits and _."""
    return _unique([(item, item) for item in ids])


def _unique(items: list[tuple[str, str]]) -> dict[str, str]:
    """key -> a name made of `text`, no two alike and none the helm's own ACTIVE/INACTIVE."""
    names: dict[str, str] = {}
    used: set[str] = set()
    for key, text in items:
        base = _UNSAFE.sub("_", text) or "_"
        name, n = base, 1
        while name in used or name in {"ACTIVE", "INACTIVE"}:
            n += 1
            name = f"{base}_{n}"
        used.add(name)
        names[key] = name
    return names


@dataclass(frozen=True)
class Group:
    """A refined goal as a helm mode: its flat id, mode name, the mode it sits in (`ACTIVE`,
    `ACTIVE:G1`), its label, and the MISSION_GOAL values (goal modes) inside it."""

    flat_id: str
    name: str
    parent: str
    label: str
    inside: tuple[str, ...]


@dataclass(frozen=True)
class HelmModes:
    """Where each goal and terminal runs in the helm's mode tree: `name` is what MISSION_GOAL
    posts (unique in the file), `path` the helm's MODE value (`ACTIVE:G1:G1_1_k1`)."""

    name: dict[str, str]
    path: dict[str, str]
    groups: tuple[Group, ...]
    within: dict[str, tuple[str, ...]]  # goal id -> flat ids of its groups, outermost first

    def condition(self, item: str) -> str:
        """What a behaviour's `MODE ==` condition names for goal or terminal `item`. pHelmIvP
        24.8 matched `ACTIVE:G1`, `G1`, `G1:G1_1_k1` and `G1_1_k1` against the mode
        ACTIVE:G1:G1_1_k1 (whole parts: not `1_k1`), but not the whole three-part string; so a
        goal inside a refinement is named by its own mode name, unique in the file."""
        return self.path[item] if item not in self.within else self.name[item]

    def goal_of(self, mode: str) -> str | None:
        """The goal or terminal a MODE value (`ACTIVE:...`) or MISSION_GOAL value names."""
        leaf = mode.rsplit(":", 1)[-1]
        return self._by_name.get(leaf)

    @cached_property
    def _by_name(self) -> dict[str, str]:
        return {name: item for item, name in self.name.items()}


def helm_modes(orders: Orders, nesting: Nesting | None = None) -> HelmModes:
    """Mode names and paths for the (flat) orders; `nesting` places the goals of refinements
    inside modes of their refined goals. Without refinements every mode sits in ACTIVE and is
    named by `mode_names`, as it always was."""
    ids = [g.id for g in orders.goals] + [t.id for t in orders.effective_terminals]
    chains = {g.id: (nesting.parents.get(g.id, ()) if nesting else ()) for g in orders.goals}
    parents: dict[str, tuple[str, tuple[str, ...]]] = {}  # flat id -> label, outer ids
    for chain in chains.values():
        for depth, (flat_id, label) in enumerate(chain):
            parents.setdefault(flat_id, (label, tuple(p for p, _ in chain[:depth])))
    if not parents:
        names = mode_names(ids)
        return HelmModes(names, {i: f"ACTIVE:{n}" for i, n in names.items()}, (), {})
    # A mode is named by the last part of its flat id, an unrolled copy's mark spelt out
    # (#k as _k<k>, @Ts as _t<T>s): G1/G1.1#1 is G1_1_k1 inside G1.
    named = _unique([(item, _spelt(item)) for item in [*parents, *ids]])
    path: dict[str, str] = {}
    inside: dict[str, list[str]] = {p: [] for p in parents}
    for item in ids:
        chain = chains.get(item, ())
        path[item] = ":".join(["ACTIVE", *(named[p] for p, _ in chain), named[item]])
        for flat_id, _ in chain:
            inside[flat_id].append(named[item])
    groups = tuple(
        Group(flat_id, named[flat_id], ":".join(["ACTIVE", *(named[o] for o in outer)]),
              label, tuple(inside[flat_id]))
        for flat_id, (label, outer) in parents.items())
    within = {item: tuple(p for p, _ in chain) for item, chain in chains.items() if chain}
    return HelmModes({i: named[i] for i in ids}, path, groups, within)


def _spelt(flat_id: str) -> str:
    return flat_id.rsplit("/", 1)[-1].replace("#", "_k").replace("@", "_t")


def _any_of(var: str, values: tuple[str, ...]) -> str:
    """`var` equals one of `values`, as a helm logic condition: `or` nested in halves, so the
    parser's depth grows with the logarithm of the goals inside, not their number."""
    if len(values) == 1:
        return f"({var} = {values[0]})"
    half = len(values) // 2
    return f"({_any_of(var, values[:half])} or {_any_of(var, values[half:])})"


class BehaviourNames:
    """Behaviour names the helm tells apart. pHelmIvP refuses a name that begins another
    (`G1_violate` and `G1_violate_C1` are "duplicates"), and ids are the user's, so a mode
    name plus a role cannot be made safe: each name starts `b<serial>_`, and two different
    serials end at a digit and an `_`, so no name begins another."""

    def __init__(self) -> None:
        self._serial = 0

    def __call__(self, mode: str, role: str) -> str:
        self._serial += 1
        return f"b{self._serial}_{mode}_{role}"


def _origin(orders: Orders) -> tuple[float, float]:
    points = [p for a in orders.areas for p in a.polygon]
    box = bounding_box(points)
    return box.centre if box is not None else (0.0, 0.0)


def _block(kind: str, lines: list[str]) -> list[str]:
    return ["Behavior = " + kind, "{", *(f"  {line}" for line in lines), "}", ""]


def _maneuver(place: Placement, origin: tuple[float, float], speed: float) -> tuple[str,
                                                                                   list[str]]:
    box = place.box
    if place.kind == "here" or box is None:
        return "BHV_StationKeep", ["center_activate = true", "inner_radius = 5",
                                   "outer_radius = 20"]
    x, y = local_xy(origin, box.centre)
    if place.kind == "rows":
        return "BHV_Waypoint", [
            f"speed = {speed:g}",
            f"points = format=lawnmower, x={x:g}, y={y:g}, height={box.height_m:.1f}, "
            f"width={box.width_m:.1f}, lane_width={lane_width(place.goal):g}, "
            "rows=north-south, degs=0",
            "repeat = 0"]
    if place.kind == "loiter":
        radius = max(20.0, min(box.width_m, box.height_m) / 2)
        lines = [f"speed = {speed:g}",
                 f"polygon = format=radial, x={x:g}, y={y:g}, radius={radius:.1f}, pts=8"]
        return "BHV_Loiter", lines + _duration(place)
    if place.kind == "station":
        return "BHV_StationKeep", [f"station_pt = {x:g},{y:g}", "inner_radius = 5",
                                   "outer_radius = 20", *_duration(place)]
    # One point in the helm's standard pts={} form. pHelmIvP 24.8 still prints "No waypts
    # given" while it builds any plain point list; the behaviour then steers to the point.
    return "BHV_Waypoint", [f"speed = {speed:g}", f"points = pts={{{x:g},{y:g}}}",
                            "capture_radius = 10"]


def _duration(place: Placement) -> list[str]:
    seconds = duration_s(place.goal)
    return [f"duration = {seconds}", "duration_idle_decay = false"] if seconds else []


def write_bhv(orders: Orders, provenance: Provenance, notes: list[ExportNote],
              nesting: Nesting | None = None,
              meets: dict[str, MeetingVars] | None = None) -> str:
    speed = speed_of(orders, notes)
    origin = _origin(orders)
    terminals = orders.effective_terminals
    helm = helm_modes(orders, nesting)
    modes = helm.name
    start = modes[str(orders.start)]
    out = [
        f"// MOOS-IvP helm behaviours for mission {orders.id}, written by Countersign.",
        f"// orders {provenance.digest}  plan {provenance.plan_id}",
        "// approval " + (json.dumps(provenance.approval, sort_keys=True)
                          if provenance.approval else "none: these orders are not signed"),
        "// A goal ends in one outcome: its maneuver's end flag is succeed; the vehicle's",
        "// monitors post GOAL_OUTCOME = fail | violate | succeed; broken constraints below",
        "// are violate. Each outcome selects the next mode through MISSION_GOAL.",
        "",
        "initialize DEPLOY = false",
        "initialize RETURN = false",
        f"initialize MISSION_GOAL = {start}",
        "initialize GOAL_OUTCOME = none",
        "initialize MISSION_RESULT = none",
        *initial(meets or {}),
        "",
        *header(meets or {}),
        "set MODE = ACTIVE {",
        "  DEPLOY = true",
        "} INACTIVE",
        "",
    ]
    out += _group_declarations(helm)
    out += _mode_declarations(orders, helm)
    scope = _constraint_scope(orders)
    relays = sum(len(watched) for watched in scope.values())
    if relays > MAX_CONSTRAINT_RELAYS:
        raise ExportError(f"{relays:,} constraint monitors (goals times constraints in scope) "
                          f"exceed the {MAX_CONSTRAINT_RELAYS:,} a helm file may hold")
    named = BehaviourNames()
    for place in placements(orders, notes):
        out += _goal_behaviours(place, modes, helm, origin, speed, scope, named, notes,
                                (meets or {}).get(place.goal.meet or ""))
    for terminal in terminals:
        name = modes[terminal.id]
        out += _block("BHV_Timer", [
            f"name = {named(name, 'stop')}", f"condition = MODE == {helm.condition(terminal.id)}",
            f"runflag = MISSION_RESULT = {terminal.kind}", "runflag = DEPLOY = false"])
    out += _unexpressed(orders, notes)
    uncarried(orders, "MOOS-IvP", notes)
    return "\n".join(out).rstrip("\n") + "\n"


def _mode_declarations(orders: Orders, helm: HelmModes) -> list[str]:
    """A mode per goal (inside its refinement groups' modes, each declared before its first
    goal) and per terminal."""
    modes, paths = helm.name, helm.path
    out: list[str] = []
    groups = {group.flat_id: group for group in helm.groups}
    declared: set[str] = set()
    for goal in orders.goals:
        for flat_id in helm.within.get(goal.id, ()):
            if flat_id not in declared:
                declared.add(flat_id)
                out += _group_mode(groups[flat_id])
        parent = paths[goal.id].rsplit(":", 1)[0]
        out += [f"// mode {modes[goal.id]} = goal {goal.id}: {_comment(goal.label)}",
                f"set MODE = {modes[goal.id]} {{", f"  MODE = {parent}",
                f"  MISSION_GOAL = {modes[goal.id]}", "}", ""]
    for terminal in orders.effective_terminals:
        out += [f"// mode {modes[terminal.id]} = terminal {terminal.id} ({terminal.kind}): "
                f"{_comment(terminal.label)}",
                f"set MODE = {modes[terminal.id]} {{", "  MODE = ACTIVE",
                f"  MISSION_GOAL = {modes[terminal.id]}", "}", ""]
    return out


def _group_declarations(helm: HelmModes) -> list[str]:
    """What the nested modes add before the goals' own (nothing without refinements)."""
    if not helm.groups:
        return []
    selectors = sum(len(group.inside) for group in helm.groups)
    if selectors > MAX_NESTED_SELECTORS:
        raise ExportError(f"the refined goals' modes name {selectors:,} goals inside them "
                          f"(goals times depth), over the {MAX_NESTED_SELECTORS:,} a helm file "
                          "may hold: refine less deeply or lower a time-out")
    return ["// A refined goal is a mode holding the modes of the goals inside it: it is",
            "// selected while MISSION_GOAL names one of them, so MODE reads ACTIVE:G1:G1_1_k1.",
            ""]


def _group_mode(group: Group) -> list[str]:
    return [f"// mode {group.name} = refined goal {group.flat_id}: {_comment(group.label)}",
            f"set MODE = {group.name} {{", f"  MODE = {group.parent}",
            f"  {_any_of('MISSION_GOAL', group.inside)}", "}", ""]


def _constraint_scope(orders: Orders) -> dict[str, list[tuple[int, str, str]]]:
    """Goal id -> (constraint index, id, helm violation condition) it must watch."""
    scope: dict[str, list[tuple[int, str, str]]] = {g.id: [] for g in orders.goals}
    for index, constraint in enumerate(orders.constraints):
        condition = violation(constraint.expr)
        if condition is None:
            continue
        goals = scope if constraint.applies_to == "mission" else constraint.applies_to
        for goal_id in goals:
            if goal_id in scope:
                scope[goal_id].append((index, constraint.id, condition))
    return scope


def _goal_behaviours(place: Placement, modes: dict[str, str], helm: HelmModes,
                     origin: tuple[float, float], speed: float,
                     scope: dict[str, list[tuple[int, str, str]]], named: BehaviourNames,
                     notes: list[ExportNote], meeting: MeetingVars | None = None) -> list[str]:
    goal = place.goal
    name = modes[goal.id]
    target = {o: modes[goal.successors(o)[0]] for o in OUTCOMES}
    when = f"condition = MODE == {helm.condition(goal.id)}"
    out = [f"//---------- goal {goal.id} ({_comment(goal.behavior or 'no behaviour')})"]
    # At a meeting nothing moves on before every member is there.
    gate = [] if meeting is None else [f"condition = {meeting.all} = true"]
    if meeting is None:
        out += _maneuver_blocks(place, name, target, when, origin, speed, named, notes)
    else:
        out += _meeting_blocks(place, name, when, origin, speed, named, meeting)
    if place.depth_m is not None:
        # Without a duration the helm ends the behaviour at once (and then has no depth
        # decision); it must hold the depth as long as its mode lasts.
        out += _block("BHV_ConstantDepth", [f"name = {named(name, 'depth')}", "pwt = 100", when,
                                            f"depth = {place.depth_m:g}",
                                            "duration = no-time-limit"])
    for outcome in OUTCOMES:
        out += _block("BHV_Timer", [
            f"name = {named(name, outcome)}", when, f"condition = GOAL_OUTCOME == {outcome}",
            *gate, "perpetual = true", f"runflag = MISSION_GOAL = {target[outcome]}",
            "runflag = GOAL_OUTCOME = none",
            *([] if meeting is None else [f"runflag = {meeting.all} = false"])])
    # At a meeting a broken constraint is the outcome the meeting ends with, not a move.
    leave = f"MISSION_GOAL = {target['violate']}" if meeting is None else "GOAL_OUTCOME = violate"
    for _, constraint_id, condition in scope[goal.id]:
        out += _block("BHV_Timer", [
            f"name = {named(name, 'violate_' + _UNSAFE.sub('_', constraint_id))}", when,
            f"condition = {condition}", "perpetual = true",
            # The outcome before the mode change, so a log names it before the next goal
            f"runflag = CONSTRAINT_VIOLATED = {_UNSAFE.sub('_', constraint_id)}",
            f"runflag = {leave}"])
    return out


def _maneuver_blocks(place: Placement, name: str, target: dict[str, str], when: str,
                     origin: tuple[float, float], speed: float, named: BehaviourNames,
                     notes: list[ExportNote]) -> list[str]:
    goal = place.goal
    kind, lines = _maneuver(place, origin, speed)
    if kind != "BHV_Waypoint" and not duration_s(goal):
        notes.append(ExportNote("SUCCEED", f"/goals/{place.index}", f"goal {goal.id} has no "
                                "ordered duration: its maneuver never ends by itself, so its "
                                "succeed must be posted as GOAL_OUTCOME = succeed"))
    return _block(kind, [f"name = {named(name, 'run')}", "pwt = 100", when, "perpetual = true",
                         f"endflag = MISSION_GOAL = {target['succeed']}",
                         "endflag = GOAL_OUTCOME = none", *lines])


def _meeting_blocks(place: Placement, name: str, when: str, origin: tuple[float, float],
                    speed: float, named: BehaviourNames, meeting: MeetingVars) -> list[str]:
    """Hold at the meeting point (no end flag: the meeting, not the maneuver, ends the goal)
    and post the arrival once there."""
    x, y = (None, None) if place.box is None else local_xy(origin, place.box.centre)
    out = [f"// meeting {meeting.meet}: holds here until {meeting.all} = true "
           f"(partners: {', '.join(_comment(p) for p in meeting.partners) or 'none'})"]
    kind, lines = hold(x, y, speed)
    out += _block(kind, [f"name = {named(name, 'hold')}", "pwt = 100", when, "perpetual = true",
                         *lines])
    out += _block("BHV_Timer", [f"name = {named(name, 'arrive')}", when,
                                *arrival_condition(x, y), "perpetual = true",
                                f"runflag = {meeting.arrived} = {meeting.vehicle}"])
    return out


def _unexpressed(orders: Orders, notes: list[ExportNote]) -> list[str]:
    out: list[str] = []
    for index, constraint in enumerate(orders.constraints):
        if violation(constraint.expr) is not None:
            continue
        out.append(f"// constraint {constraint.id} ({_comment(constraint.expr or 'no condition')}"
                   "): no helm condition can express it; the vehicle's monitor must post "
                   "GOAL_OUTCOME = violate")
        notes.append(ExportNote("MONITOR", f"/constraints/{index}",
                                f"constraint {constraint.id} cannot be a helm condition "
                                "(arithmetic, behaviour, area or context); named in a comment"))
    return out


def write_moos(orders: Orders, bhv_name: str, provenance: Provenance,
               bridge: list[str] | None = None, also_logged: tuple[str, ...] = ()) -> str:
    lat, lon = _origin(orders)
    community = _UNSAFE.sub("_", orders.vehicle or orders.id)
    vehicle = orders.target_vehicle()
    top = (vehicle.envelope.get("depth_m") if vehicle else None) or (0.0, 100.0)
    speed = (vehicle.speed_mps if vehicle and vehicle.speed_mps else 1.0) * 2
    return "\n".join([
        f"// uSimMarine run of mission {orders.id} (Countersign); behaviours in {bhv_name}",
        f"// orders {provenance.digest}  plan {provenance.plan_id}",
        "ServerHost = localhost", "ServerPort = 9000", f"Community  = {community}",
        "MOOSTimeWarp = 1", f"LatOrigin  = {lat:.6f}", f"LongOrigin = {lon:.6f}", "",
        "ProcessConfig = ANTLER", "{", "  MSBetweenLaunches = 200",
        "  Run = MOOSDB        @ NewConsole = false",
        "  Run = uSimMarine    @ NewConsole = false",
        "  Run = pMarinePID    @ NewConsole = false",
        "  Run = pHelmIvP      @ NewConsole = false",
        "  Run = pLogger       @ NewConsole = false",
        *(["  // Run = pShare    @ NewConsole = false  (the bridge below, where installed)"]
          if bridge else []), "}", "",
        # What `countersign execution check` reads, and the helm's own reports; logging every
        # variable (WildCardLogging) also works but writes megabytes a minute.
        "ProcessConfig = pLogger", "{", "  AppTick = 10", "  CommsTick = 10",
        f"  File = {_UNSAFE.sub('_', orders.id)}", "  PATH = ./", "  FileTimeStamp = false",
        "  AsyncLog = true", *(f"  Log = {var} @ 0" for var in (*LOGGED, *also_logged)), "}", "",
        *(bridge or []),
        "ProcessConfig = uSimMarine", "{", "  AppTick = 10", "  CommsTick = 10",
        "  start_pos = x=0, y=0, heading=0, speed=0, depth=0", "  prefix = NAV",
        "  buoyancy_rate = 0.025", "  max_depth_rate = 5", "  max_depth_rate_speed = 2.0", "}",
        "",
        "ProcessConfig = pHelmIvP", "{", "  AppTick = 4", "  CommsTick = 4",
        # Engaged from the start: the mission itself waits for DEPLOY = true. Depth is
        # optional: goals without an ordered depth decide none (else MissingDecVars).
        f"  behaviors = {bhv_name}", "  start_engaged = true", "  domain = course:0:359:360",
        f"  domain = speed:0:{speed:g}:21",
        f"  domain = depth:0:{top[1]:g}:{int(top[1]) + 1}:optional",
        "}", "",
        "ProcessConfig = pMarinePID", "{", "  AppTick = 10", "  CommsTick = 10",
        # Without active_start it leaves the actuators alone until MOOS_MANUAL_OVERRIDE.
        "  verbose = terse", "  active_start = true", "  depth_control = true",
        "  yaw_pid_kp = 1.2",
        "  yaw_pid_kd = 0.0", "  yaw_pid_ki = 0.3", "  yaw_pid_integral_limit = 0.07",
        "  speed_pid_kp = 1.0", "  speed_pid_kd = 0.0", "  speed_pid_ki = 0.0",
        "  speed_pid_integral_limit = 0.07", "  z_to_pitch_pid_kp = 0.12",
        "  z_to_pitch_pid_kd = 0.0", "  z_to_pitch_pid_ki = 0.004",
        "  z_to_pitch_pid_integral_limit = 0.05", "  pitch_pid_kp = 0.5",
        "  pitch_pid_kd = 1.0", "  pitch_pid_ki = 0.0", "  pitch_pid_integral_limit = 0",
        "  maxrudder = 100", "  maxthrust = 100", "  maxpitch = 15", "  maxelevator = 13",
        "  speed_factor = 20", "}", ""])


def export_moos(orders: Orders, provenance: Provenance,
                member: Member | None = None) -> VehicleExport:
    notes: list[ExportNote] = []
    meets = meeting_vars(member) if member is not None else {}
    orders, nesting = flat_with_nesting(orders, notes)
    require_sound(orders, notes)
    if nesting is not None:
        notes.append(ExportNote("NESTED", "/goals", "a refined goal is a helm mode holding the "
                                "modes of the goals inside it: MODE reads ACTIVE:G1:G1_1_k1 "
                                "(#k spelt _k<k>, @Ts _t<T>s); MISSION_GOAL names the goal's "
                                "own mode"))
    bhv_name = f"{orders.id}.bhv"
    bhv = write_bhv(orders, provenance, notes, nesting, meets)
    bridge = [] if member is None else pshare(member, meets)
    moos = write_moos(orders, bhv_name, provenance, bridge, tuple(logged(meets)))
    for meeting in meets.values():
        notes.append(ExportNote("MEET", "/goals", f"meeting {meeting.meet}: the helm holds at "
                                f"the point, posts {meeting.arrived} and leaves only after "
                                f"{meeting.all} = true, which a bridge (pShare, see the .moos) "
                                f"posts once {', '.join(meeting.partners) or 'every member'} "
                                "arrived too"))
    files = (ExportFile(bhv_name, BHV_MEDIA_TYPE, bhv.encode()),
             ExportFile(f"{orders.id}.moos", BHV_MEDIA_TYPE, moos.encode()))
    return VehicleExport("moos", files, tuple(notes))
