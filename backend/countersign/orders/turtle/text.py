"""Our Turtle (`write_turtle`): the graph's statements rendered straight from the orders as
text, through the one writer (`syntax.py`)."""

from __future__ import annotations

import json
from decimal import Decimal
from typing import Any, Final

from rdflib.namespace import RDF, RDFS, XSD

from ..canonical import orders_to_json
from ..expressions import expression_quantities
from ..model import Constraint, Orders
from ..rdf_index import paused_collection
from .syntax import DECIMAL, LOCAL, document, iri_ref, quoted
from .vocabulary import (
    _ELEMENT_LISTS,
    _JSON_SCALAR,
    _KEY_NAME,
    _NAME,
    _RESERVED,
    CS,
    CS_KEY,
    MEO,
    MISSION_BASE,
    OUTCOME_PROPERTY,
    _first_by_id,
)


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
        local = orders.id if LOCAL.fullmatch(orders.id) else None
        self.mission = f"mission:{local}" if local else iri_ref(self.base)

    # -- terms

    def element(self, kind: str, element_id: str) -> str:
        key = (kind, element_id)
        found = self._elements.get(key)
        if found is None:
            if LOCAL.fullmatch(element_id):
                found = f"{kind}:{element_id}"
            else:
                found = iri_ref(f"{self.base}/{kind}#{element_id}")
            self._elements[key] = found
        return found

    def feature(self, vehicle_id: str, feature_id: str) -> str:
        return iri_ref(f"{self.base}/vehicle/{vehicle_id}/feature#{feature_id}")

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
        goals = set(orders.goal_index())
        terminals = set(orders.terminal_index())
        self._mission_and_goals(goals, terminals)
        for terminal in orders.terminal_index().values():
            node = self.element("terminal", terminal.id)
            self.add(node, "a", "meo:Terminal")
            self.add(node, "rdfs:label", quoted(terminal.label))
        constraints = _first_by_id(orders.constraints)
        reads = self._constraints(constraints, goals, terminals)
        self._vehicles(constraints, reads)

    def _mission_and_goals(self, goals: set[str], terminals: set[str]) -> None:
        orders, add, element, mission = self.orders, self.add, self.element, self.mission
        add(mission, "a", "meo:Mission")
        add(mission, "rdfs:label", quoted(orders.title or orders.id))
        start = orders.start
        for name in ([] if start is None else [start] if isinstance(start, str) else start):
            add(mission, "meo:startsWith", self.successor(name, goals, terminals))
        outcomes = tuple((outcome, f"meo:{str(prop)[len(str(MEO)):]}")
                         for outcome, prop in OUTCOME_PROPERTY.items())
        for goal in orders.goal_index().values():
            node = element("goal", goal.id)
            add(node, "a", "meo:Goal")
            add(node, "rdfs:label", quoted(goal.label))
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
                add(node, "meo:isPartOfPhase", quoted(phase))

    def _constraints(self, constraints: list[Constraint], goals: set[str],
                     terminals: set[str]) -> dict[str, list[str]]:
        """The constraints, their scopes and the quantities they read (returned by id)."""
        orders, add, element, mission = self.orders, self.add, self.element, self.mission
        reads: dict[str, list[str]] = {}
        for constraint in constraints:
            node = element("constraint", constraint.id)
            add(node, "a", "meo:Constraint")
            add(mission, "meo:hasConstraint", node)
            if constraint.text:
                add(node, "rdfs:comment", quoted(constraint.text))
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
        return reads

    def _vehicles(self, constraints: list[Constraint], reads: dict[str, list[str]]) -> None:
        """The vehicles and their features, with what each feature can fulfil and test."""
        add, element = self.add, self.element
        performer = self.orders.target_vehicle()
        for vehicle in _first_by_id(self.orders.vehicles):
            node = element("vehicle", vehicle.id)
            add(node, "a", "meo:Vehicle")
            add(node, "rdfs:label", quoted(vehicle.title or vehicle.id))
            if vehicle is performer:
                add(self.mission, "meo:performableBy", node)
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
        self.add(mission, "cs:id", quoted(orders.id))
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
        return "cs:extra", _blank_text([("cs:key", quoted(key)),
                                        ("cs:value", _encode_text(value))])

    def write(self) -> str:
        self.meaning()
        self.record()
        prefixes = [("cs", str(CS)), ("key", str(CS_KEY)), ("meo", str(MEO)),
                    ("mission", MISSION_BASE), ("rdf", str(RDF)), ("rdfs", str(RDFS)),
                    ("xsd", str(XSD))]
        prefixes += [(kind, f"{self.base}/{kind}#") for kind in self.KINDS]
        # Every prefix declared, used or not; a blank line after the last block too.
        return document(prefixes, self.subjects.items()) + "\n"


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
        return quoted(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        lexical = format(Decimal(repr(value)), "f")
        if DECIMAL.fullmatch(lexical):
            return lexical
        return f"{quoted(lexical)}^^xsd:decimal"
    if isinstance(value, list):
        if not value:
            return "rdf:nil"
        if all(_JSON_SCALAR(item) for item in value):
            return f"{quoted(json.dumps(value, ensure_ascii=False))}^^rdf:JSON"
        return "( " + " ".join(_encode_text(item) for item in value) + " )"
    if isinstance(value, dict):
        if value and all(isinstance(key, str) and _KEY_NAME.fullmatch(key) for key in value):
            return "[ " + " ; ".join(f"key:{key} {_encode_text(item)}"
                                     for key, item in value.items()) + " ]"
        entries = ", ".join(_blank_text([("cs:key", quoted(key)),
                                         ("cs:value", _encode_text(item))])
                            for key, item in value.items())
        return "[ a cs:Map" + (f" ; cs:entry {entries}" if entries else "") + " ]"
    raise TypeError(f"cannot encode {type(value).__name__} in RDF")

