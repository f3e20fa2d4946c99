"""Read NPS AVCL mission XML (AVCL 3.0 and 3.1) as orders.

Both dialects are read: the NPS files' own (vehicleName on the root element and
MissionDefinition/AgendaMission, which most of them use though their schema does not allow it)
and schema-valid AVCL 3.1 as `write_avcl` writes it, with its head metas. The NPS tools' own
conventions (reference/nps-ethical-control/README.md) apply: the first Goal of the GoalList
starts the mission; a Goal without nextOnSuccess is a terminal goal; a missing nextOnFailure
means "same as nextOnSuccess" and a missing nextOnException "same as nextOnFailure". Every
default applied is reported as a SINK warning, so that nothing the orders leave unsaid is
hidden from the supervisor.

XML is parsed by defusedxml with DTDs, entity declarations and external references refused:
an XML bomb is rejected before any expansion.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import PurePath
from typing import Any
from xml.etree.ElementTree import Element, ParseError

from defusedxml import (
    DefusedXmlException,
    DTDForbidden,
    EntitiesForbidden,
    ExternalReferenceForbidden,
)
from defusedxml.ElementTree import fromstring
from pydantic import TypeAdapter, ValidationError

from .. import strict_json
from .avcl_writer import (
    BEHAVIOR_META,
    CHART_META,
    IDS_META,
    TERMINAL_DESCRIPTIONS,
    VEHICLE_NAME_META,
    VEHICLE_TYPE_META,
    element_behavior,
)
from .defaults import defaulted_findings
from .findings import Finding
from .model import MAX_ID_LENGTH, Id, Orders
from .reader import (
    MAX_PROBLEMS_SHOWN,
    OrdersReadError,
    Problem,
    ReadResult,
    problems_from_validation,
)

# Children of a Goal that describe how or where it runs rather than what it does.
NON_BEHAVIOR = frozenset(
    {
        "Risk",
        "OperatingArea",
        "ReportingCriteria",
        "Duration",
        "Timing",
        "Constraint",
        "ConstraintList",
        "LaunchPosition",
        "RecoveryPosition",
        "Description",
        "Metadata",
    }
)
_ABORT_WORDS = ("fail", "abort", "exception", "beacon", "await")
_COMPLETE_WORDS = ("success", "complete")
_ID_ADAPTER: TypeAdapter[str] = TypeAdapter(Id)
_DEGREES = re.compile(r"([NSEW])?\s*(\d+(?:\.\d+)?)\s*°\s*(\d+(?:\.\d+)?)?\s*'?\s*([NSEW])?")


@dataclass
class _AvclGoal:
    element: Element
    path: str
    id: str
    title: str
    description: str
    success: str | None
    failure: str | None
    exception: str | None

    @property
    def label(self) -> str:
        return f"{self.id} ({self.title})" if self.title else self.id


def read_avcl(data: bytes, name: str = "<input>") -> ReadResult:
    """Convert AVCL mission XML into orders plus the SINK warnings of the NPS defaults."""
    root = _parse(data)
    goal_list, list_path = _goal_list(root)
    problems: list[Problem] = []
    renamed = _renamed_ids(root, problems)
    raw = [
        _read_goal(element, f"{list_path}/Goal[{index}]", renamed, problems)
        for index, element in enumerate(_children(goal_list, "Goal"), start=1)
    ]
    if problems:
        raise OrdersReadError(problems[:MAX_PROBLEMS_SHOWN], total=len(problems))
    areas: list[dict[str, Any]] = []
    findings: list[Finding] = []
    goals, terminals = _goals_and_terminals(raw, areas, problems)
    if problems:
        raise OrdersReadError(problems[:MAX_PROBLEMS_SHOWN], total=len(problems))
    _named_behaviors(root, goals)

    meta = _meta(root)
    title = meta.get("title", "").strip()
    if title.lower().endswith(".xml"):
        title = title[:-4]
    title = title or PurePath(name).stem
    data_out: dict[str, Any] = {
        "id": _slug(title),
        "title": title,
        "description": meta.get("description", "").strip(),
        "start": raw[0].id if raw else None,
        "goals": goals,
        "terminals": terminals or None,
        "areas": areas,
    }
    charts = _charts(root, problems)
    if problems:
        raise OrdersReadError(problems[:MAX_PROBLEMS_SHOWN], total=len(problems))
    if charts:
        data_out["charts"] = charts
    _vehicle_data(root, meta, data_out)
    try:
        orders = Orders.model_validate(data_out)
    except ValidationError as exc:
        raise problems_from_validation(exc) from None
    return ReadResult(orders, [*findings, *defaulted_findings(orders)])


def _goal_list(root: Element) -> tuple[Element, str]:
    """The document's GoalList and its path; refused when this is no AVCL mission."""
    root_name = _local(root.tag)
    if root_name != "AVCL":
        message = f"the root element is <{root_name}>, not <AVCL>: this is not an AVCL mission"
        raise OrdersReadError([Problem(f"/{root_name}", message)])
    found = _find(root, "GoalList")
    if found is None:
        raise OrdersReadError(
            [Problem("/AVCL", "the AVCL document has no GoalList, so it orders no goals")]
        )
    return found


def _goals_and_terminals(raw: list[_AvclGoal], areas: list[dict[str, Any]],
                         problems: list[Problem]
                         ) -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
    """The goals' data and, for a goal with no successor at all, a terminal's (its kind
    from its title and whether a success reaches it)."""
    reached_on_success = {g.success for g in raw if g.success}
    goals: list[dict[str, Any]] = []
    terminals: list[dict[str, Any]] = []
    for goal in raw:
        if goal.success is None and goal.failure is None and goal.exception is None:
            kind = _terminal_kind(goal, goal.id in reached_on_success)
            terminals.append({"id": goal.id, "kind": kind, "title": goal.title})
            continue
        goals.append(_goal_data(goal, areas, problems))
        defaulted = _defaulted(goal)
        if defaulted:
            goals[-1]["defaulted"] = defaulted
    return goals, terminals


def _vehicle_data(root: Element, meta: dict[str, str], data_out: dict[str, Any]) -> None:
    """The vehicle the document names (attributes, or the metas the writer leaves)."""
    vehicle_name = (root.get("vehicleName") or meta.get(VEHICLE_NAME_META) or "").strip()
    if vehicle_name:
        vehicle: dict[str, Any] = {"id": _slug(vehicle_name), "title": vehicle_name}
        vehicle_type = root.get("vehicleType") or meta.get(VEHICLE_TYPE_META)
        if vehicle_type:
            vehicle["vehicle_type"] = vehicle_type
        data_out["vehicle"] = vehicle["id"]
        data_out["vehicles"] = [vehicle]


def _parse(data: bytes) -> Element:
    try:
        return fromstring(data, forbid_dtd=True, forbid_entities=True, forbid_external=True)
    except DTDForbidden:
        message = "the XML declares a DTD (<!DOCTYPE ...>); DTDs are refused for safety"
    except EntitiesForbidden:
        message = "the XML declares entities, which are refused (they allow XML bombs)"
    except ExternalReferenceForbidden:
        message = "the XML refers to external resources, which are refused"
    except DefusedXmlException as exc:
        message = f"the XML uses a refused construct: {exc}"
    except ParseError as exc:
        line, column = exc.position
        reason = str(exc).split(":", 1)[0]
        message = f"not well-formed XML at line {line}, column {column + 1}: {reason}"
    except (ValueError, RecursionError) as exc:
        message = f"unreadable XML: {exc}"
    raise OrdersReadError([Problem("$", message)])


def _local(tag: object) -> str:
    return tag.rsplit("}", 1)[-1] if isinstance(tag, str) else ""


def _children(element: Element, name: str) -> list[Element]:
    return [child for child in element if _local(child.tag) == name]


def _find(root: Element, name: str) -> tuple[Element, str] | None:
    """The first element with a local name in document order, with an XPath-ish path."""
    parents: dict[Element, Element] = {}
    for parent in root.iter():
        for child in parent:
            parents[child] = parent
    element = next((e for e in root.iter() if _local(e.tag) == name), None)
    if element is None:
        return None
    steps: list[str] = []
    node = element
    while node in parents:
        siblings = _children(parents[node], _local(node.tag))
        position = next(i for i, s in enumerate(siblings, 1) if s is node)
        steps.append(_local(node.tag) + (f"[{position}]" if len(siblings) > 1 else ""))
        node = parents[node]
    steps.append(_local(root.tag))
    return element, "/" + "/".join(reversed(steps))


def _attr(element: Element, name: str) -> str | None:
    value = (element.get(name) or "").strip()
    return value or None


def _check_id(value: str, path: str, problems: list[Problem]) -> None:
    try:
        _ID_ADAPTER.validate_python(value)
    except ValidationError as exc:
        reason = str(exc.errors(include_url=False)[0]["msg"]).removeprefix("Value error, ")
        problems.append(Problem(path, f"the AVCL id {value[:40]!r} cannot be used: {reason}"))


def _read_goal(element: Element, path: str, renamed: dict[str, str],
               problems: list[Problem]) -> _AvclGoal:
    goal_id = _attr(element, "id")
    if goal_id is not None:
        goal_id = renamed.get(goal_id, goal_id)
    if goal_id is None:
        problems.append(Problem(f"{path}/@id", "the Goal has no id"))
        goal_id = ""
    else:
        _check_id(goal_id, f"{path}/@id", problems)
    targets = {}
    for attribute in ("nextOnSuccess", "nextOnFailure", "nextOnException"):
        target = _attr(element, attribute)
        if target is not None:
            target = renamed.get(target, target)
            _check_id(target, f"{path}/@{attribute}", problems)
        targets[attribute] = target
    return _AvclGoal(
        element,
        path,
        goal_id,
        (element.get("title") or "").strip(),
        (element.get("description") or "").strip(),
        targets["nextOnSuccess"],
        targets["nextOnFailure"],
        targets["nextOnException"],
    )


def _terminal_kind(goal: _AvclGoal, reached_on_success: bool) -> str:
    for kind, description in TERMINAL_DESCRIPTIONS.items():
        if goal.description == description:  # written by write_avcl: no guessing
            return kind
    words = f"{goal.id} {goal.title} {goal.description}".lower()
    if any(word in words for word in _ABORT_WORDS):
        return "abort"
    if any(word in words for word in _COMPLETE_WORDS):
        return "complete"
    return "complete" if reached_on_success else "abort"


def _number(element: Element, attribute: str, path: str, problems: list[Problem]) -> float | None:
    text = _attr(element, attribute)
    if text is None:
        return None
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value) or value < 0:
        problems.append(Problem(f"{path}/@{attribute}", f"{text[:40]!r} is not a number >= 0"))
        return None
    return value


def _goal_data(
    goal: _AvclGoal, areas: list[dict[str, Any]], problems: list[Problem]
) -> dict[str, Any]:
    element, path = goal.element, goal.path
    behavior_element = next(
        (child for child in element if _local(child.tag) not in NON_BEHAVIOR and _local(child.tag)),
        None,
    )
    behavior = (element_behavior(_local(behavior_element.tag))
                if behavior_element is not None else None)
    params: dict[str, Any] = {}
    if _attr(element, "phase"):
        params["phase"] = _attr(element, "phase")
    if behavior_element is not None and _local(behavior_element.tag) == "Search":
        step = f"{path}/Search"
        pd = _number(behavior_element, "requiredPD", step, problems)
        if pd is not None:
            params["pd"] = pd
    data: dict[str, Any] = {
        "id": goal.id,
        "title": goal.title,
        "description": goal.description,
        "behavior": behavior,
        # AVCL declares no goal requirements; inventing them would make every goal an M7
        # finding against an AVCL vehicle, which lists no features either.
        "params": params,
    }
    durations = _children(element, "Duration")
    if durations:
        seconds = _number(durations[0], "value", f"{path}/Duration", problems)
        if seconds is not None:
            data["cost"] = {"duration_s": seconds}
    area = _area(goal)
    if area is not None:
        areas.append(area)
        data["area"] = area["id"]
    success = goal.success
    failure = goal.failure or success
    exception = goal.exception or failure
    handlers = {"succeed": success, "fail": failure, "violate": exception}
    # A handler still missing after the defaults stays absent: the structure check reports it.
    data["next"] = {outcome: target for outcome, target in handlers.items() if target}
    return data


def _defaulted(goal: _AvclGoal) -> dict[str, str]:
    """Which outcomes the NPS convention filled in, and the outcome each is handled like; the
    SINK warnings are derived from this record (orders.defaults)."""
    record: dict[str, str] = {}
    if goal.failure is None and goal.success is not None:
        record["fail"] = "succeed"
    if goal.exception is None and (goal.failure or goal.success) is not None:
        record["violate"] = "fail" if goal.failure is not None else "succeed"
    return record


def _coordinate(text: str | None, positive: str) -> float | None:
    if text is None:
        return None
    try:
        return float(text)
    except ValueError:
        pass
    match = _DEGREES.fullmatch(text.strip())
    if match is None:
        return None
    value = float(match[2]) + float(match[3] or 0) / 60
    hemisphere = match[1] or match[4] or positive
    return value if hemisphere == positive else -value


def _area(goal: _AvclGoal) -> dict[str, Any] | None:
    """A goal's own OperatingArea as a polygon, when it lists at least three points."""
    operating = _children(goal.element, "OperatingArea")
    if not operating:
        return None
    points: list[tuple[float, float]] = []
    for point in operating[0].iter():
        if _local(point.tag) != "LatitudeLongitude":
            continue
        lat = _coordinate(point.get("latitude"), "N")
        lon = _coordinate(point.get("longitude"), "E")
        if lat is None or lon is None or not (-90 <= lat <= 90 and -180 <= lon <= 180):
            return None
        points.append((lat, lon))
    if len(points) < 3:
        return None
    title = operating[0].get("description") or operating[0].get("id") or f"{goal.title} area"
    return {"id": f"{goal.id}-area", "title": title.strip(), "polygon": points}


def _meta(root: Element) -> dict[str, str]:
    meta: dict[str, str] = {}
    for head in _children(root, "head"):
        for element in _children(head, "meta"):
            name, content = element.get("name"), element.get("content")
            if name and content is not None:
                meta.setdefault(name, content)
    return meta


def _metas(root: Element, name: str) -> list[tuple[int, str]]:
    """Every head meta of a name, with its position among the head's metas."""
    return [(index, element.get("content") or "")
            for head in _children(root, "head")
            for index, element in enumerate(_children(head, "meta"), start=1)
            if element.get("name") == name]


def _renamed_ids(root: Element, problems: list[Problem]) -> dict[str, str]:
    """The `countersign:ids` map (XML id -> orders id) of ids that are not XML names."""
    renamed: dict[str, str] = {}
    for index, content in _metas(root, IDS_META):
        try:
            found = strict_json.loads(content)
        except ValueError as exc:
            found = exc
        if not isinstance(found, dict) or not all(
                isinstance(k, str) and isinstance(v, str) for k, v in found.items()):
            problems.append(Problem(f"/AVCL/head/meta[{index}]",
                                    "the id map is not a JSON object of strings"))
            continue
        renamed.update(found)
    return renamed


def _named_behaviors(root: Element, goals: list[dict[str, Any]]) -> None:
    """Behaviours named by `countersign:behavior` metas win over the goal action element."""
    named = dict(content.split(" ", 1) for _, content in _metas(root, BEHAVIOR_META)
                 if " " in content)
    for goal in goals:
        if goal["id"] in named:
            goal["behavior"] = named[goal["id"]]


def _charts(root: Element, problems: list[Problem]) -> list[Any]:
    """The charts written by `write_avcl`: each `<meta name="countersign:chart">` holds one
    chart as JSON (checked with the orders' own model afterwards)."""
    charts: list[Any] = []
    for index, content in _metas(root, CHART_META):
        try:
            charts.append(strict_json.loads(content))
        except ValueError as exc:
            problems.append(Problem(f"/AVCL/head/meta[{index}]", f"the chart is not JSON: {exc}"))
    return charts


def _slug(text: str) -> str:
    slug = re.sub(r"[^A-Za-z0-9_.:-]", "-", text.strip().lower()).lstrip(".:-")
    return slug[:MAX_ID_LENGTH].rstrip(".:-") or "avcl-mission"
