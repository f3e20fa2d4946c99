"""Oracle: the MEO route to findings, as the product had it before the report took C1, C2, M6
and M7 straight from the orders (countersign.verify.meo.direct): the orders as RDF, the reasoning
of countersign.verify.meo (the product keeps that for its explanation), the closed-world shapes
(tests/oracles/meo_shapes.py, natively or by pySHACL) and a finding per violation.

    result = meo_check(orders)          # findings with DESIGN.md codes, each citing its rule
    result.findings                     # list[Finding]
    result.explanation                  # the product's explanation of the same reasoning

The tests hold the product to it: the direct route gives the same C1, C2, M6 and M7 findings
(tests/verify/test_meo_direct.py), the structural check the same verdicts on M1, M2, G3, G5, SINK,
G7 and G10 (tests/verify/test_meo.py, tests/orders/test_nps_turtle.py). Two differences from
the structural check are by construction: a start given as a one-element list is a JSON-format M1
the MEO cannot see (it sees one start goal); loops are reported per strongly connected component
here and per elementary cycle there (the goals on loops are the same). DUP is not an MEO rule (an
RDF graph cannot hold two elements with one IRI).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, Literal

from rdflib import Graph
from rdflib.namespace import RDF
from rdflib.term import Node

from countersign.orders.findings import Finding, error
from countersign.orders.model import Orders, Vehicle
from countersign.orders.turtle import MEO, OUTCOME_PROPERTY, local_id, natural_key
from countersign.verify.meo.direct import _labels, _m6, _m7
from countersign.verify.meo.reasoned import explain, meo_reasoning
from countersign.verify.meo.reasoning import Inference

from .meo_shapes import Violation, native_violations, shacl_violations, validation_graph
from .shape_info import shape_info

Engine = Literal["native", "shacl"]

CODE_ORDER = ("M1", "M2", "G3", "G5", "SINK", "G7", "G10", "C1", "C2", "M6", "M7")
OUTCOME_PHRASE = {
    "succeed": "succeeds",
    "fail": "fails",
    "violate": "ends with an imminent constraint violation",
}


@dataclass
class RouteResult:
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
        return explain(self.orders, self.graph, self.inference, self.engine)


def meo_check(
    orders: Orders, *, vehicle: Vehicle | None = None, engine: Engine = "native"
) -> RouteResult:
    """Validate orders against the MEO: findings (DESIGN.md codes) and an explanation."""
    reasoned = meo_reasoning(orders, vehicle=vehicle)
    data = validation_graph(reasoned.graph, reasoned.inference)
    violations = (
        shacl_violations(data) if engine == "shacl"
        else native_violations(data, reasoned.inference)
    )
    findings = findings_from(reasoned.orders, reasoned.graph, reasoned.inference, violations)
    return RouteResult(reasoned.orders, findings, violations, reasoned.graph,
                       reasoned.inference, engine)


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


def _key(node: Node | None) -> tuple[Any, ...]:
    return natural_key(str(node)) if node is not None else ()


def _mission(graph: Graph) -> Node | None:
    return next(iter(graph.subjects(RDF.type, MEO.Mission)), None)
