"""The ontology files read by Oxigraph (orders.ontology.load_graph) hold the
statements rdflib's own Turtle parser reads from them, blank nodes and collections included."""

from __future__ import annotations

import pytest
from rdflib import Graph
from rdflib.compare import isomorphic

from countersign.ontology_files import MEO, NPS_ALIGNMENT, ontology_path
from countersign.orders.ontology import load_graph

from ..oracles.shape_info import SHAPES


@pytest.mark.parametrize("name", [MEO, SHAPES, NPS_ALIGNMENT])
def test_oxigraph_reads_the_statements_rdflib_reads(name: str) -> None:
    reference = Graph().parse(ontology_path(name), format="turtle")
    loaded = load_graph(name)
    assert len(loaded) == len(reference) > 0
    assert isomorphic(loaded, reference)
    assert dict(loaded.namespaces()).get("meo") == dict(reference.namespaces()).get("meo")


def test_shacl_validation_leaves_the_shared_shapes_graph_as_parsed() -> None:
    from ..oracles.meo_shapes import shacl_violations

    before = set(load_graph(SHAPES))
    shacl_violations(Graph())
    assert set(load_graph(SHAPES)) == before
