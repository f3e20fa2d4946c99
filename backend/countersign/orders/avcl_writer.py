"""Write orders as AVCL 3.1 mission XML that validates against the NPS schema (AVCL.3.1.xsd).

The document is `AVCL/head/meta*` plus `AVCL/body/MissionAgenda/GoalList/Goal*`. Goals keep
their successors as nextOnSuccess / nextOnFailure / nextOnException; terminals become terminal
goals (no successors), which is how AVCL ends a mission, with a description saying which kind.
A goal's behaviour becomes one of the goal actions the schema defines (Search, Reposition, ...;
SpecialGoal for the rest) and `read_avcl` reads the element back unless a head meta names the
exact behaviour. What AVCL has no place for travels in `<meta>` elements of the head (tools
ignore meta names they do not know), read back by `read_avcl`:

- `countersign:chart`: one registry chart as JSON each (AVCL has no mission-wide chart);
- `countersign:behavior`: `GOAL behaviour` where the goal action does not name the behaviour;
- `countersign:ids`: a JSON map from the XML id written to the orders id, for ids that are not
  XML names (a leading digit, a colon), since the schema types every id as xsd:ID;
- `vehicleName` / `vehicleType`: the target vehicle (the NPS files put these on the root
  element, which the schema does not allow).

Whatever the document still cannot carry is returned as gaps (code, JSON pointer, message),
which the export turns into notes. Writing uses the standard library (only reading untrusted XML
needs defusedxml).
"""

from __future__ import annotations

import json
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field

from .model import Goal, Orders, Terminal

CHART_META = "countersign:chart"
BEHAVIOR_META = "countersign:behavior"
IDS_META = "countersign:ids"
VEHICLE_NAME_META = "vehicleName"
VEHICLE_TYPE_META = "vehicleType"
HANDLERS = (("succeed", "nextOnSuccess"), ("fail", "nextOnFailure"),
            ("violate", "nextOnException"))
# The terminal goal's description; `read_avcl` takes the kind from it before any wording rule.
TERMINAL_DESCRIPTIONS = {"complete": "Mission complete, final success state",
                         "abort": "Mission aborted, final failure state"}
# The goal actions of AVCL 3.1 (group GoalAction) whose content is optional, and the behaviours
# each stands for. MarkTarget, Demolish, Decontaminate, IlluminateArea and Jam require markers,
# targets, contaminants or frequencies the orders do not state: those become SpecialGoal.
GOAL_ACTIONS: dict[str, str] = {
    **dict.fromkeys(("search", "area_search", "survey", "hydro_survey", "mine_hunt", "mapping",
                     "reacquire"), "Search"),
    **dict.fromkeys(("reposition", "transit", "transect", "goto", "return",
                     "return_to_base", "recover"), "Reposition"),
    **dict.fromkeys(("patrol", "loiter", "orbit", "track"), "Patrol"),
    **dict.fromkeys(("sample_environment", "sample"), "SampleEnvironment"),
    **dict.fromkeys(("monitor_transmissions", "surface_report", "report"),
                    "MonitorTransmissions"),
    "rendezvous": "Rendezvous", "attack": "Attack", "supply": "Supply",
    "special_goal": "SpecialGoal",
}
SPECIAL_GOAL = "SpecialGoal"
VEHICLE_TYPES = frozenset({"UAV", "UGV", "USV", "UUV", "ROV", "AGENDA", "MUNITION", "SSGN",
                           "UNKNOWN"})
# xsd:ID is an NCName; orders ids are ASCII, so only the ASCII part of NCName matters.
_NCNAME = re.compile(r"[A-Za-z_][A-Za-z0-9_.\-]*")
# Where the schema bounds a number (percentType, nonNegativeScalarType).
_PD_RANGE = (0.0, 100.0)


def element_behavior(element_name: str) -> str:
    """The behaviour `read_avcl` reads from a goal action element (Search -> search)."""
    return re.sub(r"(?<=[a-z0-9])(?=[A-Z])|(?<=[A-Z])(?=[A-Z][a-z])", "_", element_name).lower()


@dataclass(frozen=True)
class Gap:
    """Something of the orders the AVCL document does not carry (or carries differently)."""

    code: str
    path: str  # JSON pointer into the orders
    message: str


@dataclass
class AvclDocument:
    text: str
    gaps: list[Gap] = field(default_factory=list)


class _Ids:
    """Orders ids as xsd:ID values: unchanged where they are XML names, else renamed once."""

    def __init__(self, taken: set[str]) -> None:
        self.taken = set(taken)
        self.renamed: dict[str, str] = {}  # orders id -> XML id

    def __call__(self, value: str) -> str:
        if _NCNAME.fullmatch(value):
            return value
        found = self.renamed.get(value)
        if found is None:
            base = "_" + value.replace(":", "_")
            found, count = base, 1
            while found in self.taken:
                count += 1
                found = f"{base}_{count}"
            self.taken.add(found)
            self.renamed[value] = found
        return found


def write_avcl(orders: Orders) -> str:
    return avcl_document(orders).text


def avcl_document(orders: Orders) -> AvclDocument:
    gaps: list[Gap] = []
    goals, terminals = _unique_elements(orders, gaps)
    defined = {g.id for _, g in goals} | {t.id for t in terminals}
    ids = _Ids(defined)
    root = ET.Element("AVCL", {"version": "3.1"})
    head = _head(orders, root)
    body = ET.SubElement(root, "body")
    ET.SubElement(body, "UnitsOfMeasure", {"distance": "meters", "angle": "degrees",
                                           "mass": "kilograms", "time": "seconds"})
    _vehicle(orders, head, body)
    agenda = ET.SubElement(body, "MissionAgenda",
                           {"description": orders.description or orders.title})
    goal_list = ET.SubElement(agenda, "GoalList")
    start = _start(orders, gaps)
    # AVCL starts with the first goal listed, so the start goal goes first.
    ordered = sorted(goals, key=lambda item: item[1].id != start)
    dangling: dict[str, str] = {}
    for index, goal in ordered:
        where = f"/goals/{index}"
        attributes = _goal_attributes(goal, where, ids, defined, dangling, gaps)
        element = ET.SubElement(goal_list, "Goal", attributes)
        _goal_content(orders, goal, where, element, head, gaps)
    for terminal in terminals:
        ET.SubElement(goal_list, "Goal", {
            "id": ids(terminal.id), "title": terminal.label,
            "description": TERMINAL_DESCRIPTIONS[terminal.kind],
        })
    for target, named_by in dangling.items():
        # An IDREF must name an element of the document; an empty OperatingArea outside the
        # GoalList holds the id, so the file validates and the successor still names no goal.
        ET.SubElement(body, "OperatingArea", {
            "id": ids(target),
            "description": f"{target}: named as a successor by {named_by}, but no goal or "
                           "terminal of the orders has this id"})
        gaps.append(Gap("DANGLING", "/goals", f"successor {target} (of {named_by}) is no goal "
                        "or terminal: written as an id with no Goal"))
    if ids.renamed:
        _meta(head, IDS_META, json.dumps({xml: ours for ours, xml in ids.renamed.items()},
                                         separators=(",", ":")))
        gaps.append(Gap("ID", "/goals", "ids that are not XML names are written as "
                        + ", ".join(f"{xml} ({ours})" for ours, xml in ids.renamed.items())
                        + f"; the {IDS_META} meta maps them back"))
    ET.indent(root)
    text = '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, "unicode") + "\n"
    return AvclDocument(text, gaps)


def _head(orders: Orders, root: ET.Element) -> ET.Element:
    """The document's head: title, description, generator and the orders' charts."""
    head = ET.SubElement(root, "head")
    _meta(head, "title", f"{orders.id}.xml")
    if orders.title:
        _meta(head, "description", orders.title)
    _meta(head, "generator", "Countersign")
    for chart in orders.charts:
        _meta(head, CHART_META, json.dumps(chart.model_dump(mode="json", exclude_unset=True),
                                           ensure_ascii=False, separators=(",", ":")))
    return head


def _goal_attributes(goal: Goal, where: str, ids: _Ids, defined: set[str],
                     dangling: dict[str, str], gaps: list[Gap]) -> dict[str, str]:
    """A Goal element's attributes: id, title, description, phase and one successor per
    outcome (what AVCL cannot say is a gap; a successor that names nothing is `dangling`)."""
    attributes = {"id": ids(goal.id), "title": goal.title or goal.id}
    if goal.description:
        attributes["description"] = goal.description
    phase = goal.params.get("phase")
    if isinstance(phase, str) and phase:
        attributes["phase"] = phase
    for outcome, attribute in HANDLERS:
        targets = goal.successors(outcome)
        if not targets:
            # The NPS readers fill in a missing handler from the others, and take a goal
            # with none at all for a terminal goal.
            gaps.append(Gap("MISSING", f"{where}/next/{outcome}",
                            f"goal {goal.id} names no {outcome} successor; AVCL readers "
                            "apply the NPS defaults (no successor at all: a terminal)"))
            continue
        if len(targets) > 1:
            gaps.append(Gap("CHOICE", f"{where}/next/{outcome}",
                            f"goal {goal.id}: AVCL names one successor per outcome; "
                            f"{targets[0]} is written, {', '.join(targets[1:])} is not"))
        if targets[0] not in defined:
            dangling.setdefault(targets[0], goal.id)
        attributes[attribute] = ids(targets[0])
    return attributes


def _meta(head: ET.Element, name: str, content: str) -> None:
    ET.SubElement(head, "meta", {"name": name, "content": content})


def _unique_elements(orders: Orders, gaps: list[Gap]) -> tuple[list[tuple[int, Goal]],
                                                                 list[Terminal]]:
    """Goals (with their index) and terminals whose id is not used before: xsd:ID values are
    unique in a document, and the first definition is the one the checks see."""
    first = orders.goal_index()
    goals: list[tuple[int, Goal]] = []
    for index, goal in enumerate(orders.goals):
        if first[goal.id] is goal:
            goals.append((index, goal))
        else:
            gaps.append(Gap("DUP", f"/goals/{index}", f"goal id {goal.id} is used before; "
                            "this goal is not written"))
    terminals: list[Terminal] = []
    for index, terminal in enumerate(orders.effective_terminals):
        if terminal.id in first or any(t.id == terminal.id for t in terminals):
            gaps.append(Gap("DUP", f"/terminals/{index}", f"terminal id {terminal.id} is used "
                            "before; this terminal is not written"))
            continue
        terminals.append(terminal)
    return goals, terminals


def _start(orders: Orders, gaps: list[Gap]) -> str | None:
    if isinstance(orders.start, list):
        if len(orders.start) > 1:
            gaps.append(Gap("START", "/start", "AVCL starts with its first goal: "
                            f"{orders.start[0]} starts, {', '.join(orders.start[1:])} do not"))
        return orders.start[0] if orders.start else None
    return orders.start


def _vehicle(orders: Orders, head: ET.Element, body: ET.Element) -> None:
    vehicle = orders.target_vehicle()
    name = (vehicle.title or vehicle.id) if vehicle else orders.vehicle
    if name:
        _meta(head, VEHICLE_NAME_META, name)
    kind = (vehicle.model_extra or {}).get("vehicle_type") if vehicle else None
    if isinstance(kind, str) and kind:
        _meta(head, VEHICLE_TYPE_META, kind)
        if kind.upper() in VEHICLE_TYPES:
            ET.SubElement(body, "Vehicle", {"vehicleType": kind.upper()})


def _goal_content(orders: Orders, goal: Goal, where: str, element: ET.Element,
                  head: ET.Element, gaps: list[Gap]) -> None:
    """The goal action, operating area and duration, in the order agendaGoalElementType asks."""
    phase = goal.params.get("phase")
    carried = {"phase"} if isinstance(phase, str) and phase else set()
    if goal.behavior:
        name = GOAL_ACTIONS.get(goal.behavior.lower(), SPECIAL_GOAL)
        action = ET.SubElement(element, name)
        if name == SPECIAL_GOAL and goal.behavior.lower() not in GOAL_ACTIONS:
            gaps.append(Gap("BEHAVIOR", f"{where}/behavior", f"goal {goal.id}: behaviour "
                            f"{goal.behavior!r} is no AVCL goal action; written as SpecialGoal"))
        if element_behavior(name) != goal.behavior:
            _meta(head, BEHAVIOR_META, f"{goal.id} {goal.behavior}")
        pd = goal.params.get("pd")
        if name == "Search" and isinstance(pd, int | float) and not isinstance(pd, bool) and \
                _PD_RANGE[0] <= pd <= _PD_RANGE[1]:
            action.set("requiredPD", f"{pd:g}")
            carried.add("pd")
    for key in sorted(set(goal.params) - carried):
        gaps.append(Gap("PARAMS", f"{where}/params/{key}", f"goal {goal.id}: parameter {key} "
                        "has no AVCL form; not written"))
    area = orders.area_index().get(goal.area) if goal.area else None
    if area is not None and len(area.polygon) >= 3:
        operating = ET.SubElement(element, "OperatingArea",
                                  {"description": area.title or area.id})
        polygon = ET.SubElement(operating, "Polygon")
        for lat, lon in area.polygon:
            ET.SubElement(polygon, "LatitudeLongitude",
                          {"latitude": repr(lat), "longitude": repr(lon)})
    elif goal.area:
        gaps.append(Gap("AREA", f"{where}/area", f"goal {goal.id}: area {goal.area} is no "
                        "polygon of three points or more; not written"))
    if goal.cost and goal.cost.duration_s is not None:
        ET.SubElement(element, "Duration", {"value": f"{goal.cost.duration_s:g}"})
