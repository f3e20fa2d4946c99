"""A mission's status as the log tells it.

`missions.status` is a copy the app keeps for filtering; a database writer can set it, or a
submission's state, to 'approved'. What the mission list and page show is read from the log
instead: the kind of the mission's latest submission or decision entry (as its log entry
records it, not as the events row says now). A table that disagrees is named in the summary's
`integrity` list, which the pages show as a warning."""

from __future__ import annotations

import json

from sqlalchemy import select
from sqlalchemy.orm import Session as DbSession

from .tables import Event, LogEntry, Mission

# The log kinds that set a mission's status, and the status each sets (as the app writes
# missions.status: store/approvals/submission.py and decisions.py).
STATUS_OF = {"mission.created": "draft", "submission.created": "submitted",
             "submission.withdrawn": "withdrawn", "approval.approved": "approved",
             "approval.rejected": "rejected", "approval.revoked": "revoked"}


def logged_statuses(db: DbSession, mission_ids: list[str]) -> dict[str, str]:
    """The status the log gives each mission, in one query: 'draft' until a submission entry
    says more (a mission's own `mission.created` entry is appended at commit, after its first
    answer)."""
    statuses = dict.fromkeys(mission_ids, "draft")
    if not mission_ids:
        return statuses
    for (text,) in db.execute(select(LogEntry.entry).join(Event, Event.id == LogEntry.event_id)
                              .where(Event.mission_id.in_(mission_ids),
                                     Event.kind.in_(list(STATUS_OF)))
                              .order_by(LogEntry.index)):
        try:
            event = json.loads(text)["event"]
            kind, mission = event["kind"], event["mission"]
        except (ValueError, KeyError, TypeError):
            continue  # the row's event_integrity names an unreadable entry
        if mission in statuses and kind in STATUS_OF:
            statuses[mission] = STATUS_OF[kind]
    return statuses


def mission_statuses(db: DbSession,
                     missions: list[Mission]) -> dict[str, tuple[str, list[str]]]:
    """For each mission, the status to show (the log's) and how the tables disagree with it."""
    logged = logged_statuses(db, [m.id for m in missions])
    shown: dict[str, tuple[str, list[str]]] = {}
    for mission in missions:
        status = logged[mission.id]
        shown[mission.id] = (status, [] if status == mission.status else [
            f"mission {mission.id}: the table says {mission.status}, the log says {status}"])
    return shown


def mission_status(db: DbSession, mission: Mission) -> tuple[str, list[str]]:
    """The status to show (the log's) and how the tables disagree with it."""
    return mission_statuses(db, [mission])[mission.id]
