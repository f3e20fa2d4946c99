"""Fresh password re-entry for signed decisions and revocations.

A script running in the supervisor's browser can use their session and their non-extractable
signing key, but it does not know their password. So every decision and revocation carries the
password, checked here (argon2) in the same request that stores the signed statement, under
the one password throttle (login_throttle.check_password), so that no route guesses faster than
the sign-in form can.

Call `confirm_password` first in a request's transaction: what it had begun is rolled back and
the attempt committed before the hash is checked."""

from __future__ import annotations

from sqlalchemy.orm import Session as DbSession

from ..errors import Forbidden
from .login_throttle import check_password


class PasswordRequired(Forbidden):
    """The decision lacks the signer's fresh password, or it is wrong."""


WRONG_FOR_DECISION = "the password is wrong; nothing was signed or stored"


def confirm_password(db: DbSession, *, username: str, password_hash: str,
                     password: str | None, wrong: str = WRONG_FOR_DECISION) -> None:
    """Refuse unless `password` is the user's password; throttled like sign-in (429 with
    Retry-After). `wrong` is the refusal's text, saying what did not happen."""
    if not password:
        raise PasswordRequired("a signed decision needs your password, entered again: the "
                               "signature alone may come from a script in your browser")
    if not check_password(db, username=username, stored_hash=password_hash, password=password):
        raise PasswordRequired(wrong)
