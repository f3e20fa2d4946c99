"""What the approval services share: their errors, limits and small helpers."""

from __future__ import annotations

from datetime import datetime, timedelta
from typing import Any

from sqlalchemy.orm import Session as DbSession

from ...errors import Forbidden, Invalid
from ...limits import CLOCK_SKEW
from ..missions import Conflict
from ..tables import (
    User,
    utcnow,
)

STATEMENT_MAX_AGE = timedelta(hours=1)


class Refused(Forbidden):
    """The caller may not do this (wrong role, own work, someone else's key)."""


class Stale(Conflict):
    """The request was made against a state that has changed (or was already used)."""


class BadSignature(Invalid):
    pass


class BadDecision(Invalid):
    """A decision or revocation asked for wrongly (no such decision, a missing or long reason)."""


class BadKey(Invalid):
    """A signing key that cannot be registered as sent (not an Ed25519 public key)."""


def check_signed_time(value: Any) -> None:
    """A statement's `time`: an ISO 8601 UTC timestamp within the last STATEMENT_MAX_AGE (and no
    further ahead than the clock skew allows)."""
    try:
        signed_at = datetime.fromisoformat(str(value).replace("Z", "+00:00"))
        if signed_at.tzinfo is None:
            raise ValueError
    except ValueError:
        raise BadSignature("the statement's time is not an ISO 8601 UTC timestamp") from None
    now = utcnow()
    if not now - STATEMENT_MAX_AGE <= signed_at <= now + CLOCK_SKEW:
        raise Stale("the statement was prepared too long ago or in the future; prepare it again")


def _now_text() -> str:
    return utcnow().isoformat().replace("+00:00", "Z")


def _username(db: DbSession, user_id: int | None) -> str | None:
    if user_id is None:
        return None
    user = db.get(User, user_id)
    return user.username if user else f"#{user_id}"
