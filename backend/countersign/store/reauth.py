"""Fresh password re-entry for signed decisions and revocations (issue 14, item 2).

A script running in the supervisor's browser can use their session and their non-extractable
signing key, but it does not know their password. So every decision and revocation carries the
password, checked here (argon2) in the same request that stores the signed statement. Wrong
passwords count against the login throttle (the same `login_attempts` rows sign-in counts), so
the request cannot be used to guess the password faster than the sign-in form can.

Call `confirm_password` first in a request's transaction: a wrong password commits the failed
attempt (and nothing else: the caller has written nothing yet) before refusing."""

from __future__ import annotations

from argon2.exceptions import InvalidHashError, VerificationError
from sqlalchemy import func, select
from sqlalchemy.orm import Session as DbSession

from .accounts import HASHER, LOGIN_MAX_FAILURES, LOGIN_WINDOW, TooManyAttempts
from .db import database_of
from .missions import MissionError
from .tables import LoginAttempt, utcnow


class PasswordRequired(MissionError):
    """The decision lacks the signer's fresh password, or it is wrong."""

    status = 403


def confirm_password(db: DbSession, *, username: str, password_hash: str,
                     password: str | None) -> None:
    """Refuse unless `password` is the user's password; throttled like sign-in."""
    if not password:
        raise PasswordRequired("a signed decision needs your password, entered again: the "
                               "signature alone may come from a script in your browser")
    since = utcnow() - LOGIN_WINDOW
    # The throttle is read and the hash checked outside the request's write transaction (as at
    # sign-in): argon2 takes tens of milliseconds and SQLite has one writer.
    with database_of(db).session(write=False) as reader:
        failures = reader.scalar(select(func.count()).select_from(LoginAttempt).where(
            LoginAttempt.username == username, LoginAttempt.at >= since)) or 0
    if failures >= LOGIN_MAX_FAILURES:
        raise TooManyAttempts(f"too many wrong passwords for {username!r}; try again in "
                              f"{int(LOGIN_WINDOW.total_seconds() // 60)} minutes")
    try:
        HASHER.verify(password_hash, password)
    except (VerificationError, InvalidHashError):
        db.rollback()
        db.add(LoginAttempt(username=username[:64]))
        db.commit()
        raise PasswordRequired("the password is wrong; nothing was signed or stored") from None
