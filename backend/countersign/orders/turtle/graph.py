"""Orders -> RDF graph (`orders_to_graph`): the MEO meaning and the `cs:` record as rdflib
terms, which the MEO checks reason over and the NPS view renames."""

from __future__ import annotations

import functools
import itertools
import json
from decimal import Decimal
from typing import Any, Final, Protocol

from rdflib import BNode, Graph, Literal, URIRef
from rdflib.namespace import RDF, RDFS, XSD
from rdflib.term import Node

from ..canonical import orders_to_json
from ..expressions import expression_quantities
from ..model import Constraint, Orders
from .vocabulary import (
    _ELEMENT_LISTS,
    _ENTRY,
    _EXTRA,
    _FIRST,
    _JSON_SCALAR,
    _KEY,
    _KEY_NAME,
    _MAP,
    _NAME,
    _NIL,
    _NULL,
    _RDF_JSON,
    _RESERVED,
    _REST,
    _TYPE,
    _VALUE,
    CS,
    CS_KEY,
    MEO,
    MISSION_BASE,
    OUTCOME_PROPERTY,
    MissionIris,
    _first_by_id,
)


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
    fill_graph(graph, orders, record)
    return graph


class GraphSink(Protocol):
    """What `fill_graph` uses of a graph (rdflib's Graph has it; so has a plain set of
    triples, as the tests' reference writer uses)."""

    def add(self, triple: tuple[Node, Node, Node], /) -> object: ...

    def bind(self, prefix: str, namespace: Any, /) -> object: ...


def fill_graph(graph: GraphSink, orders: Orders, record: bool) -> None:
    """Add the orders' statements (the meaning, and the record when `record`) to `graph`."""
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
    resolve = _Resolver(orders, iris)
    _mission_and_goals(graph, orders, iris, resolve)
    for terminal in orders.terminal_index().values():
        node = iris.element("terminal", terminal.id)
        graph.add((node, RDF.type, MEO.Terminal))
        graph.add((node, RDFS.label, Literal(terminal.label)))
    constraints = _first_by_id(orders.constraints)
    _constraints(graph, iris, resolve, constraints)
    _vehicles(graph, orders, iris, constraints)


def _mission_and_goals(graph: Graph, orders: Orders, iris: MissionIris,
                       resolve: _Resolver) -> None:
    add = graph.add
    mission = iris.mission
    add((mission, RDF.type, MEO.Mission))
    add((mission, RDFS.label, Literal(orders.title or orders.id)))
    for start in resolve.starts(orders.start):
        add((mission, MEO.startsWith, start))
    for goal in orders.goal_index().values():
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


def _constraints(graph: Graph, iris: MissionIris, resolve: _Resolver,
                 constraints: list[Constraint]) -> None:
    """The constraints, their scopes and the quantities they read."""
    add = graph.add
    for constraint in constraints:
        node = iris.element("constraint", constraint.id)
        add((node, RDF.type, MEO.Constraint))
        add((iris.mission, MEO.hasConstraint, node))
        if constraint.text:
            add((node, RDFS.comment, Literal(constraint.text)))
        for scope in resolve.scopes(constraint.applies_to):
            add((node, MEO.appliesTo, scope))
        for quantity in expression_quantities(constraint.expr):
            q = iris.element("quantity", quantity)
            add((node, MEO.reads, q))
            add((q, RDF.type, MEO.Quantity))


def _vehicles(graph: Graph, orders: Orders, iris: MissionIris,
              constraints: list[Constraint]) -> None:
    """The vehicles and their features, with what each feature can fulfil and test."""
    add = graph.add
    performer = orders.target_vehicle()
    reads = {c.id: set(expression_quantities(c.expr)) for c in constraints}
    for vehicle in _first_by_id(orders.vehicles):
        node = iris.element("vehicle", vehicle.id)
        add((node, RDF.type, MEO.Vehicle))
        add((node, RDFS.label, Literal(vehicle.title or vehicle.id)))
        if vehicle is performer:
            add((iris.mission, MEO.performableBy, node))
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


