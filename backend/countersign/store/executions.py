"""Execution verdicts appended to the audit log (`execution.recorded`): the log is the record.

Reading and checking a log can take seconds (megabytes of vehicle messages); it happens
between `approved_orders`, in a read transaction, and `record_execution`, in the write one, so
that no writer waits for a check."""

from __future__ import annotations

import hashlib
import json
from collections.abc import Sequence
from dataclasses import dataclass
from datetime import datetime
from typing import Any, Protocol

from sqlalchemy import select
from sqlalchemy.orm import Session as DbSession

from ..approvals.signer import LogSigner
from ..orders.model import Orders
from ..orders.reader import orders_from_data
from . import missions as service
from .approvals import log_index_of
from .events import record
from .packages import NotApproved, standing_approval
from .tables import Event, LogEntry, User

MAX_RECORDED_DEVIATIONS = 20
MAX_LISTED = 200


class Deviation(Protocol):
    def to_json(self) -> dict[str, Any]: ...


class Evidence(Protocol):
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
    def status(self) -> str: ...  # no-deviation, deviation or unverified

    @property
    def evidence(self) -> Evidence: ...

    @property
    def deviations(self) -> Sequence[Deviation]: ...

    def summary(self) -> str: ...


@dataclass(frozen=True)
class ApprovedOrders:
    orders: Orders
    digest: str
    approved_at: datetime


def approved_orders(db: DbSession, *, mission_id: str, number: int) -> ApprovedOrders:
    """The orders of a version with a standing approval, and when it was approved."""
    version = service.get_version(db, mission_id, number)
    approval = standing_approval(db, version.id)
    if approval is None:
        raise NotApproved(f"version {number} of {mission_id} has no standing approval to "
                          "execute")
    return ApprovedOrders(orders_from_data(version.orders), version.digest,
                          approval.created_at)


def record_execution(
    db: DbSession, *, mission_id: str, number: int, log: bytes, actor: User,
    checked: ApprovedOrders, verdict: Verdict, source: dict[str, Any] | None = None,
                     signer: LogSigner | None,
) -> int | None:
    """Append the verdict of `log`, checked against `checked` (see `approved_orders`), and
    return its log index. The approval is looked at again: it may have been revoked while the
    log was checked. `source` names the format the log was read as and what converting it
    assumed."""
    version = service.get_version(db, mission_id, number)
    if standing_approval(db, version.id) is None or version.digest != checked.digest:
        raise NotApproved(f"version {number} of {mission_id} has no standing approval to "
                          "execute")
    detail: dict[str, Any] = {
        "version": number, "orders_digest": version.digest,
        "log_digest": "sha256:" + hashlib.sha256(log).hexdigest(),
        "ok": verdict.ok, "status": verdict.status, "path": verdict.path,
        "terminal": verdict.terminal, "summary": verdict.summary(),
        "deviations": [d.to_json() for d in verdict.deviations[:MAX_RECORDED_DEVIATIONS]],
        "evidence": verdict.evidence.to_json()}
    if source:
        detail["source"] = dict(source)
    event = record(db, signer=signer, kind="execution.recorded", actor=actor, mission_id=mission_id,
                   after=version.digest, detail=detail)
    return log_index_of(db, event.id)


def recorded_executions(db: DbSession, *, mission_id: str, number: int) -> list[dict[str, Any]]:
    """The execution verdicts of a version as its log entries hold them (the log is the
    record: a table row that disagrees with it is not what is shown), oldest first."""
    rows = db.execute(
        select(LogEntry.index, LogEntry.entry).join(Event, Event.id == LogEntry.event_id)
        .where(Event.kind == "execution.recorded", Event.mission_id == mission_id)
        .order_by(LogEntry.index)).all()
    found: list[dict[str, Any]] = []
    for index, text in rows:
        event = json.loads(text).get("event") or {}
        detail = event.get("detail") or {}
        if event.get("kind") != "execution.recorded" or detail.get("version") != number:
            continue
        found.append({"log_index": index, "at": event.get("at"), "actor": event.get("actor"),
                      **detail})
    return found[-MAX_LISTED:]
