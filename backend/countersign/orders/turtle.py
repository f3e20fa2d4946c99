"""Orders as RDF: the Mission Execution Ontology graph, Turtle in our vocabulary (lossless), an
NPS MEO 3.0 view, and import of NPS MEO Turtle (converted missions, CanonicalMission.ttl).

Two layers of triples describe one set of orders:

- **Meaning** (`meo:`, ontology/meo.ttl): the mission, its goals and terminals, start, successors
  per end condition, requirements, constraints and their scope, the vehicle, its features, what
  they fulfil and measure. Verification (`countersign.verify.meo`) reads only this layer.
- **Record** (`cs:`): how the author wrote the orders, field by field (titles, envelopes, params,
  areas, norms, list order, explicit defaults, unknown fields), so that Turtle written here reads
  back to orders with the same digest. A map is a blank node with one `key:` property per
  entry (`key:succeed "G2"`); a map with a key that is not a name, or an empty one, is a
  `cs:Map` of `cs:entry [cs:key; cs:value]` nodes, the form every map had before (still read).

Reading trusts the meaning over the record: where someone edited the `meo:` triples (say, in
Protégé) and the record disagrees, the meaning wins and the record only keeps its order.

IRIs are stable per mission id and element: the mission is
`https://countersign.example/mission/{id}`, its elements `{mission}/{kind}#{element id}`
(kinds: goal, terminal, constraint, requirement, quantity, vehicle, area, norm, property; `ref`
for a name that is none of the orders' elements, e.g. an unknown successor) and a vehicle's
features `{mission}/vehicle/{vehicle id}/feature#{feature id}`. Ids are restricted to
`[A-Za-z0-9_.:-]`, so they need no escaping. A second element with an id already used (a DUP
finding) is kept as a blank node in the record only: the meaning, like the structural check,
sees the first.

NPS Turtle is recognised by its namespaces and renamed to `meo:` with
ontology/nps-meo3-alignment.ttl; the NPS conventions then apply (a goal without successors is a
terminal, complete or abort by its wording; `rdfs:comment` "Title: description").

RDF can say things orders cannot, e.g. that a goal requires a Constraint: such statements
contradict a domain or range of meo.ttl, and the reader reports them as findings whose code is
the violated rule (`typing_findings`).

The quantities a constraint reads are the quantity names of its expression, read with the one
expression parser (`orders.expressions`); a feature can test a constraint (F2, V4) when it
measures every one of them.
"""

from __future__ import annotations

import functools
import itertools
import json
import math
import re
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field
from decimal import Decimal
from typing import Any, Final, TypeVar

from pydantic import ValidationError
from rdflib import BNode, Graph, Literal, Namespace, URIRef
from rdflib.collection import Collection
from rdflib.namespace import OWL, RDF, RDFS, XSD
from rdflib.term import Node

from .. import strict_json
from ..ontology_files import MEO as MEO_FILE
from ..ontology_files import NPS_ALIGNMENT, load_graph
from .canonical import orders_to_json
from .expressions import expression_quantities
from .findings import Finding, error
from .model import Orders
from .rdf_index import TripleIndex, TurtleSyntaxError, parse_turtle, paused_collection
from .reader import OrdersReadError, Problem, ReadResult, problems_from_validation
from .turtle_writer import TripleSet, serialize_turtle

MEO: Final = Namespace("https://countersign.example/ontology/meo#")
CS: Final = Namespace("https://countersign.example/ontology/orders#")
# A record map's keys as properties (`[ key:succeed "G2" ; key:fail "ABORT" ]`): 1 statement
# per entry instead of the 3 of a cs:entry node (issue 22). Keys that are not names keep the
# cs:entry form, which the reader also takes.
CS_KEY: Final = Namespace("https://countersign.example/ontology/orders/key#")
MISSION_BASE: Final = "https://countersign.example/mission/"
NPS3: Final = Namespace("https://savage.nps.edu/EthicalControl/ontologies/MissionExecutionOntology#")

OUTCOME_PROPERTY: Final = {
    "succeed": MEO.isNextOnSucceed,
    "fail": MEO.isNextOnFail,
    "violate": MEO.isNextOnViolate,
}
NEXT_PROPERTIES: Final = tuple(OUTCOME_PROPERTY.values())

# Fields holding lists of elements that get their own nodes (and IRIs).
_ELEMENT_LISTS: Final = {
    "goals": "goal",
    "terminals": "terminal",
    "constraints": "constraint",
    "norms": "norm",
    "areas": "area",
    "vehicles": "vehicle",
    "properties": "property",
}

# --------------------------------------------------------------------------------------------
# IRIs


@dataclass(frozen=True)
class MissionIris:
    mission_id: str

    @property
    def mission(self) -> URIRef:
        return URIRef(MISSION_BASE + self.mission_id)

    def element(self, kind: str, element_id: str) -> URIRef:
        return URIRef(f"{MISSION_BASE}{self.mission_id}/{kind}#{element_id}")

    def feature(self, vehicle_id: str, feature_id: str) -> URIRef:
        return URIRef(f"{MISSION_BASE}{self.mission_id}/vehicle/{vehicle_id}/feature#{feature_id}")

    def namespaces(self) -> dict[str, str]:
        base = f"{MISSION_BASE}{self.mission_id}"
        kinds = ("goal", "terminal", "constraint", "requirement", "quantity", "vehicle", "ref")
        return {kind: f"{base}/{kind}#" for kind in kinds}


def local_id(node: Node) -> str:
    """The element id an IRI names: the part after '#', else after the last '/'."""
    text = str(node)
    if "#" in text:
        return text.rsplit("#", 1)[1]
    return text.rstrip("/").rsplit("/", 1)[-1]


class _Resolver:
    """Maps the ids that orders name (successors, start, scope) to IRIs, as the structural check
    resolves them: a goal first, then a terminal, else a name that is neither."""

    def __init__(self, orders: Orders, iris: MissionIris) -> None:
        self.iris = iris
        self.goals = set(orders.goal_index())
        self.terminals = set(orders.terminal_index())
        self.mission_id = orders.id

    def successor(self, name: str) -> URIRef:
        if name in self.goals:
            return self.iris.element("goal", name)
        if name in self.terminals:
            return self.iris.element("terminal", name)
        return self.iris.element("ref", name)

    def scope(self, name: str) -> URIRef:
        if name in self.goals:
            return self.iris.element("goal", name)
        if name == self.mission_id:
            return self.iris.mission
        return self.successor(name)

    def scopes(self, applies_to: str | list[str]) -> list[URIRef]:
        if applies_to == "mission":
            return [self.iris.mission]
        return [self.scope(name) for name in applies_to]

    def starts(self, start: str | list[str] | None) -> list[URIRef]:
        if start is None:
            return []
        names = [start] if isinstance(start, str) else start
        return [self.successor(name) for name in names]


# --------------------------------------------------------------------------------------------
# Orders -> graph


def orders_to_graph(orders: Orders, *, record: bool = True) -> Graph:
    """The orders as an RDF graph: the MEO meaning, plus (when `record`) the `cs:` record that
    makes the graph read back to the same orders."""
    graph = Graph()
    _fill(graph, orders, record)
    return graph


def _fill(graph: Graph | TripleSet, orders: Orders, record: bool) -> None:
    iris = MissionIris(orders.id)
    graph.bind("meo", MEO)
    graph.bind("cs", CS)
    graph.bind("key", CS_KEY)
    graph.bind("mission", URIRef(MISSION_BASE))
    for prefix, namespace in iris.namespaces().items():
        graph.bind(prefix, namespace)
    _meaning(graph, orders, iris)  # type: ignore[arg-type]
    if record:
        _record(graph, orders, iris)  # type: ignore[arg-type]


def _meaning(graph: Graph, orders: Orders, iris: MissionIris) -> None:
    add = graph.add
    resolve = _Resolver(orders, iris)
    mission = iris.mission
    add((mission, RDF.type, MEO.Mission))
    add((mission, RDFS.label, Literal(orders.title or orders.id)))
    for start in resolve.starts(orders.start):
        add((mission, MEO.startsWith, start))
    goal_index = orders.goal_index()
    for goal in goal_index.values():
        node = iris.element("goal", goal.id)
        add((node, RDF.type, MEO.Goal))
        add((node, RDFS.label, Literal(goal.label)))
        add((mission, MEO.includes, node))
        for requirement in goal.requires:
            req = iris.element("requirement", requirement)
            add((node, MEO.requires, req))
            add((req, RDF.type, MEO.GoalRequirement))
        for outcome, prop in OUTCOME_PROPERTY.items():
            for target in goal.successors(outcome):
                add((node, prop, resolve.successor(target)))
        phase = goal.params.get("phase")
        if isinstance(phase, str):
            add((node, MEO.isPartOfPhase, Literal(phase)))
    for terminal in orders.terminal_index().values():
        node = iris.element("terminal", terminal.id)
        add((node, RDF.type, MEO.Terminal))
        add((node, RDFS.label, Literal(terminal.label)))
    constraints = _first_by_id(orders.constraints)
    for constraint in constraints:
        node = iris.element("constraint", constraint.id)
        add((node, RDF.type, MEO.Constraint))
        add((mission, MEO.hasConstraint, node))
        if constraint.text:
            add((node, RDFS.comment, Literal(constraint.text)))
        for scope in resolve.scopes(constraint.applies_to):
            add((node, MEO.appliesTo, scope))
        for quantity in expression_quantities(constraint.expr):
            q = iris.element("quantity", quantity)
            add((node, MEO.reads, q))
            add((q, RDF.type, MEO.Quantity))
    performer = orders.target_vehicle()
    reads = {c.id: set(expression_quantities(c.expr)) for c in constraints}
    for vehicle in _first_by_id(orders.vehicles):
        node = iris.element("vehicle", vehicle.id)
        add((node, RDF.type, MEO.Vehicle))
        add((node, RDFS.label, Literal(vehicle.title or vehicle.id)))
        if vehicle is performer:
            add((mission, MEO.performableBy, node))
        for feature in _first_by_id(vehicle.features):
            f = iris.feature(vehicle.id, feature.id)
            add((f, RDF.type, MEO.VehicleFeature))
            add((node, MEO.hasFeature, f))
            for requirement in feature.fulfills:
                req = iris.element("requirement", requirement)
                add((f, MEO.canFulfill, req))
                add((req, RDF.type, MEO.GoalRequirement))
            for quantity in feature.measures:
                q = iris.element("quantity", quantity)
                add((f, MEO.measures, q))
                add((q, RDF.type, MEO.Quantity))
            measured = set(feature.measures)
            for constraint in constraints:
                if constraint.expr is not None and reads[constraint.id] <= measured:
                    add((f, MEO.canTest, iris.element("constraint", constraint.id)))
            for constraint_id in feature.tests:  # asserted (canTest / NPS canMeasure)
                add((f, MEO.canTest, iris.element("constraint", constraint_id)))


_T = TypeVar("_T")


def _first_by_id(items: Iterable[_T]) -> list[_T]:
    """The first element of each id (a DUP finding reports the others)."""
    seen: set[str] = set()
    result: list[_T] = []
    for item in items:
        item_id = getattr(item, "id", None)
        if isinstance(item_id, str) and item_id not in seen:
            seen.add(item_id)
            result.append(item)
    return result


# The record: every field as written, generically encoded.


def _record(graph: Graph, orders: Orders, iris: MissionIris) -> None:
    data = orders_to_json(orders)
    mission = iris.mission
    graph.add((mission, CS.id, Literal(orders.id)))
    for key, value in data.items():
        if key in ("id", "format"):
            continue
        if key in _ELEMENT_LISTS and isinstance(value, list):
            kind = _ELEMENT_LISTS[key]
            nodes = _element_nodes(graph, value, iris, kind, None)
            graph.add((mission, CS[key], _list(graph, nodes)))
            continue
        _field(graph, mission, key, value)
    if orders.terminals is None:
        for terminal in orders.effective_terminals:
            graph.add((iris.element("terminal", terminal.id), CS.implicit, Literal(True)))


def _element_nodes(
    graph: Graph, items: list[Any], iris: MissionIris | None, kind: str, vehicle: str | None
) -> list[Node]:
    """Record nodes of a list of elements: the first element of an id is its IRI (shared with
    the meaning); a repeated id, and everything inside it, is a blank node."""
    nodes: list[Node] = []
    seen: set[str] = set()
    for item in items:
        item_id = item.get("id") if isinstance(item, dict) else None
        node: Node
        named = iris is not None and isinstance(item_id, str) and item_id not in seen
        if named and iris is not None and isinstance(item_id, str):
            seen.add(item_id)
            node = (
                iris.feature(vehicle, item_id) if vehicle is not None
                else iris.element(kind, item_id)
            )
        else:
            node = _blank()
        for key, value in item.items():
            if kind == "vehicle" and key == "features" and isinstance(value, list):
                inner = iris if named else None
                vehicle_id = item_id if isinstance(item_id, str) else ""
                features = _element_nodes(graph, value, inner, "feature", vehicle_id)
                graph.add((node, CS.features, _list(graph, features)))
            else:
                _field(graph, node, key, value)
        nodes.append(node)
    return nodes


def _field(graph: Graph, node: Node, key: str, value: Any) -> None:
    if _NAME.fullmatch(key) and key not in _RESERVED:
        graph.add((node, _record_property(key), _encode(graph, value)))
    else:
        entry = _blank()
        graph.add((node, _EXTRA, entry))
        graph.add((entry, _KEY, _literal("str", key)))
        graph.add((entry, _VALUE, _encode(graph, value)))


@functools.lru_cache(maxsize=1024)
def _record_property(key: str) -> URIRef:
    return CS[key]


@functools.lru_cache(maxsize=4096)
def _key_property(key: str) -> URIRef:
    return CS_KEY[key]


# Short values (keys, ids, outcome names) repeat; long texts are not kept alive by the cache.
_CACHED_TEXT: Final = 64


@functools.lru_cache(maxsize=65536)
def _literal(kind: str, value: Any) -> Literal:
    """One Literal per distinct (type, value): a record repeats its keys and ids thousands of
    times, and rdflib's Literal constructor is the writer's largest cost. `kind` keeps True
    and 1 apart."""
    return Literal(value)


_BLANK_LABELS: Final = itertools.count()


def _blank() -> BNode:
    # rdflib's BNode() draws a uuid4 each time; a counter is unique within the process and
    # costs a tenth (labels are renumbered by the Turtle writer anyway).
    return BNode(f"csr{next(_BLANK_LABELS)}")


_NAME: Final = re.compile(r"[a-z][a-z0-9_]*")
# A map key written as a key: property: a local name every Turtle reader takes as it is.
_KEY_NAME: Final = re.compile(r"[A-Za-z_][A-Za-z0-9_-]*")
_RESERVED: Final = frozenset({"extra", "key", "value", "entry", "implicit", "null", "map"})


def _list(graph: Graph, nodes: list[Node]) -> Node:
    if not nodes:
        return RDF.nil
    # The rdf:first/rdf:rest cells written directly (rdflib's Collection reads the graph back
    # at every append, which made long lists quadratic).
    head = cell = _blank()
    for index, item in enumerate(nodes):
        graph.add((cell, _FIRST, item))
        following: Node = _blank() if index + 1 < len(nodes) else _NIL
        graph.add((cell, _REST, following))
        cell = following  # type: ignore[assignment]
    return head


def _encode(graph: Graph, value: Any) -> Node:
    if value is None:
        return _NULL
    if isinstance(value, str) and len(value) > _CACHED_TEXT:
        return Literal(value)
    if isinstance(value, bool | int | str):
        return _literal(type(value).__name__, value)
    if isinstance(value, float):
        # xsd:decimal keeps every digit through rdflib's Turtle writer (xsd:double does not).
        return Literal(format(Decimal(repr(value)), "f"), datatype=XSD.decimal)
    if isinstance(value, list):
        if value and all(_JSON_SCALAR(item) for item in value):
            return Literal(json.dumps(value, ensure_ascii=False), datatype=_RDF_JSON)
        return _list(graph, [_encode(graph, item) for item in value])
    if isinstance(value, dict):
        node = _blank()
        if value and all(isinstance(key, str) and _KEY_NAME.fullmatch(key) for key in value):
            for key, item in value.items():
                graph.add((node, _key_property(key), _encode(graph, item)))
            return node
        graph.add((node, _TYPE, _MAP))
        for key, item in value.items():
            entry = _blank()
            graph.add((node, _ENTRY, entry))
            graph.add((entry, _KEY, _literal("str", key)))
            graph.add((entry, _VALUE, _encode(graph, item)))
        return node
    raise TypeError(f"cannot encode {type(value).__name__} in RDF")


# --------------------------------------------------------------------------------------------
# Writers


def write_turtle(orders: Orders) -> str:
    """Turtle in the Countersign vocabulary: MEO meaning plus the lossless record.

    Written as text straight from the orders (`_TurtleText`), without RDF term objects: the
    statements are those of `orders_to_graph` (a test checks that the two graphs are
    isomorphic), the record's values nested in place as `[ ... ]` and `( ... )`."""
    header = (
        f"# Mission orders {orders.id} ({orders.format}) as Mission Execution Ontology "
        "individuals.\n# Vocabulary: meo: ontology/meo.ttl; cs: the orders record "
        "(read back losslessly by Countersign).\n"
    )
    with paused_collection():
        return header + _TurtleText(orders).write()


def write_turtle_via_graph(orders: Orders) -> str:
    """The same statements through rdflib terms and the generic writer (the route before the
    text writer; kept as the benchmark's baseline and the tests' reference)."""
    triples = TripleSet()
    _fill(triples, orders, record=True)
    return serialize_turtle(triples)


_TEXT_ESCAPES: Final = {"\\": "\\\\", '"': '\\"', "\n": "\\n", "\r": "\\r", "\t": "\\t",
                        "\b": "\\b", "\f": "\\f"}
_TEXT_NEEDS_ESCAPE: Final = re.compile(r'[\\"\x00-\x1f\x7f]')
_TEXT_IRI_UNSAFE: Final = re.compile(r'[\x00-\x20<>"{}|^`\\]')
_TEXT_LOCAL: Final = re.compile(r"[A-Za-z_][A-Za-z0-9_-]*")
_TEXT_DECIMAL: Final = re.compile(r"[+-]?[0-9]*\.[0-9]+")


def _text_escape_char(match: re.Match[str]) -> str:
    char = match.group(0)
    return _TEXT_ESCAPES.get(char) or f"\\u{ord(char):04X}"


def _quoted(text: str) -> str:
    if _TEXT_NEEDS_ESCAPE.search(text) is None:
        return f'"{text}"'
    return '"' + _TEXT_NEEDS_ESCAPE.sub(_text_escape_char, text) + '"'


def _iri_ref(text: str) -> str:
    if _TEXT_IRI_UNSAFE.search(text):
        text = _TEXT_IRI_UNSAFE.sub(lambda m: f"\\u{ord(m.group(0)):04X}", text)
    return f"<{text}>"


class _TurtleText:
    """One mission's Turtle written as text: `_meaning` and `_record` statement for statement,
    terms rendered once each (prefixed names where the local part is a plain name), statements
    grouped by subject in first-use order, a repeated statement written once."""

    KINDS: Final = ("goal", "terminal", "constraint", "requirement", "quantity", "vehicle",
                    "ref", "area", "norm", "property")

    def __init__(self, orders: Orders) -> None:
        self.orders = orders
        self.base = f"{MISSION_BASE}{orders.id}"
        self.subjects: dict[str, dict[str, None]] = {}
        self._elements: dict[tuple[str, str], str] = {}
        local = orders.id if _TEXT_LOCAL.fullmatch(orders.id) else None
        self.mission = f"mission:{local}" if local else _iri_ref(self.base)

    # -- terms

    def element(self, kind: str, element_id: str) -> str:
        key = (kind, element_id)
        found = self._elements.get(key)
        if found is None:
            if _TEXT_LOCAL.fullmatch(element_id):
                found = f"{kind}:{element_id}"
            else:
                found = _iri_ref(f"{self.base}/{kind}#{element_id}")
            self._elements[key] = found
        return found

    def feature(self, vehicle_id: str, feature_id: str) -> str:
        return _iri_ref(f"{self.base}/vehicle/{vehicle_id}/feature#{feature_id}")

    def add(self, subject: str, predicate: str, obj: str) -> None:
        statements = self.subjects.get(subject)
        if statements is None:
            statements = self.subjects[subject] = {}
        statements[f"{predicate} {obj}"] = None

    # -- the meaning (as `_meaning`)

    def successor(self, name: str, goals: set[str], terminals: set[str]) -> str:
        if name in goals:
            return self.element("goal", name)
        if name in terminals:
            return self.element("terminal", name)
        return self.element("ref", name)

    def meaning(self) -> None:
        orders = self.orders
        add = self.add
        element = self.element
        mission = self.mission
        goal_index = orders.goal_index()
        goals = set(goal_index)
        terminals = set(orders.terminal_index())
        add(mission, "a", "meo:Mission")
        add(mission, "rdfs:label", _quoted(orders.title or orders.id))
        start = orders.start
        for name in ([] if start is None else [start] if isinstance(start, str) else start):
            add(mission, "meo:startsWith", self.successor(name, goals, terminals))
        outcomes = tuple((outcome, f"meo:{str(prop)[len(str(MEO)):]}")
                         for outcome, prop in OUTCOME_PROPERTY.items())
        for goal in goal_index.values():
            node = element("goal", goal.id)
            add(node, "a", "meo:Goal")
            add(node, "rdfs:label", _quoted(goal.label))
            add(mission, "meo:includes", node)
            for requirement in goal.requires:
                req = element("requirement", requirement)
                add(node, "meo:requires", req)
                add(req, "a", "meo:GoalRequirement")
            for outcome, prop in outcomes:
                for target in goal.successors(outcome):
                    add(node, prop, self.successor(target, goals, terminals))
            phase = goal.params.get("phase")
            if isinstance(phase, str):
                add(node, "meo:isPartOfPhase", _quoted(phase))
        for terminal in orders.terminal_index().values():
            node = element("terminal", terminal.id)
            add(node, "a", "meo:Terminal")
            add(node, "rdfs:label", _quoted(terminal.label))
        constraints = _first_by_id(orders.constraints)
        reads: dict[str, list[str]] = {}
        for constraint in constraints:
            node = element("constraint", constraint.id)
            add(node, "a", "meo:Constraint")
            add(mission, "meo:hasConstraint", node)
            if constraint.text:
                add(node, "rdfs:comment", _quoted(constraint.text))
            if constraint.applies_to == "mission":
                add(node, "meo:appliesTo", mission)
            else:
                for name in constraint.applies_to:
                    scope = (element("goal", name) if name in goals
                             else mission if name == orders.id
                             else self.successor(name, goals, terminals))
                    add(node, "meo:appliesTo", scope)
            quantities = reads[constraint.id] = list(expression_quantities(constraint.expr))
            for quantity in quantities:
                q = element("quantity", quantity)
                add(node, "meo:reads", q)
                add(q, "a", "meo:Quantity")
        performer = orders.target_vehicle()
        for vehicle in _first_by_id(orders.vehicles):
            node = element("vehicle", vehicle.id)
            add(node, "a", "meo:Vehicle")
            add(node, "rdfs:label", _quoted(vehicle.title or vehicle.id))
            if vehicle is performer:
                add(mission, "meo:performableBy", node)
            for feature in _first_by_id(vehicle.features):
                f = self.feature(vehicle.id, feature.id)
                add(f, "a", "meo:VehicleFeature")
                add(node, "meo:hasFeature", f)
                for requirement in feature.fulfills:
                    req = element("requirement", requirement)
                    add(f, "meo:canFulfill", req)
                    add(req, "a", "meo:GoalRequirement")
                for quantity in feature.measures:
                    q = element("quantity", quantity)
                    add(f, "meo:measures", q)
                    add(q, "a", "meo:Quantity")
                measured = set(feature.measures)
                for constraint in constraints:
                    if constraint.expr is not None and set(reads[constraint.id]) <= measured:
                        add(f, "meo:canTest", element("constraint", constraint.id))
                for constraint_id in feature.tests:
                    add(f, "meo:canTest", element("constraint", constraint_id))

    # -- the record (as `_record`)

    def record(self) -> None:
        orders = self.orders
        data = orders_to_json(orders)
        mission = self.mission
        self.add(mission, "cs:id", _quoted(orders.id))
        for key, value in data.items():
            if key in ("id", "format"):
                continue
            if key in _ELEMENT_LISTS and isinstance(value, list):
                nodes = self.element_nodes(value, _ELEMENT_LISTS[key], None, True)
                self.add(mission, f"cs:{key}", "( " + " ".join(nodes) + " )")
                continue
            self.add(mission, *self.field(key, value))
        if orders.terminals is None:
            for terminal in orders.effective_terminals:
                self.add(self.element("terminal", terminal.id), "cs:implicit", "true")

    def element_nodes(self, items: list[Any], kind: str, vehicle: str | None,
                      named_parent: bool) -> list[str]:
        """As `_element_nodes`: the first element of an id is its IRI, whose fields are
        statements of that subject; a repeated id is a nested blank node."""
        nodes: list[str] = []
        seen: set[str] = set()
        for item in items:
            item_id = item.get("id") if isinstance(item, dict) else None
            named = named_parent and isinstance(item_id, str) and item_id not in seen
            fields: list[tuple[str, str]] = []
            for key, value in item.items():
                if kind == "vehicle" and key == "features" and isinstance(value, list):
                    vehicle_id = item_id if isinstance(item_id, str) else ""
                    features = self.element_nodes(value, "feature", vehicle_id, named)
                    fields.append(("cs:features", "( " + " ".join(features) + " )"))
                else:
                    fields.append(self.field(key, value))
            if named and isinstance(item_id, str):
                seen.add(item_id)
                node = (self.feature(vehicle, item_id) if vehicle is not None
                        else self.element(kind, item_id))
                for predicate, obj in fields:
                    self.add(node, predicate, obj)
                nodes.append(node)
            else:
                nodes.append(_blank_text(fields))
        return nodes

    def field(self, key: str, value: Any) -> tuple[str, str]:
        if _NAME.fullmatch(key) and key not in _RESERVED:
            return f"cs:{key}", _encode_text(value)
        return "cs:extra", _blank_text([("cs:key", _quoted(key)),
                                        ("cs:value", _encode_text(value))])

    def write(self) -> str:
        self.meaning()
        self.record()
        prefixes = [("cs", str(CS)), ("key", str(CS_KEY)), ("meo", str(MEO)),
                    ("mission", MISSION_BASE), ("rdf", str(RDF)), ("rdfs", str(RDFS)),
                    ("xsd", str(XSD))]
        prefixes += [(kind, f"{self.base}/{kind}#") for kind in self.KINDS]
        parts = [f"@prefix {prefix}: <{namespace}> .\n" for prefix, namespace in prefixes]
        parts.append("\n")
        for subject, statements in self.subjects.items():
            parts.append(f"{subject} " + " ;\n    ".join(statements) + " .\n\n")
        return "".join(parts)


def _json_scalar(item: Any) -> bool:
    """A list member written inside an rdf:JSON literal: a string, boolean, integer, null or
    finite float (JSON keeps each of them exactly: floats by their shortest repr)."""
    return (item is None or isinstance(item, str | bool | int)
            or (isinstance(item, float) and math.isfinite(item)))


_JSON_SCALAR: Final = _json_scalar


def _blank_text(fields: list[tuple[str, str]]) -> str:
    if not fields:
        return "[]"
    return "[ " + " ; ".join(f"{p} {o}" for p, o in fields) + " ]"


def _encode_text(value: Any) -> str:
    """A record value as a Turtle term, as `_encode` writes it."""
    if value is None:
        return "cs:null"
    if value is True:
        return "true"
    if value is False:
        return "false"
    if isinstance(value, str):
        return _quoted(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        lexical = format(Decimal(repr(value)), "f")
        if _TEXT_DECIMAL.fullmatch(lexical):
            return lexical
        return f"{_quoted(lexical)}^^xsd:decimal"
    if isinstance(value, list):
        if not value:
            return "rdf:nil"
        if all(_JSON_SCALAR(item) for item in value):
            return f"{_quoted(json.dumps(value, ensure_ascii=False))}^^rdf:JSON"
        return "( " + " ".join(_encode_text(item) for item in value) + " )"
    if isinstance(value, dict):
        if value and all(isinstance(key, str) and _KEY_NAME.fullmatch(key) for key in value):
            return "[ " + " ; ".join(f"key:{key} {_encode_text(item)}"
                                     for key, item in value.items()) + " ]"
        entries = ", ".join(_blank_text([("cs:key", _quoted(key)),
                                         ("cs:value", _encode_text(item))])
                            for key, item in value.items())
        return "[ a cs:Map" + (f" ; cs:entry {entries}" if entries else "") + " ]"
    raise TypeError(f"cannot encode {type(value).__name__} in RDF")


def nps_graph(orders: Orders) -> Graph:
    """The orders in the NPS MEO 3.0 vocabulary: individuals of the NPS classes, successors as
    hasNextGoalOn*, goals described by rdfs:comment "Title: description", terminals as goals
    without successors (the NPS convention). Only names MEO 3.0 declares are written: the ones
    the NPS converted missions and queries use instead (hasNextOn*, isPartOfPhase with `#`,
    appliesTo) are read but never written."""
    ours = orders_to_graph(orders, record=False)
    names = _nps_names()
    iris = MissionIris(orders.id)
    graph = Graph()
    graph.bind("meo", NPS3)
    for prefix, namespace in iris.namespaces().items():
        graph.bind(prefix, namespace)
    document = URIRef(f"{iris.mission}/nps-meo3")
    graph.add((document, RDF.type, OWL.Ontology))
    graph.add((document, OWL.imports, URIRef(str(NPS3).rstrip("#"))))
    mission_iri = iris.mission
    for s, p, o in ours:
        if p == RDF.type:
            if o == MEO.Terminal:
                targets: list[Node] = [NPS3.Goal]
            else:
                targets = list(names.get(o, []))
            for target in targets:
                graph.add((s, RDF.type, target))
            if targets:
                graph.add((s, RDF.type, OWL.NamedIndividual))
            continue
        if p in (RDFS.label, RDFS.comment):
            continue
        for name in names.get(p, []):
            graph.add((s, name, o))
    for goal in orders.goal_index().values():
        comment = f"{goal.title}: {goal.description}" if goal.description else goal.label
        graph.add((iris.element("goal", goal.id), RDFS.comment, Literal(comment)))
    for terminal in orders.terminal_index().values():
        graph.add((iris.element("terminal", terminal.id), RDFS.comment, Literal(terminal.label)))
    for constraint in orders.constraints:
        if constraint.text:
            node = iris.element("constraint", constraint.id)
            graph.add((node, RDFS.comment, Literal(constraint.text)))
    if orders.description or orders.title:
        graph.add((mission_iri, RDFS.comment, Literal(orders.description or orders.title)))
    return graph


def write_nps_turtle(orders: Orders) -> str:
    header = (
        f"# Mission orders {orders.id} in the NPS Mission Execution Ontology 3.0 vocabulary\n"
        "# (a view written by Countersign: titles and successors only, not read back "
        "losslessly).\n"
    )
    return header + serialize_turtle(nps_graph(orders))


def _nps_names() -> dict[Node, list[Node]]:
    """meo: term -> its equivalents in the NPS MEO 3.0 namespace (alignment file), leaving out
    the names the alignment marks owl:deprecated (used by NPS files, not declared by MEO 3.0)."""
    names: dict[Node, list[Node]] = {}
    prefix = str(NPS3).rstrip("#")
    deprecated = set(load_graph(NPS_ALIGNMENT).subjects(OWL.deprecated, Literal(True)))
    for ours, theirs in _equivalences():
        if str(theirs).startswith(prefix) and theirs not in deprecated:
            names.setdefault(ours, []).append(theirs)
    for values in names.values():
        values.sort(key=str)
    return names


def _equivalences() -> Iterator[tuple[Node, Node]]:
    alignment = load_graph(NPS_ALIGNMENT)
    for prop in (OWL.equivalentClass, OWL.equivalentProperty):
        for ours, theirs in alignment.subject_objects(prop):
            if str(ours).startswith(str(MEO)) and isinstance(theirs, URIRef):
                yield ours, theirs


# --------------------------------------------------------------------------------------------
# Reader


def read_turtle(data: bytes, name: str = "<input>") -> ReadResult:
    """Orders from Turtle in our vocabulary (lossless) or NPS MEO Turtle (by its conventions)."""
    graph = _parse(data, name)
    renamed = _align(graph)
    try:
        with paused_collection():
            return _read(graph, renamed, name)
    except RecursionError:
        raise OrdersReadError([Problem("$", f"{name} is nested too deeply")]) from None


def _read(graph: TripleIndex, renamed: bool, name: str) -> ReadResult:
    findings = typing_findings(graph)
    result = _Reader(graph, renamed, name).read()
    return ReadResult(result.orders, findings + result.findings, "turtle")


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


def _align(graph: TripleIndex) -> bool:
    """Rename NPS terms to meo: in place; True when any NPS term was found."""
    mapping = {theirs: ours for ours, theirs in _equivalences()}
    renamed: list[tuple[tuple[Node, Node, Node], tuple[Node, Node, Node]]] = []
    for theirs, ours in mapping.items():
        renamed.extend(((s, p, o), (s, ours, o)) for s, p, o in graph.triples((None, theirs, None)))
    for s, p, o in list(graph.triples((None, RDF.type, None))):
        if o in mapping:
            renamed.append(((s, p, o), (s, p, mapping[o])))
    for old, new in renamed:
        graph.remove(old)
        graph.add(new)
    return bool(renamed)


# Terms the record decoder compares at every value, looked up once (rdflib namespaces resolve
# attributes on every access).
_NULL: Final = CS.null
_NIL: Final = RDF.nil
_FIRST: Final = RDF.first
_REST: Final = RDF.rest
_TYPE: Final = RDF.type
_MAP: Final = CS.Map
_KEY: Final = CS.key
_CS_ID: Final = CS.id
_VALUE: Final = CS.value
_EXTRA: Final = CS.extra
_ENTRY: Final = CS.entry
_KEY_PREFIX: Final = str(CS_KEY)
_FLOAT_TYPES: Final = frozenset({XSD.double, XSD.decimal, XSD.float})
_INT_TYPES: Final = frozenset({XSD.integer, XSD.int, XSD.long})
_BOOLEAN: Final = XSD.boolean
# A list of scalars in the record: one rdf:JSON literal instead of two statements per member
# (rdf:first, rdf:rest). The range [low, high] of each envelope quantity made a third of a
# mission's statements.
_RDF_JSON: Final = RDF.JSON


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
_NATURAL: Final = re.compile(r"(\d+)")
MAX_DEPTH: Final = 64
MAX_LIST_ITEMS: Final = 200_000
# A document whose values share no list decodes about one value per statement; a few times
# that (a node read twice, small documents) is allowed, more means expanding shared structure.
DECODE_FACTOR: Final = 4
DECODE_SLACK: Final = 10_000


def natural_key(text: str) -> tuple[Any, ...]:
    return tuple(int(part) if part.isdigit() else part for part in _NATURAL.split(text))


@dataclass
class _Reader:
    graph: TripleIndex
    aligned: bool  # the input used NPS names (renamed to meo:)
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
        return ReadResult(orders, self.findings, "turtle")

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


# --------------------------------------------------------------------------------------------
# Typing rules of RDF input


def typing_findings(graph: TripleIndex) -> list[Finding]:
    """Statements of a Turtle input that contradict a domain or range of meo.ttl: the subject
    or object is asserted to be of a class disjoint with the one the rule requires (under OWL
    the ontology would be inconsistent). Each finding's code is the rule of the violated axiom
    (M1, M2, M3, M5, V1, F1, F2, G1, G2, G3, G6, C1, ...); also G4 for a successor given
    without an end condition and EC1 for an end condition other than SUCCEED, FAIL, VIOLATE.
    Orders cannot express these mistakes, so they exist only in RDF input."""
    meo = load_graph(MEO_FILE)
    superclasses: dict[Node, set[Node]] = {}
    for sub, sup in meo.subject_objects(RDFS.subClassOf):
        if isinstance(sup, URIRef):
            superclasses.setdefault(sub, set()).add(sup)
    disjoint: set[tuple[Node, Node]] = set()
    for group in meo.subjects(RDF.type, OWL.AllDisjointClasses):
        head = meo.value(group, OWL.members)
        members = list(Collection(meo, head)) if head is not None else []
        disjoint.update((a, b) for a in members for b in members if a != b)
    subproperties: dict[Node, set[Node]] = {}
    for sub, sup in meo.subject_objects(RDFS.subPropertyOf):
        subproperties.setdefault(sup, set()).add(sub)

    def classes(node: Node) -> set[Node]:
        found = set(graph.objects(node, RDF.type))
        for cls in list(found):
            found |= superclasses.get(cls, set())
        return found

    def with_subproperties(prop: Node) -> set[Node]:
        result, todo = {prop}, [prop]
        while todo:
            for sub in subproperties.get(todo.pop(), ()):
                if sub not in result:
                    result.add(sub)
                    todo.append(sub)
        return result

    findings: list[Finding] = []
    seen: set[tuple[str, str, str]] = set()
    for axiom in meo.subjects(RDF.type, OWL.Axiom):
        kind = meo.value(axiom, OWL.annotatedProperty)
        if kind not in (RDFS.domain, RDFS.range):
            continue
        prop = meo.value(axiom, OWL.annotatedSource)
        required = meo.value(axiom, OWL.annotatedTarget)
        rule = str(meo.value(axiom, RDFS.label))
        if not isinstance(required, URIRef) or prop is None:
            continue
        for used in with_subproperties(prop):
            for s, o in graph.subject_objects(used):
                node = s if kind == RDFS.domain else o
                for cls in classes(node):
                    if (cls, required) in disjoint and (rule, str(node), str(cls)) not in seen:
                        seen.add((rule, str(node), str(cls)))
                        role = "subject" if kind == RDFS.domain else "object"
                        findings.append(error(
                            rule, [local_id(s), local_id(o)],
                            f"{local_id(s)} {local_id(used)} {local_id(o)}: the {role} "
                            f"{local_id(node)} is a {local_id(cls)}, but {local_id(used)} needs a "
                            f"{local_id(required)} (rule {rule}).",
                            property=local_id(used),
                        ))
    for s, o in graph.subject_objects(MEO.isNext):
        findings.append(error(
            "G4", [local_id(s), local_id(o)],
            f"{local_id(s)} isNext {local_id(o)} names a successor without an end condition: use "
            "isNextOnSucceed, isNextOnFail or isNextOnViolate (rule G4). It was not read.",
        ))
    allowed = {MEO.SUCCEED, MEO.FAIL, MEO.VIOLATE}
    for s, o in graph.subject_objects(MEO.hasEndCondition):
        if o not in allowed:
            findings.append(error(
                "EC1", [local_id(s), local_id(o)],
                f"{local_id(s)} hasEndCondition {local_id(o)}: the end conditions are SUCCEED, "
                "FAIL and VIOLATE (rule EC1).",
            ))
    return findings
