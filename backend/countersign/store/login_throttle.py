"""Sign-in throttling per account and per client address (issue 15).

Each attempt is recorded and committed *before* its password is hashed, then the attempts in
the window are counted: of N parallel tries, the one committed k-th sees at least k, so no
more than the limit are ever evaluated (the old code read the count first, and 100 parallel
tries made 28 evaluations instead of 10).

An account under attack is slowed, not locked, and only where the attack comes from: after
FREE_FAILURES failures from one address each further try from there must wait
2^(n - FREE_FAILURES) seconds since the last one whose password was checked, at most MAX_DELAY.
So a slow attacker at one address (one try a minute stays under the address limit) never delays
the real user signing in from another. Attempts of unknown origin (a wrong password re-entered
for a decision: reauth.py) count against every address. Across all addresses an account has
ACCOUNT_WIDE_FAILURES free failures before the same back-off holds for every try, so many
addresses together still cannot guess faster than that. What stops an attacker is the address
limit: more than ADDRESS_MAX_FAILURES failures in the window from one address (spraying many
accounts counts too) and that address waits out the window.
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
ACCOUNT_WIDE_FAILURES = 50


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


def wait_left(reader: DbSession, username: str, address: str | None, now: datetime,
              besides: int | None = None) -> timedelta | None:
    """How long a try for `username` from `address` must still wait, if at all: the back-off
    of the failures from that address (and of unknown origin), and the account-wide one."""
    recent = [LoginAttempt.username == username[:64], LoginAttempt.at >= now - WINDOW]
    if besides is not None:
        recent.append(LoginAttempt.id != besides)
    # One read for both: past about twenty failures every delay is already MAX_DELAY.
    everywhere = reader.execute(select(LoginAttempt.at, LoginAttempt.address).where(*recent)
                                .order_by(LoginAttempt.at.desc()).limit(128)).all()
    origin = address[:64] if address else None
    here = [at for at, where in everywhere if where is None or where == origin]
    waits = [(account_delay(len(here)), here), (
        account_delay(len(everywhere) - (ACCOUNT_WIDE_FAILURES - FREE_FAILURES)),
        [at for at, _ in everywhere])]
    left = max((wait - (now - times[0]) for wait, times in waits if times and wait),
               default=timedelta(0))
    return left if left > timedelta(0) else None


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
        left = wait_left(reader, username, address, now, besides=attempt_id)
    # A try is recorded before the count, so of parallel tries at most one sees the wait over.
    if left:
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
