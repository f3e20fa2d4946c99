"""The append-only event log: every state change, who, what, when, before and after.

`record()` is the single entry point. In the same transaction it appends the event as the next
leaf of the transparency log (approvals/log.py): entries are hash-chained and hashed into the
RFC 6962 tree, so that a checkpoint signed later covers every event before it."""

from __future__ import annotations

import sys
from typing import Any

from sqlalchemy import event as sa_event
from sqlalchemy import inspect, select, text
from sqlalchemy.orm import Session as DbSession

from ..approvals.log import GENESIS, entry_bytes, entry_leaf, event_data
from ..approvals.signer import LogSigner, SignerRefused
from ..errors import Unavailable
from .event_words import event_target
from .tables import Event, LogEntry, LogReceipt, User, utcnow

# Appends take one PostgreSQL advisory lock, so that concurrent transactions chain in order;
# SQLite serialises writers already (the event row is written before the head is read).
LOG_LOCK = 0x636F756E  # "coun"


def record(
    db: DbSession, *, signer: LogSigner | None, kind: str, actor: User | None,
    mission_id: str | None = None,
    before: str | None = None, after: str | None = None, detail: dict[str, Any] | None = None,
    log_at_commit: bool = False,
) -> Event:
    """Insert the event and append its log leaf. With `log_at_commit` the leaf is appended
    just before the transaction commits (still in it, so the log stays complete): the global
    log lock is then held only for the append and the COMMIT, not for the rest of the request.
    Callers that read the log in the same transaction (approvals) must not defer.

    `signer` receipts the entry (None: a tool run without the log key; the signer will then
    refuse to cover it). It is an argument, not found through the session, so that what a
    caller appends with is visible where it calls."""
    event = Event(kind=kind, actor_id=actor.id if actor else None, mission_id=mission_id,
                  before_digest=before, after_digest=after, detail=detail or {}, at=utcnow(),
                  target=event_target(kind, mission_id, detail or {}))
    db.add(event)
    db.flush()
    actor_name = actor.username if actor else None
    if not log_at_commit:
        append_to_log(db, event, actor_name, signer=signer)
        return event
    if not db.info.get(_LISTENING):
        db.info[_LISTENING] = True
        sa_event.listen(db, "before_commit", _append_pending)
        sa_event.listen(db, "after_rollback", _forget_pending)
    # Transaction state: the signer travels with the event it is to receipt.
    db.info.setdefault(_PENDING, []).append((event, actor_name, signer))
    return event


_PENDING = "countersign_pending_log"
_LISTENING = "countersign_log_listener"


def _append_pending(db: DbSession) -> None:
    pending = db.info.pop(_PENDING, None) or []
    for event, actor_name, signer in pending:
        if inspect(event).persistent:  # not undone by a rolled-back savepoint
            append_to_log(db, event, actor_name, signer=signer)


def _forget_pending(db: DbSession) -> None:
    if not db.in_transaction():  # the whole transaction ended, not a savepoint
        db.info.pop(_PENDING, None)


def append_to_log(db: DbSession, event: Event, actor: str | None, *,
                  signer: LogSigner | None) -> LogEntry:
    if db.get_bind().dialect.name == "postgresql":
        db.execute(text("SELECT pg_advisory_xact_lock(:key)"), {"key": LOG_LOCK})
    head = db.execute(
        select(LogEntry.index, LogEntry.leaf_hash).order_by(LogEntry.index.desc()).limit(1)
    ).first()
    index, prev = (int(head[0]) + 1, str(head[1])) if head else (0, GENESIS)
    data = entry_bytes(index, prev, event_data(
        id=event.id, at=event.at, actor=actor, kind=event.kind, mission=event.mission_id,
        before=event.before_digest, after=event.after_digest, detail=event.detail))
    entry = LogEntry(index=index, event_id=event.id, entry=data.decode(),
                     leaf_hash=entry_leaf(data))
    db.add(entry)
    db.flush()
    _receipt(db, entry, signer)
    return entry


def _receipt(db: DbSession, entry: LogEntry, signer: LogSigner | None) -> None:
    """The log signer's receipt for this entry (kept beside it, shown to the caller): the
    signer later vouches only for entries that carry one. A database without a signer (a
    tool run without the log key) appends entries the signer will refuse to cover."""
    if signer is None:
        return
    try:
        receipt = signer.receipt(entry.index, entry.leaf_hash,
                                 utcnow().isoformat().replace("+00:00", "Z"))
    except SignerRefused as exc:
        raise LogErased(f"the log signer refuses to append: {exc}") from None
    db.add(LogReceipt(index=entry.index, receipt=receipt))
    db.flush()
    if not db.info.get(_REMEMBERING):
        db.info[_REMEMBERING] = True
        sa_event.listen(db, "after_commit", _remember_committed)
        sa_event.listen(db, "after_rollback", _forget_uncommitted)
    db.info.setdefault(_APPENDED, []).append((signer, entry, entry.index, entry.leaf_hash))


_APPENDED = "countersign_appended_entries"
_REMEMBERING = "countersign_remembering"


class LogErased(Unavailable):
    """The log signer remembers a committed entry where the database now holds another."""


def _remember_committed(db: DbSession) -> None:
    """Tell the signer which entries this transaction committed (those not undone by a
    rolled-back savepoint), so that it never signs a head without them."""
    appended = db.info.pop(_APPENDED, None) or []
    # One signer per transaction in practice; grouped by identity so that none is mixed up.
    by_signer: dict[int, tuple[LogSigner, list[tuple[int, str]]]] = {}
    for signer, entry, index, leaf in appended:
        if inspect(entry).persistent:
            by_signer.setdefault(id(signer), (signer, []))[1].append((index, leaf))
    for signer, committed in by_signer.values():
        try:
            signer.remember(committed)
        except OSError as exc:
            # The transaction is committed; what is lost is only the signer's memory of it.
            sys.stderr.write(f"countersign: the log signer could not record committed "
                             f"entries {[i for i, _ in committed]}: {exc}\n")


def _forget_uncommitted(db: DbSession) -> None:
    if not db.in_transaction():
        db.info.pop(_APPENDED, None)

