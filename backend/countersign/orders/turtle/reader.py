"""Turtle -> orders (`read_turtle`): our vocabulary losslessly, NPS MEO Turtle by its
conventions; the meaning wins over the record where they disagree."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Final

from pydantic import ValidationError
from rdflib import BNode, Literal, URIRef
from rdflib.namespace import RDF, RDFS
from rdflib.term import Node

from ... import strict_json
from ..findings import Finding
from ..model import Orders
from ..rdf_index import TripleIndex, TurtleSyntaxError, parse_turtle, paused_collection
from ..reader import OrdersReadError, Problem, ReadResult, problems_from_validation
from .alignment import _align
from .typing_rules import typing_findings
from .vocabulary import (
    _BOOLEAN,
    _CS_ID,
    _ELEMENT_LISTS,
    _ENTRY,
    _FIRST,
    _FLOAT_TYPES,
    _INT_TYPES,
    _KEY,
    _KEY_PREFIX,
    _MAP,
    _NIL,
    _NULL,
    _RDF_JSON,
    _REST,
    _TYPE,
    CS,
    MEO,
    NEXT_PROPERTIES,
    OUTCOME_PROPERTY,
    _json_scalar,
    local_id,
    natural_key,
)


def read_turtle(data: bytes, name: str = "<input>") -> ReadResult:
    """Orders from Turtle in our vocabulary (lossless) or NPS MEO Turtle (by its conventions)."""
    graph = _parse(data, name)
    _align(graph)
    try:
        with paused_collection():
            return _read(graph, name)
    except RecursionError:
        raise OrdersReadError([Problem("$", f"{name} is nested too deeply")]) from None


def _read(graph: TripleIndex, name: str) -> ReadResult:
    findings = typing_findings(graph)
    result = _Reader(graph, name).read()
    return ReadResult(result.orders, findings + result.findings)


def _parse(data: bytes, name: str) -> TripleIndex:
    try:
        data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise OrdersReadError([Problem("$", f"not UTF-8 text (byte {exc.start})")]) from None
    try:
        graph = parse_turtle(data.removeprefix(b"\xef\xbb\xbf"))
    except TurtleSyntaxError as exc:
        where = f" at line {exc.line}" if exc.line is not None else ""
        raise OrdersReadError([Problem("$", f"invalid Turtle{where}: {exc.reason}")]) from None
    if len(graph) == 0:
        raise OrdersReadError([Problem("$", f"{name} holds no RDF statements")])
    return graph


def _json_list(text: str, name: str) -> list[Any]:
    try:
        value = strict_json.loads(text)
    except ValueError:
        value = None
    if not isinstance(value, list) or not all(_json_scalar(item) for item in value):
        raise OrdersReadError([Problem("$", f"{name} holds an rdf:JSON value of the record "
                                            "that is not a list of strings, numbers, booleans "
                                            "or nulls")])
    return value

MAX_DEPTH: Final = 64
MAX_LIST_ITEMS: Final = 200_000
# A document whose values share no list decodes about one value per statement; a few times
# that (a node read twice, small documents) is allowed, more means expanding shared structure.
DECODE_FACTOR: Final = 4
DECODE_SLACK: Final = 10_000



@dataclass
class _Reader:
    graph: TripleIndex
    name: str
    findings: list[Finding] = field(default_factory=list)
    _goal_ids: set[str] | None = None
    # Values decoded so far. A list or map shared by several uses is decoded at each of them,
    # so nested sharing expands exponentially: the budget keeps the work linear in the input.
    decodes: int = 0
    _decode_budget: int | None = None

    # -- the record

    def decode(self, node: Node, depth: int = 0) -> Any:
        graph = self.graph
        self.decodes += 1
        if self._decode_budget is None:
            self._decode_budget = DECODE_FACTOR * len(graph) + DECODE_SLACK
        if self.decodes > self._decode_budget:
            raise OrdersReadError(
                [Problem("$", f"{self.name} shares RDF lists or maps so that its values expand "
                         "to far more than its statements")]
            )
        if depth > MAX_DEPTH:
            raise OrdersReadError(
                [Problem("$", f"{self.name} nests values more than {MAX_DEPTH} levels deep")]
            )
        if isinstance(node, Literal):
            datatype = node.datatype
            if datatype == _RDF_JSON:
                return _json_list(str(node), self.name)
            if datatype in _FLOAT_TYPES:
                return float(str(node))
            if datatype in _INT_TYPES:
                return int(str(node))
            if datatype == _BOOLEAN:
                return str(node).strip().lower() in ("true", "1")
            return str(node)
        if node == _NULL:
            return None
        properties = graph.properties(node)
        if node == _NIL or _FIRST in properties:
            return [self.decode(item, depth + 1) for item in self.items(node)]
        mapped: dict[str, Any] | None = None
        if _MAP in properties.get(_TYPE, ()):
            mapped = {
                str(graph.value(entry, _KEY)): self.decode(_value(graph, entry), depth + 1)
                for entry in graph.objects(node, _ENTRY)
            }
        for predicate, objects in list(properties.items()):
            name = str(predicate)
            if objects and name.startswith(_KEY_PREFIX):
                if mapped is None:
                    mapped = {}
                mapped[name[len(_KEY_PREFIX):]] = self.decode(next(iter(objects)), depth + 1)
        return str(node) if mapped is None else mapped

    def has_record(self, node: Node) -> bool:
        return _CS_ID in self.graph.properties(node)

    def record(self, node: Node) -> dict[str, Any]:
        """The fields written for one node (empty when it has no record)."""
        data: dict[str, Any] = {}
        prefix = str(CS)
        for p, o in self.graph.predicate_objects(node):
            if not isinstance(p, URIRef) or not str(p).startswith(prefix):
                continue
            key = str(p)[len(prefix):]
            if key == "extra":
                data[str(self.graph.value(o, CS.key))] = self.decode(_value(self.graph, o))
            elif key not in ("implicit", "features") and key not in _ELEMENT_LISTS:
                data[key] = self.decode(o)
        return data

    def plain(self, node: Node) -> dict[str, Any]:
        """A record-only element (a repeated id): its fields, and its features if a vehicle."""
        data = self.record(node)
        features = self.graph.value(node, CS.features)
        if features is not None:
            data["features"] = [self.plain(f) for f in self.items(features)]
        return data

    def items(self, head: Node) -> list[Node]:
        """The members of an RDF list, refusing a list that loops or never ends."""
        members: list[Node] = []
        seen: set[Node] = set()
        node: Node | None = head
        while node is not None and node != _NIL:
            if node in seen or len(members) >= MAX_LIST_ITEMS:
                raise OrdersReadError(
                    [Problem("$", f"{self.name} holds an RDF list that loops or is too long")]
                )
            seen.add(node)
            first = self.graph.value(node, _FIRST)
            if first is None:
                break
            members.append(first)
            node = self.graph.value(node, _REST)
        return members

    def ordered(self, owner: Node, key: str, members: list[Node]) -> list[Node]:
        """Members in the order of the record's list, then any others by natural id order;
        blank nodes of the record (repeated ids) keep their place."""
        listed = self.graph.value(owner, CS[key])
        in_record = self.items(listed) if listed is not None else []
        member_set = set(members)
        result = [n for n in in_record if n in member_set or isinstance(n, BNode)]
        rest = sorted(member_set - set(result), key=lambda n: natural_key(self.element_id(n)))
        return result + rest

    def listed(self, owner: Node, key: str) -> bool:
        return self.graph.value(owner, CS[key]) is not None

    # -- reading

    def read(self) -> ReadResult:
        graph = self.graph
        mission = self.mission()
        data = self.record(mission)
        data["id"] = data.get("id") or local_id(mission)
        mission_id = str(data["id"])
        ours = self.has_record(mission) or any(graph.triples((None, RDF.type, MEO.Terminal)))
        goals, terminals = self.goals_and_terminals(mission, ours)
        names = {t: self.element_id(t) for t in terminals}
        names.update({g: self.element_id(g) for g in goals})

        def elements(key: str, members: list[Node], read: Callable[[Node], dict[str, Any]]
                     ) -> None:
            nodes = self.ordered(mission, key, members)
            if nodes or self.listed(mission, key):
                data[key] = [self.plain(n) if isinstance(n, BNode) else read(n) for n in nodes]

        elements("goals", goals, lambda n: self.goal(n, names))
        implicit = all((t, CS.implicit, Literal(True)) in graph for t in terminals)
        if implicit and graph.value(mission, CS.terminals) == CS.null:
            data["terminals"] = None
        elif self.listed(mission, "terminals") or not implicit:
            elements("terminals", terminals, self.terminal)
        start = self.start(mission, data.get("start", _ABSENT), names)
        data.pop("start", None)
        if start is not _ABSENT:
            data["start"] = start
        constraints = self.constraints(mission)
        elements("constraints", constraints, lambda n: self.constraint(n, mission, names,
                                                                       mission_id))
        vehicles = self.members(MEO.Vehicle, (mission, MEO.performableBy))
        elements("vehicles", vehicles, self.vehicle)
        for key in ("norms", "areas", "properties"):
            listed = graph.value(mission, CS[key])
            if listed is not None:
                data[key] = [self.plain(node) for node in self.items(listed)]
        self.performer(mission, data)
        if not self.has_record(mission):
            data.setdefault("title", mission_id)
            comment = graph.value(mission, RDFS.comment)
            if comment is not None and str(comment).strip():
                data.setdefault("description", str(comment).strip())
        try:
            orders = Orders.model_validate(data)
        except ValidationError as exc:
            raise problems_from_validation(exc) from None
        return ReadResult(orders, self.findings)

    def mission(self) -> Node:
        graph = self.graph
        candidates: dict[Node, None] = dict.fromkeys(graph.subjects(RDF.type, MEO.Mission))
        for prop in (MEO.startsWith, MEO.includes, MEO.hasConstraint, MEO.performableBy):
            candidates.update(dict.fromkeys(graph.subjects(prop, None)))
        missions = list(candidates)
        if not missions:
            raise OrdersReadError(
                [Problem("$", f"{self.name} describes no mission: no meo:Mission individual "
                              "and nothing that starts with or includes a goal")]
            )
        if len(missions) > 1:
            listed = ", ".join(sorted(local_id(m) for m in missions)[:5])
            raise OrdersReadError(
                [Problem("$", f"{self.name} describes {len(missions)} missions ({listed}); "
                              "read one mission per file")]
            )
        return missions[0]

    def members(self, cls: URIRef, link: tuple[Node, URIRef]) -> list[Node]:
        found: dict[Node, None] = dict.fromkeys(self.graph.subjects(RDF.type, cls))
        for node in self.graph.objects(*link):
            if _declared(self.graph, node):
                found[node] = None
        return list(found)

    def constraints(self, mission: Node) -> list[Node]:
        found = dict.fromkeys(self.members(MEO.Constraint, (mission, MEO.hasConstraint)))
        found.update(dict.fromkeys(self.graph.subjects(MEO.appliesTo, None)))
        return list(found)

    def goals_and_terminals(self, mission: Node, ours: bool) -> tuple[list[Node], list[Node]]:
        graph = self.graph
        if ours:
            terminals = list(dict.fromkeys(graph.subjects(RDF.type, MEO.Terminal)))
            terminal_set = set(terminals)
            found = dict.fromkeys(
                g for g in graph.subjects(RDF.type, MEO.Goal) if g not in terminal_set
            )
            found.update(
                dict.fromkeys(
                    g for g in graph.objects(mission, MEO.includes)
                    if g not in terminal_set and _declared(graph, g)
                )
            )
            return list(found), terminals
        # The NPS convention: a goal without successors is a terminal; a name that nothing
        # describes is neither (the structural check reports it as G3 or M1).
        nodes: dict[Node, None] = dict.fromkeys(graph.subjects(RDF.type, MEO.Goal))
        for prop in NEXT_PROPERTIES:
            for s, o in graph.subject_objects(prop):
                nodes[s] = None
                if _declared(graph, o):
                    nodes[o] = None
        for prop in (MEO.startsWith, MEO.includes):
            for o in graph.objects(mission, prop):
                if _declared(graph, o):
                    nodes[o] = None
        goals = [n for n in nodes if any(True for p in NEXT_PROPERTIES
                                         for _ in graph.objects(n, p))]
        goal_set = set(goals)
        return goals, [n for n in nodes if n not in goal_set]

    def element_id(self, node: Node) -> str:
        recorded = self.graph.value(node, _CS_ID)
        return str(recorded) if recorded is not None else local_id(node)

    def name_of(self, node: Node, names: dict[Node, str]) -> str:
        return names.get(node) or self.element_id(node)

    def describe(self, node: Node, data: dict[str, Any]) -> None:
        """Title and description from rdfs:label / rdfs:comment for an element without a
        record (NPS: comment "Title: description")."""
        if self.has_record(node):
            return
        label = self.graph.value(node, RDFS.label)
        comment = self.graph.value(node, RDFS.comment)
        if label is not None:
            data["title"] = str(label).strip()
            if comment is not None and str(comment).strip():
                data["description"] = str(comment).strip()
        elif comment is not None:
            title, sep, description = str(comment).partition(": ")
            data["title"] = title.strip()
            if sep and description.strip():
                data["description"] = description.strip()

    def goal(self, node: Node, names: dict[Node, str]) -> dict[str, Any]:
        """A goal: its record, with successors, requirements and phase from the meaning."""
        graph = self.graph
        data = self.record(node)
        data["id"] = self.element_id(node)
        self.describe(node, data)
        written_next = data.get("next")
        next_data: dict[str, Any] = dict(written_next) if isinstance(written_next, dict) else {}
        for outcome, prop in OUTCOME_PROPERTY.items():
            meaning = [self.name_of(t, names) for t in graph.objects(node, prop)]
            written = next_data.get(outcome)
            listed = [] if written is None else [written] if isinstance(written, str) else written
            if set(listed) == set(meaning):
                continue
            ordered = _ordered_union(listed, meaning)
            if not ordered:
                next_data.pop(outcome, None)
            else:
                next_data[outcome] = ordered[0] if len(ordered) == 1 else ordered
        if next_data or isinstance(written_next, dict):
            data["next"] = next_data
        meaning = [self.element_id(r) for r in graph.objects(node, MEO.requires)]
        written_requires = data.get("requires")
        written_list = written_requires if isinstance(written_requires, list) else []
        if set(written_list) != set(meaning) or (meaning and written_requires is None):
            data["requires"] = _ordered_union(written_list, meaning)
        phase = graph.value(node, MEO.isPartOfPhase)
        params = data.get("params") if isinstance(data.get("params"), dict) else None
        written_phase = params.get("phase") if params is not None else None
        if phase is not None and str(phase) not in ("'undefined'", written_phase):
            data["params"] = {**(params or {}), "phase": str(phase)}
        return data

    def terminal(self, node: Node) -> dict[str, Any]:
        data = self.record(node)
        data["id"] = self.element_id(node)
        self.describe(node, data)
        if "kind" not in data:
            data["kind"] = self.terminal_kind(node, data)
        return data

    def terminal_kind(self, node: Node, data: dict[str, Any]) -> str:
        """The NPS wording convention (as for AVCL): abort words, complete words, else how the
        terminal is reached."""
        words = " ".join(
            [data["id"], str(data.get("title", "")), str(data.get("description", ""))]
        ).lower()
        if any(w in words for w in ("fail", "abort", "exception", "beacon", "await")):
            return "abort"
        if any(w in words for w in ("success", "complete")):
            return "complete"
        reached_on_success = any(True for _ in self.graph.subjects(MEO.isNextOnSucceed, node))
        return "complete" if reached_on_success else "abort"

    def start(self, mission: Node, written: Any, names: dict[Node, str]) -> Any:
        meaning = [self.name_of(s, names) for s in self.graph.objects(mission, MEO.startsWith)]
        if written is _ABSENT or written is None:
            listed: list[str] = []
        elif isinstance(written, str):
            listed = [written]
        else:
            listed = list(written)
        if set(listed) == set(meaning):
            return written
        ordered = _ordered_union(listed, meaning)
        if not ordered:
            return _ABSENT if written is _ABSENT else None
        return ordered[0] if len(ordered) == 1 else ordered

    def constraint(
        self, node: Node, mission: Node, names: dict[Node, str], mission_id: str
    ) -> dict[str, Any]:
        graph = self.graph
        data = self.record(node)
        data["id"] = self.element_id(node)
        if not self.has_record(node):
            comment = graph.value(node, RDFS.comment) or graph.value(node, RDFS.label)
            if comment is not None:
                data["text"] = str(comment).strip()
        meaning = {
            "mission" if s == mission else self.name_of(s, names)
            for s in graph.objects(node, MEO.appliesTo)
        }
        written = data.get("applies_to", "mission")
        if written == "mission":
            written_meaning = {"mission"}
        else:
            goal_ids = self.goal_ids(names)
            written_meaning = {
                "mission" if (n == mission_id and n not in goal_ids) else n
                for n in (written if isinstance(written, list) else [])
            }
        if written_meaning != meaning:
            if meaning == {"mission"}:
                data["applies_to"] = "mission"
            else:
                listed = written if isinstance(written, list) else []
                data["applies_to"] = _ordered_union(
                    listed, [mission_id if m == "mission" else m for m in meaning]
                )
        return data

    def goal_ids(self, names: dict[Node, str]) -> set[str]:
        if self._goal_ids is None:
            self._goal_ids = set(names.values())
        return self._goal_ids

    def vehicle(self, node: Node) -> dict[str, Any]:
        graph = self.graph
        data = self.record(node)
        data["id"] = self.element_id(node)
        if not self.has_record(node):
            label = graph.value(node, RDFS.label)
            if label is not None and str(label) != data["id"]:
                data["title"] = str(label)
        features = list(graph.objects(node, MEO.hasFeature))
        if features or graph.value(node, CS.features) is not None:
            data["features"] = [
                self.plain(f) if isinstance(f, BNode) else self.feature(f)
                for f in self.ordered(node, "features", features)
            ]
        return data

    def feature(self, node: Node) -> dict[str, Any]:
        graph = self.graph
        data = self.record(node)
        data["id"] = self.element_id(node)
        for key, prop in (("fulfills", MEO.canFulfill), ("measures", MEO.measures)):
            meaning = [self.element_id(o) for o in graph.objects(node, prop)]
            written = data.get(key)
            listed = written if isinstance(written, list) else []
            if set(listed) != set(meaning) or (meaning and written is None):
                data[key] = _ordered_union(listed, meaning)
        # An asserted canTest is kept when no record says otherwise (our own records derive it
        # from the measures, so copying it there would change the orders on a round trip).
        tested = sorted((self.element_id(o) for o in graph.objects(node, MEO.canTest)),
                        key=natural_key)
        if tested and not self.has_record(node):
            data["tests"] = tested
        return data

    def performer(self, mission: Node, data: dict[str, Any]) -> None:
        """`vehicle`: the vehicle the mission is performable by, where the record says another."""
        performer = self.graph.value(mission, MEO.performableBy)
        if performer is None:
            return
        performer_id = self.element_id(performer)
        written = data.get("vehicle")
        vehicles = data.get("vehicles") or []
        implied = (
            written if written is not None
            else vehicles[0].get("id") if len(vehicles) == 1 and isinstance(vehicles[0], dict)
            else None
        )
        if implied != performer_id:
            data["vehicle"] = performer_id


class _Absent:
    def __repr__(self) -> str:
        return "<absent>"


_ABSENT: Final = _Absent()


def _declared(graph: TripleIndex, node: Node) -> bool:
    """Something the graph says anything about (not merely a name used as an object)."""
    return any(True for _ in graph.predicate_objects(node))


def _value(graph: TripleIndex, entry: Node) -> Node:
    value = graph.value(entry, CS.value)
    return CS.null if value is None else value


def _ordered_union(written: list[str], meaning: list[str]) -> list[str]:
    """The meaning's members, in the written order where written, then in natural order."""
    wanted = set(meaning)
    result = list(dict.fromkeys(x for x in written if x in wanted))
    rest = sorted(wanted - set(result), key=natural_key)
    return result + rest


