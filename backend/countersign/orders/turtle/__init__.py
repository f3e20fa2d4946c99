"""Orders as RDF: the Mission Execution Ontology graph, Turtle in our vocabulary (lossless), an
NPS MEO 3.0 view, and import of NPS MEO Turtle (converted missions, CanonicalMission.ttl).

Two layers of triples describe one set of orders:

- **Meaning** (`meo:`, ontology/meo.ttl): the mission, its goals and terminals, start, successors
  per end condition, requirements, constraints and their scope, the vehicle, its features, what
  they fulfil and measure. Verification (`countersign.verify.meo`) reads only this layer.
- **Record** (`cs:`): how the author wrote the orders, field by field (titles, envelopes, params,
  areas, norms, list order, explicit defaults, unknown fields), so that Turtle written here reads
  back to orders with the same digest. A map is a blank node with one `key:` property per
  entry (`key:succeed "G2"`); a map with a key that is not a name, or an empty one, is a
  `cs:Map` of `cs:entry [cs:key; cs:value]` nodes, the form every map had before (still read).

Reading trusts the meaning over the record: where someone edited the `meo:` triples (say, in
Protégé) and the record disagrees, the meaning wins and the record only keeps its order.

IRIs are stable per mission id and element: the mission is
`https://countersign.example/mission/{id}`, its elements `{mission}/{kind}#{element id}`
(kinds: goal, terminal, constraint, requirement, quantity, vehicle, area, norm, property; `ref`
for a name that is none of the orders' elements, e.g. an unknown successor) and a vehicle's
features `{mission}/vehicle/{vehicle id}/feature#{feature id}`. Ids are restricted to
`[A-Za-z0-9_.:-]`, so they need no escaping. A second element with an id already used (a DUP
finding) is kept as a blank node in the record only: the meaning, like the structural check,
sees the first.

NPS Turtle is recognised by its namespaces and renamed to `meo:` with
ontology/nps-meo3-alignment.ttl; the NPS conventions then apply (a goal without successors is a
terminal, complete or abort by its wording; `rdfs:comment` "Title: description").

RDF can say things orders cannot, e.g. that a goal requires a Constraint: such statements
contradict a domain or range of meo.ttl, and the reader reports them as findings whose code is
the violated rule (`typing_findings`).

The quantities a constraint reads are the quantity names of its expression, read with the one
expression parser (`orders.expressions`); a feature can test a constraint (F2, V4) when it
measures every one of them.

One module per job: `vocabulary` (names and IRIs), `graph` (orders -> rdflib graph), `syntax`
(the one Turtle writer), `text` (our Turtle), `nps` and `alignment` (the NPS view and names),
`reader` (Turtle -> orders) and `typing_rules`. This package re-exports what the rest of the
code base uses.
"""

from .graph import orders_to_graph
from .nps import nps_graph, write_nps_turtle
from .reader import read_turtle
from .text import write_turtle
from .typing_rules import typing_findings
from .vocabulary import (
    CS,
    CS_KEY,
    MEO,
    MISSION_BASE,
    NEXT_PROPERTIES,
    NPS3,
    OUTCOME_PROPERTY,
    MissionIris,
    _first_by_id,
    local_id,
    natural_key,
)

__all__ = [
    "CS",
    "CS_KEY",
    "MEO",
    "MISSION_BASE",
    "NEXT_PROPERTIES",
    "NPS3",
    "OUTCOME_PROPERTY",
    "MissionIris",
    "_first_by_id",
    "local_id",
    "natural_key",
    "nps_graph",
    "orders_to_graph",
    "read_turtle",
    "typing_findings",
    "write_nps_turtle",
    "write_turtle",
]
