"""What keeps a decision honest beyond its signature.

- Row locks: a decision locks its submission row and a submission locks its version row
  (SELECT ... FOR UPDATE on PostgreSQL, where READ COMMITTED let two requests both see
  "submitted"); SQLite's writers begin IMMEDIATE (store/db.py), so they are serialised already
  and SQLAlchemy renders no FOR UPDATE there. Unique partial indexes (migration 0005) close
  the race on both engines even if a lock were missed.
- Separation of duties by person: every actor who created the mission, edited its draft or
  cut a version up to this one.
- Key status from the log: a key is revoked when the log says so, whatever its row says."""

from __future__ import annotations

import json

from sqlalchemy import select
from sqlalchemy.orm import Session as DbSession

from ..approvals.duty_rules import EDIT_KINDS
from .tables import Event, LogEntry, MissionVersion, Submission


def lock_submission(db: DbSession, submission_id: int) -> None:
    db.execute(select(Submission.id).where(Submission.id == submission_id).with_for_update())


def lock_version(db: DbSession, version_id: int) -> None:
    db.execute(select(MissionVersion.id).where(MissionVersion.id == version_id)
               .with_for_update())


def _version_event_id(db: DbSession, version: MissionVersion) -> int | None:
    """The id of the event that cut this version (its `version.created`)."""
    for event_id, detail in db.execute(select(Event.id, Event.detail).where(
            Event.mission_id == version.mission_id, Event.kind == "version.created",
            Event.after_digest == version.digest).order_by(Event.id)):
        if isinstance(detail, dict) and detail.get("number") == version.number:
            return int(event_id)
    return None


def editors_up_to(db: DbSession, version: MissionVersion) -> set[int]:
    """Everyone who authored or edited any revision leading to this version: each
    mission.created, draft.updated and version.created event of the mission up to the one
    that cut this version, whatever digest it produced (an edit later undone still counts)."""
    query = select(Event.actor_id).where(Event.mission_id == version.mission_id,
                                         Event.kind.in_(EDIT_KINDS))
    cut = _version_event_id(db, version)
    if cut is not None:
        query = query.where(Event.id <= cut)
    # Without its version.created event (rows written behind the app's back) every edit of
    # the mission counts: refusing too many people is safe, too few is not.
    actors = set(db.scalars(query))
    return {a for a in actors if a is not None} | {version.author_id}


def logged_key_revocation(db: DbSession, key_id: str) -> int | None:
    """The index of the log entry that revoked this key, or None. Log entries are RFC 8785
    JSON, so the match on the text is narrowed by LIKE and confirmed by parsing."""
    rows = db.execute(select(LogEntry.index, LogEntry.entry).where(
        LogEntry.entry.like('%"kind":"key.revoked"%'), LogEntry.entry.like(f"%{key_id}%"))
        .order_by(LogEntry.index))
    for index, text in rows:
        try:
            event = json.loads(text)["event"]
        except (ValueError, KeyError, TypeError):
            continue
        if event.get("kind") == "key.revoked" and \
                (event.get("detail") or {}).get("key_id") == key_id:
            return int(index)
    return None
