"""Rows checked against the log: the log is the source of truth, so what the
API shows of an approval or a submission is compared with the log entries that record it, and
every disagreement is returned as a sentence (the responses' `integrity` lists; the pages show
them as warnings) instead of being shown as fact."""

from __future__ import annotations

import json
from datetime import UTC
from typing import Any

from sqlalchemy import or_, select
from sqlalchemy.orm import Session as DbSession

from ..approvals.log import event_data
from ..approvals.log_rules import row_problems, submission_state
from .event_words import event_target
from .tables import Approval, Event, LogEntry, Submission


def _event(text: str) -> dict[str, Any] | None:
    try:
        event = json.loads(text)["event"]
    except (ValueError, KeyError, TypeError):
        return None
    return event if isinstance(event, dict) else None


def logged_event(db: DbSession, event_id: int) -> dict[str, Any] | None:
    text = db.scalar(select(LogEntry.entry).where(LogEntry.event_id == event_id))
    return _event(text) if text is not None else None


def approval_problems(approval: Approval, event: dict[str, Any] | None) -> list[str]:
    """How an approval row disagrees with the event its log entry recorded (None: no entry)."""
    what = f"approval {approval.id}"
    problems = row_problems({"decision": approval.decision, "reason": approval.reason,
                             "key_id": approval.key_id, "submission": approval.submission_id,
                             "orders_digest": approval.orders_digest,
                             "mission": approval.mission_id}, event, what)
    if event is not None and event.get("kind") != f"approval.{approval.decision}":
        problems.append(f"{what}: the table says {approval.decision}, its log entry records "
                        f"{event.get('kind')}")
    return problems


def logged_events(db: DbSession, event_ids: list[int]
                  ) -> dict[int, tuple[int, dict[str, Any] | None]]:
    """Each event's log index and the event its entry recorded, read in batches of 500 (events
    whose entry is gone are absent)."""
    found: dict[int, tuple[int, dict[str, Any] | None]] = {}
    for start in range(0, len(event_ids), 500):
        for event_id, index, text in db.execute(
                select(LogEntry.event_id, LogEntry.index, LogEntry.entry)
                .where(LogEntry.event_id.in_(event_ids[start:start + 500]))):
            found[event_id] = (index, _event(text))
    return found


# Submissions whose log entries one query reads: two LIKE patterns each, well below SQLite's
# limit on the depth of an expression (1000).
_CHECKED_PER_QUERY = 100


def _mentions(sid: int) -> tuple[str, str]:
    # RFC 8785 entries: `"submission":N` is followed by `,` or `}`.
    return f'"submission":{sid},', f'"submission":{sid}}}'


def submissions_checked(db: DbSession, submissions: list[Submission]
                        ) -> dict[int, tuple[str, list[str]]]:
    """Each submission's state as the log tells it (the row's when the log never created it),
    and how its row disagrees. The log's state is what the API shows: a forged row is named,
    not shown. The log entries that mention the submissions are read in one query per hundred
    submissions (not one per submission)."""
    # What LIKE matches, here in Python: SQLite's LIKE ignores the case of ASCII letters.
    fold = str.lower if db.get_bind().dialect.name == "sqlite" else str
    checked: dict[int, tuple[str, list[str]]] = {}
    for start in range(0, len(submissions), _CHECKED_PER_QUERY):
        chunk = submissions[start:start + _CHECKED_PER_QUERY]
        patterns = [pattern for s in chunk for pattern in _mentions(s.id)]
        texts = [(fold(text), text) for text in db.scalars(
            select(LogEntry.entry).where(or_(*(LogEntry.entry.like(f"%{p}%") for p in patterns)))
            .order_by(LogEntry.index))]
        for submission in chunk:
            sid = submission.id
            comma, brace = _mentions(sid)
            mine = (_event(text) for folded, text in texts if comma in folded or brace in folded)
            logged = submission_state([e for e in mine if e is not None], sid)
            if logged is None:
                checked[sid] = (submission.state, [f"submission {sid} has no log entry"])
            elif logged != submission.state:
                checked[sid] = (logged, [f"submission {sid}: the table says "
                                         f"{submission.state}, the log says {logged}"])
            else:
                checked[sid] = (logged, [])
    return checked


def event_integrity(db: DbSession, events: list[Event], actors: dict[int, str]
                    ) -> dict[int, list[str]]:
    """For each listed event row, how it disagrees with the log entry that recorded it (the
    entry's event is what the row said when it was appended; a later UPDATE shows here)."""
    logged = logged_events(db, [e.id for e in events])
    out: dict[int, list[str]] = {}
    for event in events:
        found = logged.get(event.id)
        if found is None:
            out[event.id] = [f"event {event.id} has no log entry"]
            continue
        index, entry = found
        at = event.at if event.at.tzinfo is not None else event.at.replace(tzinfo=UTC)
        row = event_data(id=event.id, at=at, actor=actors.get(event.actor_id or -1),
                         kind=event.kind, mission=event.mission_id, before=event.before_digest,
                         after=event.after_digest, detail=event.detail)
        differing = sorted(k for k in row if entry is None or row[k] != entry.get(k))
        if entry is not None and event.target != event_target(
                str(entry.get("kind")), entry.get("mission"), entry.get("detail") or {}):
            differing.append("target")
        out[event.id] = [f"event {event.id}: the table's {', '.join(differing)} disagree"
                         f"{'s' if len(differing) == 1 else ''} with log entry {index}"
                         ] if differing else []
    return out


def log_indexes(db: DbSession, event_ids: list[int]) -> dict[int, int]:
    """Each event's index in the transparency log (events whose entry is gone are absent)."""
    found: dict[int, int] = {}
    for start in range(0, len(event_ids), 500):
        found.update({int(e): int(i) for e, i in db.execute(
            select(LogEntry.event_id, LogEntry.index)
            .where(LogEntry.event_id.in_(event_ids[start:start + 500])))})
    return found
