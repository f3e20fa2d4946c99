"""Execution verdicts appended to the audit log (`execution.recorded`): the log is the record."""

from __future__ import annotations

import hashlib
from collections.abc import Callable, Sequence
from typing import Any, Protocol, TypeVar

from sqlalchemy.orm import Session as DbSession

from ..orders.model import Orders
from ..orders.reader import orders_from_data
from . import missions as service
from .approvals import log_index_of
from .events import record
from .packages import NotApproved, standing_approval
from .tables import User

MAX_RECORDED_DEVIATIONS = 20


class Deviation(Protocol):
    def to_json(self) -> dict[str, Any]: ...


class Verdict(Protocol):
    """What the execution checker (rehearse.execution) answers; the store records it without
    importing the checker (validation and checking stay out of the store's imports)."""

    @property
    def path(self) -> int | None: ...

    @property
    def terminal(self) -> str | None: ...

    @property
    def ok(self) -> bool: ...

    @property
    def deviations(self) -> Sequence[Deviation]: ...

    def summary(self) -> str: ...


V = TypeVar("V", bound=Verdict)


def record_execution(
    db: DbSession, *, mission_id: str, number: int, log: str, actor: User,
    check: Callable[[Orders, str], V],
) -> tuple[V, int | None]:
    """Check the log against the version's approved orders with `check` and append the
    verdict."""
    version = service.get_version(db, mission_id, number)
    if standing_approval(db, version.id) is None:
        raise NotApproved(f"version {number} of {mission_id} has no standing approval to "
                          "execute")
    verdict = check(orders_from_data(version.orders), log)
    detail: dict[str, Any] = {
        "version": number, "orders_digest": version.digest,
        "log_digest": "sha256:" + hashlib.sha256(log.encode()).hexdigest(),
        "ok": verdict.ok, "path": verdict.path, "terminal": verdict.terminal,
        "summary": verdict.summary(),
        "deviations": [d.to_json() for d in verdict.deviations[:MAX_RECORDED_DEVIATIONS]]}
    event = record(db, kind="execution.recorded", actor=actor, mission_id=mission_id,
                   after=version.digest, detail=detail)
    return verdict, log_index_of(db, event.id)
