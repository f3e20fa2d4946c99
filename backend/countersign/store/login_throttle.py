"""Sign-in throttling per account and per client address (issue 15).

Each attempt is recorded and committed *before* its password is hashed, then the attempts in
the window are counted: of N parallel tries, the one committed k-th sees at least k, so no
more than the limit are ever evaluated (the old code read the count first, and 100 parallel
tries made 28 evaluations instead of 10).

An account under attack is slowed, not locked: after FREE_FAILURES failures each further try
must wait 2^(n - FREE_FAILURES) seconds since the last one whose password was checked, at most
MAX_DELAY, so its real user waits a minute at worst instead of 15. What stops an attacker is
the address limit: more than ADDRESS_MAX_FAILURES failures in the window from one address
(spraying many accounts counts too) and that address waits out the window.
"""

from __future__ import annotations

import math
from datetime import datetime, timedelta

from sqlalchemy import delete, func, select
from sqlalchemy.orm import Session as DbSession

from .db import database_of
from .tables import LoginAttempt, utcnow

WINDOW = timedelta(minutes=15)
FREE_FAILURES = 5
MAX_DELAY = timedelta(seconds=60)
ADDRESS_MAX_FAILURES = 30


class Throttled(Exception):
    def __init__(self, message: str, retry_after_s: int) -> None:
        super().__init__(message)
        self.retry_after_s = max(1, retry_after_s)


def account_delay(failures: int) -> timedelta:
    """How long an account with this many recent failures waits between tries."""
    if failures < FREE_FAILURES:
        return timedelta(0)
    exponent = min(failures - FREE_FAILURES, 16)
    return min(timedelta(seconds=2 ** exponent), MAX_DELAY)


def admit(db: DbSession, username: str, address: str | None) -> int:
    """Record an attempt (committed at once) and return its id, or raise `Throttled`."""
    now = utcnow()
    since = now - WINDOW
    with database_of(db).session() as writer:
        attempt = LoginAttempt(username=username[:64], address=(address or "")[:64] or None,
                               at=now)
        writer.add(attempt)
        writer.flush()
        attempt_id = attempt.id
    with database_of(db).session(write=False) as reader:
        if address:
            from_address = reader.scalar(
                select(func.count()).select_from(LoginAttempt)
                .where(LoginAttempt.address == address[:64], LoginAttempt.at >= since)) or 0
            if from_address > ADDRESS_MAX_FAILURES:
                raise Throttled("too many sign-in attempts from this address; try again later",
                                int(WINDOW.total_seconds()))
        earlier: list[datetime] = list(reader.scalars(
            select(LoginAttempt.at)
            .where(LoginAttempt.username == username[:64], LoginAttempt.at >= since,
                   LoginAttempt.id != attempt_id)
            .order_by(LoginAttempt.at.desc()).limit(64)))
    # A try is recorded before the count, so of parallel tries at most one sees the wait over.
    wait = account_delay(len(earlier))
    if earlier and wait and now - earlier[0] < wait:
        left = wait - (now - earlier[0])
        # A try refused here checked no password: forgetting it keeps the wait measured from
        # the last try that did, so waiting Retry-After works and retrying early does not
        # shut the account (recorded, each one restarted a longer wait).
        with database_of(db).session() as writer:
            writer.execute(delete(LoginAttempt).where(LoginAttempt.id == attempt_id))
        raise Throttled(f"too many failed sign-ins for {username!r}; try again in "
                        f"{math.ceil(left.total_seconds())} s",
                        math.ceil(left.total_seconds()))
    return attempt_id


def succeeded(db: DbSession, username: str) -> None:
    """A correct password: the account's failures are forgotten (its address's are not)."""
    db.execute(delete(LoginAttempt).where(LoginAttempt.username == username[:64]))
