"""The NPS MEO 3.0 view of the orders (`nps_graph`, `write_nps_turtle`): written, never read
back losslessly."""

from __future__ import annotations

from rdflib import Graph, Literal, URIRef
from rdflib.namespace import OWL, RDF, RDFS
from rdflib.term import Node

from ..model import Orders
from .alignment import _nps_names
from .graph import orders_to_graph
from .syntax import serialize_turtle
from .vocabulary import (
    MEO,
    NPS3,
    MissionIris,
)


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
