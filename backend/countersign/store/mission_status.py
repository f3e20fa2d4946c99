"""A mission's status as the log tells it (issue 34 item 9).

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


def logged_status(db: DbSession, mission_id: str) -> str:
    """The status the log gives the mission: 'draft' until a submission entry says more (a
    mission's own `mission.created` entry is appended at commit, after its first answer)."""
    status = "draft"
    for (text,) in db.execute(select(LogEntry.entry).join(Event, Event.id == LogEntry.event_id)
                              .where(Event.mission_id == mission_id,
                                     Event.kind.in_(list(STATUS_OF)))
                              .order_by(LogEntry.index)):
        try:
            event = json.loads(text)["event"]
            kind, mission = event["kind"], event["mission"]
        except (ValueError, KeyError, TypeError):
            continue  # the row's event_integrity names an unreadable entry
        if mission == mission_id and kind in STATUS_OF:
            status = STATUS_OF[kind]
    return status


def mission_status(db: DbSession, mission: Mission) -> tuple[str, list[str]]:
    """The status to show (the log's) and how the tables disagree with it."""
    logged = logged_status(db, mission.id)
    if logged != mission.status:
        return logged, [f"mission {mission.id}: the table says {mission.status}, the log says "
                        f"{logged}"]
    return logged, []
