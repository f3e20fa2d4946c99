"""The bundle the server serves is a `Bundle` (approvals/bundle_model.py) written back byte for
byte: the route, the builder and the offline verifier share one type."""

from __future__ import annotations

import json

from countersign.approvals.bundle import verify_bundle
from countersign.approvals.bundle_model import Bundle
from countersign.approvals.dsse import read_envelope
from countersign.approvals.statement import read_statement

from .approval_helpers import approve, new_version, register_key, submit
from .conftest import World


def test_the_served_bundle_is_a_bundle(world: World) -> None:
    supervisor = world.client("supervisor")
    approve(world, supervisor, register_key(supervisor), submit(world, new_version(world)))
    served = world.client("auditor").get("/api/audit/bundle")
    assert served.status_code == 200
    data = served.json()
    bundle = Bundle.from_json(data)
    assert json.dumps(bundle.to_json()) == json.dumps(data)
    assert verify_bundle(bundle).ok
    # Its envelopes hold typed statements about orders the bundle carries.
    (approval,) = bundle.approvals
    statement = read_statement(read_envelope(approval.envelope).payload_bytes)
    assert statement.predicate.decision == approval.decision == "approved"
    assert statement.orders_digest in bundle.orders
