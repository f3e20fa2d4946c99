"""The mission's standing keeps the latest approved version apart from the
latest decision (after v2 is rejected, v1 still stands approved)."""

from __future__ import annotations

from .approval_helpers import MISSION, approve, new_version, register_key, submit
from .conftest import World


def test_a_rejected_v2_does_not_hide_the_approved_v1(world: World) -> None:
    reader = world.client("auditor")
    empty = reader.get(f"/api/missions/{MISSION}/standing")
    assert empty.status_code == 200, empty.text
    assert empty.json() == {"approved": None, "latest": None}

    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    first = approve(world, supervisor, signer, submit(world, new_version(world)))
    rejected = approve(world, supervisor, signer, submit(world, new_version(world)),
                       decision="rejected", reason="rendezvous too close to the lane")
    standing = reader.get(f"/api/missions/{MISSION}/standing").json()
    assert standing["approved"] == {"version": 1, "decision": "approved", "record": first["id"]}
    assert standing["latest"] == {"version": 2, "decision": "rejected",
                                  "record": rejected["id"]}
    assert reader.get("/api/missions/no-such-mission/standing").status_code == 404
