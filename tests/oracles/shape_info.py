"""The closed-world rules' labels: ontology/shapes.ttl names, for every shape, the finding code
and the Table 2 rules it checks; a finding cites them in `details["rules"]` (the product keeps
the rules of the codes it reports in a table, `verify.meo.direct.RULES`, which the tests hold
to this reading).

The rules themselves are checked directly: C1, C2, M6 and M7 by `direct.py`, the structural
rules by `countersign.verify.structure`. The shapes' own evaluation (natively and by pySHACL) is
the oracle the tests hold those checks to (tests/oracles/meo_shapes.py).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

from rdflib import Namespace

from countersign.orders.ontology import load_graph

# ontology/shapes.ttl, the SHACL shapes of the MEO rules: only the oracles read them (a
# validation evaluates the rules natively, verify/meo/direct.py).
SHAPES = "shapes.ttl"
MSH = Namespace("https://countersign.example/ontology/meo-shapes#")
SH = Namespace("http://www.w3.org/ns/shacl#")


@dataclass(frozen=True)
class ShapeInfo:
    code: str
    rules: tuple[str, ...]
    outcome: str | None


@cache
def shape_info() -> dict[str, ShapeInfo]:
    """Finding code, rules and end condition of every shape, as shapes.ttl declares them."""
    shapes = load_graph(SHAPES)
    info: dict[str, ShapeInfo] = {}
    for shape, code in shapes.subject_objects(MSH.code):
        name = str(shape).removeprefix(str(MSH))
        rule = shapes.value(shape, MSH.rule)
        outcome = shapes.value(shape, MSH.outcome)
        info[name] = ShapeInfo(
            str(code),
            tuple(str(rule).split()) if rule is not None else (),
            str(outcome) if outcome is not None else None,
        )
    return info
