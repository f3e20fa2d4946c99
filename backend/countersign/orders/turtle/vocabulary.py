"""The names both layers of the orders' RDF use: namespaces, the successor properties, IRIs
per mission and element, the record's terms, and the small helpers the graph, the text writer,
the reader and the MEO checks share."""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Any, Final

from rdflib import Namespace, URIRef
from rdflib.namespace import RDF, XSD

# The IRIs as strings and the id helpers live where rdflib is not needed (validate reads them).
from ..iris import MISSION_BASE as MISSION_BASE
from ..iris import first_by_id
from ..iris import local_id as local_id
from ..iris import natural_key as natural_key

MEO: Final = Namespace("https://countersign.example/ontology/meo#")
CS: Final = Namespace("https://countersign.example/ontology/orders#")
# A record map's keys as properties (`[ key:succeed "G2" ; key:fail "ABORT" ]`): 1 statement
# per entry instead of the 3 of a cs:entry node. Keys that are not names keep the
# cs:entry form, which the reader also takes.
CS_KEY: Final = Namespace("https://countersign.example/ontology/orders/key#")
# The name the turtle modules import it by.
_first_by_id: Final = first_by_id
NPS3: Final = Namespace("https://savage.nps.edu/EthicalControl/ontologies/MissionExecutionOntology#")

OUTCOME_PROPERTY: Final = {
    "succeed": MEO.isNextOnSucceed,
    "fail": MEO.isNextOnFail,
    "violate": MEO.isNextOnViolate,
}
NEXT_PROPERTIES: Final = tuple(OUTCOME_PROPERTY.values())

# Fields holding lists of elements that get their own nodes (and IRIs).
_ELEMENT_LISTS: Final = {
    "goals": "goal",
    "terminals": "terminal",
    "constraints": "constraint",
    "norms": "norm",
    "areas": "area",
    "vehicles": "vehicle",
    "properties": "property",
}

# --------------------------------------------------------------------------------------------
# IRIs


@dataclass(frozen=True)
class MissionIris:
    mission_id: str

    @property
    def mission(self) -> URIRef:
        return URIRef(MISSION_BASE + self.mission_id)

    def element(self, kind: str, element_id: str) -> URIRef:
        return URIRef(f"{MISSION_BASE}{self.mission_id}/{kind}#{element_id}")

    def feature(self, vehicle_id: str, feature_id: str) -> URIRef:
        return URIRef(f"{MISSION_BASE}{self.mission_id}/vehicle/{vehicle_id}/feature#{feature_id}")

    def namespaces(self) -> dict[str, str]:
        base = f"{MISSION_BASE}{self.mission_id}"
        kinds = ("goal", "terminal", "constraint", "requirement", "quantity", "vehicle", "ref")
        return {kind: f"{base}/{kind}#" for kind in kinds}


_NAME: Final = re.compile(r"[a-z][a-z0-9_]*")
# A map key written as a key: property: a local name every Turtle reader takes as it is.
_KEY_NAME: Final = re.compile(r"[A-Za-z_][A-Za-z0-9_-]*")
_RESERVED: Final = frozenset({"extra", "key", "value", "entry", "implicit", "null", "map"})


# Terms the record decoder compares at every value, looked up once (rdflib namespaces resolve
# attributes on every access).
_NULL: Final = CS.null
_NIL: Final = RDF.nil
_FIRST: Final = RDF.first
_REST: Final = RDF.rest
_TYPE: Final = RDF.type
_MAP: Final = CS.Map
_KEY: Final = CS.key
_CS_ID: Final = CS.id
_VALUE: Final = CS.value
_EXTRA: Final = CS.extra
_ENTRY: Final = CS.entry
_KEY_PREFIX: Final = str(CS_KEY)
_FLOAT_TYPES: Final = frozenset({XSD.double, XSD.decimal, XSD.float})
_INT_TYPES: Final = frozenset({XSD.integer, XSD.int, XSD.long})
_BOOLEAN: Final = XSD.boolean
# A list of scalars in the record: one rdf:JSON literal instead of two statements per member
# (rdf:first, rdf:rest). The range [low, high] of each envelope quantity made a third of a
# mission's statements.
_RDF_JSON: Final = RDF.JSON


def _json_scalar(item: Any) -> bool:
    """A list member written inside an rdf:JSON literal: a string, boolean, integer, null or
    finite float (JSON keeps each of them exactly: floats by their shortest repr)."""
    return (item is None or isinstance(item, str | bool | int)
            or (isinstance(item, float) and math.isfinite(item)))


_JSON_SCALAR: Final = _json_scalar
