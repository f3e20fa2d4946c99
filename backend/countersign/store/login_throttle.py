"""The one throttle for every password check: sign-in, decisions, revocations, signing keys,
password changes, role changes and grants.

`check_password` records the attempt and commits it *before* the hash is checked, then counts
the attempts in the window: of N parallel tries, the one committed k-th sees at least k, so no
more than a limit are ever evaluated, whatever the route (a review found the decision route
reading the back-off first and recording only failures: 3.5 times sign-in's guessing rate).
A try refused here checked no hash and is forgotten at once, so refusals never count as the
account's failures (refusals of the address limit did, and one address flooding
wrong sign-ins kept the real user out everywhere).

Limits, all read from the database so that they hold across server processes and replicas:
- At most ACCOUNT_HASHES_PER_MINUTE hashes per account per minute, and at most
  ADDRESS_HASHES_PER_MINUTE wrong ones from one address, so one address can never use up
  what the real user at another address needs to sign in.
- An account under attack is slowed, not locked, and only where the attack comes from: after
  FREE_FAILURES failures from one address each further try from there waits
  2^(n - FREE_FAILURES) seconds since the last one, at most MAX_DELAY. Attempts of unknown
  origin (the command line) count against every address. Across all addresses an account has
  ACCOUNT_WIDE_FAILURES free failures before the same back-off holds for every try.
- More than ADDRESS_MAX_FAILURES failures from one address in the window (spraying many
  accounts counts too) and that address waits out the window.
"""

from __future__ import annotations

import ipaddress
import math
from contextvars import ContextVar
from datetime import datetime, timedelta

from argon2.exceptions import InvalidHashError, VerificationError
from sqlalchemy import delete, func, select, update
from sqlalchemy.orm import Session as DbSession

from ..errors import TooMany
from ..settings import password_checks_per_minute
from .db import Database, database_of
from .hashing import HASHER, HashingBusy
from .tables import LoginAttempt, utcnow

WINDOW = timedelta(minutes=15)
MINUTE = timedelta(minutes=1)
FREE_FAILURES = 5
MAX_DELAY = timedelta(seconds=60)
ADDRESS_MAX_FAILURES = 30
ACCOUNT_WIDE_FAILURES = 50
# The per-account limit: 10, unless the deployment sets COUNTERSIGN_PASSWORD_CHECKS_PER_MINUTE
# (the browser suite does: it signs its few shared accounts in more often than a person would).
ACCOUNT_HASHES_PER_MINUTE = password_checks_per_minute()
# Half the account's minute: an attacker at one address leaves the other half to the others.
ADDRESS_HASHES_PER_MINUTE = max(1, ACCOUNT_HASHES_PER_MINUTE // 2)

FAILED, OK, FORGIVEN = "failed", "ok", "forgiven"

# The client address of the request being served, set by the web app for each request
# (web/client_address.py) so that every route's password check counts where it came from,
# not only sign-in's. None (the command line) is an attempt of unknown origin.
CLIENT_ADDRESS: ContextVar[str | None] = ContextVar("countersign_client_address",
                                                     default=None)


class Throttled(TooMany):
    def __init__(self, message: str, retry_after_s: int) -> None:
        super().__init__(message)
        self.retry_after_s = max(1, retry_after_s)


def counted_address(address: str | None) -> str | None:
    """The address attempts are counted under: an IPv6 client by its /64, since one host is
    usually given a whole /64 and could otherwise try from 2^64 addresses."""
    if not address:
        return None
    try:
        parsed = ipaddress.ip_address(address)
    except ValueError:
        return address[:64]
    if isinstance(parsed, ipaddress.IPv6Address):
        if parsed.ipv4_mapped is not None:
            return str(parsed.ipv4_mapped)
        return str(ipaddress.IPv6Network((parsed, 64), strict=False))
    return str(parsed)


def check_password(db: DbSession, *, username: str, stored_hash: str, password: str,
                   address: str | None = None) -> bool:
    """Whether `password` matches `stored_hash`, checked under the throttle; raises `Throttled`
    (nothing hashed) or HashingBusy. Call it before the request's transaction writes anything:
    what it has begun is rolled back, so that the attempt can be committed beside it (on SQLite
    a second writer would wait for the lock this thread holds) and no lock is held while
    hashing. `address` defaults to the current request's (CLIENT_ADDRESS)."""
    if db.new or db.dirty or db.deleted:
        raise RuntimeError("check passwords before the transaction writes anything")
    if db.info.get("may_end"):  # a request's session (Database.open): its lock is released
        db.rollback()
    database = database_of(db)
    if not HASHER.has_room():  # before counting: a busy server costs the account nothing
        raise HashingBusy("the server is busy checking passwords; retry in a moment")
    origin = counted_address(address if address is not None else CLIENT_ADDRESS.get())
    attempt_id = admit(database, username, origin)
    try:
        HASHER.verify(stored_hash, password)
    except (VerificationError, InvalidHashError):
        return False  # the row stays: a failure, counted from the moment it was recorded
    except BaseException:
        _forget(database, attempt_id)  # no hash was checked (a full or broken hashing queue)
        raise
    _succeeded(database, username, attempt_id)
    return True


def account_delay(failures: int) -> timedelta:
    """How long an account with this many recent failures waits between tries."""
    if failures < FREE_FAILURES:
        return timedelta(0)
    exponent = min(failures - FREE_FAILURES, 16)
    return min(timedelta(seconds=2 ** exponent), MAX_DELAY)


def admit(database: Database, username: str, origin: str | None) -> int:
    """Record an attempt (committed at once) and return its id, or forget it and raise
    `Throttled`."""
    name = username[:64]
    now = utcnow()
    with database.session() as writer:
        attempt = LoginAttempt(username=name, address=origin, at=now, outcome=FAILED)
        writer.add(attempt)
        writer.flush()
        attempt_id = attempt.id
        # Rows past the window decide nothing: cleared here, no background job needed.
        writer.execute(delete(LoginAttempt).where(LoginAttempt.at < now - WINDOW))
    with database.session(write=False) as reader:
        refusal = _refusal(reader, name, origin, now, attempt_id)
    if refusal is not None:
        _forget(database, attempt_id)
        raise refusal
    return attempt_id


def _refusal(reader: DbSession, name: str, origin: str | None, now: datetime,
             attempt_id: int) -> Throttled | None:
    if origin is not None:
        from_address = reader.scalar(
            select(func.count()).select_from(LoginAttempt)
            .where(LoginAttempt.address == origin, LoginAttempt.at >= now - WINDOW,
                   LoginAttempt.outcome != OK, LoginAttempt.id != attempt_id)) or 0
        if from_address >= ADDRESS_MAX_FAILURES:
            return Throttled("too many wrong passwords from this address; try again later",
                             int(WINDOW.total_seconds()))
    # One read for every account limit: past about twenty failures each delay is MAX_DELAY,
    # and the minute's limits need at most ACCOUNT_HASHES_PER_MINUTE rows.
    rows = reader.execute(
        select(LoginAttempt.at, LoginAttempt.address, LoginAttempt.outcome)
        .where(LoginAttempt.username == name, LoginAttempt.at >= now - WINDOW,
               LoginAttempt.id != attempt_id)
        .order_by(LoginAttempt.at.desc()).limit(128)).all()
    minute = [(at, where, outcome) for at, where, outcome in rows if at > now - MINUTE]
    # An address's share counts its wrong (and pending) passwords only: the real user signing
    # in and then deciding uses the account's minute, not an attacker's share of it.
    mine = [at for at, where, outcome in minute if where == origin and outcome != OK]
    for limit, times in ((ADDRESS_HASHES_PER_MINUTE, mine),
                         (ACCOUNT_HASHES_PER_MINUTE, [at for at, _, _ in minute])):
        if len(times) >= limit:
            # Free again when the oldest of the last `limit` leaves the minute.
            left = times[limit - 1] + MINUTE - now
            return Throttled(f"too many password checks for {name!r}; try again in "
                             f"{_seconds(left)} s", _seconds(left))
    failures = [(at, where) for at, where, outcome in rows if outcome == FAILED]
    here = [at for at, where in failures if where is None or where == origin]
    everywhere = [at for at, _ in failures]
    waits = [(account_delay(len(here)), here),
             (account_delay(len(everywhere) - (ACCOUNT_WIDE_FAILURES - FREE_FAILURES)),
              everywhere)]
    # Measured from the newest other attempt, recorded or in flight: of parallel tries at
    # most one sees the wait over.
    left = max((wait - (now - times[0]) for wait, times in waits if times and wait),
               default=timedelta(0))
    if left > timedelta(0):
        return Throttled(f"too many wrong passwords for {name!r}; try again in "
                         f"{_seconds(left)} s", _seconds(left))
    return None


def _seconds(left: timedelta) -> int:
    return max(1, math.ceil(left.total_seconds()))


def _forget(database: Database, attempt_id: int) -> None:
    # A try refused before its hash checked nothing: forgetting it keeps every wait measured
    # from the last try that did, so waiting Retry-After works and retrying early (or from
    # an address past its limit) does not shut the account for anyone else.
    with database.session() as writer:
        writer.execute(delete(LoginAttempt).where(LoginAttempt.id == attempt_id))


def _succeeded(database: Database, username: str, attempt_id: int) -> None:
    """A right password: the account's failures are forgiven (its back-off ends), but they
    still count against their addresses, and every row still counts as a hash checked."""
    with database.session() as writer:
        writer.execute(update(LoginAttempt).where(LoginAttempt.id == attempt_id)
                       .values(outcome=OK))
        writer.execute(update(LoginAttempt)
                       .where(LoginAttempt.username == username[:64],
                              LoginAttempt.outcome == FAILED, LoginAttempt.id < attempt_id)
                       .values(outcome=FORGIVEN))
