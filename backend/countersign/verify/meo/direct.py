"""The four MEO rules no other check covers (C1, C2, M6, M7), read straight from the orders: the
product's one implementation of them.

The MEO route (the RDF graph, owlrl and the closed-world shapes) gave the same findings at 300 to
500 times the cost (measured on this machine: 12 ms against 0.1 ms on the exemplar, 1.4 s against
3 ms at 1,000 goals; 9.6 s at 10,000), for what is a linear pass over constraints, goals and
features; it is kept as the tests' oracle (tests/oracles/meo_route.py). This module evaluates
the same rules on the same facts the MEO route asserts and infers, without a graph:

- includes (M4, G10): every declared goal, the start(s), and what follows a start;
- appliesTo after C3: a constraint's named scopes, and the mission's goals when it applies to
  the mission;
- canIdentify (V4): a feature of the performing vehicle tests the constraint (it measures every
  quantity the expression reads, or lists it in `tests`);
- meetsRequirement (V3): a feature of the performing vehicle fulfils the requirement.

The findings are the very `Finding`s the oracle's `meo_check` gives for these codes, in the same
order (tests/verify/test_meo_direct.py compares both routes on generated and example orders; the
reasoning keeps its own tests proving it equal to owlrl's naive closure).
"""

from __future__ import annotations

from collections import deque
from typing import Any

from ...orders.expressions import expression_quantities
from ...orders.findings import Finding, error
from ...orders.iris import element_iri, first_by_id, local_id, mission_iri, natural_key
from ...orders.model import Constraint, Orders, Vehicle

CODES = frozenset({"C1", "C2", "M6", "M7"})

# The Table 2 rules each finding cites, as ontology/shapes.ttl's shapes of these codes name them
# (`msh:rule`): written here so that a validation does not parse the shapes with rdflib
# (tests/verify/test_meo_direct.py holds the table equal to `shapes.shape_info()`).
RULES: dict[str, tuple[str, ...]] = {
    "C1": ("C1",), "C2": ("C2", "C3"), "M6": ("M6",), "M7": ("M7", "V5"),
}


def meo_only_findings(orders: Orders) -> list[Finding]:
    """The MEO's C1, C2, M6 and M7 findings (as the shapes route would give them), without the
    graph."""
    nodes = _Nodes(orders)
    constraints = first_by_id(orders.constraints)
    findings = _scope_findings(orders, nodes, _includes(orders, nodes), constraints)
    return findings + _vehicle_findings(orders, constraints)


class _Nodes:
    """The orders' elements as (kind, name) nodes, and their IRIs as plain strings: they are
    only compared, sorted and read back as ids here."""

    def __init__(self, orders: Orders) -> None:
        self.orders = orders
        self.goals = orders.goal_index()
        self.terminals = orders.terminal_index()

    def iri(self, kind_and_name: tuple[str, str]) -> str:
        kind, name = kind_and_name
        if kind == "mission":
            return mission_iri(self.orders.id)
        return element_iri(self.orders.id, kind, name)

    def successor(self, name: str) -> tuple[str, str]:
        if name in self.goals:
            return ("goal", name)
        if name in self.terminals:
            return ("terminal", name)
        return ("ref", name)

    def scope(self, name: str) -> tuple[str, str]:
        if name in self.goals:
            return ("goal", name)
        if name == self.orders.id:
            return ("mission", name)
        return self.successor(name)


def _includes(orders: Orders, nodes: _Nodes) -> set[tuple[str, str]]:
    """includes: the declared goals (asserted), the starts (M4) and what follows them (G10)."""
    start = orders.start
    starts = [] if start is None else [start] if isinstance(start, str) else list(start)
    start_nodes = [nodes.successor(s) for s in starts]
    reached: set[tuple[str, str]] = set()
    queue: deque[tuple[str, str]] = deque()

    def visit(source: tuple[str, str]) -> None:
        if source[0] != "goal":
            return  # only goals name successors
        goal = nodes.goals[source[1]]
        for outcome in ("succeed", "fail", "violate"):
            for target in goal.successors(outcome):
                found = nodes.successor(target)
                if found not in reached:
                    reached.add(found)
                    queue.append(found)

    for begin in start_nodes:
        visit(begin)
    while queue:
        visit(queue.popleft())
    includes: set[tuple[str, str]] = {("goal", g) for g in nodes.goals}
    if start_nodes:  # the G10 chain needs a startsWith triple
        includes |= reached
    includes.update(start_nodes)
    return includes


def _details(shape: str, **extra: Any) -> dict[str, Any]:
    return {"rules": list(RULES[shape]), **extra}


def _scope_findings(orders: Orders, nodes: _Nodes, includes: set[tuple[str, str]],
                    constraints: list[Constraint]) -> list[Finding]:
    """C1 (a constraint applies to something that is neither the mission nor its goal) and
    C2 (a constraint applies to no goal)."""
    c1: set[tuple[str, str]] = set()
    c2: set[str] = set()
    for constraint in constraints:
        scopes = ([("mission", orders.id)] if constraint.applies_to == "mission"
                  else [nodes.scope(name) for name in constraint.applies_to])
        to_mission = ("mission", orders.id) in scopes
        for target in scopes:
            if target[0] in ("mission", "goal") or (to_mission and target in includes):
                continue
            c1.add((element_iri(orders.id, "constraint", constraint.id), nodes.iri(target)))
        if not any(t[0] == "goal" for t in scopes) and not (to_mission and nodes.goals):
            c2.add(element_iri(orders.id, "constraint", constraint.id))

    findings: list[Finding] = []
    key = natural_key
    for constraint_iri, scope_iri in sorted(c1, key=lambda p: (key(p[0]), key(p[1]))):
        constraint_id = local_id(constraint_iri)
        scope_id = orders.id if "#" not in scope_iri else local_id(scope_iri)
        findings.append(error(
            "C1", [constraint_id, scope_id],
            f"Constraint {constraint_id} applies to {scope_id}, which is neither the mission "
            "nor one of its goals (rule C1).", **_details("C1")))
    for constraint_iri in sorted(c2, key=key):
        constraint_id = local_id(constraint_iri)
        findings.append(error(
            "C2", [constraint_id],
            f"Constraint {constraint_id} applies to no goal, neither directly nor through the "
            "mission (rules C2 and C3): it would never be monitored.", **_details("C2")))
    return findings


def _vehicle_findings(orders: Orders, constraints: list[Constraint]) -> list[Finding]:
    """M6 (the performing vehicle cannot identify a constraint) and M7 (it lacks a goal's
    capability); none when no listed vehicle performs the mission."""
    vehicle = orders.target_vehicle()
    performer = next((v for v in first_by_id(orders.vehicles) if v is vehicle), None)
    if performer is None:
        return []
    identified: set[str] = set()
    met: set[str] = set()
    reads = {c.id: set(expression_quantities(c.expr)) for c in constraints
             if c.expr is not None}
    for feature in first_by_id(performer.features):
        measured = set(feature.measures)
        identified.update(c for c, read in reads.items() if read <= measured)
        identified.update(feature.tests)
        met.update(feature.fulfills)
    findings: list[Finding] = []
    m6 = {element_iri(orders.id, "constraint", c.id) for c in constraints if c.id not in identified}
    for constraint_iri in sorted(m6, key=natural_key):
        findings.append(_m6(orders, local_id(constraint_iri), vehicle, _details("M6")))
    labels = _labels(orders)

    def say(node_id: str) -> str:
        label = labels.get(node_id)
        return f"{node_id} ({label})" if label and label != node_id else node_id

    m7 = {element_iri(orders.id, "goal", g.id) for g in orders.goal_index().values()
          if any(r not in met for r in g.requires)}
    for goal_iri in sorted(m7, key=natural_key):
        findings.append(_m7(orders, local_id(goal_iri), vehicle, say, _details("M7")))
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


__all__ = ["CODES", "meo_only_findings"]
