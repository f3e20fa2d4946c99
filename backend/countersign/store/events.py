"""The append-only event log: every state change, who, what, when, before and after."""

from __future__ import annotations

from typing import Any

from sqlalchemy.orm import Session as DbSession

from .tables import Event, User


def record(
    db: DbSession, *, kind: str, actor: User | None, mission_id: str | None = None,
    before: str | None = None, after: str | None = None, detail: dict[str, Any] | None = None,
) -> Event:
    event = Event(kind=kind, actor_id=actor.id if actor else None, mission_id=mission_id,
                  before_digest=before, after_digest=after, detail=detail or {})
    db.add(event)
    return event
