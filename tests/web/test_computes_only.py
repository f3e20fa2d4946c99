"""A POST that only computes declares it on its route (deps.computing), not in a list of URLs:
its session opens without the write lock; other POSTs take it."""

from __future__ import annotations

from contextlib import AbstractContextManager

import pytest
from sqlalchemy.orm import Session

from countersign.orders.canonical import orders_to_json
from countersign.orders.examples import load_example

from .conftest import World


def test_only_a_declared_post_opens_without_the_write_lock(
    world: World, monkeypatch: pytest.MonkeyPatch
) -> None:
    opened: list[bool] = []
    real = world.database.open

    def recording(write: bool = True) -> AbstractContextManager[Session]:
        opened.append(write)
        return real(write=write)

    monkeypatch.setattr(world.database, "open", recording)
    client = world.client("operator")
    orders = orders_to_json(load_example("search-and-sample"))
    assert client.post("/api/validate", json=orders).status_code == 200
    assert opened == [False]

    opened.clear()
    created = client.post("/api/missions", json={**orders, "id": "computes-only"})
    assert created.status_code in (200, 201), created.text
    assert opened == [True]


