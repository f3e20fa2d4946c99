"""Stored rehearsal records: written once when a rehearsal stops, cited by submissions.

A record arrives from the rehearsal (rehearse/manager.py) as its JSON, its digest and viser's
standalone HTML replay; this module stores them with who rehearsed which orders, and records
the event. Attaching a record to a submission requires the record to be about exactly the
submitted version's orders (same orders digest)."""

from __future__ import annotations

import hashlib
from typing import Any

from sqlalchemy import select
from sqlalchemy.orm import Session as DbSession
from sqlalchemy.orm import undefer

from ..approvals.signer import LogSigner
from .events import record as record_event
from .missions import Conflict, NotFound
from .tables import MissionVersion, RehearsalRecord, Submission, User


class RecordNotThisVersion(Conflict):
    """The record rehearsed other orders than the submitted version."""


def save_record(
    db: DbSession, *, digest: str, record: dict[str, Any], replay_html: bytes, mission_id: str,
    version: int | None, orders_digest: str, source: str, owner: User, rehearsal_id: str,
                signer: LogSigner | None,
) -> RehearsalRecord:
    """Store a finished rehearsal's record (once: the digest names its content)."""
    existing = db.get(RehearsalRecord, digest)
    if existing is not None:
        return existing
    replay_digest = "sha256:" + hashlib.sha256(replay_html).hexdigest()
    event = record_event(db, kind="rehearsal.recorded", actor=owner, mission_id=mission_id,
                         after=orders_digest, detail={
                             "rehearsal": rehearsal_id, "record_digest": digest,
                             "replay_digest": replay_digest, "version": version,
                             "source": source}, signer=signer)
    row = RehearsalRecord(digest=digest, mission_id=mission_id, version=version,
                          orders_digest=orders_digest, owner_id=owner.id, source=source,
                          record=record, replay_html=replay_html, replay_digest=replay_digest,
                          event_id=event.id)
    db.add(row)
    db.flush()
    return row


def get_record(db: DbSession, digest: str, *, with_replay: bool = False) -> RehearsalRecord:
    query = select(RehearsalRecord).where(RehearsalRecord.digest == digest)
    if with_replay:
        query = query.options(undefer(RehearsalRecord.replay_html))
    row = db.scalar(query)
    if row is None:
        raise NotFound(f"no rehearsal record {digest}")
    return row


def list_records(db: DbSession, *, mission_id: str, limit: int) -> list[RehearsalRecord]:
    return list(db.scalars(select(RehearsalRecord)
                           .where(RehearsalRecord.mission_id == mission_id)
                           .order_by(RehearsalRecord.created_at.desc()).limit(limit)))


def attach(db: DbSession, *, submission: Submission, digest: str, actor: User,
           signer: LogSigner | None) -> None:
    """Cite a stored record in a submission; it must rehearse exactly the submitted orders."""
    if submission.state != "submitted":
        raise Conflict(f"submission {submission.id} is {submission.state}; records can be "
                       "attached only while it awaits a decision")
    row = get_record(db, digest)
    version = db.get_one(MissionVersion, submission.version_id)
    if row.orders_digest != version.digest:
        raise RecordNotThisVersion(
            f"the record {digest} rehearsed orders {row.orders_digest}, but version "
            f"{version.number} of {version.mission_id} is {version.digest}: rehearse that "
            "version and attach its record")
    submission.rehearsal_digest = digest
    record_event(db, signer=signer, kind="submission.rehearsal_attached", actor=actor,
                 mission_id=version.mission_id, after=version.digest,
                 detail={"submission": submission.id, "version": version.number,
                         "record_digest": digest})


def record_summary(db: DbSession, row: RehearsalRecord) -> dict[str, Any]:
    owner = db.get(User, row.owner_id)
    return {"digest": row.digest, "mission": row.mission_id, "version": row.version,
            "orders_digest": row.orders_digest, "source": row.source,
            "owner": owner.username if owner else None, "created_at": row.created_at,
            "replay_digest": row.replay_digest,
            "replay": f"/api/rehearsal-records/{row.digest}/replay.html"}
