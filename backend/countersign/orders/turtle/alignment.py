"""NPS MEO 3.0 names and ours (ontology/nps-meo3-alignment.ttl): the NPS view writes theirs
for ours, the reader renames theirs to ours."""

from __future__ import annotations

from collections.abc import Iterator

from rdflib import Literal, URIRef
from rdflib.namespace import OWL, RDF
from rdflib.term import Node

from ...ontology_files import NPS_ALIGNMENT
from ..ontology import load_graph
from ..rdf_index import TripleIndex
from .vocabulary import MEO, NPS3


def _nps_names() -> dict[Node, list[Node]]:
    """meo: term -> its equivalents in the NPS MEO 3.0 namespace (alignment file), leaving out
    the names the alignment marks owl:deprecated (used by NPS files, not declared by MEO 3.0)."""
    names: dict[Node, list[Node]] = {}
    prefix = str(NPS3).rstrip("#")
    deprecated = set(load_graph(NPS_ALIGNMENT).subjects(OWL.deprecated, Literal(True)))
    for ours, theirs in _equivalences():
        if str(theirs).startswith(prefix) and theirs not in deprecated:
            names.setdefault(ours, []).append(theirs)
    for values in names.values():
        values.sort(key=str)
    return names


def _equivalences() -> Iterator[tuple[Node, Node]]:
    alignment = load_graph(NPS_ALIGNMENT)
    for prop in (OWL.equivalentClass, OWL.equivalentProperty):
        for ours, theirs in alignment.subject_objects(prop):
            if str(ours).startswith(str(MEO)) and isinstance(theirs, URIRef):
                yield ours, theirs


def _align(graph: TripleIndex) -> None:
    """Rename NPS terms to meo: in place."""
    mapping = {theirs: ours for ours, theirs in _equivalences()}
    renamed: list[tuple[tuple[Node, Node, Node], tuple[Node, Node, Node]]] = []
    for theirs, ours in mapping.items():
        renamed.extend(((s, p, o), (s, ours, o)) for s, p, o in graph.triples((None, theirs, None)))
    for s, p, o in list(graph.triples((None, RDF.type, None))):
        if o in mapping:
            renamed.append(((s, p, o), (s, p, mapping[o])))
    for old, new in renamed:
        graph.remove(old)
        graph.add(new)

