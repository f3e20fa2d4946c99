"""Typing rules of RDF input (`typing_findings`): statements that contradict a domain or range
of meo.ttl, reported as findings of the violated rule."""

from __future__ import annotations

from rdflib import Graph, URIRef
from rdflib.collection import Collection
from rdflib.namespace import OWL, RDF, RDFS
from rdflib.term import Node

from ...ontology_files import MEO as MEO_FILE
from ..findings import Finding, error
from ..ontology import load_graph
from ..rdf_index import TripleIndex
from .vocabulary import (
    MEO,
    local_id,
)


def typing_findings(graph: TripleIndex) -> list[Finding]:
    """Statements of a Turtle input that contradict a domain or range of meo.ttl: the subject
    or object is asserted to be of a class disjoint with the one the rule requires (under OWL
    the ontology would be inconsistent). Each finding's code is the rule of the violated axiom
    (M1, M2, M3, M5, V1, F1, F2, G1, G2, G3, G6, C1, ...); also G4 for a successor given
    without an end condition and EC1 for an end condition other than SUCCEED, FAIL, VIOLATE.
    Orders cannot express these mistakes, so they exist only in RDF input."""
    meo = load_graph(MEO_FILE)
    return _axiom_findings(graph, meo, _Hierarchy(meo)) + _end_condition_findings(graph)


class _Hierarchy:
    """meo.ttl's class and property hierarchy, and its disjoint classes."""

    def __init__(self, meo: Graph) -> None:
        self.superclasses: dict[Node, set[Node]] = {}
        for sub, sup in meo.subject_objects(RDFS.subClassOf):
            if isinstance(sup, URIRef):
                self.superclasses.setdefault(sub, set()).add(sup)
        self.disjoint: set[tuple[Node, Node]] = set()
        for group in meo.subjects(RDF.type, OWL.AllDisjointClasses):
            head = meo.value(group, OWL.members)
            members = list(Collection(meo, head)) if head is not None else []
            self.disjoint.update((a, b) for a in members for b in members if a != b)
        self.subproperties: dict[Node, set[Node]] = {}
        for sub, sup in meo.subject_objects(RDFS.subPropertyOf):
            self.subproperties.setdefault(sup, set()).add(sub)

    def classes(self, graph: TripleIndex, node: Node) -> set[Node]:
        """The node's asserted classes and their superclasses."""
        found = set(graph.objects(node, RDF.type))
        for cls in list(found):
            found |= self.superclasses.get(cls, set())
        return found

    def with_subproperties(self, prop: Node) -> set[Node]:
        result, todo = {prop}, [prop]
        while todo:
            for sub in self.subproperties.get(todo.pop(), ()):
                if sub not in result:
                    result.add(sub)
                    todo.append(sub)
        return result


def _axiom_findings(graph: TripleIndex, meo: Graph, hierarchy: _Hierarchy) -> list[Finding]:
    """A finding per node of a class disjoint with a domain or range axiom's class, once per
    rule, node and class."""
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
        for used in hierarchy.with_subproperties(prop):
            for s, o in graph.subject_objects(used):
                node = s if kind == RDFS.domain else o
                for cls in hierarchy.classes(graph, node):
                    if ((cls, required) in hierarchy.disjoint
                            and (rule, str(node), str(cls)) not in seen):
                        seen.add((rule, str(node), str(cls)))
                        role = "subject" if kind == RDFS.domain else "object"
                        findings.append(error(
                            rule, [local_id(s), local_id(o)],
                            f"{local_id(s)} {local_id(used)} {local_id(o)}: the {role} "
                            f"{local_id(node)} is a {local_id(cls)}, but {local_id(used)} needs a "
                            f"{local_id(required)} (rule {rule}).",
                            property=local_id(used),
                        ))
    return findings


def _end_condition_findings(graph: TripleIndex) -> list[Finding]:
    """G4: a successor without an end condition; EC1: an end condition that is not one."""
    findings: list[Finding] = []
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
