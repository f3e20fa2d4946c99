"""The ontology files (`ontology_files`) as rdflib graphs, parsed once per process.

Here, in `orders`, rather than in the leaf `ontology_files`, because the parser is the orders'
own (`rdf_index`): the leaf only finds the files and imports nothing of ours.
"""

from __future__ import annotations

import re
from functools import cache

from rdflib import Graph

from ..ontology_files import ontology_path
from .rdf_index import parse_turtle


@cache
def load_graph(name: str) -> Graph:
    """One ontology file, parsed once per process. Callers must not modify the result.

    Oxigraph parses the Turtle (orders/rdf_index.py), about ten times faster than rdflib's
    parser: a quarter of the MEO check of `countersign validate` went to reading these files.
    The graph holds the same statements (tests/core/test_ontology_files.py)."""
    path = ontology_path(name)
    graph = Graph()
    graph.addN((s, p, o, graph) for s, p, o in parse_turtle(path.read_bytes()))
    for prefix, namespace in _prefixes(path.read_text(encoding="utf-8")):
        graph.bind(prefix, namespace, override=True)
    return graph


def _prefixes(text: str) -> list[tuple[str, str]]:
    """The document's @prefix declarations (for serialising the graph with its own names)."""
    return re.findall(r"^\s*@prefix\s+([\w-]*):\s*<([^>]*)>\s*\.", text, flags=re.MULTILINE)
