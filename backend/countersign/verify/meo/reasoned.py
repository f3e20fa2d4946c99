"""The MEO route: the orders as RDF, what the MEO infers from them, and the explanation
(the package's docstring describes the pipeline)."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

from rdflib import Graph
from rdflib.namespace import RDF
from rdflib.term import Node

from ...orders.model import Orders, Vehicle
from ...orders.turtle import MEO, local_id, natural_key, orders_to_graph
from .reasoning import Inference, infer


@dataclass
class MeoResult:
    orders: Orders
    graph: Graph = field(repr=False)
    inference: Inference = field(repr=False)

    @cached_property
    def explanation(self) -> dict[str, Any]:
        """The inferred facts that matter, each with the rule and the facts it follows from."""
        return explain(self.orders, self.graph, self.inference, "native")


def meo_reasoning(orders: Orders, *, vehicle: Vehicle | None = None) -> MeoResult:
    """The orders as RDF and the MEO's inferences about them (with `vehicle` as the target
    vehicle's profile when the orders carry none)."""
    if vehicle is not None and orders.target_vehicle() is None:
        orders = orders.model_copy(
            update={"vehicles": [*orders.vehicles, vehicle], "vehicle": vehicle.id}
        )
    graph = orders_to_graph(orders, record=False)
    return MeoResult(orders, graph, infer(graph))


# --------------------------------------------------------------------------------------------
# Explanation


def explain(orders: Orders, graph: Graph, inference: Inference, engine: str) -> dict[str, Any]:
    """Inferred facts with their rule and premises, the scope of every constraint after C3, and
    what the reasoner worked on. Element ids stand for IRIs; the mission is its id."""
    facts = _Facts(orders)
    _inclusion_facts(facts, inference)
    _application_facts(facts, graph, inference)
    _vehicle_facts(facts, graph, inference)
    name = facts.name
    return {
        "mission": orders.id,
        "engine": engine,
        "facts": facts.facts,
        "constraint_scope": _constraint_scope(facts, graph, inference),
        "performable_by": sorted(name(v) for _, v in inference.pairs(MEO.performableBy)),
        "reasoning": {
            "goals": inference.goals,
            "representatives": inference.representatives,
            "owlrl_triples": inference.owlrl_triples,
        },
    }


class _Facts:
    """The explained facts in the order they are found, each with its rule and premises."""

    def __init__(self, orders: Orders) -> None:
        self.mission = orders.id
        self.facts: list[dict[str, Any]] = []

    def name(self, node: Node) -> str:
        return self.mission if "#" not in str(node) else local_id(node)

    def add(self, s: Node, prop: str, o: Node, rule: str, because: list[list[str]]) -> None:
        self.facts.append({"subject": self.name(s), "property": prop, "object": self.name(o),
                           "rule": rule, "because": because})


def _inclusion_facts(facts: _Facts, inference: Inference) -> None:
    """includes: a start (M4), or a goal reached from the start (G10)."""
    name = facts.name
    reach = inference.reachability
    starts = set(reach.starts)
    for mission, goal in sorted(inference.inferred(MEO.includes), key=_pair_key):
        if goal in starts:
            facts.add(mission, "includes", goal, "M4", [[name(mission), "startsWith", name(goal)]])
        elif goal in reach.reached:
            parent = reach.reached[goal]
            assert parent is not None
            start = next(iter(starts))
            because = [[name(mission), "startsWith", name(start)]]
            because.append([name(parent), "isNext", name(goal)])
            if parent != start:
                because.insert(1, [name(start), "follows", name(parent)])
            facts.add(mission, "includes", goal, "G10", because)


def _application_facts(facts: _Facts, graph: Graph, inference: Inference) -> None:
    """appliesTo through the mission's includes (C3)."""
    name = facts.name
    includes = inference.pairs(MEO.includes)
    for constraint, goal in sorted(inference.inferred(MEO.appliesTo), key=_pair_key):
        via = next(
            (m for m in graph.objects(constraint, MEO.appliesTo) if (m, goal) in includes),
            None,
        )
        if via is not None:
            facts.add(constraint, "appliesTo", goal, "C3",
                      [[name(constraint), "appliesTo", name(via)],
                       [name(via), "includes", name(goal)]])


def _vehicle_facts(facts: _Facts, graph: Graph, inference: Inference) -> None:
    """What a vehicle's features give it (V3, V4), its capabilities (V5) and the missions it
    can perform (V2)."""
    name = facts.name
    features = inference.pairs(MEO.hasFeature)
    for prop, via, rule in (
        (MEO.meetsRequirement, MEO.canFulfill, "V3"),
        (MEO.canIdentify, MEO.canTest, "V4"),
    ):
        linked = inference.pairs(via)
        for vehicle, target in sorted(inference.pairs(prop), key=_pair_key):
            witness = next(
                (f for v, f in sorted(features, key=_pair_key)
                 if v == vehicle and (f, target) in linked),
                None,
            )
            if witness is not None:
                facts.add(vehicle, str(prop).rsplit("#", 1)[1], target, rule,
                          [[name(vehicle), "hasFeature", name(witness)],
                           [name(witness), str(via).rsplit("#", 1)[1], name(target)]])
    capability = capabilities(graph, inference)
    for vehicle, goal in sorted(capability, key=_pair_key):
        requirements = sorted(name(r) for r in graph.objects(goal, MEO.requires))
        facts.add(vehicle, "hasCapability", goal, "V5",
                  [[name(vehicle), "meetsRequirement", r] for r in requirements]
                  or [[name(goal), "requires", "nothing"]])
    for mission, vehicle in sorted(inference.pairs(MEO.performableBy), key=_pair_key):
        facts.add(vehicle, "canPerform", mission, "V2",
                  [[name(mission), "performableBy", name(vehicle)]])


def _constraint_scope(facts: _Facts, graph: Graph, inference: Inference
                      ) -> dict[str, list[str]]:
    """Each constraint's goals after C3 (an empty list for one that applies to none)."""
    name = facts.name
    scope: dict[str, list[str]] = {}
    declared = set(graph.subjects(RDF.type, MEO.Goal))
    for constraint, target in inference.pairs(MEO.appliesTo):
        if target in declared:
            scope.setdefault(name(constraint), []).append(name(target))
    for constraint in graph.objects(None, MEO.hasConstraint):
        scope.setdefault(name(constraint), [])
    return {c: sorted(g, key=natural_key) for c, g in sorted(scope.items())}


def capabilities(graph: Graph, inference: Inference) -> set[tuple[Node, Node]]:
    """V5 (closed world): a vehicle has the capability for a goal when it meets every
    requirement of the goal."""
    met: dict[Node, set[Node]] = {}
    for vehicle, requirement in inference.pairs(MEO.meetsRequirement):
        met.setdefault(vehicle, set()).add(requirement)
    vehicles = set(graph.subjects(RDF.type, MEO.Vehicle))
    result: set[tuple[Node, Node]] = set()
    goals = set(graph.subjects(RDF.type, MEO.Goal))
    for vehicle in vehicles:
        have = met.get(vehicle, set())
        for goal in goals:
            if all(r in have for r in graph.objects(goal, MEO.requires)):
                result.add((vehicle, goal))
    return result


def _pair_key(pair: tuple[Node, Node]) -> tuple[Any, ...]:
    return (natural_key(str(pair[0])), natural_key(str(pair[1])))


__all__ = ["MeoResult", "capabilities", "explain", "meo_reasoning"]
