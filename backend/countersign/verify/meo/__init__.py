"""Semantic validation of orders against the Mission Execution Ontology (seed 000, Table 2).

    result = meo_check(orders)          # findings with DESIGN.md codes, each citing its rule
    result.findings                     # list[Finding]
    result.explanation                  # why: the inferred facts that matter, JSON-able

The pipeline, and why it is shaped this way (DESIGN.md, "MEO reasoning: measured"):

1. **Orders to RDF** (`countersign.orders.turtle.orders_to_graph`): the MEO meaning of the
   orders, with stable IRIs per mission id and element.
2. **Reasoning** (`reasoning.infer`): the graph rules G8, G9 and the chain of G10 by a search
   over the successor edges (no quadratic `follows` closure); the role rules M4, V2, V3, V4 and
   C3 by owlrl's OWL 2 RL engine over the role axioms of ontology/meo.ttl, on one representative
   per class of interchangeable goals. Tests prove the facts equal owlrl's naive full closure.
3. **Closed-world rules** (`shapes`): ontology/shapes.ttl (M1, M2, SINK/G4, G3, G5, G7, G10, C1,
   C2, M6, M7/V5) evaluated natively (default, linear) or by pySHACL (`engine="shacl"`, for
   audits and the equivalence tests: about a second per 100 goals).
4. **Findings**: each violation becomes a finding with the DESIGN.md code its shape names and
   `details["rules"]` listing the Table 2 rules involved.

The structural module (`verify.structure`) is an independent route to the verdicts on M1, M2,
G3, G5, SINK, G7 and G10; tests require both to agree on every input of the suite. Two
differences are by construction: a start given as a one-element list is a JSON-format M1 the
MEO cannot see (it sees one start goal); loops are reported per strongly connected component
here and per elementary cycle there (the goals on loops are the same). DUP is not an MEO rule
(an RDF graph cannot hold two elements with one IRI): the structural check reports it.
C1, C2, M6 and M7 are checked only here.

A vehicle profile is checked (M6, M7) when the orders carry the profile of their target vehicle;
pass `vehicle=` to check a profile from the server's registry.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, Literal

from rdflib import Graph
from rdflib.namespace import RDF
from rdflib.term import Node

from ...orders.expressions import expression_quantities
from ...orders.findings import Finding, error
from ...orders.model import Orders, Vehicle
from ...orders.turtle import (
    MEO,
    OUTCOME_PROPERTY,
    local_id,
    natural_key,
    orders_to_graph,
)
from .reasoning import Inference, infer
from .shapes import (
    Violation,
    native_violations,
    shacl_violations,
    shape_info,
    validation_graph,
)

Engine = Literal["native", "shacl"]

CODE_ORDER = ("M1", "M2", "G3", "G5", "SINK", "G7", "G10", "C1", "C2", "M6", "M7")
OUTCOME_PHRASE = {
    "succeed": "succeeds",
    "fail": "fails",
    "violate": "ends with an imminent constraint violation",
}


@dataclass
class MeoResult:
    orders: Orders
    findings: list[Finding]
    violations: set[Violation]
    graph: Graph = field(repr=False)
    inference: Inference = field(repr=False)
    engine: Engine = "native"

    @property
    def ok(self) -> bool:
        return not any(f.severity == "error" for f in self.findings)

    @cached_property
    def explanation(self) -> dict[str, Any]:
        """The inferred facts that matter, each with the rule and the facts it follows from."""
        return explain(self.orders, self.graph, self.inference, self.engine)


def meo_check(
    orders: Orders, *, vehicle: Vehicle | None = None, engine: Engine = "native"
) -> MeoResult:
    """Validate orders against the MEO: findings (DESIGN.md codes) and an explanation."""
    if vehicle is not None and orders.target_vehicle() is None:
        orders = orders.model_copy(
            update={"vehicles": [*orders.vehicles, vehicle], "vehicle": vehicle.id}
        )
    graph = orders_to_graph(orders, record=False)
    inference = infer(graph)
    data = validation_graph(graph, inference)
    violations = (
        shacl_violations(data) if engine == "shacl" else native_violations(data, inference)
    )
    findings = findings_from(orders, graph, inference, violations)
    return MeoResult(orders, findings, violations, graph, inference, engine)


# --------------------------------------------------------------------------------------------
# Findings


def findings_from(
    orders: Orders, graph: Graph, inference: Inference, violations: Iterable[Violation]
) -> list[Finding]:
    """Findings (DESIGN.md codes, `details["rules"]` the Table 2 rules) from shape violations,
    in a stable order; the same for both engines."""
    info = shape_info()
    by_shape: dict[str, list[Violation]] = {}
    for violation in sorted(violations, key=lambda v: (v.shape, _key(v.focus), _key(v.value))):
        by_shape.setdefault(violation.shape, []).append(violation)
    labels = _labels(orders)
    vehicle = orders.target_vehicle()
    findings: list[Finding] = []

    def name(node: Node | None) -> str:
        if node is None:
            return ""
        return orders.id if "#" not in str(node) else local_id(node)

    def say(node_id: str) -> str:
        label = labels.get(node_id)
        return f"{node_id} ({label})" if label and label != node_id else node_id

    def details(shape: str, **extra: Any) -> dict[str, Any]:
        rules = list(info[shape].rules)
        return {"rules": rules, **extra}

    # M1
    counted = by_shape.get("M1-count", [])
    for violation in counted:
        starts = sorted((name(s) for s in graph.objects(violation.focus, MEO.startsWith)),
                        key=natural_key)
        if not starts:
            findings.append(error("M1", [orders.id], "The orders name no start goal: a mission "
                                  "starts with exactly one goal (rule M1).",
                                  **details("M1-count")))
        else:
            findings.append(error(
                "M1", starts,
                f"The orders name {len(starts)} start goals ({', '.join(starts)}); a mission "
                "starts with exactly one goal (rule M1).", **details("M1-count")))
    if not counted:
        terminals = {t.id for t in orders.effective_terminals}
        for violation in by_shape.get("M1-goal", []):
            start = name(violation.focus)
            why = "a terminal, not a goal" if start in terminals and "/terminal#" in str(
                violation.focus) else "not a goal of these orders"
            findings.append(error("M1", [start], f"The start goal {start} is {why}: a mission "
                                  "can only start with one of its goals (rule M1).",
                                  **details("M1-goal")))
    for _ in by_shape.get("M2", []):
        findings.append(error("M2", [orders.id], "The orders include no goal: there is nothing "
                              "to execute (rule M2).", **details("M2")))
    # G3, G5
    for outcome, prop in OUTCOME_PROPERTY.items():
        for violation in by_shape.get(f"G3-{outcome}", []):
            goal, target = name(violation.focus), name(violation.value)
            findings.append(error(
                "G3", [goal, target],
                f"When goal {say(goal)} {OUTCOME_PHRASE[outcome]}, the orders continue with "
                f"{target}, which is neither a goal nor a terminal of the orders (rule G3).",
                **details(f"G3-{outcome}", outcome=outcome)))
        for violation in by_shape.get(f"G5-{outcome}", []):
            goal = name(violation.focus)
            targets = sorted((name(t) for t in graph.objects(violation.focus, prop)),
                             key=natural_key)
            findings.append(error(
                "G5", [goal, *targets],
                f"Goal {say(goal)} names {len(targets)} next steps when it "
                f"{OUTCOME_PHRASE[outcome]} ({', '.join(targets)}); it may name at most one "
                "(rule G5).", **details(f"G5-{outcome}", outcome=outcome)))
    # SINK (G4)
    sinks = [(v, o) for o in OUTCOME_PROPERTY for v in by_shape.get(f"SINK-{o}", [])]
    for violation, outcome in sorted(sinks, key=lambda x: (_key(x[0].focus),
                                                           list(OUTCOME_PROPERTY).index(x[1]))):
        goal = name(violation.focus)
        findings.append(error(
            "SINK", [goal],
            f"Goal {say(goal)} says nothing about what comes next when it "
            f"{OUTCOME_PHRASE[outcome]}: every end condition of a goal needs a next goal or a "
            "terminal (rule G4).", **details(f"SINK-{outcome}", outcome=outcome)))
    # G7: one finding per strongly connected component of goals that follow themselves.
    looping = {v.focus for v in by_shape.get("G7", [])}
    for component in inference.reachability.cycles:
        members = sorted((name(n) for n in component if n in looping), key=natural_key)
        if not members:
            continue
        if len(members) == 1:
            text = f"Goal {say(members[0])} follows itself: the mission can loop back to it"
        else:
            text = (f"Goals {', '.join(members)} follow themselves: each can come after "
                    "itself through the others")
        findings.append(error(
            "G7", members,
            f"{text} (rule G7, with G8 and G9: follows is the transitive closure of isNext). "
            "A strategic-level mission must not loop.", **details("G7")))
    # G10
    for violation in by_shape.get("G10", []):
        goal = name(violation.focus)
        start = name(graph.value(_mission(graph), MEO.startsWith))
        findings.append(error(
            "G10", [goal],
            f"Goal {say(goal)} can never run: it does not follow the start goal {start} "
            "(rule G10: a mission includes exactly the goals that follow its start).",
            **details("G10")))
    # C1, C2
    for violation in by_shape.get("C1", []):
        constraint, scope = name(violation.focus), name(violation.value)
        findings.append(error(
            "C1", [constraint, scope],
            f"Constraint {constraint} applies to {scope}, which is neither the mission nor one "
            "of its goals (rule C1).", **details("C1")))
    for violation in by_shape.get("C2", []):
        constraint = name(violation.focus)
        findings.append(error(
            "C2", [constraint],
            f"Constraint {constraint} applies to no goal, neither directly nor through the "
            "mission (rules C2 and C3): it would never be monitored.", **details("C2")))
    # M6, M7
    for violation in by_shape.get("M6", []):
        constraint_id = name(violation.value)
        findings.append(_m6(orders, constraint_id, vehicle, details("M6")))
    for violation in by_shape.get("M7", []):
        findings.append(_m7(orders, name(violation.value), vehicle, say, details("M7")))
    findings.sort(key=lambda f: CODE_ORDER.index(f.code) if f.code in CODE_ORDER else 99)
    return findings


def _m6(
    orders: Orders, constraint_id: str, vehicle: Vehicle | None, details: dict[str, Any]
) -> Finding:
    constraint = next(c for c in orders.constraints if c.id == constraint_id)
    reads = expression_quantities(constraint.expr)
    vehicle_id = vehicle.id if vehicle else ""
    measured = sorted({q for f in (vehicle.features if vehicle else []) for q in f.measures})
    if constraint.expr is None:
        why = "it has no expression, so no feature can be shown to test it"
    elif not (vehicle and vehicle.features):
        why = "the vehicle profile lists no features"
    else:
        missing = [q for q in reads if q not in measured]
        if missing:
            why = f"no feature measures {', '.join(missing)}"
        else:
            why = (f"no single feature measures all of {', '.join(reads)} (a feature can test a "
                   "constraint when it measures every quantity the constraint reads)")
    return error(
        "M6", [constraint_id, vehicle_id],
        f"Vehicle {vehicle_id} cannot identify constraint {constraint_id}: {why} "
        "(rule M6, with V4 and F2).",
        **details, reads=reads, measured=measured,
    )


def _m7(
    orders: Orders, goal_id: str, vehicle: Vehicle | None, say: Any, details: dict[str, Any]
) -> Finding:
    goal = orders.goal_index()[goal_id]
    fulfilled = {r for f in (vehicle.features if vehicle else []) for r in f.fulfills}
    unmet = [r for r in dict.fromkeys(goal.requires) if r not in fulfilled]
    vehicle_id = vehicle.id if vehicle else ""
    return error(
        "M7", [goal_id, vehicle_id],
        f"Vehicle {vehicle_id} lacks the capability for goal {say(goal_id)}: no feature "
        f"fulfils {', '.join(unmet)} (rule M7, with V3 and V5).",
        **details, unmet=unmet,
    )


def _labels(orders: Orders) -> dict[str, str]:
    labels = {t.id: t.label for t in orders.effective_terminals}
    labels.update({g.id: g.label for g in orders.goals})
    return labels


def _key(node: Node | None) -> tuple[Any, ...]:
    return natural_key(str(node)) if node is not None else ()


def _mission(graph: Graph) -> Node | None:
    return next(iter(graph.subjects(RDF.type, MEO.Mission)), None)


# --------------------------------------------------------------------------------------------
# Explanation


def explain(orders: Orders, graph: Graph, inference: Inference, engine: str) -> dict[str, Any]:
    """Inferred facts with their rule and premises, the scope of every constraint after C3, and
    what the reasoner worked on. Element ids stand for IRIs; the mission is its id."""

    def name(node: Node) -> str:
        return orders.id if "#" not in str(node) else local_id(node)

    facts: list[dict[str, Any]] = []

    def fact(s: Node, prop: str, o: Node, rule: str, because: list[list[str]]) -> None:
        facts.append({"subject": name(s), "property": prop, "object": name(o), "rule": rule,
                      "because": because})

    reach = inference.reachability
    starts = set(reach.starts)
    for mission, goal in sorted(inference.inferred(MEO.includes), key=_pair_key):
        if goal in starts:
            fact(mission, "includes", goal, "M4", [[name(mission), "startsWith", name(goal)]])
        elif goal in reach.reached:
            parent = reach.reached[goal]
            assert parent is not None
            start = next(iter(starts))
            because = [[name(mission), "startsWith", name(start)]]
            because.append([name(parent), "isNext", name(goal)])
            if parent != start:
                because.insert(1, [name(start), "follows", name(parent)])
            fact(mission, "includes", goal, "G10", because)
    includes = inference.pairs(MEO.includes)
    for constraint, goal in sorted(inference.inferred(MEO.appliesTo), key=_pair_key):
        via = next(
            (m for m in graph.objects(constraint, MEO.appliesTo) if (m, goal) in includes),
            None,
        )
        if via is not None:
            fact(constraint, "appliesTo", goal, "C3",
                 [[name(constraint), "appliesTo", name(via)],
                  [name(via), "includes", name(goal)]])
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
                fact(vehicle, str(prop).rsplit("#", 1)[1], target, rule,
                     [[name(vehicle), "hasFeature", name(witness)],
                      [name(witness), str(via).rsplit("#", 1)[1], name(target)]])
    capability = capabilities(graph, inference)
    for vehicle, goal in sorted(capability, key=_pair_key):
        requirements = sorted(name(r) for r in graph.objects(goal, MEO.requires))
        fact(vehicle, "hasCapability", goal, "V5",
             [[name(vehicle), "meetsRequirement", r] for r in requirements]
             or [[name(goal), "requires", "nothing"]])
    for mission, vehicle in sorted(inference.pairs(MEO.performableBy), key=_pair_key):
        fact(vehicle, "canPerform", mission, "V2",
             [[name(mission), "performableBy", name(vehicle)]])

    scope: dict[str, list[str]] = {}
    declared = set(graph.subjects(RDF.type, MEO.Goal))
    for constraint, target in inference.pairs(MEO.appliesTo):
        if target in declared:
            scope.setdefault(name(constraint), []).append(name(target))
    for constraint in graph.objects(None, MEO.hasConstraint):
        scope.setdefault(name(constraint), [])
    return {
        "mission": orders.id,
        "engine": engine,
        "facts": facts,
        "constraint_scope": {c: sorted(g, key=natural_key) for c, g in sorted(scope.items())},
        "performable_by": sorted(name(v) for _, v in inference.pairs(MEO.performableBy)),
        "reasoning": {
            "goals": inference.goals,
            "representatives": inference.representatives,
            "owlrl_triples": inference.owlrl_triples,
        },
    }


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


__all__ = ["Engine", "MeoResult", "capabilities", "explain", "findings_from", "meo_check"]
