"""A role change needs the admin's password, entered again: a script in the admin's browser
(or an arrow key on a focused drop-down) must not turn a user into an admin or a supervisor.
The check and its throttle are the decisions' (store/reauth.py)."""

from __future__ import annotations

from sqlalchemy.orm import Session

from .reauth import PasswordRequired, confirm_password
from .tables import User


def confirm_role_change(db: Session, admin: User, password: str | None) -> None:
    """Call first in the request's transaction (a wrong password commits its attempt)."""
    if not password:
        raise PasswordRequired("a role change needs your password, entered again "
                               "(admin_password)")
    confirm_password(db, username=admin.username, password_hash=admin.password_hash,
                     password=password, wrong="the password is wrong; no role was changed")
