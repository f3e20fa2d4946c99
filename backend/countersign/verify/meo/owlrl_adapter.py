"""owlrl's private API, in one place (owlrl pinned <7.7 in pyproject).

owlrl has no option to leave out rule eq-ref; overriding its private `_equality` hook is the
one way. tests/codebase/test_private_apis.py fails first when owlrl renames or reshapes it, and
tests/verify (the MEO route against the unmodified closure) when its meaning changes."""

from __future__ import annotations

import owlrl
from rdflib.namespace import OWL, RDF
from rdflib.term import Node


class RoleSemantics(owlrl.OWLRL_Semantics):  # type: ignore[misc]
    """OWL 2 RL as owlrl implements it, without rule eq-ref alone.

    eq-ref states `x owl:sameAs x` for every term of every triple: true of any graph, and no
    other rule derives anything new from it (eq-rep-* with x = y rewrite a triple into itself).
    owlrl stores those statements anyway, which doubles the graph every cycle walks; skipping
    them halves the reasoning time and changes no role assertion (the tests compare with the
    unmodified closure). Triples about equality itself still get the full eq-* rules.
    """

    def _equality(self, triple: tuple[Node, Node, Node], cycle_num: int) -> None:
        _s, p, o = triple
        if p in (OWL.sameAs, OWL.differentFrom) or (p == RDF.type and o == OWL.AllDifferent):
            super()._equality(triple, cycle_num)
