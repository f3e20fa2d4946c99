"""Fresh password re-entry for signed decisions and revocations (issue 14, item 2).

A script running in the supervisor's browser can use their session and their non-extractable
signing key, but it does not know their password. So every decision and revocation carries the
password, checked here (argon2) in the same request that stores the signed statement. Wrong
passwords count against the login throttle (the same `login_attempts` rows sign-in counts), so
the request cannot be used to guess the password faster than the sign-in form can.

Call `confirm_password` first in a request's transaction: a wrong password commits the failed
attempt (and nothing else: the caller has written nothing yet) before refusing."""

from __future__ import annotations

import math

from argon2.exceptions import InvalidHashError, VerificationError
from sqlalchemy.orm import Session as DbSession

from ..errors import Forbidden
from .accounts import HASHER, TooManyAttempts
from .db import database_of
from .login_throttle import wait_left
from .tables import LoginAttempt, utcnow


class PasswordRequired(Forbidden):
    """The decision lacks the signer's fresh password, or it is wrong."""


WRONG_FOR_DECISION = "the password is wrong; nothing was signed or stored"


def confirm_password(db: DbSession, *, username: str, password_hash: str,
                     password: str | None, wrong: str = WRONG_FOR_DECISION) -> None:
    """Refuse unless `password` is the user's password; throttled like sign-in. `wrong` is the
    refusal's text, saying what did not happen (a decision, a role change)."""
    if not password:
        raise PasswordRequired("a signed decision needs your password, entered again: the "
                               "signature alone may come from a script in your browser")
    now = utcnow()
    # The throttle is read and the hash checked outside the request's write transaction (as at
    # sign-in): argon2 takes tens of milliseconds and SQLite has one writer. The back-off is
    # sign-in's (store/login_throttle.py) for an attempt of unknown address.
    with database_of(db).session(write=False) as reader:
        wait = wait_left(reader, username, None, now)
    if wait:
        left = math.ceil(wait.total_seconds())
        raise TooManyAttempts(f"too many wrong passwords for {username!r}; try again in "
                              f"{left} s", left)
    try:
        HASHER.verify(password_hash, password)
    except (VerificationError, InvalidHashError):
        db.rollback()
        db.add(LoginAttempt(username=username[:64]))
        db.commit()
        raise PasswordRequired(wrong) from None
