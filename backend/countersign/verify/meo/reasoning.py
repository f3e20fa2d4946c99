"""OWL reasoning over the orders graph, staged so that it stays linear in the number of goals.

A naive OWL-RL closure of meo.ttl plus the orders is quadratic or worse (DESIGN.md, "MEO
reasoning: measured on this machine"): `follows` is transitive (G9), so its closure alone holds
about n^2/2 pairs. The facts validation needs are role assertions (includes, appliesTo,
meetsRequirement, canIdentify, performableBy, canPerform), and they come from two kinds of rules:

1. **Graph rules** G8 (isNext implies follows), G9 (follows is transitive) and the chain of G10
   (startsWith o follows implies includes). Evaluated here by a breadth-first search from the
   start over the successor edges, in O(goals + edges), without materialising `follows`.
2. **Role rules** M4 (startsWith implies includes), V2 (performableBy inverse of canPerform),
   V3 and V4 (property chains through hasFeature), C3 (appliesTo o includes implies appliesTo).
   These run in owlrl's OWL 2 RL engine over the role-producing axioms of meo.ttl (sub-property,
   inverse and chain axioms: OWL-RL rules prp-spo1, prp-spo2, prp-inv) and the assertions of the
   properties they mention. Domain, range and class axioms only add rdf:type statements, which
   no role rule of meo.ttl reads (there is no hasValue restriction, functional property, key or
   owl:sameAs), so they are left out of this run.

Goals with the same role assertions (typically: included by the mission, nothing else, or the
same goal-scoped constraints) are interchangeable for every rule above: swapping two of them is
an automorphism of the reasoning graph, and rule application commutes with automorphisms. So
owlrl reasons over one representative per class of such goals and the results are copied back
to every member. The reasoning graph then grows with the mission's distinct kinds of goals, not
with its length.

The textbook route (owlrl over all of meo.ttl and every triple, `naive_closure` in
tests/bench/bench_meo.py) is the oracle: tests prove that both routes give the same facts, and
the benchmark compares their cost.
"""

from __future__ import annotations

import threading
from collections import deque
from collections.abc import Iterable
from dataclasses import dataclass, field

import owlrl
from cachetools import LRUCache
from rdflib import BNode, Graph, URIRef
from rdflib.collection import Collection
from rdflib.namespace import OWL, RDF, RDFS
from rdflib.term import Node

from ...ontology_files import MEO as MEO_FILE
from ...orders.ontology import load_graph
from ...orders.turtle import MEO, NEXT_PROPERTIES
from .owlrl_adapter import RoleSemantics

# Properties whose axioms the graph stage evaluates instead of owlrl.
GRAPH_PROPERTIES = frozenset({MEO.isNext, MEO.follows, *NEXT_PROPERTIES})
ROLE_AXIOMS = (RDFS.subPropertyOf, OWL.inverseOf, OWL.propertyChainAxiom)

# The role assertions explanations and validation read.
FACT_PROPERTIES = (
    MEO.startsWith,
    MEO.includes,
    MEO.hasConstraint,
    MEO.appliesTo,
    MEO.performableBy,
    MEO.canPerform,
    MEO.hasFeature,
    MEO.canFulfill,
    MEO.canTest,
    MEO.meetsRequirement,
    MEO.canIdentify,
    MEO.requires,
)


@dataclass
class Reachability:
    """What the graph stage derives from the successor edges."""

    successors: dict[Node, list[Node]]
    starts: list[Node]
    # Every node that follows some start (G10 chain), with the BFS parent for explanations.
    reached: dict[Node, Node | None]
    # Strongly connected components with a cycle: their members follow themselves (G7 after
    # G8, G9).
    cycles: list[list[Node]]


@dataclass
class Inference:
    """Role assertions after reasoning: asserted plus inferred, as sets of (subject, object)."""

    facts: dict[URIRef, set[tuple[Node, Node]]]
    reachability: Reachability
    representatives: int = 0
    goals: int = 0
    owlrl_triples: int = 0
    asserted: dict[URIRef, set[tuple[Node, Node]]] = field(default_factory=dict)

    def pairs(self, prop: URIRef) -> set[tuple[Node, Node]]:
        return self.facts.get(prop, set())

    def objects(self, subject: Node, prop: URIRef) -> list[Node]:
        return [o for s, o in self.pairs(prop) if s == subject]

    def inferred(self, prop: URIRef) -> set[tuple[Node, Node]]:
        return self.pairs(prop) - self.asserted.get(prop, set())


def role_tbox() -> Graph:
    """The role-producing axioms of meo.ttl, minus those of the graph properties."""
    meo = load_graph(MEO_FILE)
    tbox = Graph()
    for prop in ROLE_AXIOMS:
        for s, o in meo.subject_objects(prop):
            if isinstance(s, BNode) or s in GRAPH_PROPERTIES:
                continue
            if prop == OWL.propertyChainAxiom:
                chain = list(Collection(meo, o))
                if any(link in GRAPH_PROPERTIES for link in chain):
                    continue
                head = BNode()
                Collection(tbox, head, chain)
                tbox.add((s, prop, head))
            elif o not in GRAPH_PROPERTIES:
                tbox.add((s, prop, o))
    return tbox


_ROLE_TBOX: Graph | None = None


def _cached_tbox() -> Graph:
    global _ROLE_TBOX
    if _ROLE_TBOX is None:
        _ROLE_TBOX = role_tbox()
    return _ROLE_TBOX


def _role_properties(tbox: Graph) -> set[Node]:
    props: set[Node] = set()
    for s, p, o in tbox:
        if p == OWL.propertyChainAxiom:
            props.add(s)
            props.update(Collection(tbox, o))
        elif p in (RDFS.subPropertyOf, OWL.inverseOf):
            props.update((s, o))
    return props


def reachability(graph: Graph) -> Reachability:
    """Successor edges, what follows the start goals, and which nodes follow themselves."""
    successors: dict[Node, list[Node]] = {}
    for prop in NEXT_PROPERTIES:
        for s, o in graph.subject_objects(prop):
            successors.setdefault(s, []).append(o)
    starts = list(graph.objects(None, MEO.startsWith))
    reached: dict[Node, Node | None] = {}
    queue: deque[Node] = deque()
    for start in starts:
        for target in successors.get(start, ()):
            if target not in reached:
                reached[target] = start
                queue.append(target)
    while queue:
        node = queue.popleft()
        for target in successors.get(node, ()):
            if target not in reached:
                reached[target] = node
                queue.append(target)
    return Reachability(successors, starts, reached, _cycles(successors))


def _cycles(successors: dict[Node, list[Node]]) -> list[list[Node]]:
    """Strongly connected components that hold a cycle: more than one node, or a self-loop
    (Tarjan's algorithm, iterative)."""
    index: dict[Node, int] = {}
    low: dict[Node, int] = {}
    on_stack: set[Node] = set()
    stack: list[Node] = []
    result: list[list[Node]] = []
    counter = 0
    for root in list(successors):
        if root in index:
            continue
        work: list[tuple[Node, int]] = [(root, 0)]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            node, position = work[-1]
            targets = successors.get(node, [])
            if position < len(targets):
                work[-1] = (node, position + 1)
                target = targets[position]
                if target not in index:
                    index[target] = low[target] = counter
                    counter += 1
                    stack.append(target)
                    on_stack.add(target)
                    work.append((target, 0))
                elif target in on_stack:
                    low[node] = min(low[node], index[target])
                continue
            work.pop()
            if work:
                parent = work[-1][0]
                low[parent] = min(low[parent], low[node])
            if low[node] == index[node]:
                component: list[Node] = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1 or node in successors.get(node, []):
                    result.append(component)
    return result


# infer() reads only these predicates of the orders graph (successor edges, start, the role
# facts and rdf:type), so its result is a pure function of those triples: an edit that changes
# titles, descriptions, parameters or expressions reuses the reasoning. Inference objects are
# never mutated after infer() returns, so cached ones are shared.
_INFER_INPUTS = frozenset((*NEXT_PROPERTIES, MEO.startsWith, *FACT_PROPERTIES, RDF.type))
_INFER_CACHE_SIZE = 128
_INFER_CACHE: LRUCache[frozenset[tuple[Node, Node, Node]], Inference] = \
    LRUCache(_INFER_CACHE_SIZE)
_INFER_LOCK = threading.Lock()


def _infer_key(graph: Graph) -> frozenset[tuple[Node, Node, Node]] | None:
    """The triples infer() reads, compared exactly (no digest that could collide)."""
    triples = []
    for prop in _INFER_INPUTS:
        for s, o in graph.subject_objects(prop):
            if isinstance(s, BNode) or isinstance(o, BNode):
                return None  # blank node labels differ between graphs: no stable key
            triples.append((s, prop, o))
    return frozenset(triples)


def infer(graph: Graph) -> Inference:
    """Staged reasoning over an orders graph (see the module docstring), cached per content of
    the triples it reads."""
    key = _infer_key(graph)
    if key is not None:
        with _INFER_LOCK:
            cached = _INFER_CACHE.get(key)
            if cached is not None:
                return cached
    result = _infer(graph)
    if key is not None:
        with _INFER_LOCK:
            _INFER_CACHE[key] = result
    return result


def _infer(graph: Graph) -> Inference:
    reach = reachability(graph)
    tbox = _cached_tbox()
    roles = _role_properties(tbox)
    abox = Graph()
    asserted: dict[URIRef, set[tuple[Node, Node]]] = {p: set() for p in FACT_PROPERTIES}
    for prop in FACT_PROPERTIES:
        pairs = asserted[prop]
        for s, o in graph.subject_objects(prop):
            pairs.add((s, o))
            if prop in roles:
                abox.add((s, prop, o))
    # G10 chain, evaluated by the graph stage: startsWith o follows implies includes.
    for mission in set(graph.subjects(MEO.startsWith, None)):
        for node in reach.reached:
            abox.add((mission, MEO.includes, node))

    goals = set(graph.subjects(RDF.type, MEO.Goal)) | set(graph.subjects(RDF.type, MEO.Terminal))
    goals |= set(abox.objects(None, MEO.includes))
    members = _interchangeable(abox, goals)
    representative = {m: rep for rep, group in members.items() for m in group}
    reduced = Graph()
    for s, p, o in abox:
        if (s in representative and representative[s] != s) or (
            o in representative and representative[o] != o
        ):
            continue
        reduced.add((s, p, o))
    for triple in tbox:
        reduced.add(triple)
    owlrl.DeductiveClosure(
        RoleSemantics, axiomatic_triples=False, datatype_axioms=False
    ).expand(reduced)

    facts: dict[URIRef, set[tuple[Node, Node]]] = {p: set() for p in FACT_PROPERTIES}
    for prop in FACT_PROPERTIES:
        pairs = facts[prop]
        for s, o in reduced.subject_objects(prop):
            for subject in members.get(s, (s,)):
                for obj in members.get(o, (o,)):
                    pairs.add((subject, obj))
        pairs.update(asserted.get(prop, ()))
    return Inference(
        facts,
        reach,
        representatives=len(members),
        goals=len(goals),
        owlrl_triples=len(reduced),
        asserted=asserted,
    )


def _interchangeable(abox: Graph, goals: Iterable[Node]) -> dict[Node, list[Node]]:
    """Classes of goals with identical role assertions: representative -> members. A goal
    linked to another goal is left alone (it would not be interchangeable)."""
    goal_set = set(goals)
    signature: dict[Node, list[tuple[str, Node, Node]]] = {g: [] for g in goal_set}
    linked: set[Node] = set()
    for s, p, o in abox:
        if s in goal_set:
            signature[s].append(("out", p, o))
            if o in goal_set:
                linked.update((s, o))
        if o in goal_set:
            signature[o].append(("in", p, s))
    groups: dict[object, list[Node]] = {}
    for goal in goal_set:
        key: object = ("alone", goal) if goal in linked else frozenset(signature[goal])
        groups.setdefault(key, []).append(goal)
    result: dict[Node, list[Node]] = {}
    for group in groups.values():
        group.sort(key=str)
        result[group[0]] = group
    return result
