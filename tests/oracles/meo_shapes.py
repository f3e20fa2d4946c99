"""Oracle: the closed-world rules of ontology/shapes.ttl, by two routes that give the same
violations. The product checks C1, C2, M6 and M7 directly (countersign.verify.meo.direct) and the
structural rules in countersign.verify.structure; the tests hold both to these shapes.

- `shacl_violations`: pySHACL validates the data graph against shapes.ttl. Faithful to the
  file, but pySHACL costs about a second per 100 goals (DESIGN.md), and its G7/G10 property
  paths run a search per goal.
- `native_violations`: the same shapes evaluated directly in Python over the same data graph
  and the graph stage's reachability, linear in its size.

A violation is (shape, focus node, value): the shape's local name in shapes.ttl, the node it
was checked on, and the offending value where the shape has one (a successor that is not a goal,
a scope that is not the mission or a goal, a constraint the vehicle cannot identify, a goal it
lacks the capability for). Tests run both routes on every input of the suite and require equal
sets, so shapes.ttl stays the specification and the fast route provably implements it.

The data graph (`validation_graph`) is the mission as written plus the inferred role assertions
(includes, appliesTo, canIdentify, meetsRequirement, performableBy, canPerform); inferred types
are left out on purpose (shapes.ttl explains why).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from functools import cache

from rdflib import Graph, URIRef
from rdflib.namespace import RDF
from rdflib.term import Node

from countersign.orders.ontology import load_graph
from countersign.orders.turtle import MEO, OUTCOME_PROPERTY
from countersign.verify.meo.reasoning import Inference

from .shape_info import MSH, SH, SHAPES, ShapeInfo, shape_info

# Inferred role assertions added to the data graph.
INFERRED_ROLES = (
    MEO.includes,
    MEO.appliesTo,
    MEO.canIdentify,
    MEO.meetsRequirement,
    MEO.performableBy,
    MEO.canPerform,
)
# Shapes whose violations carry a value (the others report only the focus node).
VALUE_SHAPES = frozenset(
    {"G3-succeed", "G3-fail", "G3-violate", "C1", "M6", "M7"}
)


@dataclass(frozen=True, order=True)
class Violation:
    shape: str
    focus: Node
    value: Node | None = None


def validation_graph(graph: Graph, inference: Inference) -> Graph:
    data = Graph()
    for triple in graph:
        data.add(triple)
    for prop in INFERRED_ROLES:
        for s, o in inference.pairs(prop):
            data.add((s, prop, o))
    return data


# --------------------------------------------------------------------------------------------
# pySHACL


@cache
def _shapes_given_to_pyshacl() -> Graph:
    # pyshacl adds statements to the shapes graph it is given (owl:Class rdfs:subClassOf
    # rdfs:Class, ...): it gets a copy of its own, never the shared parsed file.
    copy = Graph()
    copy += load_graph(SHAPES)
    return copy


def shacl_violations(data: Graph) -> set[Violation]:
    from pyshacl import validate

    shapes = load_graph(SHAPES)
    _conforms, report, _text = validate(
        data, shacl_graph=_shapes_given_to_pyshacl(), inference="none", advanced=False,
        allow_warnings=True,
    )
    assert isinstance(report, Graph)
    parents = {prop: shape for shape, prop in shapes.subject_objects(SH.property)}
    known = shape_info()
    found: set[Violation] = set()
    for result in report.subjects(RDF.type, SH.ValidationResult):
        source = report.value(result, SH.sourceShape)
        while source is not None and not _named_shape(source, known):
            source = parents.get(source)
        if source is None:
            continue
        name = str(source).removeprefix(str(MSH))
        focus = report.value(result, SH.focusNode)
        assert focus is not None
        value = report.value(result, SH.value) if name in VALUE_SHAPES else None
        found.add(Violation(name, focus, value))
    return found


def _named_shape(node: Node, known: dict[str, ShapeInfo]) -> bool:
    return isinstance(node, URIRef) and str(node).removeprefix(str(MSH)) in known


# --------------------------------------------------------------------------------------------
# Native evaluation


def native_violations(data: Graph, inference: Inference) -> set[Violation]:
    return set(_native(data, inference))


def _native(data: Graph, inference: Inference) -> Iterator[Violation]:
    types: dict[Node, set[Node]] = {}
    for s, o in data.subject_objects(RDF.type):
        types.setdefault(s, set()).add(o)

    def is_a(node: Node, cls: URIRef) -> bool:
        return cls in types.get(node, ())

    def non_terminal_goal(node: Node) -> bool:
        return is_a(node, MEO.Goal) and not is_a(node, MEO.Terminal)

    missions = [s for s, kinds in types.items() if MEO.Mission in kinds]
    goals = [s for s, kinds in types.items() if MEO.Goal in kinds]
    constraints = [s for s, kinds in types.items() if MEO.Constraint in kinds]

    def values(subject: Node, prop: URIRef) -> list[Node]:
        return list(data.objects(subject, prop))

    # M1, M2
    for mission in missions:
        starts = values(mission, MEO.startsWith)
        if len(starts) != 1:
            yield Violation("M1-count", mission)
        if not any(non_terminal_goal(g) for g in values(mission, MEO.includes)):
            yield Violation("M2", mission)
    for start in set(data.objects(None, MEO.startsWith)):
        if not non_terminal_goal(start):
            yield Violation("M1-goal", start)

    # SINK (G4), G3, G5
    for outcome, prop in OUTCOME_PROPERTY.items():
        for goal in goals:
            if not is_a(goal, MEO.Terminal) and (goal, prop, None) not in data:
                yield Violation(f"SINK-{outcome}", goal)
        targets_of: dict[Node, list[Node]] = {}
        for s, o in data.subject_objects(prop):
            targets_of.setdefault(s, []).append(o)
        for goal, targets in targets_of.items():
            if len(targets) > 1:
                yield Violation(f"G5-{outcome}", goal)
            for target in targets:
                if not (is_a(target, MEO.Goal) or is_a(target, MEO.Terminal)):
                    yield Violation(f"G3-{outcome}", goal, target)

    # G7: follows(g, g) after G8 and G9 (the graph stage found the cycles).
    on_cycle = {node for component in inference.reachability.cycles for node in component}
    for goal in goals:
        if goal in on_cycle:
            yield Violation("G7", goal)

    # G10: every included goal follows the one start goal.
    reached = inference.reachability.reached
    for mission in missions:
        starts = values(mission, MEO.startsWith)
        if len(starts) != 1 or not non_terminal_goal(starts[0]):
            continue
        start = starts[0]
        for goal in values(mission, MEO.includes):
            if (
                is_a(goal, MEO.Goal)
                and not is_a(goal, MEO.Terminal)
                and goal != start
                and goal not in reached
            ):
                yield Violation("G10", goal)

    # C1, C2 (after C3)
    includes: dict[Node, set[Node]] = {}
    for mission, goal in data.subject_objects(MEO.includes):
        includes.setdefault(mission, set()).add(goal)
    for constraint in constraints:
        scopes = values(constraint, MEO.appliesTo)
        by_mission: set[Node] = set()
        for scope in scopes:
            if is_a(scope, MEO.Mission):
                by_mission |= includes.get(scope, set())
        for scope in scopes:
            if not (is_a(scope, MEO.Mission) or non_terminal_goal(scope) or scope in by_mission):
                yield Violation("C1", constraint, scope)
        if not any(non_terminal_goal(s) for s in scopes):
            yield Violation("C2", constraint)

    # M6, M7 (with V5)
    for mission in missions:
        for vehicle in values(mission, MEO.performableBy):
            if not is_a(vehicle, MEO.Vehicle):
                continue
            identified = set(values(vehicle, MEO.canIdentify))
            for constraint in values(mission, MEO.hasConstraint):
                if constraint not in identified:
                    yield Violation("M6", mission, constraint)
            met = set(values(vehicle, MEO.meetsRequirement))
            for goal in values(mission, MEO.includes):
                if not non_terminal_goal(goal):
                    continue
                if any(r not in met for r in values(goal, MEO.requires)):
                    yield Violation("M7", mission, goal)
