"""The audit bundle reads its approvals in batches (a few queries per 500), not several queries
per approval: a log of thousands of decisions is exported without thousands of round trips."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from sqlalchemy import event

from .approval_helpers import approve, new_version, register_key, submit
from .conftest import World


def statements_of(world: World, action: Callable[[], Any]) -> int:
    seen: list[str] = []

    def record(_conn: Any, _cursor: Any, statement: str, *_: Any) -> None:
        seen.append(statement)

    event.listen(world.database.engine, "before_cursor_execute", record)
    try:
        action()
    finally:
        event.remove(world.database.engine, "before_cursor_execute", record)
    return len(seen)


def test_the_bundle_makes_as_many_queries_for_five_approvals_as_for_one(world: World) -> None:
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    auditor = world.client("auditor")

    def bundle() -> None:
        answer = auditor.get("/api/audit/bundle")
        assert answer.status_code == 200, answer.text

    approve(world, supervisor, signer, submit(world, new_version(world)))
    bundle()  # the first signs a checkpoint; compare the ones after it
    one = statements_of(world, bundle)
    for _ in range(4):
        approve(world, supervisor, signer, submit(world, new_version(world)))
    bundle()
    five = statements_of(world, bundle)
    assert len(auditor.get("/api/audit/bundle").json()["approvals"]) == 5
    assert five == one, (one, five)
