"""Our Turtle the slow way, through rdflib terms and the generic writer: the tests' reference
for the text writer (the same statements) and the benchmark's baseline."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from rdflib import URIRef
from rdflib.namespace import OWL, RDF, RDFS, XSD
from rdflib.term import Node

from countersign.orders.model import Orders
from countersign.orders.turtle.graph import fill_graph
from countersign.orders.turtle.syntax import serialize_turtle


class TripleSet:
    """The part of rdflib's Graph that the orders writers use (add, bind), as an ordered set of
    triples: a tenth of the cost of a Graph's indexes for output that is never queried."""

    def __init__(self) -> None:
        self._triples: dict[tuple[Node, Node, Node], None] = {}
        self._namespaces: dict[str, URIRef] = {
            "rdf": URIRef(str(RDF)), "rdfs": URIRef(str(RDFS)), "xsd": URIRef(str(XSD)),
            "owl": URIRef(str(OWL)),
        }

    def add(self, triple: tuple[Node, Node, Node]) -> None:
        self._triples[triple] = None

    def bind(self, prefix: str, namespace: Any) -> None:
        self._namespaces[prefix] = URIRef(str(namespace))

    def namespaces(self) -> Iterator[tuple[str, URIRef]]:
        return iter(self._namespaces.items())

    def __iter__(self) -> Iterator[tuple[Node, Node, Node]]:
        return iter(self._triples)

    def __len__(self) -> int:
        return len(self._triples)


def write_turtle_via_graph(orders: Orders) -> str:
    """The same statements as `write_turtle`, through rdflib terms and the generic writer."""
    triples = TripleSet()
    fill_graph(triples, orders, record=True)
    return serialize_turtle(triples)
