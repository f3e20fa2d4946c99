"""Editing bursts: the editor saves every edit at once, so that nothing is lost, and
each save bumps the draft's revision (its ETag, for compare-and-set). The event log, though,
records one `draft.updated` entry per burst of saves by one author, not one per keystroke pause
(108 entries in 20 minutes flooded the activity log): the burst is kept on the mission row and
logged when it ends - when someone else saves, after BURST of quiet, before a version is made
or the draft deleted, and before the events are read - saying which items changed."""

from __future__ import annotations

from datetime import datetime, timedelta
from typing import Any

from sqlalchemy import select
from sqlalchemy.orm import Session as DbSession

from ..approvals.signer import LogSigner
from .db import writable, writes
from .events import record
from .tables import Mission, User, utcnow

BURST = timedelta(minutes=2)
MAX_CHANGED = 100  # items named in one entry; more are counted
_LISTS = {"goals": "goal", "terminals": "terminal", "constraints": "constraint",
          "norms": "norm", "areas": "area", "vehicles": "vehicle", "properties": "property"}


def changed_items(before: dict[str, Any], after: dict[str, Any]) -> list[str]:
    """What differs between two drafts, in words: "goal G3", "norm N2 added", "title"."""
    out: list[str] = []
    for key in sorted(set(before) | set(after)):
        old, new = before.get(key), after.get(key)
        if old == new:
            continue
        word = _LISTS.get(key)
        if word is None or not isinstance(old or [], list) or not isinstance(new or [], list):
            out.append(key)
            continue
        olds = {x.get("id"): x for x in old or [] if isinstance(x, dict)}
        news = {x.get("id"): x for x in new or [] if isinstance(x, dict)}
        for item in [*news, *(i for i in olds if i not in news)]:
            if item not in olds:
                out.append(f"{word} {item} added")
            elif item not in news:
                out.append(f"{word} {item} removed")
            elif olds[item] != news[item]:
                out.append(f"{word} {item}")
    return out


def joins(mission: Mission, author: User, now: datetime) -> bool:
    """Whether a save by `author` now continues the mission's open burst."""
    burst = mission.burst
    return (burst is not None and burst.get("by") == author.id and mission.burst_at is not None
            and now - mission.burst_at <= BURST)


def extended(mission: Mission, author: User, *, previous: dict[str, Any],
             draft: dict[str, Any], before: str, revision: int, now: datetime
             ) -> dict[str, Any]:
    """The burst after this save (a new one unless it continues the open one); `previous`
    is the draft this save replaces."""
    burst = mission.burst if joins(mission, author, now) else None
    named: list[str] = list(burst["changed"]) if burst else []
    for item in changed_items(previous, draft):
        if item not in named:
            named.append(item)
    return {"by": author.id, "before": burst["before"] if burst else before,
            "from": burst["from"] if burst else revision,
            "saves": (burst["saves"] if burst else 0) + 1,
            "changed": named[:MAX_CHANGED], "more": max(0, len(named) - MAX_CHANGED)}


def flush(db: DbSession, mission: Mission, *, signer: LogSigner | None) -> None:
    """Logs the mission's open burst (one `draft.updated` entry) and closes it."""
    burst = mission.burst
    if burst is None:
        return
    author = db.get(User, burst["by"])
    detail = {"revision": mission.revision, "from_revision": burst["from"],
              "saves": burst["saves"], "changed": burst["changed"], "more": burst.get("more", 0)}
    record(db, signer=signer, kind="draft.updated", actor=author, mission_id=mission.id,
           before=burst["before"], after=mission.draft_digest, detail=detail, log_at_commit=True)
    mission.burst = None
    mission.burst_at = None


def flush_quiet(db: DbSession, now: datetime | None = None, *, signer: LogSigner | None) -> None:
    """Logs every burst that has been quiet for BURST (before the events are read)."""
    limit = (now or utcnow()) - BURST
    for mission in db.scalars(select(Mission).where(Mission.burst_at.is_not(None),
                                                   Mission.burst_at < limit)):
        flush(db, mission, signer=signer)


def flush_quiet_before_reading(db: DbSession, *, signer: LogSigner | None) -> None:
    """flush_quiet for a request about to read the events: through a write session of its own
    when this one only reads, whose snapshot is then ended, so that the read sees the entries."""
    limit = utcnow() - BURST
    quiet = select(Mission.id).where(Mission.burst_at.is_not(None), Mission.burst_at < limit)
    if db.scalar(quiet.limit(1)) is None:
        return
    with writable(db) as writer:
        flush_quiet(writer, signer=signer)
    if not writes(db):
        db.commit()
