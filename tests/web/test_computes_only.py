"""A POST that only computes declares it on its route (deps.computing), not in a list of URLs:
its session opens without the write lock; other POSTs take it."""

from __future__ import annotations

import pytest

from countersign.orders.canonical import orders_to_json
from countersign.orders.examples import load_example

from .approval_helpers import approve, new_version, prepare, register_key, submit
from .conftest import World
from .write_lock import record_opens


def test_only_a_declared_post_opens_without_the_write_lock(
    world: World, monkeypatch: pytest.MonkeyPatch
) -> None:
    opened = record_opens(world, monkeypatch)
    client = world.client("operator")
    orders = orders_to_json(load_example("search-and-sample"))
    assert client.post("/api/validate", json=orders).status_code == 200
    assert opened == [False]

    opened.clear()
    created = client.post("/api/missions", json={**orders, "id": "computes-only"})
    assert created.status_code in (200, 201), created.text
    assert opened == [True]




def test_preparing_a_statement_to_sign_takes_no_write_lock(
    world: World, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A statement is prepared, never stored; building it (the report, the vehicle exports'
    digests: 0.6 s for the exemplar, more for large orders) held the write lock, and every
    other user's writes waited for it."""
    number = new_version(world)
    submission = submit(world, number)
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    approval = approve(world, supervisor, signer, submission)
    second = submit(world, new_version(world))
    opened = record_opens(world, monkeypatch)
    prepare(supervisor, second, signer)
    revocation = supervisor.post(f"/api/approvals/{approval['id']}/statement",
                                 json={"reason": "superseded", "key_id": signer.key_id})
    assert revocation.status_code == 200, revocation.text
    assert opened == [False, False]
