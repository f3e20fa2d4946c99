"""Canonical bytes and digest of orders: exactly what the author (or importer) wrote, in RFC 8785
form. A signed digest must never move, so the bytes are pinned here: orders that leave defaults
out must not gain them, and orders that spell defaults out must keep them."""

from __future__ import annotations

import copy
import hashlib
import json
from typing import Any

import pytest

from countersign.orders.avcl import read_avcl
from countersign.orders.canonical import canonical_bytes, digest, orders_to_json
from countersign.orders.examples import example_names, load_example
from countersign.orders.model import Orders

from .test_avcl import avcl

NEXT = {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"}
LEFT_OUT: dict[str, Any] = {
    "id": "m", "vehicle": "v", "start": "G1",
    "goals": [{"id": "G1", "behavior": "transit", "next": NEXT}],
}
# The same orders with every default the model would fill in written out by hand.
SPELLED_OUT: dict[str, Any] = {
    **copy.deepcopy(LEFT_OUT),
    "format": "countersign.orders/1",
    "goals": [{"id": "G1", "behavior": "transit", "area": None, "next": NEXT, "requires": [],
               "params": {}, "envelope": {}}],
    "terminals": [{"id": "COMPLETE", "kind": "complete"}, {"id": "ABORT", "kind": "abort"}],
    "constraints": [{"id": "C1", "applies_to": "mission", "expr": "true"}],
    "norms": [],
    "areas": [],
}

PINNED = {
    "left out": (
        b'{"format":"countersign.orders/1","goals":[{"behavior":"transit","id":"G1","next":'
        b'{"fail":"ABORT","succeed":"COMPLETE","violate":"ABORT"}}],"id":"m","start":"G1",'
        b'"vehicle":"v"}'
    ),
    "spelled out": (
        b'{"areas":[],"constraints":[{"applies_to":"mission","expr":"true","id":"C1"}],'
        b'"format":"countersign.orders/1","goals":[{"area":null,"behavior":"transit",'
        b'"envelope":{},"id":"G1","next":{"fail":"ABORT","succeed":"COMPLETE","violate":"ABORT"},'
        b'"params":{},"requires":[]}],"id":"m","norms":[],"start":"G1","terminals":'
        b'[{"id":"COMPLETE","kind":"complete"},{"id":"ABORT","kind":"abort"}],"vehicle":"v"}'
    ),
}


@pytest.mark.parametrize(("name", "data"), [("left out", LEFT_OUT), ("spelled out", SPELLED_OUT)])
def test_canonical_bytes_are_what_was_written(name: str, data: dict[str, Any]) -> None:
    orders = Orders.model_validate(data)
    assert canonical_bytes(orders) == PINNED[name]
    assert digest(orders) == "sha256:" + hashlib.sha256(PINNED[name]).hexdigest()
    # The stored JSON (what the browser re-hashes) reads back to the same bytes.
    again = Orders.model_validate(json.loads(json.dumps(orders_to_json(orders))))
    assert canonical_bytes(again) == PINNED[name]


def test_an_importers_defaulted_handlers_stay_inside_the_digest() -> None:
    """AVCL handlers filled in by the NPS convention are recorded on the goal and signed."""
    result = read_avcl(avcl(
        '<Goal id="A" title="Search" nextOnSuccess="DONE"><Search requiredPD="0.8"/></Goal>'
        '<Goal id="DONE" title="Halt" description="Operations complete"/>'
    ), "test.xml")
    [goal] = orders_to_json(result.orders)["goals"]
    assert goal["next"] == {"succeed": "DONE", "fail": "DONE", "violate": "DONE"}
    assert goal["defaulted"] == {"fail": "succeed", "violate": "succeed"}
    assert b'"defaulted":{"fail":"succeed","violate":"succeed"}' in canonical_bytes(result.orders)


@pytest.mark.parametrize("name", example_names())
def test_orders_as_json_are_plain_json_data(name: str) -> None:
    """What is stored and served is JSON: envelopes are lists, not the model's tuples."""
    data = orders_to_json(load_example(name))
    assert json.loads(json.dumps(data)) == data
