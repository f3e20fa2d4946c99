"""Stored rehearsal campaigns: the campaign, one result row per simulation index,
progress, cancel, the sealed record and its attachment to a submission.

Results are inserted with ON CONFLICT DO NOTHING against the unique (campaign, index): a job
retried after its worker died, or run twice by two workers at once, stores each simulation
once. What to simulate and how to summarise is `countersign.campaigns` (the store does not
import the simulation); `countersign.jobs` runs the jobs.
"""

from __future__ import annotations

import secrets
from typing import Any

from sqlalchemy import CursorResult, func, select, update
from sqlalchemy.dialects.postgresql import insert as pg_insert
from sqlalchemy.dialects.sqlite import insert as sqlite_insert
from sqlalchemy.orm import Session as DbSession

from ..approvals.signer import LogSigner
from ..approvals.statement import json_digest
from ..errors import Conflict, NotFound, TooMany
from .events import record as record_event
from .tables import (
    Campaign,
    CampaignAttachment,
    CampaignRun,
    MissionVersion,
    Submission,
    User,
    utcnow,
)

ACTIVE_STATES = ("queued", "running")
# Campaigns one person may have queued or running at once: each holds workers for minutes.
MAX_ACTIVE_PER_USER = 2


class CampaignNotThisVersion(Conflict):
    """The campaign simulated other orders than the submitted version."""


class RecordChanged(Conflict):
    """A sealed campaign record that no longer hashes to its digest: it was changed in the
    database by something other than the app, so it is neither shown nor cited."""


def sealed_record(row: Campaign, digest: str | None = None) -> dict[str, Any] | None:
    """The row's record (None before it is sealed), once it hashes to `digest` (the row's own
    by default); RecordChanged when it does not. Every reader of a record goes through here, not
    only the audit bundle afterwards: a supervisor must never sign over results the seal did not
    cover."""
    expected = digest or row.digest
    if expected is None or row.record is None:
        return row.record
    if json_digest(row.record) != expected:
        raise RecordChanged(f"campaign {row.id}: the stored record does not hash to its digest "
                            f"{expected}; it was changed outside the app")
    return row.record


def create(db: DbSession, *, orders: dict[str, Any], orders_digest: str, spec: dict[str, Any],
           simulations: int, owner: User | None, mission_id: str | None = None,
           version: int | None = None, signer: LogSigner | None) -> Campaign:
    """A queued campaign; TooMany when the owner already has MAX_ACTIVE_PER_USER active."""
    if owner is not None:
        if db.get_bind().dialect.name == "postgresql":
            # Serialise one person's creations, so two at once cannot both pass the count.
            db.execute(select(User.id).where(User.id == owner.id).with_for_update())
        active = db.scalar(select(func.count()).select_from(Campaign).where(
            Campaign.owner_id == owner.id, Campaign.state.in_(ACTIVE_STATES)))
        if active is not None and active >= MAX_ACTIVE_PER_USER:
            raise TooMany(f"you have {active} campaigns queued or running (at most "
                          f"{MAX_ACTIVE_PER_USER}); wait for one to finish or cancel it")
    row = Campaign(id=secrets.token_hex(8), mission_id=mission_id, version=version,
                   orders_digest=orders_digest, orders=orders, owner_id=owner.id if owner else None,
                   spec=spec, simulations=simulations, state="queued")
    db.add(row)
    db.flush()
    # Logged alike whoever starts it: a person in the app, or the command line (no actor).
    record_event(db, signer=signer, kind="campaign.created", actor=owner, mission_id=mission_id,
                 after=orders_digest, detail={"campaign": row.id, "version": version,
                                              "spec": spec})
    return row


def owner_backlog(db: DbSession, campaign_id: str) -> int:
    """Simulations the campaign's owner still has waiting in their other active campaigns:
    how far back in the shared queue this one's jobs belong (jobs/pg.py)."""
    row = get(db, campaign_id)
    others = select(Campaign.id).where(Campaign.owner_id == row.owner_id,
                                       Campaign.state.in_(ACTIVE_STATES),
                                       Campaign.id != campaign_id)
    total = db.scalar(select(func.coalesce(func.sum(Campaign.simulations), 0))
                      .where(Campaign.id.in_(others))) or 0
    done = db.scalar(select(func.count()).select_from(CampaignRun)
                     .where(CampaignRun.campaign_id.in_(others))) or 0
    return max(0, int(total) - int(done))


def get(db: DbSession, campaign_id: str) -> Campaign:
    row = db.get(Campaign, campaign_id) if isinstance(campaign_id, str) else None
    if row is None:
        raise NotFound(f"no campaign {str(campaign_id)[:40]!r}")
    return row


def list_for_mission(db: DbSession, mission_id: str, *, limit: int = 50) -> list[Campaign]:
    return list(db.scalars(select(Campaign).where(Campaign.mission_id == mission_id)
                           .order_by(Campaign.created_at.desc()).limit(limit)))


def unfinished(db: DbSession) -> list[Campaign]:
    return list(db.scalars(select(Campaign).where(Campaign.state.in_(ACTIVE_STATES))
                           .order_by(Campaign.created_at)))


def done_indexes(db: DbSession, campaign_id: str, start: int = 0,
                 stop: int | None = None) -> set[int]:
    query = select(CampaignRun.index).where(CampaignRun.campaign_id == campaign_id,
                                            CampaignRun.index >= start)
    if stop is not None:
        query = query.where(CampaignRun.index < stop)
    return set(db.scalars(query))


def count_done(db: DbSession, campaign_id: str) -> int:
    return int(db.scalar(select(func.count()).select_from(CampaignRun)
                         .where(CampaignRun.campaign_id == campaign_id)) or 0)


def store_result(db: DbSession, campaign_id: str, index: int, result: dict[str, Any]) -> bool:
    """Insert one simulation's result; False when that index was already stored."""
    values = {"campaign_id": campaign_id, "index": index, "result": result}
    dialect = db.get_bind().dialect.name
    if dialect == "postgresql":
        statement: Any = pg_insert(CampaignRun).values(**values).on_conflict_do_nothing(
            index_elements=["campaign_id", "index"])
    else:
        statement = sqlite_insert(CampaignRun).values(**values).on_conflict_do_nothing(
            index_elements=["campaign_id", "index"])
    inserted: CursorResult[Any] = db.execute(statement)  # type: ignore[assignment]
    return bool(inserted.rowcount)


def mark_running(db: DbSession, campaign_id: str) -> None:
    db.execute(update(Campaign).where(Campaign.id == campaign_id, Campaign.state == "queued")
               .values(state="running"))


def state_of(db: DbSession, campaign_id: str) -> str | None:
    return db.scalar(select(Campaign.state).where(Campaign.id == campaign_id))


def results(db: DbSession, campaign_id: str) -> list[dict[str, Any]]:
    return [r for (r,) in db.execute(select(CampaignRun.result)
                                      .where(CampaignRun.campaign_id == campaign_id)
                                      .order_by(CampaignRun.index))]


def seal(db: DbSession, campaign_id: str, record: dict[str, Any]) -> str | None:
    """Finish the campaign with its record (once; a second caller changes nothing). The
    record's digest is sha256 over its RFC 8785 form. Returns the digest when this call
    finished it."""
    digest = json_digest(record)
    statement = (update(Campaign)
                 .where(Campaign.id == campaign_id, Campaign.state.in_(ACTIVE_STATES))
                 .values(state="finished", record=record, digest=digest, ended_at=utcnow()))
    done: CursorResult[Any] = db.execute(statement)  # type: ignore[assignment]
    return digest if done.rowcount else None


def fail(db: DbSession, campaign_id: str, reason: str) -> None:
    """A campaign whose jobs kept failing: it stops, with the reason in its record."""
    db.execute(update(Campaign).where(Campaign.id == campaign_id,
                                      Campaign.state.in_(ACTIVE_STATES))
               .values(state="failed", ended_at=utcnow(), record={"error": reason[:500]}))


def cancel(db: DbSession, campaign_id: str, *, actor: User | None,
           signer: LogSigner | None) -> Campaign:
    """Stop a queued or running campaign: its jobs see the state and stop at the next
    simulation. Cancelling a cancelled campaign is a no-op; a finished one is a Conflict."""
    row = get(db, campaign_id)
    if row.state == "cancelled":
        return row
    if row.state not in ACTIVE_STATES:
        raise Conflict(f"campaign {row.id} is {row.state}; only a queued or running campaign "
                       "can be cancelled")
    row.state = "cancelled"
    row.ended_at = utcnow()
    db.flush()
    record_event(db, kind="campaign.cancelled", actor=actor, mission_id=row.mission_id,
                 after=row.orders_digest, detail={"campaign": row.id,
                                                  "done": count_done(db, row.id)},
                 signer=signer)
    return row


def attach(db: DbSession, *, submission: Submission, campaign_id: str, actor: User,
           signer: LogSigner | None) -> None:
    """Cite a finished campaign's record in a submission; it must have simulated exactly the
    submitted orders."""
    if submission.state != "submitted":
        raise Conflict(f"submission {submission.id} is {submission.state}; campaigns can be "
                       "attached only while it awaits a decision")
    row = get(db, campaign_id)
    if row.state != "finished" or row.digest is None:
        raise Conflict(f"campaign {row.id} is {row.state}; only a finished campaign can be "
                       "attached")
    sealed_record(row)
    version = db.get_one(MissionVersion, submission.version_id)
    if row.orders_digest != version.digest:
        raise CampaignNotThisVersion(
            f"campaign {row.id} simulated orders {row.orders_digest}, but version "
            f"{version.number} of {version.mission_id} is {version.digest}")
    exists = db.scalar(select(CampaignAttachment.id).where(
        CampaignAttachment.submission_id == submission.id,
        CampaignAttachment.campaign_id == row.id))
    if exists is not None:
        return
    db.add(CampaignAttachment(submission_id=submission.id, campaign_id=row.id, digest=row.digest,
                              attached_by=actor.id))
    record_event(db, signer=signer, kind="submission.campaign_attached", actor=actor,
                 mission_id=version.mission_id, after=version.digest,
                 detail={"submission": submission.id, "campaign": row.id,
                         "record_digest": row.digest})


def attached(db: DbSession, submission_id: int) -> list[CampaignAttachment]:
    return list(db.scalars(select(CampaignAttachment)
                           .where(CampaignAttachment.submission_id == submission_id)
                           .order_by(CampaignAttachment.id)))


def cited_digests(db: DbSession, submission_id: int) -> list[str]:
    """The attached campaigns' record digests, for a statement to cite; RecordChanged when a
    record no longer hashes to the digest it was attached with."""
    digests = []
    for attachment in attached(db, submission_id):
        sealed_record(get(db, attachment.campaign_id), attachment.digest)
        digests.append(attachment.digest)
    return digests


def summary(db: DbSession, row: Campaign) -> dict[str, Any]:
    owner = db.get(User, row.owner_id) if row.owner_id is not None else None
    done = row.simulations if row.state == "finished" else count_done(db, row.id)
    try:
        record = sealed_record(row) or {}
    except RecordChanged as changed:
        return {**_summary(row, owner, done, {}), "error": str(changed), "results": None}
    return _summary(row, owner, done, record)


def _summary(row: Campaign, owner: User | None, done: int,
             record: dict[str, Any]) -> dict[str, Any]:
    return {"id": row.id, "mission": row.mission_id, "version": row.version,
            "orders_digest": row.orders_digest, "owner": owner.username if owner else None,
            "spec": row.spec, "simulations": row.simulations, "done": done,
            "state": row.state, "created_at": row.created_at, "ended_at": row.ended_at,
            "digest": row.digest, "error": record.get("error"),
            "results": record.get("results")}
